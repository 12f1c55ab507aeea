"""Monte-Carlo ZUPT EKF batched over runs (Zampella et al. 2011, section IV-B,
Tables II-III)."""
import numpy as np
import pytest

from pdr_ins_ekf import zupt_ekf
from pdr_ins_ekf.studies.ekf_montecarlo import (
    XSENS_MTI,
    detect_runs,
    ekf_study,
    estimator_detector,
    filter_for,
    polynomial_fit,
    rest_samples,
    run_batch,
    stance_times,
)
from pdr_ins_ekf.studies.montecarlo import NoiseLevels, noisy_signals, straight_walk
from pdr_ins_ekf.zero_velocity import (
    AdaptiveShoeDetector,
    AngularRateEnergyDetector,
    ConditionVoteDetector,
    MagnitudeDetector,
    MovingVarianceDetector,
    ShoeDetector,
)

RATE = 100.0


@pytest.fixture(scope="module")
def walk():
    return straight_walk(20, RATE, rest_s=10.0)


@pytest.fixture(scope="module")
def signals(walk):
    return noisy_signals(walk.accel, walk.gyro, RATE, XSENS_MTI, 5, range(4))


@pytest.mark.parametrize("detector", [
    ConditionVoteDetector(variant="original"), ConditionVoteDetector(variant="limited"),
    ConditionVoteDetector(variant="retarded"), ShoeDetector(), AdaptiveShoeDetector(),
    MovingVarianceDetector(), MagnitudeDetector(), AngularRateEnergyDetector()],
    ids=lambda d: type(d).__name__ + getattr(d, "variant", ""))
def test_detectors_decide_all_runs_at_once_as_one_by_one(signals, detector):
    a, w = signals
    batched = detect_runs(detector, a, w, RATE)
    for r in range(len(a)):
        np.testing.assert_array_equal(batched[r], detector.detect(a[r], w[r], RATE).mask)


@pytest.mark.parametrize("states", [9, 15])
def test_batch_runs_are_the_single_run_filter(walk, signals, states):
    a, w = signals
    config = filter_for(XSENS_MTI, states=states)
    detector = ConditionVoteDetector(variant="limited")
    keep = stance_times(walk, 1.0, 40)
    stance = detect_runs(detector, a, w, RATE)
    batch = run_batch(walk, a, w, stance, config, keep)
    for r in range(len(a)):
        single = zupt_ekf.run(walk.t_s, a[r], w[r], stance[r], config, rest_samples(walk),
                              walk.yaw[0])
        np.testing.assert_array_equal(batch.position[r], single.position[keep])
        np.testing.assert_array_equal(batch.variance[r], single.variance[keep])
        np.testing.assert_array_equal(batch.position_cov[r], single.position_cov[keep])


def test_study_keeps_stance_samples_and_the_filters_own_view(walk):
    keep = stance_times(walk, 1.0, 30)
    assert walk.at_rest[keep].all() and walk.t_s[keep[0]] >= walk.rest_s + 1.0
    study = ekf_study(walk, NoiseLevels.only("acc_noise", 0.002), 10,
                      ConditionVoteDetector(variant="retarded"), filter_for(XSENS_MTI))
    c = study.consistency
    assert study.growth.t_s[0] >= 1.0
    assert (c.sigma_p_q05_m <= c.sigma_p_m).all() and (c.sigma_p_m <= c.sigma_p_q95_m).all()
    assert np.isfinite(c.nees_position).all()
    # Measured value ±25 % (not a χ² band: a consistent filter would give a mean of 3 for
    # 3 dof, but this filter's covariance carries the MTi's gyro noise, biases and the
    # ZUPT's r, which this walk with accelerometer noise alone does not have): mean NEES
    # 0.236 over the 89 kept times, 0.112-0.373 at each, so well below 3 at every one.
    assert c.nees_position.mean() == pytest.approx(0.236, rel=0.25)
    assert c.nees_position.max() < 1


@pytest.fixture(scope="module")
def long_walk():
    return straight_walk(100, RATE, rest_s=10.0)


def final(walk, source, estimator, states=15, rest_gyro_bias=True):
    study = ekf_study(walk, NoiseLevels.only(source, getattr(
        XSENS_MTI, next(f for f in NoiseLevels.__dataclass_fields__ if f.startswith(source)))),
        20, estimator_detector(estimator), filter_for(XSENS_MTI, states=states), seed=2,
        rest_gyro_bias=rest_gyro_bias)
    return study.growth.sigma_p_m[-1], study.growth.sigma_yaw_rad[-1]


def test_limited_and_retarded_windows_beat_the_original_under_accelerometer_noise(long_walk):
    """Table II, first row: 2e-2·t^1.11 (original) against 6e-4·t and 3e-4·t."""
    # σ_p of the original detector over the window's at the end of this 100-stride,
    # 20-run study, seed 2: 12.95 and 17.10 measured, ±10 % (seeds 0-5 give 11.4-12.95 and
    # 14.2-18.8; docs/error_analysis.md: 6× and 7× at t = 1,199 s with 100 runs of 1,000
    # strides)
    original = final(long_walk, "acc_noise", "ekf_original")[0]
    for window, ratio in (("ekf_limited", 12.95), ("ekf_retarded", 17.10)):
        assert (original / final(long_walk, "acc_noise", window)[0]
                == pytest.approx(ratio, rel=0.10)), window


def test_gyro_bias_dominates_yaw_unless_the_filter_estimates_it(long_walk):
    """Table III: with biases not estimated (9 states, no calibration at rest) the gyro
    bias dominates the long-term yaw error; the 15-state filter with ZARU removes it."""
    yaw = {s: final(long_walk, s, "ekf_limited", 9, False)[1]
           for s in ("acc_noise", "gyro_noise", "acc_bias", "gyro_bias")}
    assert yaw["gyro_bias"] > 10 * max(yaw["acc_noise"], yaw["gyro_noise"], yaw["acc_bias"])
    estimated = final(long_walk, "gyro_bias", "ekf_limited", 15, False)[1]
    assert estimated < yaw["gyro_bias"] / 100


def test_polynomial_fit_recovers_the_table_form():
    t = np.geomspace(1, 1000, 50)
    assert polynomial_fit(t, 2e-3 * t + 1.5e-4 * t**2) == pytest.approx((2e-3, 1.5e-4))


def test_unknown_estimator_and_state_count_are_refused():
    with pytest.raises(ValueError, match="unknown estimator 'ekf_magic'"):
        estimator_detector("ekf_magic")
    with pytest.raises(ValueError, match="states must be 9 or 15"):
        filter_for(XSENS_MTI, states=12)
