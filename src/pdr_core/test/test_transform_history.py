"""Transforms over time and REP-105's map → odom (pdr_core.ros.transform_history)."""
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from pdr_core.ros.transform_history import TransformHistory, map_to_odom


def moving(stamps_ns: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """0.5 m/s forward, turning 0.2 rad/s about the vertical."""
    t = stamps_ns * 1e-9
    return (np.column_stack([0.5 * t, np.zeros_like(t), np.zeros_like(t)]),
            Rotation.from_euler("z", 0.2 * t[:, None]).as_quat())


def test_a_lookup_between_two_poses_interpolates_and_none_outside():
    history = TransformHistory(100)
    stamps = np.arange(0, 10) * 100_000_000
    for s, p, q in zip(stamps, *moving(stamps), strict=True):
        history.add(int(s), p, q)
    wanted = np.array([-1, 50_000_000, 450_000_000, 900_000_000, 900_000_001])
    position, quaternion, found = history.at(wanted)
    assert found.tolist() == [False, True, True, True, False]
    expected_p, expected_q = moving(wanted[found])
    np.testing.assert_allclose(position, expected_p, atol=1e-12)
    assert (Rotation.from_quat(quaternion) * Rotation.from_quat(expected_q).inv()
            ).magnitude().max() < 1e-12


def test_poses_a_lookup_has_passed_are_forgotten_and_the_rest_kept():
    history = TransformHistory(100)
    for k in range(10):
        history.add(k, np.zeros(3), np.array([0, 0, 0, 1.0]))
    history.at(np.array([4]))
    assert history.stamp_ns.tolist() == [4, 5, 6, 7, 8, 9]
    history.at(np.array([6]))
    assert history.stamp_ns[0] == 6
    capped = TransformHistory(3)
    for k in range(10):
        capped.add(k, np.zeros(3), np.array([0, 0, 0, 1.0]))
    assert capped.at(np.array([2, 8]))[2].tolist() == [False, True]


def test_a_later_pose_of_an_equal_stamp_replaces_the_first():
    history = TransformHistory(10)
    history.add(5, np.zeros(3), np.array([0, 0, 0, 1.0]))
    history.add(5, np.ones(3), np.array([0, 0, 0, 1.0]))
    np.testing.assert_array_equal(history.at(np.array([5]))[0], [[1, 1, 1]])


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_map_to_odom_composes_with_odometry_to_the_pose(seed):
    rng = np.random.default_rng(seed)
    p_mb, p_ob = rng.normal(size=(5, 3)), rng.normal(size=(5, 3))
    r_mb, r_ob = Rotation.random(5, rng), Rotation.random(5, rng)
    p_mo, q_mo = map_to_odom(p_mb, r_mb.as_quat(), p_ob, r_ob.as_quat())
    r_mo = Rotation.from_quat(q_mo)
    np.testing.assert_allclose(p_mo + r_mo.apply(p_ob), p_mb, atol=1e-12)
    assert ((r_mo * r_ob) * r_mb.inv()).magnitude().max() < 1e-9
