"""Drift corrections in the foot filter (pdr_ins_ekf.corrections, .correctable): the
Kalman update of each part, the gate, all or nothing, and at the stride they name."""
from dataclasses import replace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdr_core.corrections.correction import Correction
from pdr_core.io.bag import BagReader
from pdr_ins_ekf import corrections
from pdr_ins_ekf.config import load_run_config, run_config
from pdr_ins_ekf.correctable import concatenated
from pdr_ins_ekf.kernel_data import HEADING
from pdr_ins_ekf.streaming import StreamingNavigator
from pdr_ins_ekf.zupt_ekf import FilterConfig, ZuptEkf

LEVEL = np.eye(3)


def yaw(ekf: ZuptEkf) -> float:
    return float(Rotation.from_matrix(ekf.C).as_euler("ZYX")[0])


def filter_with(states: int, heading_sigma_rad: float) -> ZuptEkf:
    config = FilterConfig(bias_model="none" if states == 9 else "random_walk",
                          init_yaw_sigma_rad=heading_sigma_rad)
    return ZuptEkf(config, LEVEL)


def test_a_yaw_change_is_taken_by_its_share_of_the_variances_exactly():
    """ψ moves by P/(P + R)·Δψ: a 40° change at equal variances turns it by 20°, the
    exact rotation, not its first order (tan⁻¹ of it would give 19.3°)."""
    ekf = filter_with(9, np.radians(30.0))
    c = Correction(yaw_rad=np.radians(40.0), yaw_variance_rad2=np.radians(30.0) ** 2)
    assert corrections.refusal(c, 9) is None
    problem, nis = corrections.gate(c, ekf.state)
    assert problem is None and nis["yaw"] == pytest.approx(40**2 / (2 * 30**2))
    corrections.apply(c, ekf.state)
    assert np.degrees(yaw(ekf)) == pytest.approx(20.0, abs=1e-9)
    assert ekf.P[HEADING, HEADING] == pytest.approx(np.radians(30.0) ** 2 / 2)
    np.testing.assert_allclose(ekf.C @ ekf.C.T, np.eye(3), atol=1e-12)


def test_the_bias_part_needs_bias_states_and_moves_the_z_gyro_bias():
    c = Correction(gyro_bias_z_radps=1e-3, gyro_bias_z_variance_rad2ps2=1e-12)
    assert "the filter has 9 states and no gyro bias" in corrections.refusal(c, 9)
    ekf = filter_with(15, 1e-3)
    corrections.apply(c, ekf.state)
    assert ekf.b[5] == pytest.approx(1e-3, rel=1e-6)


def test_a_position_fix_and_the_gate():
    ekf = filter_with(9, 1e-3)
    ekf.P[:3, :3] = np.eye(3) * 1.0
    fix = Correction(position_m=np.array([1.0, -1.0, 0.0]), position_covariance_m2=np.eye(3))
    assert corrections.gate(fix, ekf.state)[0] is None
    far = replace(fix, position_m=np.array([10.0, 0.0, 0.0]))
    problem, nis = corrections.gate(far, ekf.state)
    assert problem.startswith("position refused by the χ² gate") and nis["position"] == 50.0
    corrections.apply(fix, ekf.state)
    np.testing.assert_allclose(ekf.p, [0.5, -0.5, 0.0])


@pytest.mark.parametrize("correction, reason", [
    (Correction(), "nothing to apply"),
    (Correction(yaw_rad=0.1, yaw_variance_rad2=0.0), "yaw_variance is 0"),
    (Correction(yaw_rad=np.nan, yaw_variance_rad2=1.0), "yaw nan is not finite")])
def test_unusable_corrections_are_refused_by_name(correction, reason):
    assert reason in corrections.refusal(correction, 15)


@pytest.fixture(scope="module")
def imu(request):
    return BagReader(request.config.rootpath / "bags" / "foot_walk").read("/imu/data")


def pushed(navigator: StreamingNavigator, imu, stop: int | None = None) -> list:
    """The navigator's outputs for the samples up to ``stop`` (all: flushed), in blocks."""
    runs, end = [], len(imu) if stop is None else stop
    for first in range(0, end, 37):
        part = slice(first, min(first + 37, end))
        runs.append(navigator.push_many(imu.stamp_ns[part], imu["linear_acceleration"][part],
                                        imu["angular_velocity"][part]))
    if stop is None:
        runs.append(navigator.flush())
    return runs


def test_a_correction_at_a_past_stride_equals_one_taken_then(imu):
    """Taken at the end at the sixth stride's stamp, the samples since filtered again give
    exactly what a navigator that took it right at that sample gives."""
    config = load_run_config(None)
    late = StreamingNavigator(config)
    strides = [s for run in pushed(late, imu) for s in run.strides]
    c = Correction(yaw_rad=0.02, yaw_variance_rad2=1e-4, stamp_ns=strides[5].stamp_ns)
    result = late.apply_correction(c)
    assert result.accepted, result.message
    revised = concatenated(result.revised)
    assert len(revised.strides) == len(strides) - 6
    then = StreamingNavigator(config)
    runs = []
    for k in range(len(imu)):
        runs += pushed_one(then, imu, k)
        if len(runs[-1].stamp_ns) and runs[-1].stamp_ns[-1] == c.stamp_ns:
            assert then.apply_correction(replace(c, stamp_ns=0)).accepted
    runs.append(then.flush())
    stamps = np.concatenate([r.stamp_ns for r in runs])
    position = np.concatenate([r.output.position for r in runs])
    after = stamps > c.stamp_ns
    np.testing.assert_array_equal(stamps[after], revised.block.stamp_ns)
    np.testing.assert_array_equal(position[after], revised.output.position)


def pushed_one(navigator: StreamingNavigator, imu, k: int) -> list:
    return [navigator.push_many(imu.stamp_ns[k:k + 1], imu["linear_acceleration"][k:k + 1],
                                imu["angular_velocity"][k:k + 1])]


def test_a_refused_correction_changes_nothing_and_stamps_out_of_reach_are_named(imu):
    navigator = StreamingNavigator(load_run_config(None), correction_window_s=10.0)
    before = StreamingNavigator(load_run_config(None), correction_window_s=10.0)
    strides = [s for run in pushed(navigator, imu, 5000) for s in run.strides]
    pushed(before, imu, 5000)
    refused = navigator.apply_correction(Correction(yaw_rad=1.0, yaw_variance_rad2=1e-6,
                                                    stamp_ns=strides[-2].stamp_ns))
    assert not refused.accepted and "yaw refused by the χ² gate" in refused.message
    rest = slice(5000, None)
    np.testing.assert_array_equal(
        np.concatenate([r.output.position for r in pushed_rest(navigator, imu, rest)]),
        np.concatenate([r.output.position for r in pushed_rest(before, imu, rest)]))
    old = navigator.apply_correction(Correction(yaw_rad=0.01, yaw_variance_rad2=1e-4,
                                                stamp_ns=strides[0].stamp_ns))
    assert "beyond the correction window of 10 s of IMU data" in old.message
    later = navigator.apply_correction(Correction(yaw_rad=0.01, yaw_variance_rad2=1e-4,
                                                  stamp_ns=int(imu.stamp_ns[-1]) + 10**9))
    assert "after the last sample filtered" in later.message
    assert navigator.corrections == {"accepted": 0, "refused": 3}


def pushed_rest(navigator: StreamingNavigator, imu, rest: slice) -> list:
    part = np.arange(len(imu))[rest]
    return [navigator.push_many(imu.stamp_ns[part], imu["linear_acceleration"][part],
                                imu["angular_velocity"][part]), navigator.flush()]


def test_the_segmented_smoother_refuses_corrections(imu):
    navigator = StreamingNavigator(run_config({"smoother": {"mode": "segmented"}}))
    pushed(navigator, imu, 3000)
    result = navigator.apply_correction(Correction(yaw_rad=0.01, yaw_variance_rad2=1e-4))
    assert not result.accepted and "segmented smoother" in result.message
    assert navigator.corrections == {"accepted": 0, "refused": 1}
