"""The pocket navigator with a barometer (issue 41) against the simulator's truth:
``imu/pressure`` from pdr-sim's barometer (the consumer phone's: 0.03 hPa noise, 0.01 hPa
steps, 25 Hz, weather drift), the xsens_mtw IMU and the filter matched to it
(config/pocket_pdr_xsens_mtw.yaml).

- UP/DW, the building walk and the lift walk (building_lift: one floor up the stairs,
  three up by lift, one down the stairs, three down by lift): every level step on its
  floor (the half-landings of a U-shaped stair, within a quarter floor of a half floor,
  belong to neither), every lift ride found and said by the step after it, with its
  floors; the height at the end within 0.5 m of the truth, also with a weather drift of
  1 hPa/h (8.3 m/h);
- a 0.3 hPa offset lasting a minute (a lift lobby or a pressurised stairwell, about 2.5
  m) on the level H1 walk invents no floor change and no ride;
- the steps without the barometer's readings are the steps as before (pdr_pocket's
  other tests hold those figures), and the accelerometer alone cannot see a lift."""
from __future__ import annotations

from functools import cache

import numpy as np
import pytest

from pdr_core import topics
from pdr_core.vocabulary import Activity, Ride
from pdr_pocket.config import default_config_path, load_pocket_config
from pdr_pocket.inputs import pocket_inputs
from pdr_pocket.navigator import PocketNavigator
from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

MTW = load_pocket_config(default_config_path().with_name("pocket_pdr_xsens_mtw.yaml"))
FLOOR_M = MTW.stairs.floor_height_m
DRIFT = (("drift_hpa_per_h", 1.0), ("drift_sigma_hpa_per_h", 0.0))
OFFSET = (("offsets", ((("at_s", 100.0), ("size_hpa", 0.3), ("duration_s", 60.0)),)),)


def _dict(pairs):
    """Hashable overrides (tuples of pairs) back to the simulator's dicts and lists."""
    if isinstance(pairs, tuple) and pairs and isinstance(pairs[0], tuple) \
            and len(pairs[0]) == 2 and isinstance(pairs[0][0], str):
        return {k: _dict(v) for k, v in pairs}
    if isinstance(pairs, tuple):
        return [_dict(v) for v in pairs]
    return pairs


@cache
def walked(name: str, baro: tuple = (), barometer: bool = True):
    """The simulation (seed 1, with its barometer) and the navigator after it, given the
    barometer's readings or not."""
    _, data = load_pocket_scenario(name)
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, name), data, "xsens_mtw",
                                    {"baro": _dict(baro)} if baro else {}, 100.0, 1,
                                    placement="pocket", pressure=True))
    inputs = pocket_inputs(sim.imu, sim.mag, None,
                           {topics.IMU_PRESSURE: sim.pressure} if barometer else None)
    navigator = PocketNavigator(MTW)
    navigator.process(inputs.samples)
    return sim, navigator


def true_height(sim, t_s) -> np.ndarray:
    """The truth's height above the start [m] at times ``t_s`` [s]."""
    z = sim.trajectory.position[:, 2]
    return np.interp(t_s, sim.trajectory.t, z - z[0])


def level_floors(sim, navigator) -> tuple[np.ndarray, np.ndarray]:
    """The level steps' floors and the truth's, off the half-landings."""
    level = [s for s in navigator.steps if s.activity == Activity.WALKING]
    floors = true_height(sim, [s.t for s in level]) / FLOOR_M
    on_floor = np.abs(floors - np.round(floors)) < 0.25
    return (np.array([s.floor for s in level])[on_floor],
            np.round(floors[on_floor]).astype(int))


@pytest.mark.parametrize("name, baro, end_m", [("up_dw", (), 0.75), ("building", (), 0.5),
                                               ("building_lift", (), 0.5),
                                               ("building_lift", DRIFT, 0.5),
                                               ("up_dw", DRIFT, 0.75)])
def test_every_floor_right_and_the_end_within_half_a_metre(name, baro, end_m):
    """docs/pocket.md: every level step on its floor; the end within 0.5 m, UP/DW's within
    0.75 m (0.64 m, 0.72 m with the drift: the first steps of three of its flights read as
    level climb nothing, and a level step's climb is certain, so the barometer cannot make
    it up; 0.32 m before issue 53, when the thesis' filter read one of them as stairs)."""
    sim, navigator = walked(name, baro)
    found, truth = level_floors(sim, navigator)
    assert np.array_equal(found, truth), np.flatnonzero(found != truth)
    end = navigator.steps[-1]
    assert abs(end.position[2] - true_height(sim, end.t)) <= end_m


def test_the_lift_rides_are_found_and_said_by_the_step_after_them():
    sim, navigator = walked("building_lift")
    rides = sim_rides(sim)
    said = [s for s in navigator.steps if s.ride]
    assert [s.ride for s in said] == [Ride.LIFT] * len(rides) == [Ride.LIFT, Ride.LIFT]
    for step, ride in zip(said, rides, strict=True):
        assert step.t > ride["end_s"]
        assert step.ride_height == pytest.approx(ride["rise_m"], abs=0.25)
        assert step.vertical_displacement == pytest.approx(step.ride_height, abs=0.1)


def sim_rides(sim) -> list[dict]:
    """The simulation's lift rides (its record's)."""
    from pdr_sim.simulation import simulation_record

    return simulation_record(sim)["lift_rides"]


def test_without_the_barometer_a_lift_is_not_seen():
    """The accelerometer's floors alone: a standing ride leaves no step, so the three
    floors up by lift are not counted (the table of docs/pocket.md)."""
    sim, navigator = walked("building_lift", barometer=False)
    assert not any(s.ride for s in navigator.steps)
    found, truth = level_floors(sim, navigator)
    assert (found != truth).sum() >= 40


def test_a_pressure_offset_of_a_minute_invents_no_floor():
    _, navigator = walked("h1_rectangle", OFFSET)
    assert {s.floor for s in navigator.steps} == {0}
    assert not any(s.ride for s in navigator.steps)
    assert max(abs(s.position[2]) for s in navigator.steps) < 0.5
    assert navigator.assembly.height.rides == []
