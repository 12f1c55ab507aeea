"""Sensor error models: statistics of each source, determinism, and the Allan reading of
the configured profile (issue 3, acceptance 2 at the library level)."""
import numpy as np
import pytest

from pdr_core import units
from pdr_core.errors import InputError
from pdr_core.sensors.allan import allan_deviation, allan_deviation_model, noise_parameters
from pdr_core.sensors.imu_errors import TriadErrors, corrupt, gauss_markov
from pdr_core.sensors.imu_profiles import imu_errors, profile


def test_white_noise_std_is_density_times_sqrt_rate():
    errors = TriadErrors(white_density=(0.01, 0.02, 0.03))
    y = corrupt(np.zeros((200_000, 3)), errors, 400.0, np.random.default_rng(0))
    np.testing.assert_allclose(y.std(axis=0), np.array([0.01, 0.02, 0.03]) * 20, rtol=0.01)


def test_gauss_markov_is_stationary_with_the_right_correlation():
    rng = np.random.default_rng(1)
    b = gauss_markov(rng, (400, 2000, 3), np.array([1.0, 2.0, 3.0]), np.array([0.5] * 3), 0.01)
    np.testing.assert_allclose(b[:, [0, -1]].std(axis=(0, 1)), [1, 2, 3], rtol=0.05)
    lag = 50  # 0.5 s = one correlation time
    corr = (b[:, :-lag, 0] * b[:, lag:, 0]).mean() / b[:, :, 0].var()
    assert corr == pytest.approx(np.exp(-1), abs=0.03)


def test_random_walk_variance_grows_linearly():
    errors = TriadErrors(random_walk_density=(0.1, 0.1, 0.1))
    y = corrupt(np.zeros((1000, 3)), errors, 100.0, np.random.default_rng(2), runs=500)
    assert y[:, -1].var() == pytest.approx(0.1**2 * 10.0, rel=0.1)


def test_the_warm_up_is_not_there_at_the_start_and_reached_after_it():
    """b_w = warmup·(1 − e^{−t/τ}): nothing at the first sample, 63 % after τ, all of it
    after many, from the profile keys in their units."""
    errors = imu_errors({"gyro": {"warmup_bias_deg_per_s": [0, 0, 0.05],
                                  "warmup_time_constant_s": 60.0}}, "p").gyro
    y = corrupt(np.zeros((100 * 600 + 1, 3)), errors, 100.0, np.random.default_rng(4))
    z = np.degrees(y[:, 2])
    assert z[0] == 0 and z[6000] == pytest.approx(0.05 * (1 - np.exp(-1)), rel=1e-9)
    assert z[-1] == pytest.approx(0.05, rel=1e-4) and (y[:, :2] == 0).all()
    with pytest.raises(InputError, match=r"p\.gyro\.warmup_time_constant_s: must be > 0"):
        imu_errors({"gyro": {"warmup_time_constant_s": 0.0}}, "p")


def test_scale_misalignment_saturation_and_quantisation():
    errors = TriadErrors(scale_factor=(0.01, 0.0, 0.0),
                         misalignment=((0, 0.002, 0), (0.002, 0, 0), (0, 0, 0)),
                         saturation=15.0, quantum=0.01)
    y = corrupt(np.array([[10.0, 0.0, 0.0], [20.0, 0.0, 0.0]]), errors, 100.0,
                np.random.default_rng(3))
    np.testing.assert_allclose(y, [[10.1, 0.02, 0.0], [15.0, 0.04, 0.0]])


def test_same_seed_same_measurements_vectorised_over_runs():
    errors = profile("consumer_phone").gyro
    a = corrupt(np.ones((100, 3)), errors, 100.0, np.random.default_rng(7), runs=4)
    b = corrupt(np.ones((100, 3)), errors, 100.0, np.random.default_rng(7), runs=4)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a[0], a[1])


def test_profile_allan_reading_matches_configuration():
    """1 h of static xsens_mtw gyro data: ARW and bias instability read back within 10 %."""
    errors = profile("xsens_mtw").gyro
    y = corrupt(np.zeros((360_000, 3)), errors, 100.0, np.random.default_rng(11))
    for axis in range(3):
        taus, adev = allan_deviation(y[:, axis], 100.0)
        p = noise_parameters(taus, adev, 100.0)
        assert units.arw_from_si(p.white_density) == pytest.approx(0.6, rel=0.1)
        assert p.bias_instability / units.deg_per_h_to_si(1) == pytest.approx(10.0, rel=0.1)
        model = allan_deviation_model(taus, errors.white_density[axis], errors.gm_sigma[axis],
                                      errors.gm_tau_s[axis])
        assert np.median(np.abs(adev / model - 1)[taus < 100]) < 0.05


def test_gauss_markov_sigma_and_tau_directly():
    errors = imu_errors({"gyro": {"gauss_markov_sigma_deg_per_s": 0.01,
                                  "bias_correlation_time_s": [50, 60, 70]}})
    np.testing.assert_allclose(errors.gyro.gm_sigma, np.radians(0.01))
    assert errors.gyro.gm_tau_s == (50.0, 60.0, 70.0)


@pytest.mark.parametrize("config, key", [
    ({"gyro": {"arw_deg_per_sqrt_h": -1}}, "p.gyro.arw_deg_per_sqrt_h"),
    ({"gyro": {"arw_deg_per_sqrt": 1}}, "p.gyro.arw_deg_per_sqrt"),
    ({"sonar": {}}, "p.sonar"),
    ({"accel": {"bias_instability_mg": 0.1}}, "p.accel.bias_correlation_time_s"),
    ({"accel": {"bias_mg": [1, 2]}}, "p.accel.bias_mg"),
    ({"accel": {"gauss_markov_sigma_mg": 0.1}}, "p.accel.bias_correlation_time_s"),
    ({"gyro": {"gauss_markov_sigma_deg_per_s": 0.1, "bias_instability_deg_per_h": 5,
               "bias_correlation_time_s": 100}}, "p.gyro.gauss_markov_sigma_deg_per_s"),
    ({"gyro": {"bias_instability_deg_per_h": 10, "bias_correlation_time_s": 200}},
     "p.gyro.bias_instability_deg_per_h"),
])
def test_bad_profile_configuration_names_the_key(config, key):
    with pytest.raises(InputError) as err:
        imu_errors(config, "p")
    assert str(err.value).startswith(key + ":")


def test_the_allan_model_is_finite_where_the_bias_term_rounds():
    taus = np.logspace(-3, 5, 1600)
    curve = allan_deviation_model(taus, 0.0, 1e-4, 200.0)
    assert np.all(np.isfinite(curve)) and np.all(curve >= 0)
