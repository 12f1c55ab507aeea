"""The orientation filter's gyro bias model and its rest bias update (issue 40).

- ``bias_model``: allan, the σ of the Gauss-Markov bias whose modelled Allan deviation
  has its minimum at the bias instability β (what pdr_core.sensors.allan fits and the simulator
  draws), or thesis, σ_bias = β/√τ (Muñoz Díaz 2016, Eq. (3.11)); either drives the
  process noise σ_n² = σ_bias²(1 − e^{−2/τ}) of Eq. (3.9). Bad values are named.
- ``imu_profile``: the gyroscope noise of a profile of pdr_core.sensors.imu_profiles for each key
  not given.
- ZARU (Eq. (3.22)) at rest as VQF finds it (Laidig and Seel 2023): every rate of the
  window close to their mean, whatever the bias; the mean of the window's older half is
  the measurement; a steady slow turn fails its χ² gate.
"""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core import units
from pdr_core.errors import InputError
from pdr_core.sensors.allan import gm_sigma_for_bias_instability
from pdr_core.sensors.imu_profiles import PROFILES
from pdr_pocket import compiled_orientation as k
from pdr_pocket.config import pocket_config
from pdr_pocket.orientation import OrientationFilter
from pdr_pocket.orientation_config import OrientationConfig, Updates, profile_noise

ZARU_ONLY = Updates(False, False, False, False, False, True, False)
RATE_HZ = 100.0
G = 9.80665


def test_allan_sigma_is_the_gauss_markov_bias_of_the_allan_minimum_and_thesis_eq_3_11():
    mtw = OrientationConfig(imu_profile="xsens_mtw")
    expected = gm_sigma_for_bias_instability(units.deg_per_h_to_si(10.0), 200.0,
                                             units.arw_to_si(0.6))
    assert mtw.bias_sigma_radps == pytest.approx(expected, rel=1e-12)
    assert mtw.bias_sigma_radps / units.deg_per_h_to_si(1) == pytest.approx(25.3, abs=0.1)
    thesis = OrientationConfig(imu_profile="xsens_mtw", bias_model="thesis")
    assert thesis.bias_sigma_radps / units.deg_per_h_to_si(1) == pytest.approx(
        10.0 / np.sqrt(200.0 * 100.0), rel=1e-12)          # 0.07 °/h
    for config in (mtw, thesis):
        assert config.params().bias_sigma == config.bias_sigma_radps
        assert config.params().bias_tau_s == 200.0


def test_the_profile_fills_the_noise_keys_not_given_and_a_key_given_wins():
    phone = PROFILES["consumer_phone"]["gyro"]
    raw = OrientationConfig(imu_profile="consumer_phone")
    assert raw.noise("gyro_arw_deg_per_sqrt_h") == phone["arw_deg_per_sqrt_h"]
    assert raw.noise("bias_instability_deg_per_h") == phone["bias_instability_deg_per_h"]
    assert raw.noise("bias_instability_time_s") == phone["bias_correlation_time_s"]
    assert raw.noise("initial_bias_sigma_deg_per_s") == phone["bias_sigma_deg_per_s"]


def test_a_profile_given_by_its_gauss_markov_sigma_has_that_sigma_back():
    """calibrated_phone, the default, gives the simulator the Gauss-Markov σ of its gyro
    bias directly: the filter reads the β of its Allan minimum, from which the allan bias
    model gives the same σ, and its own initial σ (0.25 °/s)."""
    gyro = PROFILES["calibrated_phone"]["gyro"]
    default = OrientationConfig()
    assert default.imu_profile == "calibrated_phone"
    assert default.bias_sigma_radps == pytest.approx(
        np.radians(gyro["gauss_markov_sigma_deg_per_s"]), rel=1e-3)
    assert default.noise("bias_instability_time_s") == gyro["bias_correlation_time_s"]
    assert default.noise("initial_bias_sigma_deg_per_s") == 0.25
    given = OrientationConfig(imu_profile="xsens_mtw", bias_instability_deg_per_h=5.0)
    assert given.noise("bias_instability_deg_per_h") == 5.0
    assert given.noise("gyro_arw_deg_per_sqrt_h") == profile_noise("xsens_mtw")[
        "gyro_arw_deg_per_sqrt_h"] == 0.6
    read = pocket_config({"orientation": {"imu_profile": "xsens_mtw"}}).orientation
    assert read == OrientationConfig(imu_profile="xsens_mtw")


@pytest.mark.parametrize(("orientation", "names"), [
    ({"bias_model": "random_walk"}, ("config.orientation", "bias_model", "allan, thesis")),
    ({"imu_profile": "vn200"}, ("imu_profile", "calibrated_phone, consumer_phone, xsens_mtw")),
    ({"bias_instability_deg_per_h": 0.5},
     ("bias_instability_deg_per_h 0.5", "gyro_arw_deg_per_sqrt_h 0.42", "bias_model allan")),
    ({"zaru_gate_probability": 1.0}, ("zaru_gate_probability",)),
    ({"initial_bias_sigma_deg_per_s": -1.0}, ("initial_bias_sigma_deg_per_s",)),
])
def test_bad_bias_settings_are_refused_by_name(orientation, names):
    with pytest.raises(InputError) as info:
        pocket_config({"orientation": orientation})
    for name in names:
        assert name in str(info.value)


def still(seconds: float, bias_deg_per_s, turn_deg_per_s: float = 0.0, seed: int = 0):
    """A sensor lying level, z up, with a constant gyro bias [°/s] and consumer-phone
    white noise (0.007 °/s/√Hz), turning about z at ``turn_deg_per_s``."""
    rng = np.random.default_rng(seed)
    n = int(seconds * RATE_HZ)
    t = np.arange(n) / RATE_HZ
    gyro = np.radians(np.asarray(bias_deg_per_s, float) + [0.0, 0.0, turn_deg_per_s]) + \
        rng.standard_normal((n, 3)) * np.radians(0.007) * np.sqrt(RATE_HZ)
    accel = np.tile([0.0, 0.0, G], (n, 1)) + rng.standard_normal((n, 3)) * 0.02
    return t, gyro, accel


def test_rest_is_found_whatever_the_bias_and_teaches_it():
    """A phone's turn-on bias of 3.5 °/s in norm: every rate beyond the old detector's
    3 °/s, yet a rest; the ZARU learns the bias within 0.01 °/s in 20 s."""
    bias = np.array([2.0, -2.5, 1.5])
    t, gyro, accel = still(20.0, bias)
    est = OrientationFilter(OrientationConfig(filter="thesis", imu_profile="consumer_phone",
                                          updates=ZARU_ONLY)).run(t, gyro, accel)
    assert est.detected[t > 1.0, k.ZERO_RATE].all()
    assert np.abs(np.degrees(est.bias[-1]) - bias).max() < 0.01


def test_a_slow_steady_turn_is_refused_by_the_zaru_gate():
    """20 s at rest (bias 0.3 °/s on z learned), then a steady turn at 6 °/s about z: the
    rate spreads no more than at rest, but its mean is 6 °/s off the bias learned, so
    the χ² gate refuses it and the bias stays."""
    t1, g1, a1 = still(20.0, [0.0, 0.0, 0.3])
    t2, g2, a2 = still(20.0, [0.0, 0.0, 0.3], turn_deg_per_s=6.0, seed=1)
    f = OrientationFilter(OrientationConfig(filter="thesis", imu_profile="consumer_phone",
                                          updates=ZARU_ONLY))
    f.run(t1, g1, a1)
    turning = f.run(t2 + 20.0, g2, a2)
    assert turning.detected[:, k.ZERO_RATE].mean() > 0.9
    assert not turning.ran[:, k.ZARU].any()
    assert np.degrees(turning.bias[-1, 2]) == pytest.approx(0.3, abs=0.01)


def test_an_allan_csv_whose_minimum_leaves_no_gauss_markov_dip_is_refused_by_name(tmp_path):
    """The Xsens MTw's modelled Allan minimum (10 °/h) lies at 27 s; taken as the AR(1)'s
    time constant it is too short for a dip to 10 °/h over 0.6 °/√h, so the allan model
    refuses it naming the keys; the thesis' model takes it as Eq. (3.10) does."""
    from pdr_pocket.orientation_config import orientation_from_allan

    csv = tmp_path / "allan.csv"
    csv.write_text("axis,arw_deg_per_sqrt_h,bias_instability_deg_per_h,t_beta_s\n" +
                   "".join(f"gyro_{a},0.6,10.0,27.4\n" for a in "xyz"))
    with pytest.raises(InputError) as info:
        orientation_from_allan(csv)
    assert "bias_instability_time_s 27.4" in str(info.value)
    thesis = orientation_from_allan(csv, OrientationConfig(bias_model="thesis"))
    assert thesis.noise("bias_instability_time_s") == pytest.approx(27.4)
