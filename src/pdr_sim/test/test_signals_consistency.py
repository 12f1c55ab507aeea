"""The generated signals agree with the trajectory they come from (issue 3, acceptance 1).

- A test-side strapdown integrator (second order: midpoint rotation, trapezoidal
  velocity and position) on the noiseless signals returns to the true trajectory.
- The analytic accelerations and turn rates agree with the paper's numerical route:
  finite differences of the positions through Eq. (6), and the matrix logarithm of
  Eq. (10) (Zampella et al. 2011).
"""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.maths.rotations import body_rate_from_matrix_log
from pdr_sim import signals
from pdr_sim.foot_trajectory import FootTrajectory
from pdr_sim.scenario import scenario_from_dict

G = STANDARD_GRAVITY_MPS2
WALKS = {
    "straight": [{"type": "standing", "duration_s": 1.0}, {"type": "straight", "steps": 10},
                 {"type": "standing", "duration_s": 0.5}],
    "curved": [{"type": "standing", "duration_s": 1.0},
               {"type": "curve", "steps": 5, "radius_m": 3.0, "direction": "left"},
               {"type": "turn", "angle_deg": -60, "duration_s": 1.0},
               {"type": "curve", "steps": 5, "radius_m": 2.0, "direction": "right"},
               {"type": "standing", "duration_s": 0.5}],
}


def walk(name, **extra):
    return FootTrajectory(scenario_from_dict({"segments": WALKS[name],
                                              "initial": {"yaw_deg": 30, "pitch_deg": 5},
                                              **extra}, name))


def interval_integrals(x, dt):
    """∫ over each sample interval, (N−1, ...), by the four-point rule
    dt/24·(−x_{k−1} + 13x_k + 13x_{k+1} − x_{k+2}) (trapezoid on the first and last)."""
    out = (x[:-1] + x[1:]) / 2 * dt
    out[1:-1] = (-x[:-3] + 13 * x[1:-2] + 13 * x[2:-1] - x[3:]) / 24 * dt
    return out


def strapdown(traj, gyro, accel, rate_hz):
    """Reference integration from the true initial state: rotation increments with the
    coning term ω_k × ω_{k+1}·dt²/12, then velocity and position by the four-point rule."""
    dt = 1.0 / rate_hz
    angle = interval_integrals(gyro, dt) + np.cross(gyro[:-1], gyro[1:]) * dt**2 / 12
    attitude = [traj.attitude[0]]
    for inc in Rotation.from_rotvec(angle):
        attitude.append(attitude[-1] * inc)
    acc_n = Rotation.concatenate(attitude).apply(accel) - [0.0, 0.0, G]
    vel = traj.velocity[0] + np.concatenate([[np.zeros(3)],
                                             np.cumsum(interval_integrals(acc_n, dt), axis=0)])
    return traj.position[0] + np.concatenate([[np.zeros(3)],
                                              np.cumsum(interval_integrals(vel, dt), axis=0)])


def final_error(name, rate_hz):
    traj = walk(name).sample(rate_hz)
    pos = strapdown(traj, signals.angular_rate(traj), signals.specific_force(traj), rate_hz)
    return np.linalg.norm(pos - traj.position, axis=1).max()


@pytest.mark.parametrize("name", WALKS)
def test_strapdown_returns_to_truth_and_converges(name):
    e1k, e2k = final_error(name, 1000.0), final_error(name, 2000.0)
    assert e1k < 1e-3, f"{name}: max position error {e1k:.2e} m at 1 kHz"
    assert e1k / e2k >= 3.0, f"{name}: error fell only {e1k / e2k:.2f}x from 1 to 2 kHz"


def interior(traj, phases, rate_hz, margin=2):
    """Samples at least ``margin`` samples away from every phase boundary."""
    edges = np.round(np.concatenate([phases.start, [phases.end_time]]) * rate_hz)
    k = np.arange(len(traj.t))
    return np.abs(k[:, None] - edges[None, :]).min(axis=1) > margin


@pytest.mark.parametrize("name", WALKS)
@pytest.mark.parametrize("timing", ["smooth", "linear"])
def test_analytic_acceleration_matches_finite_differences(name, timing):
    rate = 10000.0
    model = walk(name, timing=timing)
    traj = model.sample(rate)
    fd = (traj.position[2:] - 2 * traj.position[1:-1] + traj.position[:-2]) * rate**2
    ok = interior(traj, model.phases, rate)[1:-1]
    f_fd = traj.attitude[1:-1].inv().apply(fd + np.array([0, 0, G]))[ok]
    f = signals.specific_force(traj)[1:-1][ok]
    assert np.abs(f_fd - f).max() / np.abs(f).max() < 1e-6


@pytest.mark.parametrize("name", WALKS)
@pytest.mark.parametrize("timing", ["smooth", "linear"])
def test_analytic_rate_matches_matrix_log(name, timing):
    rate = 10000.0
    model = walk(name, timing=timing)
    traj = model.sample(2 * rate)
    even = slice(0, None, 2)
    omega_log = body_rate_from_matrix_log(traj.attitude[even], 1.0 / rate)
    omega_mid = traj.body_rate[1::2][: len(omega_log)]
    ok = interior(traj, model.phases, 2 * rate)[1::2][: len(omega_log)]
    scale = np.abs(traj.body_rate).max()
    assert np.abs(omega_log - omega_mid)[ok].max() / scale < 1e-6


def test_smooth_timing_is_continuous_through_boundaries():
    """At a stance/swing boundary the smooth timing changes f and ω by O(dt²) between
    samples; the paper's linear timing jumps (by SL·π²/(2t_u²) and 2πθ_max/t_u)."""
    for timing, small in (("smooth", True), ("linear", False)):
        model = walk("straight", timing=timing)
        traj = model.sample(1000.0)
        edge = ~interior(traj, model.phases, 1000.0, margin=1)[:-1]
        df = np.abs(np.diff(signals.specific_force(traj), axis=0))[edge].max()
        dw = np.abs(np.diff(traj.body_rate, axis=0))[edge].max()
        if small:
            assert df < 1e-2 and dw < 1e-3, (df, dw)
        else:
            assert df > 5.0 and dw > 4.0, (df, dw)
