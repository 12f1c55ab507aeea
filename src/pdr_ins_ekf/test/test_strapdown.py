"""Attitude increments and pure INS against the simulator's ground truth."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdr_ins_ekf.attitude_update import (
    METHODS,
    closed_form_increments,
    increments,
    pade_coefficients,
)
from pdr_ins_ekf.strapdown import mechanize, propagate_attitude
from pdr_sim import signals
from pdr_sim.foot_trajectory import FootTrajectory
from pdr_sim.scenario import scenario_from_dict


def test_pade_11_is_eq_11():
    n, d = pade_coefficients(1, 1)
    np.testing.assert_allclose(n, [1, 0.5])
    np.testing.assert_allclose(d, [1, 0.5])
    omega = np.array([[0.3, -1.2, 2.0]])
    a = np.array([[0, -2.0, -1.2], [2.0, 0, -0.3], [1.2, 0.3, 0]]) * 0.01
    eq11 = (2 * np.eye(3) + a) @ np.linalg.inv(2 * np.eye(3) - a)
    np.testing.assert_allclose(increments("pade11", omega, 0.01)[0], eq11, atol=1e-15)


@pytest.mark.parametrize("method", METHODS)
def test_increments_approach_the_exact_rotation(method):
    rng = np.random.default_rng(0)
    omega = rng.normal(scale=3.0, size=(50, 3))
    dt = 0.005
    exact = Rotation.from_rotvec(omega * dt).as_matrix()
    if method == "quaternion":
        q0 = np.array([0.1, -0.2, 0.3, 0.9])
        q0 /= np.linalg.norm(q0)
        q1 = increments(method, omega, dt) @ q0
        got = (Rotation.from_quat(q0).inv() * Rotation.from_quat(q1)).as_matrix()
    else:
        got = increments(method, omega, dt)
    tolerance = 1e-5 if method == "pade11" else 1e-12
    np.testing.assert_allclose(got, exact, atol=tolerance)


def test_closed_form_at_zero_rate_is_identity():
    np.testing.assert_allclose(closed_form_increments(np.zeros((2, 3)), 0.01), [np.eye(3)] * 2)


def test_pure_ins_follows_the_noiseless_truth():
    data = {"segments": [{"type": "standing", "duration_s": 1.0},
                         {"type": "straight", "steps": 10}], "initial": {"yaw_deg": 30}}
    traj = FootTrajectory(scenario_from_dict(data, "walk")).sample(1000.0)
    sol = mechanize(signals.angular_rate(traj), signals.specific_force(traj), 1000.0,
                    traj.matrix[0], method="closed_form")
    attitude_error = np.linalg.norm(
        (Rotation.from_matrix(sol.attitude[-1]).inv() * traj.attitude[-1]).as_rotvec())
    assert attitude_error < 1e-4
    assert np.linalg.norm(sol.position[-1] - traj.position[-1]) < 0.05


def test_unknown_method():
    with pytest.raises(ValueError, match="unknown attitude method 'pade44'"):
        propagate_attitude(np.eye(3), np.zeros((3, 3)), 0.01, "pade44")
