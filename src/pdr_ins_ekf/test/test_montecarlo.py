"""Monte-Carlo pure INS (Zampella et al. 2011, section III-B, Table I)."""
import numpy as np
import pytest

from pdr_ins_ekf.studies.montecarlo import (
    NoiseLevels,
    ins_batch,
    ins_loop,
    ins_study,
    log_spaced,
    noisy_signals,
    power_law,
    straight_walk,
)

RATE = 100.0


@pytest.fixture(scope="module")
def walk():
    return straight_walk(25, RATE)  # 30 s


def test_batch_runs_are_the_single_run_mechanization(walk):
    a, w = noisy_signals(walk.accel, walk.gyro, RATE, NoiseLevels(0.01, 1e-3, 0.01, 1e-3), 3,
                         range(5))
    keep = log_spaced(len(walk.t_s), 100, 50)
    pos, yaw = ins_batch(walk.t_s, a, w, walk.start_attitude, 9.80665, keep)
    for r in range(5):
        p, y = ins_loop(walk.t_s, a[r], w[r], walk.start_attitude, 9.80665)
        np.testing.assert_array_equal(pos[r], p[keep])
        np.testing.assert_array_equal(yaw[r], y[keep])


# Table I: σ_p ∝ t^1.5, t^2.5, t^2, t^3; σ_ψ ∝ t^0.5 (gyro noise), t (gyro bias).
# Measured with these 200 runs of 30 s, σ_p from the noise alone (what docs/error_analysis.md
# fits: 1.504, 2.485, 1.998, 2.996 with 1,000 runs of 100 s): 1.477, 2.495, 1.997, 2.994,
# σ_ψ 0.504 and 1.006, so within 0.023 of Table I (another seed scheme gave 0.011); the
# tolerance, 0.025, is twice the 0.011 rounded up. Against the truth the noiseless
# mechanization's own error adds in: 1.551, 2.480, 2.002, 2.969 measured; tolerance 0.10
# for accelerometer noise (smallest error, 0.051 off), 0.05 for the others (0.031 off).
NOISE_TOLERANCE = 0.025


@pytest.mark.parametrize("noise, p_exponent, yaw_exponent, truth_tolerance", [
    (NoiseLevels(acc_noise_mps2_per_sqrt_hz=0.01), 1.5, None, 0.10),
    (NoiseLevels(gyro_noise_radps_per_sqrt_hz=1e-3), 2.5, 0.5, 0.05),
    (NoiseLevels(acc_bias_mps2=0.01), 2.0, None, 0.05),
    (NoiseLevels(gyro_bias_radps=1e-3), 3.0, 1.0, 0.05)], ids=["acc_noise", "gyro_noise",
                                                               "acc_bias", "gyro_bias"])
def test_error_growth_exponents_of_table_1(walk, noise, p_exponent, yaw_exponent,
                                           truth_tolerance):
    study = ins_study(walk, noise, runs=200, seed=1)
    for growth, tolerance in ((study.noise_only, NOISE_TOLERANCE),
                              (study.against_truth, truth_tolerance)):
        assert (power_law(growth.t_s, growth.sigma_p_m)[1]
                == pytest.approx(p_exponent, abs=tolerance))
        if yaw_exponent is None:
            assert growth.sigma_yaw_rad.max() < 1e-9
        else:
            assert (power_law(growth.t_s, growth.sigma_yaw_rad)[1]
                    == pytest.approx(yaw_exponent, abs=NOISE_TOLERANCE))


def test_impossible_noise_is_refused():
    with pytest.raises(ValueError, match="acc_noise_mps2_per_sqrt_hz must be a finite value >= 0"):
        NoiseLevels(acc_noise_mps2_per_sqrt_hz=-1.0)
