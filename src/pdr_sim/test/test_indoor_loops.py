"""The built-in ``indoor_loops`` (issue 53): loops around a 3.4 m x 5.4 m room in its own
magnetic field, as the OxIOD recordings walk; the ``indoor:`` key of a scenario's
magnetic field, and ``repeat`` in pocket scenarios."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.io.bag import BagReader
from pdr_core.sensors.magnetic_field import UT, IndoorDisturbance, MagneticField
from pdr_sim.cli import main
from pdr_sim.pocket_scenario import POCKET_BUILTIN, load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, magnetic_environment, simulate
from pdr_sim.thigh_trajectory import ThighTrajectory

ROOM_T = (0.0, 14.3 * UT, -34.5 * UT)


def walk_positions() -> np.ndarray:
    """The sensor's positions [m] along indoor_loops at 100 Hz."""
    model = ThighTrajectory(load_pocket_scenario("indoor_loops")[0])
    return model.at(np.arange(0.0, model.duration_s, 0.01)).position


def test_indoor_loops_walks_loops_around_a_small_room():
    scenario, data = load_pocket_scenario("indoor_loops")
    assert "indoor_loops" in POCKET_BUILTIN
    field, distortion = magnetic_environment(scenario.environment.magnetic_field)
    assert distortion is None and field.indoor == IndoorDisturbance(seed=1)
    np.testing.assert_allclose(field.h_inf_t, ROOM_T)
    sim = simulate(SimulationConfig(scenario, data, "calibrated_phone", {}, 100.0, 1,
                                    placement="pocket"))
    t, position = sim.trajectory.t, sim.trajectory.position
    assert 180.0 < t[-1] < 240.0                                  # 3-4 minutes
    assert position[:, 0].min() > 0.0 and position[:, 0].max() < 5.5   # the room
    assert position[:, 1].min() > 0.0 and position[:, 1].max() < 3.4
    # the heading of the phone's level axis (x: across the thigh): six turns to the left in
    # all, with laps to the right between
    across = sim.trajectory.attitude.apply([1.0, 0.0, 0.0])
    heading = np.unwrap(np.arctan2(across[:, 1], across[:, 0]))
    assert np.degrees(heading[-1] - heading[0]) == pytest.approx(6 * 360, abs=10)
    assert np.sum(np.diff(sim.model.route["heading"]) < -0.1) >= 12
    assert len(sim.model.landmarks) > 40                           # a corner every few metres
    # the field the phone sees moves with the place, as the indoor disturbance has it
    np.testing.assert_allclose(sim.trajectory.attitude.apply(sim.true_mag), field.at(position),
                               atol=1e-12)


def test_a_walk_of_the_room_measures_the_oxiod_spread():
    """Along the walk, about its own median, as measured on OxIOD's room (documented in
    pdr_core.sensors.magnetic_field.IndoorDisturbance): on average over ten buildings (seeds)
    6.2° azimuth, 1.9 µT norm, 2.9° dip, the azimuth's autocorrelation at 1/e in about
    1.6 s; OxIOD's walks: 5.5-6.8°, 1.8-1.9 µT, 2.3-4.3°, 1.5-2.2 s."""
    position = walk_positions()
    stats = []
    for seed in range(10):
        h = MagneticField(ROOM_T, indoor=IndoorDisturbance(seed=seed)).at(position)
        azimuth = np.degrees(np.arctan2(h[:, 0], h[:, 1]))
        norm = np.linalg.norm(h, axis=1)
        dip = np.degrees(np.arcsin(-h[:, 2] / norm))
        spectrum = np.fft.rfft(azimuth - azimuth.mean(), 2 * len(azimuth))
        autocorrelation = np.fft.irfft(spectrum * spectrum.conj())[:len(azimuth)]
        one_over_e_s = np.argmax(autocorrelation < autocorrelation[0] / np.e) * 0.01
        stats.append((np.std(azimuth), np.std(norm) / UT, np.std(dip), one_over_e_s))
    azimuth_deg, norm_ut, dip_deg, one_over_e_s = np.mean(stats, axis=0)
    assert 5.0 < azimuth_deg < 7.5
    assert 1.5 < norm_ut < 2.4
    assert 2.3 < dip_deg < 3.6
    assert 1.2 < one_over_e_s < 2.2


def test_cli_generates_indoor_loops(tmp_path, capsys):
    out = tmp_path / "indoor"
    with pytest.raises(SystemExit) as status:
        main(["generate", "--placement", "pocket", "--scenario", "indoor_loops", "--imu",
              "calibrated_phone", "--seed", "2", "--set",
              "environment.magnetic_field.indoor.seed=2", "--out", str(out)])
    assert status.value.code == 0
    assert "indoor_loops" in capsys.readouterr().out
    reader = BagReader(out)
    record = reader.custom_data("pdr.simulation")
    assert record["imu_profile"] == "calibrated_phone"
    assert record["scenario"]["environment"]["magnetic_field"]["indoor"] == {"seed": 2}
    mag = reader.read(topics.IMU_MAG)["magnetic_field"]
    assert 30 * UT < np.median(np.linalg.norm(mag, axis=1)) < 45 * UT


@pytest.mark.parametrize(("indoor", "message"), [
    ({"spread_deg": 3}, "s: environment.magnetic_field.indoor.spread_deg: unknown key"),
    ({"azimuth_sigma_deg": 50}, "indoor.azimuth_sigma_deg: must be below 45 degrees"),
    ({"norm_sigma_ut": -1}, "indoor.norm_sigma_ut: must be >= 0.0"),
    ({"correlation_length_m": 0}, "indoor.correlation_length_m: must be > 0.0"),
    ({"seed": -1}, "indoor.seed: must be a non-negative integer"),
    ("yes", "s: environment.magnetic_field.indoor: expected a mapping"),
])
def test_bad_indoor_settings_are_refused_by_key(indoor, message):
    data = {"environment": {"magnetic_field": {"indoor": indoor}},
            "segments": [{"type": "standing", "duration_s": 2}]}
    with pytest.raises(InputError) as err:
        pocket_scenario_from_dict(data, "s")
    assert message in str(err.value)


def test_an_azimuth_spread_without_a_horizontal_field_is_refused():
    data = {"environment": {"magnetic_field": {"preset": "north_pole", "indoor": {}}},
            "segments": [{"type": "standing", "duration_s": 2}]}
    scenario = pocket_scenario_from_dict(data, "s")
    with pytest.raises(InputError, match=r"indoor\.azimuth_sigma_deg: an azimuth spread needs"):
        magnetic_environment(scenario.environment.magnetic_field)
    data["environment"]["magnetic_field"]["indoor"] = None          # none, as if not given
    assert pocket_scenario_from_dict(data, "s").environment.magnetic_field.indoor is None


def test_pocket_scenarios_repeat_segments():
    lap = [{"type": "walk", "steps": 2}, {"type": "turn", "angle_deg": 90, "steps": 1}]
    repeated = pocket_scenario_from_dict(
        {"segments": [{"type": "standing", "duration_s": 2},
                      {"type": "repeat", "times": 4, "segments": lap}]}, "s")
    written = pocket_scenario_from_dict(
        {"segments": [{"type": "standing", "duration_s": 2}, *lap * 4]}, "s")
    assert repeated.segments == written.segments
    with pytest.raises(InputError, match=r"s: segments\[1\]\.segments\[0\]\.type: unknown "
                                         r"segment type 'jog'"):
        pocket_scenario_from_dict({"segments": [
            {"type": "standing", "duration_s": 2},
            {"type": "repeat", "times": 2, "segments": [{"type": "jog", "steps": 2}]}]}, "s")
