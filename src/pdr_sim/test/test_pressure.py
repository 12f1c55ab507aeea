"""The simulated barometer (issue 41): its errors have the profile's statistics, its height
follows the truth, and a run without it is the run it always was; the lift ride of the
pocket scenarios carries the standing person by the floors asked, without a step."""
from __future__ import annotations

import numpy as np
import pytest
import yaml

from pdr_core import topics
from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.io import cdr
from pdr_core.io.bag import BagReader
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import FLUID_PRESSURE, typestore
from pdr_core.sensors.atmosphere import height_m, metres_per_pascal, pressure_pa
from pdr_core.sensors.imu_errors import (
    BarometerErrors,
    barometer_readings,
    barometer_run,
    low_passed,
)
from pdr_core.sensors.imu_profiles import (
    IPHONE_BAROMETER,
    PHONE_BAROMETER,
    barometer_errors,
    profile,
)
from pdr_core.vocabulary import FLOOR_HEIGHT_M, LandmarkType
from pdr_sim.lift import LiftMotion, LiftRide
from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate, simulation_record
from wstest import cli

G = STANDARD_GRAVITY_MPS2
HOUR_S = 3600.0
# 2 s standing, a few steps, two floors up by lift, a few steps, a corner, standing
LIFT_WALK = {"name": "lift_walk", "seed": 3, "segments": [
    {"type": "standing", "duration_s": 2}, {"type": "walk", "steps": 4},
    {"type": "lift", "direction": "up", "floors": 2},
    {"type": "walk", "steps": 3}, {"type": "turn", "angle_deg": 90, "steps": 2},
    {"type": "walk", "steps": 2}, {"type": "standing", "duration_s": 2}]}
NO_WEATHER = {"drift_sigma_hpa_per_h": 0.0}


def run(data=LIFT_WALK, imu="consumer_phone", overrides=None, pressure=True, seed=5,
        rate=100.0):
    scenario = pocket_scenario_from_dict(data, data["name"])
    return simulate(SimulationConfig(scenario, data, imu, overrides or {}, rate, seed,
                                     placement="pocket", pressure=pressure))


def long_readings(errors: BarometerErrors, duration_s: float = 2000.0, seed: int = 1):
    t = np.arange(0.0, duration_s, 1.0 / errors.rate_hz)
    true = np.full(len(t), 95_000.0)
    readings, run_ = barometer_readings(true, t, errors, np.random.default_rng(seed))
    return t, readings - true, run_


def test_fluid_pressure_is_encoded_as_rosbags_does_and_decoded_back():
    batch = MessageBatch(FLUID_PRESSURE, [5, 2_000_000_001], "imu_link",
                         {"fluid_pressure": np.array([101_325.0, 95_000.5]),
                          "variance": np.array([9.0, 0.0])})
    store = typestore()
    types = store.types
    expected = [bytes(store.serialize_cdr(types[FLUID_PRESSURE](
        header=types["std_msgs/msg/Header"](
            stamp=types["builtin_interfaces/msg/Time"](sec=int(ns // 10**9),
                                                       nanosec=int(ns % 10**9)),
            frame_id="imu_link"), fluid_pressure=p, variance=v), FLUID_PRESSURE))
        for ns, p, v in zip(batch.stamp_ns, batch["fluid_pressure"], batch["variance"],
                            strict=True)]
    assert cdr.encode(batch) == expected
    back = cdr.decode(FLUID_PRESSURE, expected)
    np.testing.assert_array_equal(back["fluid_pressure"], batch["fluid_pressure"])
    np.testing.assert_array_equal(back.stamp_ns, batch.stamp_ns)


# --- the error model ---------------------------------------------------------------------
def test_white_noise_and_quantisation_of_the_phone_profile():
    errors = barometer_errors({**PHONE_BAROMETER, **NO_WEATHER})
    _, error, _ = long_readings(errors)
    assert errors.noise_pa == pytest.approx(3.0) and errors.quantum_pa == pytest.approx(1.0)
    assert error.std() == pytest.approx(np.hypot(3.0, 1.0 / np.sqrt(12)), rel=0.03)
    readings = error + 95_000.0
    np.testing.assert_allclose(readings, np.round(readings), atol=1e-6)   # 0.01 hPa steps
    assert abs(error.mean()) < 0.1


def test_drift_slope_and_a_sudden_offset_are_as_set():
    """1 hPa/h of weather drift and a 0.3 hPa offset for 60 s from t = 500 s, exactly."""
    errors = barometer_errors({"drift_hpa_per_h": 1.0, "offsets": [
        {"at_s": 500, "size_hpa": 0.3, "duration_s": 60}]})
    t, error, run_ = long_readings(errors)
    offset = (t >= 500) & (t < 560)
    np.testing.assert_allclose(error[~offset], 100.0 / HOUR_S * t[~offset], atol=1e-9)
    np.testing.assert_allclose(error[offset] - 100.0 / HOUR_S * t[offset], 30.0, atol=1e-9)
    [(start, duration, size)] = [(o.start_s, o.duration_s, o.size_pa) for o in run_.offsets]
    assert (start, duration, size) == pytest.approx((500.0, 60.0, 30.0))
    assert np.diff(t[offset])[0] == pytest.approx(1 / 25)
    assert offset.sum() == pytest.approx(60 * 25, abs=1)


def test_random_drift_and_offsets_have_their_statistics():
    errors = barometer_errors({"drift_sigma_hpa_per_h": 0.3, "offsets_per_h": 60,
                               "offset_size_hpa": [0.2, 0.4], "offset_duration_s": 60})
    drifts = [long_readings(errors, 10.0, seed)[2].drift_pa_per_s for seed in range(400)]
    assert np.std(drifts) * HOUR_S / 100 == pytest.approx(0.3, rel=0.1)
    run_ = barometer_run(errors, 20 * HOUR_S, np.random.default_rng(2))
    sizes = np.abs([o.size_pa for o in run_.offsets])
    assert len(run_.offsets) == pytest.approx(20 * 60, rel=0.1)
    assert sizes.min() >= 20.0 and sizes.max() <= 40.0
    assert sizes.mean() == pytest.approx(30, rel=0.05)
    assert {o.duration_s for o in run_.offsets} == {60.0}


@pytest.mark.parametrize(("config", "message"), [
    ({"noise_hpa": -1}, "p.noise_hpa: must be >= 0"),
    ({"rate_hz": 0}, "p.rate_hz: must be > 0"),
    ({"drift_hpa": 1}, "p.drift_hpa: unknown key"),
    ({"offsets": [{"at_s": 5, "size_hpa": 0.3}]}, "p.offsets[0]: expected {at_s, size_hpa"),
    ({"offsets": [{"at_s": 5, "size_hpa": 0.3, "duration_s": 0}]},
     "p.offsets[0].duration_s: must be > 0"),
    ({"offset_size_hpa": [0.4, 0.2]}, "p.offset_size_hpa: the least is larger"),
    ({"hold_share": 1}, "p.hold_share: must be < 1"),
    ({"lag_s": -1}, "p.lag_s: must be >= 0"),
    ({"warmup_time_constant_s": 0}, "p.warmup_time_constant_s: must be > 0"),
])
def test_bad_barometer_keys_are_named(config, message):
    with pytest.raises(InputError) as err:
        barometer_errors(config, "p")
    assert str(err.value).startswith(message)


def test_every_profile_has_a_barometer_and_ideal_an_ideal_one():
    assert profile("ideal").baro == BarometerErrors()
    assert profile("xsens_mtw").baro == profile("consumer_phone").baro
    assert profile("xsens_mtw", {"baro": {"noise_hpa": 0.1}}).baro.noise_pa == \
        pytest.approx(10.0)


# --- the simulated barometer --------------------------------------------------------------
@pytest.fixture(scope="module")
def with_and_without():
    return run(pressure=True), run(pressure=False)


def test_without_pressure_nothing_changes(with_and_without):
    """The barometer draws from a stream of its own: the sensors' noise is the same."""
    on, off = with_and_without
    assert topics.IMU_PRESSURE in on.batches and topics.IMU_PRESSURE not in off.batches
    assert list(off.batches) == [t for t in on.batches if t != topics.IMU_PRESSURE]
    for topic, batch in off.batches.items():
        other = on.batches[topic]
        np.testing.assert_array_equal(batch.stamp_ns, other.stamp_ns)
        for name, values in batch.fields.items():
            np.testing.assert_array_equal(values, other.fields[name], err_msg=f"{topic} {name}")
    assert "pressure" not in simulation_record(off) and "pressure" in simulation_record(on)


def test_rate_stamps_frame_and_variance(with_and_without):
    on, _ = with_and_without
    pressure = on.pressure
    assert pressure.msgtype == "sensor_msgs/msg/FluidPressure"
    np.testing.assert_array_equal(np.diff(pressure.stamp_ns), 40_000_000)   # 25 Hz
    assert pressure.stamp_ns[0] == on.imu.stamp_ns[0]
    assert set(pressure.frame_id) == set(on.imu.frame_id)
    np.testing.assert_allclose(pressure["variance"], 3.0**2)


def test_height_from_the_pressure_follows_the_truth():
    sim = run(overrides={"baro": NO_WEATHER})
    t = (sim.pressure.stamp_ns - sim.pressure.stamp_ns[0]) * 1e-9
    truth = sim.model.at(t).position[:, 2]
    error = height_m(sim.pressure["fluid_pressure"]) - truth
    expected = 3.0 * abs(metres_per_pascal(pressure_pa(0.0)))     # 3 Pa: 0.25 m
    assert abs(error.mean()) < 0.05 and error.std() == pytest.approx(expected, rel=0.1)
    assert np.ptp(truth) == pytest.approx(2 * FLOOR_HEIGHT_M, abs=0.2)


def test_a_set_offset_is_deterministic_and_only_in_the_pressure():
    base = {"noise_hpa": 0.0, "resolution_hpa": 0.0, "drift_sigma_hpa_per_h": 0.0}
    step = {**base, "offsets": [{"at_s": 10.0, "size_hpa": 0.3, "duration_s": 8.0}]}
    plain, stepped = run(overrides={"baro": base}), run(overrides={"baro": step})
    t = (plain.pressure.stamp_ns - plain.pressure.stamp_ns[0]) * 1e-9
    inside = (t >= 10.0) & (t < 18.0)
    difference = stepped.pressure["fluid_pressure"] - plain.pressure["fluid_pressure"]
    np.testing.assert_allclose(difference[inside], 30.0, atol=1e-9)
    np.testing.assert_array_equal(difference[~inside], 0.0)
    assert simulation_record(stepped)["pressure"]["offsets"] == [
        {"at_s": 10.0, "size_hpa": 0.3, "duration_s": 8.0}]


# --- the lift ------------------------------------------------------------------------------
def test_a_lift_profile_reaches_its_limits_and_stops_at_the_rise():
    motion = LiftMotion(1.6, 0.8, 1.2)
    ride = LiftRide(5.0, -3 * FLOOR_HEIGHT_M, -3, motion)
    t = np.linspace(0.0, 5.0 + ride.duration_s + 5.0, 20001)
    h, v, a = ride.at(t)
    assert h[0] == 0.0 and h[-1] == -3 * FLOOR_HEIGHT_M and v[-1] == 0.0 and a[-1] == 0.0
    assert -v.min() == pytest.approx(1.6, abs=1e-9) and np.abs(a).max() == pytest.approx(0.8)
    assert np.abs(np.diff(a) / np.diff(t)).max() == pytest.approx(1.2, rel=1e-3)
    dt = np.diff(t)
    np.testing.assert_allclose(np.cumsum(v[:-1] * dt)[-1], h[-1], atol=2e-3)
    # docs/simulator.md: a 3.5 m floor in 4.9 s, three in 9.2 s
    assert [round(LiftRide(0.0, n * 3.5, n).duration_s, 1) for n in (1, 3)] == [4.9, 9.2]
    short = LiftRide(0.0, 0.5, 0, motion)          # too short to reach the speed or a
    h, v, a = short.at(np.linspace(0.0, short.duration_s, 2001))
    assert h[-1] == pytest.approx(0.5) and v.max() < 1.6 and a.max() < 0.8


def test_the_lift_ride_carries_the_person_without_a_step():
    sim = run(imu="ideal", pressure=False)
    [ride] = sim.model.plan.rides
    t = sim.trajectory.t
    z = sim.pose["pose.position"][:, 2]
    before, after = z[t < ride.start_s - 0.5], z[(t > ride.end_s) & (t < ride.end_s + 2)]
    assert np.ptp(before[-100:]) < 1e-3 and np.ptp(after) < 1e-3    # standing in the car
    assert after.mean() - before[-1] == pytest.approx(2 * FLOOR_HEIGHT_M, abs=1e-3)
    steps = sim.truth[topics.GROUND_TRUTH_STEP]
    ends = steps.t_s - sim.imu.t_s[0]
    assert not ((ends > ride.start_s - 4.0) & (ends < ride.end_s + 4.0)).any()
    assert np.all(steps["vertical_displacement"] == 0.0)
    # the specific force along the vertical: g, then g ± the car's acceleration
    f_n = sim.trajectory.attitude.apply(sim.true_accel)
    riding = (t > ride.start_s) & (t < ride.end_s)
    np.testing.assert_allclose(f_n[riding, 2] - G, sim.trajectory.acceleration[riding, 2],
                               atol=1e-9)
    assert (f_n[riding, 2] - G).max() == pytest.approx(0.8, abs=1e-3)
    assert (f_n[riding, 2] - G).min() == pytest.approx(-0.8, abs=1e-3)
    assert np.abs(f_n[t < ride.start_s - 0.5, 2][-50:] - G).max() < 1e-3
    corner = [m for m in sim.model.landmarks if m.type == LandmarkType.CORNER]
    assert corner and all(m.floor == 2 for m in corner)
    assert corner[0].position[2] == pytest.approx(2 * FLOOR_HEIGHT_M)
    assert simulation_record(sim)["lift_rides"] == [
        {"start_s": round(ride.start_s, 3), "end_s": round(ride.end_s, 3),
         "rise_m": 7.0, "floors": 2}]


@pytest.mark.parametrize(("segment", "message"), [
    ({"type": "lift", "direction": "up"}, "segments[2].floors: give floors or height_m"),
    ({"type": "lift", "floors": 2}, "segments[2].direction: required for a 'lift' segment"),
    ({"type": "lift", "direction": "up", "floors": 2, "speed_mps": 20},
     "segments[2].speed_mps: 20 is beyond a passenger lift's speed"),
    ({"type": "lift", "direction": "up", "floors": 2, "acceleration_mps2": 3},
     "segments[2].acceleration_mps2: 3 is beyond a passenger lift's acceleration"),
    ({"type": "lift", "direction": "up", "floors": 2, "steps": 3},
     "segments[2].steps: not a key of a 'lift' segment"),
])
def test_bad_lift_segments_are_named(segment, message):
    data = {"segments": [{"type": "standing", "duration_s": 2},
                         {"type": "walk", "steps": 2}, segment]}
    with pytest.raises(InputError) as err:
        pocket_scenario_from_dict(data, "s")
    assert message in str(err.value)


def test_a_height_gives_the_floors_it_spans():
    data = {"segments": [{"type": "lift", "direction": "down", "height_m": 10.5}]}
    [segment] = pocket_scenario_from_dict(data, "s").segments
    assert segment.floors == 3 and segment.rise_m == -10.5


def test_building_lift_goes_up_and_down_by_lift_and_stairs():
    scenario, data = load_pocket_scenario("building_lift")
    sim = simulate(SimulationConfig(scenario, data, "ideal", {}, 50.0, 0, placement="pocket"))
    rides = sim.model.plan.rides
    assert [r.floors for r in rides] == [3, -3]
    floors = {m.floor for m in sim.model.landmarks}
    assert floors == {0, 1, 3, 4}
    z = sim.pose["pose.position"][:, 2]
    assert z.max() - z[0] == pytest.approx(4 * FLOOR_HEIGHT_M, abs=0.2)
    assert z[-1] == pytest.approx(z[0], abs=1e-6)
    steps = sim.truth[topics.GROUND_TRUTH_STEP]
    assert np.abs(steps["vertical_displacement"]).sum() == pytest.approx(2 * FLOOR_HEIGHT_M)


def test_generate_writes_imu_pressure_only_when_asked(tmp_path):
    scenario = tmp_path / "lift_walk.yaml"
    scenario.write_text(yaml.safe_dump(LIFT_WALK))
    common = ["generate", "--placement", "pocket", "--scenario", str(scenario), "--rate", "50"]
    on = cli("pdr-sim", *common, "--out", tmp_path / "on", "--pressure", "--imu-set",
             "baro.drift_hpa_per_h=1.0", "--imu-set", "baro.drift_sigma_hpa_per_h=0")
    off = cli("pdr-sim", *common, "--out", tmp_path / "off")
    assert on.returncode == 0 and off.returncode == 0, on.stderr + off.stderr
    assert "1 lift rides" in on.stdout
    with_baro, without = BagReader(tmp_path / "on"), BagReader(tmp_path / "off")
    assert topics.IMU_PRESSURE not in without.topics
    pressure = with_baro.read(topics.IMU_PRESSURE)
    assert pressure.msgtype == "sensor_msgs/msg/FluidPressure" and len(pressure) > 100
    record = with_baro.custom_data("pdr.simulation")
    assert record["pressure"]["drift_hpa_per_h"] == 1.0 and record["lift_rides"][0]["floors"] == 2
    for topic in without.topics:
        a, b = without.read(topic), with_baro.read(topic)
        assert all(np.array_equal(a.fields[k], b.fields[k]) for k in a.fields), topic


def test_the_iphone_barometer_settles_lags_and_holds_as_the_shared_file_does():
    """IPHONE_BAROMETER at rest: 1 Hz, the settling 0.095·(1 − e^{−t/3 s}) hPa, a quarter
    of the readings repeating the one before, level readings within 0.004 hPa of each
    other (the iPhone's Barometer.csv of ../shared/data/phone/sensor_logger)."""
    errors = barometer_errors(IPHONE_BAROMETER | NO_WEATHER)
    assert errors.rate_hz == 1.0
    t, error, _ = long_readings(errors, 600.0)
    settling = low_passed(9.5 * -np.expm1(-t / 3.0), t, 1.0)
    held = np.r_[False, np.diff(error) == 0]
    assert np.abs(error - settling)[~held].max() < 0.6  # Pa: three σ of the noise
    steps = np.diff(error[20:])
    assert np.mean(steps == 0) == pytest.approx(0.25, abs=0.05)
    assert np.abs(steps).max() < 0.4 * PHONE_BAROMETER["noise_hpa"] * 100


def test_the_lag_follows_a_step_of_the_pressure_with_its_time_constant():
    """A first-order low-pass: a step of 100 Pa is 63 % through after lag_s."""
    t = np.arange(0.0, 20.0, 0.1)
    true = 95_000.0 + 100.0 * (t >= 5.0)
    readings, _ = barometer_readings(true, t, BarometerErrors(rate_hz=10.0, lag_s=2.0),
                                     np.random.default_rng(0))
    at_lag = readings[np.searchsorted(t, 5.0 + 2.0 - 0.05)] - 95_000.0
    assert at_lag == pytest.approx(100.0 * (1 - np.exp(-2.0 / 2.0)), abs=3.0)
    assert readings[t < 5.0] == pytest.approx(95_000.0)


def test_without_the_new_errors_the_readings_are_as_before():
    """warmup, lag and holds off: the same draws and readings (no realisation changes)."""
    errors = barometer_errors(PHONE_BAROMETER)
    _, before, _ = long_readings(errors, 200.0)
    _, after, _ = long_readings(BarometerErrors(**{**errors.__dict__, "lag_s": 0.0,
                                                   "hold_share": 0.0, "warmup_pa": 0.0}),
                                200.0)
    assert np.array_equal(before, after)
