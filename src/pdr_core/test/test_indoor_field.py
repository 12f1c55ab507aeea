"""The indoor magnetic disturbance (issue 53): its spread of azimuth, norm and dip and its
correlation length are the configured ones, a seed fixes it, and impossible settings are
refused; and the calibrated_phone profile (an OS-calibrated gyroscope, a phone-fixed
magnetometer offset)."""
import numpy as np
import pytest

from pdr_core.sensors.imu_profiles import PROFILES, profile
from pdr_core.sensors.magnetic_field import UT, IndoorDisturbance, MagneticField, homogeneous

ROOM_T = np.array([0.0, 14.3, -34.5]) * UT          # the OxIOD room's Earth field
POINTS = 20000


def field_angles(h: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Azimuth from north [deg], norm [µT] and dip [deg] of ENU fields (N, 3) [T]."""
    norm = np.linalg.norm(h, axis=1)
    return (np.degrees(np.arctan2(h[:, 0], h[:, 1])), norm / UT,
            np.degrees(np.arcsin(-h[:, 2] / norm)))


def wide_area(n: int = POINTS, seed: int = 0) -> np.ndarray:
    """Positions [m] over 200 m x 200 m, 0-3 m high: many correlation lengths."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-100, 100, (n, 2)), rng.uniform(0.0, 3.0, n)])


@pytest.mark.parametrize("disturbance", [
    IndoorDisturbance(),                               # the defaults, from OxIOD's room
    IndoorDisturbance(azimuth_sigma_deg=12.0, norm_sigma_ut=4.0, dip_sigma_deg=1.5,
                      correlation_length_m=3.0, seed=7),
])
def test_spread_and_correlation_length_are_the_configured_ones(disturbance):
    """Over an area of many correlation lengths the azimuth, norm and dip spread by the
    configured σ (within 10 %: the azimuth's first-order sizing and a finite area), and
    the correlation of the disturbance at d is exp(-d²/ℓ²) within 0.05."""
    field = MagneticField(tuple(ROOM_T), indoor=disturbance)
    here = wide_area()
    azimuth, norm, dip = field_angles(field.at(here))
    assert np.std(azimuth) == pytest.approx(disturbance.azimuth_sigma_deg, rel=0.1)
    assert np.std(norm) == pytest.approx(disturbance.norm_sigma_ut, rel=0.1)
    assert np.std(dip) == pytest.approx(disturbance.dip_sigma_deg, rel=0.1)
    ell = disturbance.correlation_length_m
    delta = disturbance.at(here, ROOM_T)
    rng = np.random.default_rng(1)
    for distance in (0.5 * ell, ell, 2.0 * ell):
        towards = rng.standard_normal(here.shape)
        towards /= np.linalg.norm(towards, axis=1, keepdims=True)
        there = disturbance.at(here + distance * towards, ROOM_T)
        correlation = np.sum(delta * there) / np.sum(delta * delta)
        assert correlation == pytest.approx(np.exp(-(distance / ell) ** 2), abs=0.05)


def test_each_spread_moves_only_its_own_angle():
    """The three components are along H∞ (norm), across it horizontally (azimuth) and
    across it in its vertical plane (dip): with the other two at 0, one moves alone."""
    here = wide_area(4000)
    azimuth, norm, dip = field_angles(MagneticField(tuple(ROOM_T), indoor=IndoorDisturbance(
        azimuth_sigma_deg=0.0, dip_sigma_deg=0.0)).at(here))
    assert np.ptp(azimuth) < 1e-9 and np.ptp(dip) < 1e-9 and np.std(norm) > 1.0
    azimuth, norm, dip = field_angles(MagneticField(tuple(ROOM_T), indoor=IndoorDisturbance(
        norm_sigma_ut=0.0, dip_sigma_deg=0.0)).at(here))
    assert np.std(azimuth) > 3.0            # the norm and dip move to second order only
    assert np.std(norm) < 0.03 * np.std(azimuth) and np.std(dip) < 0.1 * np.std(azimuth)
    azimuth, norm, dip = field_angles(MagneticField(tuple(ROOM_T), indoor=IndoorDisturbance(
        norm_sigma_ut=0.0, azimuth_sigma_deg=0.0)).at(here))
    assert np.ptp(azimuth) < 1e-9 and np.std(dip) > 1.5 and np.std(norm) < 0.05 * np.std(dip)


def test_a_seed_fixes_the_field():
    here = wide_area(500)
    first = IndoorDisturbance(seed=3).at(here, ROOM_T)
    np.testing.assert_array_equal(IndoorDisturbance(seed=3).at(here, ROOM_T), first)
    assert np.abs(IndoorDisturbance(seed=4).at(here, ROOM_T) - first).max() > 1 * UT
    # one position at a time gives what a whole walk gives (no state between calls)
    np.testing.assert_array_equal(IndoorDisturbance(seed=3).at(here[7], ROOM_T)[0], first[7])


def test_the_field_is_smooth_along_a_walk():
    """A sensor moving 1 cm sees the field change by a few nT only (ℓ = 1.6 m)."""
    path = np.column_stack([np.linspace(0.0, 5.0, 501), np.full(501, 1.0), np.full(501, 0.7)])
    step = np.diff(MagneticField(tuple(ROOM_T), indoor=IndoorDisturbance()).at(path), axis=0)
    assert np.abs(step).max() < 0.05 * UT


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"azimuth_sigma_deg": 45.0}, "azimuth_sigma_deg must be within 0-45"),
    ({"dip_sigma_deg": -1.0}, "dip_sigma_deg must be within 0-45"),
    ({"norm_sigma_ut": -0.1}, "norm_sigma_ut must be >= 0"),
    ({"correlation_length_m": 0.0}, "correlation_length_m > 0"),
])
def test_impossible_settings_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        IndoorDisturbance(**kwargs)


def test_an_azimuth_spread_needs_a_horizontal_field():
    pole = homogeneous("north_pole")
    with pytest.raises(ValueError, match="horizontal part"):
        MagneticField(tuple(pole), indoor=IndoorDisturbance()).at(np.zeros((1, 3)))
    h = MagneticField(tuple(pole), indoor=IndoorDisturbance(azimuth_sigma_deg=0.0)).at(
        wide_area(100))
    assert np.all(np.isfinite(h))


def test_calibrated_phone_is_consumer_phone_with_the_os_calibration():
    """The same sensors as consumer_phone (noise, misalignment, accelerometer), the gyro's
    turn-on bias replaced by the small residual an OS calibration leaves and its slow
    variation, a 0.3 % scale factor, and a smoother magnetometer with a phone-fixed offset
    of σ 3 µT per axis (values and sources in pdr_core.sensors.imu_profiles)."""
    phone, calibrated = PROFILES["consumer_phone"], PROFILES["calibrated_phone"]
    assert set(calibrated) == {"gyro", "accel", "mag", "baro"}
    assert calibrated["accel"] == phone["accel"] and calibrated["baro"] == phone["baro"]
    for key in ("arw_deg_per_sqrt_h", "misalignment_mrad", "range_deg_per_s",
                "resolution_deg_per_s"):
        assert calibrated["gyro"][key] == phone["gyro"][key]
    assert calibrated["gyro"]["bias_sigma_deg_per_s"] == 0.25 < phone["gyro"][
        "bias_sigma_deg_per_s"]
    assert calibrated["gyro"]["gauss_markov_sigma_deg_per_s"] == 0.1
    assert calibrated["gyro"]["bias_correlation_time_s"] == 100.0
    assert calibrated["gyro"]["scale_factor_ppm"] == 3000.0
    assert calibrated["mag"] == {"noise_ut_per_sqrt_hz": 0.01, "bias_sigma_ut": 3.0}
    errors = profile("calibrated_phone")
    np.testing.assert_allclose(errors.gyro.bias_sigma, np.radians(0.25))
    np.testing.assert_allclose(errors.gyro.gm_sigma, np.radians(0.1))
    np.testing.assert_allclose(errors.mag.bias_sigma, 3.0 * UT)
    assert errors.gyro.bias == (0.0, 0.0, 0.0) and errors.mag.bias == (0.0, 0.0, 0.0)
