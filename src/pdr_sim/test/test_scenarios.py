"""Scenarios: geometry matches the specification, and bad files are refused by key
(issue 3, acceptance 4 and 6)."""
import numpy as np
import pytest

from pdr_core.errors import InputError
from pdr_sim.foot_trajectory import FootTrajectory, draw_strides
from pdr_sim.scenario import BUILTIN, GAIT_SCENARIOS, load_scenario, scenario_from_dict
from pdr_sim.simulation import SimulationConfig


def path_length(traj):
    """∫|v_h| dt by Simpson's rule over each pair of intervals."""
    speed = np.linalg.norm(traj.velocity[:, :2], axis=1)
    dt = traj.t[1] - traj.t[0]
    n = (len(speed) - 1) // 2 * 2
    return dt / 3 * (speed[0:n:2] + 4 * speed[1:n:2] + speed[2:n + 1:2]).sum()


@pytest.mark.parametrize("name", [n for n in BUILTIN if n not in GAIT_SCENARIOS])
def test_builtin_path_length_and_heading_change_match_the_specification(name):
    scenario, _ = load_scenario(name)
    model = FootTrajectory(scenario)
    traj = model.sample(1000.0)
    phases = model.phases
    expected_length = sum(s.length_m for s in draw_strides(scenario))
    turned = sum(np.radians(s.angle_deg) for s in scenario.segments if s.type == "turn")
    curved = sum(s.steps for s in scenario.segments if s.type == "curve")
    assert phases.path_length_m == pytest.approx(expected_length, rel=1e-12)
    assert path_length(traj) == pytest.approx(expected_length, rel=1e-6)
    heading_change = traj.euler[-1, 2] - traj.euler[0, 2]
    assert heading_change == pytest.approx(phases.heading_change_rad, abs=1e-9)
    if curved == 0:
        assert heading_change == pytest.approx(turned, abs=1e-9)


def test_curve_heading_change_is_arc_over_radius():
    data = {"segments": [{"type": "curve", "steps": 7, "radius_m": 2.5, "direction": "right"}]}
    model = FootTrajectory(scenario_from_dict(data, "t"))
    traj = model.sample(500.0)
    assert traj.euler[-1, 2] == pytest.approx(-7 * 1.3 / 2.5, abs=1e-12)
    centre = np.array([0.0, -2.5])
    radius = np.linalg.norm(traj.position[:, :2] - centre, axis=1)
    np.testing.assert_allclose(radius, 2.5, atol=1e-12)


def test_variation_is_seeded():
    data = {"seed": 4, "variation": {"length_m": 0.1},
            "segments": [{"type": "straight", "steps": 20}]}
    a = FootTrajectory(scenario_from_dict(data, "a")).phases
    b = FootTrajectory(scenario_from_dict(data, "b")).phases
    c = FootTrajectory(scenario_from_dict({**data, "seed": 5}, "c")).phases
    np.testing.assert_array_equal(a.length, b.length)
    assert not np.array_equal(a.length, c.length)


@pytest.mark.parametrize("data, key", [
    ({"segments": [{"type": "straight", "steps": 3}], "stpe": {}}, "x.yaml: stpe"),
    ({"segments": [{"type": "standing", "duration_s": -1}]}, "segments[0].duration_s"),
    ({"segments": [{"type": "straight", "steps": 2, "step": {"height_m": -0.1}}]},
     "segments[0].step.height_m"),
    ({"segments": [{"type": "straight", "steps": 2}], "step": {"swing_s": 0}}, "step.swing_s"),
    ({"segments": [{"type": "curve", "steps": 2, "radius_m": 3}]}, "segments[0].direction"),
    ({"segments": [{"type": "curve", "steps": 2, "radius_m": 0, "direction": "left"}]},
     "segments[0].radius_m"),
    ({"segments": [{"type": "jump", "steps": 2}]}, "segments[0].type"),
    ({"segments": [{"type": "straight", "steps": 2, "duration_s": 3}]}, "segments[0].duration_s"),
    ({"segments": []}, "segments"),
    ({"segments": [{"type": "straight", "steps": 1.5}]}, "segments[0].steps"),
    ({"segments": [{"type": "straight", "steps": 2}], "timing": "fast"}, "timing"),
    ({"segments": [{"type": "repeat", "times": 0, "segments": [
        {"type": "straight", "steps": 2}]}]}, "segments[0].times"),
    ({"segments": [{"type": "repeat", "times": 2, "segments": [
        {"type": "straight", "steps": 0}]}]}, "segments[0].segments[0].steps"),
    ({"segments": [{"type": "repeat", "times": 2, "laps": 3, "segments": [
        {"type": "straight", "steps": 2}]}]}, "segments[0].laps"),
])
def test_bad_scenarios_name_the_key(data, key):
    with pytest.raises(InputError) as err:
        scenario_from_dict(data, "x.yaml")
    assert key in str(err.value)


def test_a_repeat_walks_its_segments_again_in_place():
    lap = [{"type": "straight", "steps": 3}, {"type": "turn", "angle_deg": 90, "duration_s": 1}]
    repeated = scenario_from_dict({"segments": [
        {"type": "standing", "duration_s": 2},
        {"type": "repeat", "times": 4, "segments": lap}]}, "x.yaml")
    written = scenario_from_dict({"segments": [{"type": "standing", "duration_s": 2},
                                               *lap * 4]}, "x.yaml")
    assert repeated.segments == written.segments and len(repeated.segments) == 9


def test_unknown_profile_and_rate_out_of_range():
    scenario, data = load_scenario("straight")
    with pytest.raises(InputError, match="--imu: unknown profile 'mti_9000'"):
        SimulationConfig(scenario, data, imu="mti_9000")
    with pytest.raises(InputError, match="--rate: must be within 50-1000 Hz"):
        SimulationConfig(scenario, data, rate_hz=2000.0)


def test_missing_scenario_file():
    with pytest.raises(InputError, match="no such scenario file"):
        load_scenario("/nonexistent/walk.yaml")
