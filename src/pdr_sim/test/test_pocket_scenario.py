"""Pocket scenarios: every key checked, a value the body cannot do refused with the key
named, nothing clipped (issue 15, bad input); every IMU profile and magnetic environment
works for the pocket placement."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core.errors import InputError
from pdr_core.sensors.imu_profiles import PROFILES
from pdr_sim.pocket_scenario import POCKET_BUILTIN, load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

WALK = [{"type": "standing", "duration_s": 2}, {"type": "walk", "distance_m": 10}]


def scenario(*segments, **top):
    return {"segments": [*WALK, *segments], **top}


@pytest.mark.parametrize(("data", "message"), [
    (scenario({"type": "walk", "steps": 3, "speed_kmh": 0.5}),
     "s: segments[2].speed_kmh: 0.238 is beyond a human stride at 0.5 km/h (m) (0.3-2.2)"),
    (scenario(person={"cadence_hz_at_rest": 0.3, "cadence_hz_per_mps": 0.0}),
     "segments[1].speed_kmh: 3.24 is beyond a human stride at 3.5 km/h (m) (0.3-2.2)"),
    (scenario({"type": "walk", "steps": 3, "speed_kmh": 1.0}),
     "segments[2].speed_kmh: 1.14 is beyond the pitch amplitude (deg) of a 0.45 m stride"),
    (scenario({"type": "walk", "steps": 3, "speed_kmh": 9}),
     "segments[2].speed_kmh: 9 is beyond walking speed (0.5-7)"),
    (scenario({"type": "stairs", "direction": "up", "riser_m": 0.32}),
     "segments[2].riser_m: 0.32 is beyond a human-range riser (0.05-0.25)"),
    (scenario({"type": "stairs", "direction": "up", "riser_m": 0.17, "tread_m": 0.9}),
     "segments[2].tread_m: 0.9 is beyond a human-range tread (0.2-0.5)"),
    (scenario({"type": "stairs", "direction": "up"}),
     "segments[2].riser_m: required for a 'stairs' segment"),
    (scenario({"type": "sitting", "duration_s": 30, "pitch_deg": 20}),
     "segments[2].pitch_deg: 20 is beyond a sitting pitch (30-100)"),
    (scenario({"type": "sitting", "duration_s": 30, "pitch_deg": 110}),
     "segments[2].pitch_deg: 110 is beyond a sitting pitch (30-100)"),
    (scenario({"type": "sitting", "duration_s": 2}),
     "segments[2].duration_s: sitting takes at least 4 s"),
    (scenario({"type": "turn", "angle_deg": 270, "steps": 2}),
     "segments[2].angle_deg: 270° in 2 step(s) is 135° per step, sharper than a step allows"),
    (scenario({"type": "turn", "angle_deg": 90, "steps": 2, "duration_s": 2}),
     "segments[2].duration_s: a turn is walked (steps) or in place"),
    (scenario({"type": "stairs", "direction": "up", "riser_m": 0.17, "landing_steps": 1}),
     "segments[2].landing_turn_deg: 180° per landing step is sharper than a step allows"),
    (scenario({"type": "walk", "distance_m": 5, "steps": 4}),
     "segments[2].distance_m: give either distance_m or steps"),
    (scenario({"type": "jog", "steps": 4}), "segments[2].type: unknown segment type 'jog'"),
    (scenario({"type": "walk", "steps": 4, "pitch_deg": 30}),
     "segments[2].pitch_deg: not a key of a 'walk' segment"),
    (scenario({"type": "stairs", "direction": "sideways", "riser_m": 0.17}),
     "segments[2].direction: must be up or down"),
    (scenario(person={"stride_m": 1.2}), "s: person.stride_m: unknown key"),
    (scenario(person={"leg": "middle"}), "s: person.leg: must be left or right"),
    (scenario(person={"faster_swing_back_fraction": 1.5}),
     "s: person.faster_swing_back_fraction: a share of the swing, at most 1, got 1.5"),
    (scenario(person={"pitch_min_fraction": -0.1}), "s: person.pitch_min_fraction: must be >= 0"),
    (scenario(mounting="belt"), "s: mounting: unknown mounting 'belt'"),
    (scenario(mounting={"rpy_deg": [0, 0]}), "s: mounting.rpy_deg: expected a list of 3"),
    (scenario(placement="foot"), "s: placement: a pocket scenario"),
    (scenario(remounts=[{"at_s": 5}]), "s: remounts[0].mounting: required"),
    (scenario(remounts=[{"at_s": 5, "mounting": "belt"}]),
     "s: remounts[0].mounting: unknown mounting 'belt'"),
    (scenario(remounts=[{"at_s": 5, "mounting": "thigh_frame", "duration_s": 2},
                        {"at_s": 6, "mounting": "phone_front_pocket"}]),
     "s: remounts[1].at_s: 6 s starts before the remount before it has ended (7 s)"),
    ({"segments": []}, "s: segments: expected a non-empty list"),
])
def test_impossible_scenarios_are_refused_by_key(data, message):
    with pytest.raises(InputError) as err:
        pocket_scenario_from_dict(data, "s")
    assert message in str(err.value)


def test_builtin_scenarios_load():
    for name in POCKET_BUILTIN:
        assert load_pocket_scenario(name)[0].segments


ENVIRONMENTS = {
    "homogeneous": {"preset": "equator"},
    "cylinders": {"preset": "munich", "cylinders": [{"east_m": 5.0, "north_m": 1.0,
                                                     "radius_m": 0.3}]},
    "distorted": {"preset": "north_pole", "distortion": "table_3_3"},
    "indoor": {"vector_ut": [0.0, 14.3, -34.5], "indoor": {"seed": 2}},
}


@pytest.mark.parametrize("imu", list(PROFILES))
@pytest.mark.parametrize("environment", list(ENVIRONMENTS))
def test_every_profile_and_environment_works_in_the_pocket(imu, environment):
    data = scenario({"type": "turn", "angle_deg": 90, "steps": 2},
                    environment={"latitude_deg": 48.0,
                                 "magnetic_field": ENVIRONMENTS[environment]})
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, "s"), data, imu, {}, 100.0,
                                    3, placement="pocket"))
    for batch, field in ((sim.imu, "angular_velocity"), (sim.imu, "linear_acceleration"),
                         (sim.mag, "magnetic_field")):
        assert np.isfinite(batch[field]).all()
    gyro_error = np.abs(sim.imu["angular_velocity"] - sim.true_gyro).max()
    assert (gyro_error == 0) == (imu == "ideal")
    if environment == "distorted":
        assert np.abs(sim.mag["magnetic_field"] - sim.true_mag).max() > 1e-6
