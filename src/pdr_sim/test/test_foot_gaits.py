"""Foot gaits beyond level walking (issue 30): the trajectories are consistent, the stance
truth is where the velocity is zero, stairs climb their height, and each gait has the
stance fraction, cadence and impact its docstring (pdr_sim.foot_gaits) documents."""
import numpy as np
import pytest
from rotation_products import prefix_products
from scipy.spatial.transform import Rotation

from pdr_core import topics
from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.maths.rotations import body_rate_from_matrix_log
from pdr_sim import signals
from pdr_sim.foot_gaits import GAITS, stance_timing
from pdr_sim.foot_pieces import SWING
from pdr_sim.foot_trajectory import PIECE, FootTrajectory, level_walk_like
from pdr_sim.scenario import GAIT_SCENARIOS, load_scenario, scenario_from_dict
from pdr_sim.simulation import (
    STATIONARY_RATE_RADPS,
    STATIONARY_SPEED_MPS,
    SimulationConfig,
    simulate,
)

G = STANDARD_GRAVITY_MPS2
GAITS_UNDER_TEST = {
    "walk": {}, "run": {}, "in_place": {}, "back_steps": {}, "crawl": {},
    "stairs_up": {"type": "stairs", "direction": "up"},
    "stairs_down": {"type": "stairs", "direction": "down"},
    "side_steps": {"direction": "left"},
}


def gait_walk(name: str, steps: int = 4, **extra) -> FootTrajectory:
    segment = {"type": name, "steps": steps, **GAITS_UNDER_TEST[name]}
    data = {"initial": {"yaw_deg": 30}, "seed": 3,
            "segments": [{"type": "standing", "duration_s": 1.0}, segment,
                         {"type": "standing", "duration_s": 1.0}], **extra}
    return FootTrajectory(scenario_from_dict(data, name))


def landings(model: FootTrajectory) -> np.ndarray:
    return model.phases.impacts.time


def away_from(t: np.ndarray, events: np.ndarray, margin: float) -> np.ndarray:
    return np.abs(t[:, None] - events[None, :]).min(axis=1) > margin


@pytest.mark.parametrize("name", GAITS_UNDER_TEST)
def test_velocity_and_acceleration_are_the_derivatives_of_position(name):
    """Central differences at 20 kHz agree with the analytic velocity and acceleration
    away from the piece boundaries (where the jerk jumps) and the landings (where the
    velocity has a kink, as a contact force makes it)."""
    rate = 20000.0
    model = gait_walk(name)
    traj = model.sample(rate)
    p = traj.position
    fd_v = (p[2:] - p[:-2]) * rate / 2
    fd_a = (p[2:] - 2 * p[1:-1] + p[:-2]) * rate**2
    ok = away_from(traj.t[1:-1], np.concatenate([landings(model), model.phases.start]),
                   2.5 / rate)
    scale_v, scale_a = np.abs(traj.velocity).max(), np.abs(traj.acceleration).max()
    assert np.abs(fd_v - traj.velocity[1:-1])[ok].max() < 2e-6 * scale_v
    assert np.abs(fd_a - traj.acceleration[1:-1])[ok].max() < 1e-4 * scale_a


@pytest.mark.parametrize("name", GAITS_UNDER_TEST)
def test_turn_rate_is_the_derivative_of_attitude(name):
    """The analytic body rate agrees with Zampella et al. 2011, Eq. (10)'s matrix
    logarithm between samples at 10 kHz to 1e-5 of the largest rate (the midpoint's
    O(h²) differs from the interval's mean rate by about that where the impact rings),
    away from the piece boundaries and landings, where the angular acceleration jumps."""
    rate = 10000.0
    model = gait_walk(name)
    traj = model.sample(2 * rate)
    omega_log = body_rate_from_matrix_log(traj.attitude[::2], 1.0 / rate)
    omega_mid = traj.body_rate[1::2][: len(omega_log)]
    ok = away_from(traj.t[1::2][: len(omega_log)],
                   np.concatenate([landings(model), model.phases.start]), 1 / rate)
    assert np.abs(omega_log - omega_mid)[ok].max() < 1e-5 * np.abs(traj.body_rate).max()


@pytest.mark.parametrize("name", GAITS_UNDER_TEST)
def test_strapdown_of_the_signals_returns_to_the_truth(name):
    """Integrating the noiseless gyroscope (rotation vectors with the coning term) and
    specific force (trapezoids) at 2 kHz from the true initial state follows the true
    position to 2 mm over the whole segment."""
    rate = 2000.0
    traj = gait_walk(name).sample(rate)
    gyro, accel, dt = signals.angular_rate(traj), signals.specific_force(traj), 1 / rate
    increments = (gyro[:-1] + gyro[1:]) / 2 * dt + np.cross(gyro[:-1], gyro[1:]) * dt**2 / 12
    attitude = prefix_products(Rotation.concatenate([traj.attitude[0],
                                                     Rotation.from_rotvec(increments)]))
    acc_n = attitude.apply(accel) - [0.0, 0.0, G]
    vel = np.concatenate([[np.zeros(3)], np.cumsum((acc_n[1:] + acc_n[:-1]) / 2 * dt, 0)])
    pos = traj.position[0] + np.concatenate([[np.zeros(3)],
                                             np.cumsum((vel[1:] + vel[:-1]) / 2 * dt, 0)])
    assert np.abs(vel - traj.velocity).max() < 5e-3
    assert np.linalg.norm(pos - traj.position, axis=1).max() < 2e-3


@pytest.mark.parametrize("name", GAITS_UNDER_TEST)
def test_stance_truth_is_where_the_velocity_is_zero(name):
    """ground_truth/stance is |v| < 1e-9 m/s and |ω| < 1e-9 rad/s per IMU sample:
    standing and a still foot flat, never a roll about a contact or an impact."""
    model = gait_walk(name)
    scenario = model.scenario
    sim = simulate(SimulationConfig(scenario, {}, "ideal", {}, 200.0, 0))
    stance = sim.truth[topics.GROUND_TRUTH_STANCE]
    speed = np.linalg.norm(sim.trajectory.velocity, axis=1)
    rate = np.linalg.norm(sim.trajectory.body_rate, axis=1)
    np.testing.assert_array_equal(stance.stamp_ns, sim.imu.stamp_ns)
    np.testing.assert_array_equal(stance["stationary"], (speed < STATIONARY_SPEED_MPS)
                                  & (rate < STATIONARY_RATE_RADPS))
    np.testing.assert_array_equal(stance["statistic"], speed)
    spec = scenario.segments[1].gait
    t = sim.trajectory.t
    in_gait = (t > 1.0 + spec.settle_s + 1e-9) & (t < model.duration_s - 1.0 - spec.settle_s)
    still = stance["stationary"][in_gait].mean()
    # a still foot flat is the only rest within the strides (eversion_deg 0 keeps it still)
    expected = spec.flat_s / spec.cycle_s if spec.eversion_deg == 0 else 0.0
    assert still == pytest.approx(expected, abs=0.05)


@pytest.mark.parametrize("direction, sign", [("up", 1), ("down", -1)])
def test_stairs_climb_two_risers_per_stride_and_end_level(direction, sign):
    model = gait_walk(f"stairs_{direction}", steps=6)
    spec = model.scenario.segments[1].gait
    traj = model.sample(500.0)
    assert traj.position[-1, 2] - traj.position[0, 2] == pytest.approx(
        sign * 12 * spec.riser_m, abs=1e-9)
    along = np.hypot(*(traj.position[-1, :2] - traj.position[0, :2]))
    assert along == pytest.approx(12 * spec.tread_m, abs=1e-9)
    assert traj.euler[-1, :2] == pytest.approx([0.0, 0.0], abs=1e-12), "ends flat"
    # toe first: the pitch at each landing is the landing pitch, toes down
    k = np.searchsorted(traj.t, landings(model))
    np.testing.assert_allclose(np.degrees(traj.euler[k, 1]), spec.landing_pitch_deg, atol=0.5)


@pytest.mark.parametrize("name", GAITS_UNDER_TEST)
def test_stance_fraction_and_cadence_are_as_documented(name):
    model = gait_walk(name, steps=30)
    spec = model.scenario.segments[1].gait
    phases = model.phases
    land = landings(model)
    cycle = np.diff(land)
    assert cycle.mean() == pytest.approx(spec.cycle_s, rel=0.02)
    assert cycle.std() == pytest.approx(spec.cycle_variation * spec.cycle_s, rel=0.4)
    swings = phases.duration[(phases.kind == PIECE) & (phases.pieces.kind == SWING)][1:]
    stance = cycle - swings
    assert stance == pytest.approx(stance_timing(spec)[0], abs=1e-9)
    assert stance.mean() / cycle.mean() == pytest.approx(spec.stance_fraction, rel=0.02)
    assert phases.path_length_m == pytest.approx(30 * spec.stride_m, rel=1e-9)


@pytest.mark.parametrize("name, low_g, high_g", [("walk", 2.5, 5.0), ("run", 7.0, 12.0),
                                                 ("crawl", 1.0, 2.5)])
def test_landing_impact_peaks_as_documented(name, low_g, high_g):
    """Peak specific force: ~3-4 g walking, ~9 g running (Lafortune 1991: tibia 2.7-3.7 g
    walking, 10.6 g running; the pyshoe VICON trials 3.9-4.6 g and 8-12 g)."""
    traj = gait_walk(name, steps=10).sample(1000.0)
    peak = np.linalg.norm(signals.specific_force(traj), axis=1).max() / G
    assert low_g < peak < high_g


def test_running_stance_never_stops_turning():
    """The running foot is never still: its slowest turn rate in each stance is
    10-30 deg/s, as in the pyshoe running trials."""
    model = gait_walk("run", steps=12)
    traj = model.sample(1000.0)
    rate = np.degrees(np.linalg.norm(traj.body_rate, axis=1))
    stance = stance_timing(model.scenario.segments[1].gait)[0]
    slowest = [rate[(traj.t >= t0) & (traj.t < t0 + stance)].min()
               for t0 in landings(model)[:-1]]
    assert min(slowest) > 10.0 and max(slowest) < 30.0


def test_impact_ends_exactly_at_rest():
    """After the impact's duration a still foot flat has exactly zero velocity."""
    model = gait_walk("walk", steps=3)
    spec = model.scenario.segments[1].gait
    for t0 in landings(model)[:-1]:
        t = t0 + spec.loading_s + np.linspace(0.0, spec.flat_s, 50)
        assert not np.any(model.at(t).velocity)


def test_builtin_gait_scenarios_last_60_to_100_s_and_start_and_end_standing():
    for name in GAIT_SCENARIOS:
        scenario, _ = load_scenario(name)
        assert 60.0 <= FootTrajectory(scenario).duration_s <= 100.0, name
        assert scenario.segments[0].type == scenario.segments[-1].type == "standing"


@pytest.mark.parametrize("name", GAIT_SCENARIOS[:-1])
def test_level_walk_like_lasts_as_long(name):
    scenario, data = load_scenario(name)
    walk = scenario_from_dict(level_walk_like(scenario, data), "walk")
    assert FootTrajectory(walk).duration_s == pytest.approx(
        FootTrajectory(scenario).duration_s, abs=1e-6)
    assert {s.type for s in walk.segments} == {"standing", "walk", "turn"}


@pytest.mark.parametrize("segment, key", [
    ({"type": "run", "steps": 3, "gait": {"stride": 2.0}}, "segments[0].gait.stride"),
    ({"type": "run", "steps": 3, "gait": {"riser_m": 0.2}}, "segments[0].gait.riser_m"),
    ({"type": "stairs", "steps": 3}, "segments[0].direction"),
    ({"type": "stairs", "steps": 3, "direction": "left"}, "segments[0].direction"),
    ({"type": "stairs", "steps": 3, "direction": "up", "gait": {"stride_m": 0.6}},
     "segments[0].gait.stride_m"),
    ({"type": "in_place", "steps": 3, "gait": {"stride_m": 0.6}}, "segments[0].gait.stride_m"),
    ({"type": "walk", "steps": 3, "gait": {"loading_s": 0.6}}, "segments[0].gait.loading_s"),
    ({"type": "walk", "steps": 3, "gait": {"cycle_s": 0}}, "segments[0].gait.cycle_s"),
    ({"type": "walk", "steps": 3, "gait": {"stance_fraction": 1.2}},
     "segments[0].gait.stance_fraction"),
    ({"type": "walk", "steps": 3, "gait": {"stance_pitch_deg": 5}}, "segments[0].gait.settle_s"),
    ({"type": "walk", "steps": 3, "gait": {"clearance_m": "high"}},
     "segments[0].gait.clearance_m"),
    ({"type": "walk", "steps": 3, "step": {"length_m": 1.0}}, "segments[0].step"),
    ({"type": "crawl", "steps": 0}, "segments[0].steps"),
    ({"type": "side_steps", "steps": 3, "direction": "up"}, "segments[0].direction"),
])
def test_bad_gait_segments_name_the_key(segment, key):
    with pytest.raises(InputError) as err:
        scenario_from_dict({"segments": [segment]}, "x.yaml")
    assert key in str(err.value)


def test_gait_defaults_are_the_documented_ones():
    """Every gait's stance fraction and cycle are within the ranges docs/simulator.md
    cites, and the landing contact is the documented one."""
    documented = {"walk": (0.58, 0.62, 1.0, 1.2), "run": (0.31, 0.39, 0.65, 0.75),
                  "stairs_up": (0.6, 0.7, 1.1, 1.4), "stairs_down": (0.6, 0.7, 1.1, 1.4),
                  "in_place": (0.55, 0.65, 0.9, 1.1), "side_steps": (0.55, 0.7, 1.0, 1.4),
                  "back_steps": (0.6, 0.7, 1.0, 1.2), "crawl": (0.6, 0.8, 1.2, 2.0)}
    for name, (low, high, fast, slow) in documented.items():
        spec = GAITS[name]
        assert low <= spec.stance_fraction <= high and fast <= spec.cycle_s <= slow, name
    assert GAITS["walk"].landing_pitch_deg < 0 and GAITS["run"].landing_pitch_deg < 0
    assert all(GAITS[g].landing_pitch_deg > 0 for g in ("stairs_up", "stairs_down",
                                                        "in_place", "back_steps", "crawl"))
