"""pdr_core.maths.angles and the tilt and turn of pdr_core.maths.rotations: the wrap, the
axial wrap, the circular mean, the roll and pitch that level a specific force, the turn
about the vertical."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pdr_core.maths.angles import circular_mean, wrap_angle, wrap_angle_jit, wrap_axial
from pdr_core.maths.rotations import about_vertical, rotation_from_euler, tilt_from_specific_force

ROUNDING = 1e-12            # [rad]: the wrap's rounding grows with |angle| (1e3 rad: 2e-13)
angles = st.floats(-1e3, 1e3)
directions = st.floats(-np.pi, np.pi)


def same_direction(a, b, tolerance: float = ROUNDING) -> bool:
    """a and b [rad] are one direction, up to ``tolerance`` [rad]."""
    return abs(np.sin(a - b)) < tolerance and np.cos(a - b) > 0


@given(angles)
def test_the_wrap_is_in_range_and_equal_modulo_two_pi(a):
    w = wrap_angle(a)
    assert -np.pi <= w <= np.pi
    assert same_direction(w, a)
    assert abs((a - w) / (2 * np.pi) - round((a - w) / (2 * np.pi))) < ROUNDING


@given(angles)
def test_the_wrap_is_idempotent(a):
    w = wrap_angle(a)
    assert same_direction(wrap_angle(w), w)
    if abs(w) < 3.0:                      # away from ±π, where a rounding may flip the sign
        assert wrap_angle(w) == pytest.approx(w, abs=ROUNDING)


def test_the_wrap_of_numbers_it_leaves_alone_and_of_the_half_turn():
    np.testing.assert_allclose(wrap_angle(np.array([0.0, 1.0, -3.0, 3.0])),
                               [0.0, 1.0, -3.0, 3.0], atol=1e-15)
    assert wrap_angle(np.pi) == np.pi and wrap_angle(-np.pi) == np.pi
    assert wrap_angle(2.5 * np.pi) == pytest.approx(0.5 * np.pi)


def test_the_compiled_wrap_gives_the_same_bits():
    a = np.random.default_rng(0).uniform(-50, 50, 10_000)
    assert np.array_equal(wrap_angle_jit(a), wrap_angle(a))
    assert all(wrap_angle_jit(float(x)) == wrap_angle(float(x)) for x in a[:100])


@given(angles)
def test_the_axial_wrap_is_in_range_and_equal_modulo_pi(a):
    w = float(wrap_axial(a))
    assert -np.pi / 2 <= w <= np.pi / 2
    assert abs(np.sin(a - w)) < ROUNDING


@given(st.lists(directions, min_size=1, max_size=20), directions)
def test_the_circular_mean_of_a_rotated_set_is_rotated(values, turn):
    s, c = np.sin(values).sum(), np.cos(values).sum()
    if np.hypot(s, c) < 1e-3 * len(values):     # no mean direction: the vectors cancel
        return
    rotated = circular_mean(np.asarray(values) + turn)
    assert same_direction(rotated, circular_mean(values) + turn, 1e-9)


def test_the_circular_mean_across_the_half_turn():
    assert circular_mean([np.pi - 0.1, -np.pi + 0.1]) == pytest.approx(np.pi)
    assert circular_mean([0.1, -0.1, 0.3]) == pytest.approx(np.arctan2(
        np.sin(0.3), 2 * np.cos(0.1) + np.cos(0.3)))


@given(st.floats(-3.0, 3.0), st.floats(-1.5, 1.5), st.floats(-np.pi, np.pi),
       st.floats(5.0, 15.0))
def test_the_tilt_levels_the_specific_force_at_rest(roll, pitch, yaw, g):
    """f = C_b^nᵀ·[0, 0, g]: the tilt gives back roll and pitch, whatever the yaw."""
    force = rotation_from_euler(roll, pitch, yaw).inv().apply([0.0, 0.0, g])
    r, p = tilt_from_specific_force(force)
    assert same_direction(r, roll, 1e-9)
    assert p == pytest.approx(pitch, abs=1e-9)


def test_the_tilt_of_many_forces_is_per_force():
    forces = np.array([[[0.0, 0.0, 9.8], [0.0, 9.8, 0.0]], [[-9.8, 0.0, 0.0], [0, 0, -9.8]]])
    roll, pitch = tilt_from_specific_force(forces)
    np.testing.assert_allclose(roll, [[0.0, np.pi / 2], [0.0, np.pi]])
    np.testing.assert_allclose(pitch, [[0.0, 0.0], [np.pi / 2, 0.0]])


@given(directions, st.lists(st.floats(-1e3, 1e3), min_size=3, max_size=3))
def test_the_turn_about_the_vertical_is_scipys_yaw_and_keeps_the_height(angle, point):
    turned = about_vertical(np.array(point), angle)
    np.testing.assert_allclose(turned, rotation_from_euler(0.0, 0.0, angle).apply(point),
                               atol=1e-9)
    assert turned[2] == point[2]
    np.testing.assert_allclose(about_vertical(turned, -angle), point, atol=1e-9)


def test_the_turn_about_the_vertical_takes_any_leading_shape():
    points = np.arange(24.0).reshape(2, 4, 3)
    turned = about_vertical(points, np.pi / 2)
    assert turned.shape == points.shape
    np.testing.assert_allclose(turned[1, 2], [-points[1, 2, 1], points[1, 2, 0], points[1, 2, 2]])
