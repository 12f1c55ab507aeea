"""Simulated sensor signals: gravity, Earth rate, magnetic norm, determinism."""
import numpy as np
import pytest

from pdr_core.constants import EARTH_RATE_RADPS
from pdr_core.sensors.magnetic_field import UT
from pdr_sim.scenario import load_scenario, scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

STATIC = {"segments": [{"type": "standing", "duration_s": 10.0}]}


def run(data, imu="ideal", seed=0, rate=100.0):
    return simulate(SimulationConfig(scenario_from_dict(data, "t"), data, imu, {}, rate, seed))


def test_static_level_sensor_reads_gravity_and_the_earth_rate():
    data = {**STATIC, "environment": {"latitude_deg": 48.15}}
    sim = run(data)
    np.testing.assert_allclose(sim.imu["linear_acceleration"], [[0, 0, 9.80665]] * len(sim.imu),
                               atol=1e-12)
    lat = np.radians(48.15)
    expected = EARTH_RATE_RADPS * np.array([0.0, np.cos(lat), np.sin(lat)])  # facing east
    np.testing.assert_allclose(sim.imu["angular_velocity"], [expected] * len(sim.imu),
                               atol=1e-15)


def test_homogeneous_field_norm_is_constant_to_the_noise_level():
    scenario, data = load_scenario("square_loop")
    sim = simulate(SimulationConfig(scenario, data, "xsens_mtw", {}, 100.0, 2))
    norm = np.linalg.norm(sim.mag["magnetic_field"], axis=1)
    per_axis = 0.0015 * UT * np.sqrt(100.0)  # the profile's density at 100 Hz
    assert np.mean(norm) == pytest.approx(48 * UT, abs=3 * per_axis)
    assert np.std(norm) == pytest.approx(per_axis, rel=0.1)
    exact = np.linalg.norm(sim.true_mag, axis=1)
    np.testing.assert_allclose(exact, 48 * UT, rtol=1e-12)


def test_cylinders_bend_the_field_along_the_path():
    data = {"environment": {"magnetic_field": {"preset": "equator", "cylinders": [
        {"east_m": 6.5, "north_m": 0.6, "radius_m": 0.3}]}},
        "segments": [{"type": "straight", "steps": 10}]}
    norm = np.linalg.norm(run(data).true_mag, axis=1) / UT
    assert norm.max() - norm.min() > 5.0, "passing 0.6 m from a streetlight"
    # at the start, (x, y) = (−6.5, −0.6) m from the axis: Eq. (3.29) gives
    # |H| = 25·|(k·r_c/r·sin 2ρ, 1 + k·r_c/r·cos 2ρ)| µT = 23.88 µT (the 1/r decay is slow)
    k, r = 199 / 201 * 0.3 / np.hypot(6.5, 0.6), np.hypot(6.5, 0.6)
    rho2 = 2 * np.arctan2(-6.5, -0.6)
    assert r > 6 and norm[0] == pytest.approx(
        25 * np.hypot(k * np.sin(rho2), 1 + k * np.cos(rho2)), rel=1e-9)


def test_same_seed_same_bag_other_seed_other_noise():
    a, b = run(STATIC, "consumer_phone", 3), run(STATIC, "consumer_phone", 3)
    c = run(STATIC, "consumer_phone", 4)
    np.testing.assert_array_equal(a.imu["angular_velocity"], b.imu["angular_velocity"])
    assert not np.array_equal(a.imu["angular_velocity"], c.imu["angular_velocity"])


@pytest.mark.parametrize("rate", [50.0, 1000.0])
def test_rate_limits(rate):
    sim = run(STATIC, rate=rate)
    assert len(sim.imu) == int(10 * rate) + 1
    assert np.diff(sim.imu.stamp_ns).max() == round(1e9 / rate)


def test_covariances_follow_the_profile():
    sim = run(STATIC, "xsens_mtw")
    gyro_var = (0.6 * np.pi / 180 / 60) ** 2 * 100.0
    np.testing.assert_allclose(sim.imu["angular_velocity_covariance"][0, [0, 4, 8]], gyro_var)
    assert sim.imu["orientation_covariance"][0, 0] == -1.0
