"""The foot of the pocket's leg on the same walk (pdr_sim.paired_foot, issue 57): the two
sensors share every stride, and the person's strides deviate from their line."""
import numpy as np
import pytest
import yaml

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.io.bag import BagReader
from pdr_sim.foot_trajectory import CURVE, REST, STRAIGHT, TURN
from pdr_sim.gait_plan import plan_gait
from pdr_sim.paired_foot import STANCE_FRACTION, foot_seed, paired_foot, paired_phases
from pdr_sim.pocket_scenario import pocket_scenario_from_dict
from pdr_sim.thigh_trajectory import ThighTrajectory
from wstest import cli

WALK = {"name": "short two-IMU walk", "seed": 3,
        "person": {"stride_scatter_m": 0.035, "centre_scatter": False},
        "segments": [{"type": "standing", "duration_s": 3},
                     {"type": "walk", "distance_m": 12, "speed_kmh": 4.0},
                     {"type": "turn", "angle_deg": 90, "steps": 2},
                     {"type": "stairs", "direction": "up", "risers": 4, "riser_m": 0.17},
                     {"type": "turn", "angle_deg": 180, "duration_s": 2.0},
                     {"type": "walk", "distance_m": 6},
                     {"type": "standing", "duration_s": 3}]}


@pytest.fixture(scope="module")
def pair():
    thigh = ThighTrajectory(pocket_scenario_from_dict(WALK, "walk"))
    return thigh, paired_foot(thigh)


def test_the_foot_lands_where_the_pocket_s_route_puts_each_stride(pair):
    thigh, foot = pair
    route, cycles = thigh.route, thigh.plan.cycles
    landing = cycles.start + cycles.duration
    traj = foot.at(landing)
    np.testing.assert_allclose(traj.position, route["start"] + route["step"], atol=1e-9)
    lift_off = cycles.start + STANCE_FRACTION * cycles.duration
    np.testing.assert_allclose(foot.at(lift_off).position, route["start"], atol=1e-9)
    assert foot.duration_s == thigh.duration_s


def test_the_foot_stands_still_in_stance_and_at_rest_and_turns_in_place(pair):
    thigh, foot = pair
    phases = foot.phases
    kinds = set(phases.kind.tolist())
    assert kinds == {REST, STRAIGHT, CURVE, TURN}
    still = phases.kind == REST
    t = phases.start[still] + 0.5 * phases.duration[still]
    traj = foot.at(t)
    assert np.abs(traj.velocity).max() == 0.0 and np.abs(traj.body_rate).max() == 0.0
    swings = (phases.kind == STRAIGHT) | (phases.kind == CURVE)
    assert swings.sum() == len(thigh.plan.cycles)
    assert phases.climb[swings].sum() == pytest.approx(4 * 0.17)


def test_the_foot_path_is_continuous_and_climbs_the_stairs(pair):
    _, foot = pair
    traj = foot.sample(200.0)
    step = np.abs(np.diff(traj.position, axis=0)).max()
    assert step < 0.05                       # 10 m/s at 200 Hz: no jump anywhere
    assert np.abs(np.diff(np.unwrap(traj.euler[:, 2]))).max() < 0.05
    assert traj.position[-1, 2] == pytest.approx(4 * 0.17)
    # the velocity is the position's derivative (the climb's too)
    mid = 0.5 * (traj.velocity[1:] + traj.velocity[:-1])
    np.testing.assert_allclose(np.diff(traj.position, axis=0) * 200.0, mid, atol=0.05)


def test_the_strides_deviate_from_the_line_without_being_centred():
    plan = plan_gait(pocket_scenario_from_dict(WALK, "walk"))
    centred = {**WALK, "person": {"stride_scatter_m": 0.035}}
    centred_plan = plan_gait(pocket_scenario_from_dict(centred, "walk"))
    level = np.isnan(plan.cycles.stair_stride_m)
    group = plan.cycles.group[level]
    means = [plan.cycles.scatter_m[level][group == g].mean() for g in np.unique(group)]
    centred_means = [centred_plan.cycles.scatter_m[level][group == g].mean()
                     for g in np.unique(group)]
    assert np.abs(centred_means).max() < 1e-12
    assert np.abs(means).max() > 1e-3
    with pytest.raises(InputError, match="centre_scatter"):
        pocket_scenario_from_dict({**WALK, "person": {"centre_scatter": 1}}, "walk")


def test_a_walk_with_a_lift_ride_is_refused_for_the_foot():
    data = {"name": "lift", "segments": [
        {"type": "walk", "distance_m": 5},
        {"type": "lift", "direction": "up", "floors": 1}, {"type": "walk", "distance_m": 5}]}
    with pytest.raises(InputError, match="lift rides"):
        paired_phases(ThighTrajectory(pocket_scenario_from_dict(data, "lift")), 0.1, 0.5)


def test_generate_with_foot_writes_both_imus_on_one_clock(tmp_path):
    scenario = tmp_path / "walk.yaml"
    scenario.write_text(yaml.safe_dump(WALK))
    out = tmp_path / "pair"
    made = cli("pdr-sim", "generate", "--placement", "pocket", "--scenario", scenario,
               "--with-foot", "--out", out)
    assert made.returncode == 0, made.stderr
    assert "with the foot's IMU (xsens_mtw) under /foot" in made.stdout
    reader = BagReader(out)
    foot_imu = topics.FOOT_NAMESPACE + topics.IMU_DATA
    assert {topics.IMU_DATA, foot_imu, topics.FOOT_NAMESPACE + topics.GROUND_TRUTH_STANCE,
            topics.FOOT_NAMESPACE + topics.GROUND_TRUTH_POSE} <= set(reader.topics)
    batches = reader.read_batches([topics.IMU_DATA, foot_imu])
    pocket, foot = batches[topics.IMU_DATA], batches[foot_imu]
    np.testing.assert_array_equal(pocket.stamp_ns, foot.stamp_ns)
    assert not np.allclose(pocket["angular_velocity"], foot["angular_velocity"])
    assert foot_seed(0) != 0 and foot_seed(0) != foot_seed(1)
    refused = cli("pdr-sim", "generate", "--placement", "foot", "--with-foot", "--out",
                  tmp_path / "x")
    assert refused.returncode != 0 and "--with-foot" in refused.stderr
    assert "is for a pocket placement" in refused.stderr
