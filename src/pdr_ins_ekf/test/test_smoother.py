"""RTS smoothing of the ZUPT-aided INS (Simón Colomar et al. 2012, section III) on a
simulated 200-step walk with xsens_mtw noise."""
import numpy as np
import pytest

from pdr_core.evaluation.metrics import within_step_rmse
from pdr_ins_ekf.compiled_smoother import spd_solve
from pdr_ins_ekf.config import load_run_config
from pdr_ins_ekf.kernel_data import AXES, VELOCITY
from pdr_ins_ekf.zero_velocity import ConditionVoteDetector
from pdr_ins_ekf.zupt_ekf import FilterConfig, SmootherConfig, run, smooth
from pdr_sim.scenario import scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

WALK = {"segments": [{"type": "standing", "duration_s": 2.0}, {"type": "straight", "steps": 200},
                     {"type": "standing", "duration_s": 1.0}]}
RATE = 100.0
ALIGN = slice(0, 150)


@pytest.fixture(scope="module")
def simulated():
    return simulate(SimulationConfig(scenario_from_dict(WALK, "walk"), WALK, "xsens_mtw", {},
                                     RATE, 1))


@pytest.fixture(scope="module")
def walk(simulated):
    sim = simulated
    t = sim.imu.t_s - sim.imu.t_s[0]
    accel, gyro = sim.imu["linear_acceleration"], sim.imu["angular_velocity"]
    stance = ConditionVoteDetector(variant="retarded").detect(accel, gyro, RATE).mask
    args = (t, accel, gyro, stance, FilterConfig())
    return stance, run(*args, ALIGN), {
        mode: smooth(*args, SmootherConfig(mode, covariance=True), ALIGN)
        for mode in ("segmented", "full")}


def onsets(stance):
    return np.flatnonzero(stance[1:] & ~stance[:-1]) + 1


def largest_onset_jump(position, stance):
    k = onsets(stance)
    return np.linalg.norm(position[k] - position[k - 1], axis=1).max()


@pytest.mark.parametrize("mode", ["segmented", "full"])
def test_smoothing_removes_the_jumps_at_zupt_onsets(walk, mode):
    stance, filtered, smoothed = walk
    assert (largest_onset_jump(filtered.position, stance)
            >= 10 * largest_onset_jump(smoothed[mode].position, stance))


def test_segments_follow_the_steps(walk):
    stance, _, smoothed = walk
    steps = len(onsets(stance))
    assert abs(len(smoothed["segmented"].segment_ends) - steps) <= 0.05 * steps
    assert len(smoothed["full"].segment_ends) == 1
    ends = smoothed["segmented"].segment_ends
    assert stance[ends[:-1]].all(), "segments end in a stance"


def peaks(variance, stance):
    """Where in each swing (0: lift-off, 1: next ZUPT) ``variance`` peaks."""
    out = []
    for first in np.flatnonzero(stance[:-1] & ~stance[1:]) + 1:
        later = onsets(stance)[onsets(stance) > first]
        if len(later):
            out.append((np.argmax(variance[first:later[0]]) + 0.5) / (later[0] - first))
    return np.array(out)


def test_smoothed_velocity_variance_peaks_mid_swing(walk):
    """Simón Colomar et al. 2012, section III: the smoothed velocity variance peaks
    mid-swing, the filter's at the end. The filter's does so for the vertical velocity,
    which heading does not touch. Horizontally it peaks mid-swing too once the
    unobservable heading has some uncertainty: δv ≈ δψ × v grows with the foot's speed
    (with a start heading known to 1e-6 rad the first 9 steps peak at the end, later ones
    mid-swing)."""
    stance, filtered, smoothed = walk
    middle = peaks(smoothed["segmented"].velocity_variance.sum(axis=1), stance)
    assert np.mean((middle >= 1 / 3) & (middle <= 2 / 3)) >= 0.9
    vertical = peaks(smoothed["segmented"].velocity_variance[:, 2], stance)
    assert np.mean((vertical >= 1 / 3) & (vertical <= 2 / 3)) >= 0.9
    assert np.mean(peaks(filtered.variance[:, VELOCITY + 2], stance) >= 2 / 3) >= 0.9
    variance = smoothed["segmented"].velocity_variance.sum(axis=1)
    # never above the filter's (the open-loop pass linearises about a slightly different
    # nominal state than the closed-loop filter, hence the 1 % margin)
    assert (variance <= filtered.variance[:, VELOCITY:VELOCITY + AXES].sum(axis=1)
            * 1.01).all()


def test_bad_smoother_configuration():
    with pytest.raises(ValueError, match="mode must be one of"):
        SmootherConfig("fixed_lag")
    with pytest.raises(ValueError, match="gamma_s_m2ps2 > 0"):
        SmootherConfig("segmented", gamma_s_m2ps2=0.0)


def test_segmented_and_full_smoothing_agree_within_2_mm(walk):
    _, _, smoothed = walk
    difference = smoothed["segmented"].position - smoothed["full"].position
    # docs/smoothing.md: "now 2 mm" (+5 %); 1.92 mm measured
    assert np.sqrt(np.mean(np.sum(difference**2, axis=1))) < 0.0021


# docs/smoothing.md: 30 % (segmented) and 48 % (full) closer, less 5 % of each;
# 30.5 % and 47.95 % measured
@pytest.mark.parametrize("mode, gain", [("segmented", 0.285), ("full", 0.456)])
def test_smoothing_reduces_the_error_within_steps(simulated, walk, mode, gain):
    """Issue 5 asks for a smoothed RMSE against the truth ≤ the filter's. With the 9
    states of these tests, over 200 steps that RMSE is the heading drift of an unestimated
    gyro bias (1.5 m), which no smoother can see, and both stay within 1 % of each other
    (filter 1.557, segmented 1.563, full 1.584 m; with the IMU's own configuration see
    the next test). With each step's
    heading error removed (pdr_core.evaluation.metrics.within_step_rmse) the smoothed steps are
    30 % (segmented) and 48 % (full) closer to the truth: 1.59 against 1.11 and 0.83 mm."""
    stance, filtered, smoothed = walk
    truth = simulated.trajectory.position
    cuts = np.flatnonzero(stance[:-1] & ~stance[1:])
    before = within_step_rmse(filtered.position, truth, cuts)
    after = within_step_rmse(smoothed[mode].position, truth, cuts)
    assert before == pytest.approx(1.59e-3, rel=0.05)  # 1.591 mm measured
    assert after <= (1 - gain) * before


@pytest.mark.parametrize("mode", ["segmented", "full"])
def test_smoothed_rmse_is_at_most_the_filters_with_the_imus_configuration(simulated, mode):
    """Issue 5, acceptance 1: with the configuration made for the simulated IMU
    (foot_ekf_xsens_mtw.yaml: gyro biases estimated, gated ZARU) the RMSE against the
    truth of the full smoother's path is at most the filter's, and the segmented one's
    equal to it (its segments end at each stance, so it mends the steps, not the yaw):
    0.361 m filtered, 0.362 m segmented, 0.321 m full. Over seeds 0-5: means 0.190,
    0.191 and 0.173 m, the segmented one within 0.5 % of the filter on the mean. (Before
    the ZARU's innovation gate: 0.321, 0.317 and 0.273 m; means 0.188, within 0.3 %, and
    0.170 m. With the default ZARU σ of 0.01 rad/s the full smoother's yaw was worse than
    the filter's, mean 0.48 m.)"""
    config = load_run_config(imu_profile="xsens_mtw")
    sim = simulated
    accel, gyro = sim.imu["linear_acceleration"], sim.imu["angular_velocity"]
    args = (sim.imu.t_s - sim.imu.t_s[0], accel, gyro,
            config.detector.detect(accel, gyro, RATE).mask, config.filter)
    truth = sim.trajectory.position - sim.trajectory.position[0]

    def rmse(position):
        return np.sqrt(np.mean(np.sum((position - position[0] - truth) ** 2, axis=1)))

    filtered = rmse(run(*args, ALIGN).position)
    smoothed = rmse(smooth(*args, SmootherConfig(mode, config.smoother.gamma_s_m2ps2),
                           ALIGN).position)
    print(f"RMSE: filter {filtered:.4f} m, {mode} {smoothed:.4f} m")
    if mode == "full":
        assert smoothed <= filtered
    else:
        assert smoothed == pytest.approx(filtered, rel=0.005)


@pytest.mark.parametrize("mode", ["segmented", "full"])
def test_states_alone_are_the_states_smoothed_with_the_covariance(simulated, walk, mode):
    """Without the covariance the backward pass applies Aₙ to one vector instead of
    forming it: the same smoothed trajectory to rounding, and no variances."""
    stance, _, smoothed = walk
    sim = simulated
    args = (sim.imu.t_s - sim.imu.t_s[0], sim.imu["linear_acceleration"],
            sim.imu["angular_velocity"], stance, FilterConfig())
    alone = smooth(*args, SmootherConfig(mode), ALIGN)
    np.testing.assert_allclose(alone.position, smoothed[mode].position, rtol=0, atol=1e-9)
    np.testing.assert_allclose(alone.attitude, smoothed[mode].attitude, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(alone.segment_ends, smoothed[mode].segment_ends)
    assert np.isnan(alone.velocity_variance).all()


@pytest.mark.parametrize("mode", ["segmented", "full"])
@pytest.mark.parametrize("filter_config", [
    FilterConfig(bias_model="random_walk", zaru=True),
    FilterConfig(bias_model="gauss_markov", bias_tau_s=5.0)], ids=["random_walk", "gauss_markov"])
def test_states_alone_with_bias_states(simulated, walk, mode, filter_config):
    """The 15-state filter: the backward recursion through F⁻¹ inverts the bias blocks
    (and divides out the Gauss–Markov decay) and takes the ZARU updates; it gives the
    states of Eq. (9) with the covariance."""
    stance = walk[0]
    sim = simulated
    args = (sim.imu.t_s - sim.imu.t_s[0], sim.imu["linear_acceleration"],
            sim.imu["angular_velocity"], stance, filter_config)
    alone = smooth(*args, SmootherConfig(mode), ALIGN)
    written = smooth(*args, SmootherConfig(mode, covariance=True), ALIGN)
    np.testing.assert_allclose(alone.position, written.position, rtol=0, atol=1e-9)
    np.testing.assert_allclose(alone.attitude, written.attitude, rtol=0, atol=1e-12)


def test_segments_longer_than_the_store_grow_it():
    """A 12 s stop makes a segment of more than the store's 1,024 first samples: the
    store grows mid-segment, keeping what it holds, in both layouts."""
    stop = {"segments": [{"type": "standing", "duration_s": 2.0},
                         {"type": "straight", "steps": 6},
                         {"type": "standing", "duration_s": 12.0},
                         {"type": "straight", "steps": 6}]}
    sim = simulate(SimulationConfig(scenario_from_dict(stop, "stop"), stop, "xsens_mtw", {},
                                    RATE, 1))
    accel, gyro = sim.imu["linear_acceleration"], sim.imu["angular_velocity"]
    stance = ConditionVoteDetector(variant="retarded").detect(accel, gyro, RATE).mask
    args = (sim.imu.t_s - sim.imu.t_s[0], accel, gyro, stance, FilterConfig())
    alone = smooth(*args, SmootherConfig("segmented"), ALIGN)
    written = smooth(*args, SmootherConfig("segmented", covariance=True), ALIGN)
    assert np.diff(alone.segment_ends).max() > 1024
    assert np.abs(alone.position - run(*args, ALIGN).position).max() < 0.05
    np.testing.assert_allclose(alone.position, written.position, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(alone.segment_ends, written.segment_ends)


def test_spd_solve_solves_indefinite_matrices_too():
    """Cholesky for the positive-definite Pₙ₊₁|ₙ; LU for one that zeroing the
    heading–position cross-covariance made indefinite (it used to return NaN)."""
    rng = np.random.default_rng(1)
    A = rng.normal(size=(15, 15))
    B = rng.normal(size=(15, 4))
    for S in (A @ A.T + np.eye(15), A + A.T):
        np.testing.assert_allclose(S @ spd_solve(S, B), B, atol=1e-9)


def test_zeroing_the_heading_position_cross_covariance(simulated, walk):
    """Simón Colomar et al. 2012, section IV's remedy against sharp corrections, and what
    it costs, measured on the 200-step walk (which has no sharp corrections to remove):
    the covariance is no longer the filter's, and the smoothed steps end up worse than
    the filter's (within-step RMSE 3.25 mm, against 1.59 mm filtered and 1.11 mm smoothed
    without it), 1.6 cm RMS away from the filter's path (0.26 cm without it). The smoothed
    states stay finite: they used to turn NaN once the zeroed covariance was indefinite
    (on four of the seven VICON trials)."""
    stance, filtered, smoothed = walk
    sim = simulated
    args = (sim.imu.t_s - sim.imu.t_s[0], sim.imu["linear_acceleration"],
            sim.imu["angular_velocity"], stance, FilterConfig())
    zeroed = smooth(*args, SmootherConfig("segmented", zero_heading_position=True), ALIGN)
    assert np.isfinite(zeroed.position).all()
    truth = sim.trajectory.position
    cuts = np.flatnonzero(stance[:-1] & ~stance[1:])
    within = {name: within_step_rmse(position, truth, cuts) for name, position in
              (("filter", filtered.position), ("smoothed", smoothed["segmented"].position),
               ("zeroed", zeroed.position))}
    print({k: round(v * 1e3, 3) for k, v in within.items()}, "mm")
    assert within["smoothed"] < within["filter"] < within["zeroed"]
    # docs/smoothing.md: 3.25 mm against 1.59 mm (2.04×), ±5 %; 3.249 / 1.591 mm measured
    assert within["zeroed"] == pytest.approx(3.25e-3, rel=0.05)
    assert within["zeroed"] / within["filter"] == pytest.approx(2.04, rel=0.05)

    def rms_from_filter(position):
        return np.sqrt(np.mean(np.sum((position - filtered.position) ** 2, axis=1)))

    # docstring: 0.26 cm without zeroing (+5 %), 0.262 cm measured; docs/smoothing.md:
    # 1.6 cm RMS away (±5 %), 1.56 cm measured
    assert rms_from_filter(smoothed["segmented"].position) < 0.00273
    assert rms_from_filter(zeroed.position) == pytest.approx(0.016, rel=0.05)
