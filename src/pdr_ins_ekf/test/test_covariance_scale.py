"""The published covariance scaled by the touchdown innovations (``covariance_scale:
innovations``, pdr_ins_ekf.compiled_filter.covariance_scale; docs/foot_ins.md, "Covariance
honesty"): the estimates and the filter's own covariance are the configured filter's, the
published covariances (pose, odometry, velocity) λ times it, λ the mean νᵀ·P_v⁻¹·ν / 3 of
the ZUPTs at touchdown so far."""
from dataclasses import replace

import numpy as np
import pytest

from pdr_core import topics
from pdr_ins_ekf.kernel_data import ATTITUDE, VELOCITY
from pdr_ins_ekf.offline import FootRun, output_batches
from pdr_ins_ekf.strides import StrideTracker
from pdr_ins_ekf.zero_velocity import ConditionVoteDetector
from pdr_ins_ekf.zupt_ekf import FilterConfig, ZuptEkf, run
from pdr_sim.scenario import scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

WALK = {"segments": [{"type": "standing", "duration_s": 2.0}, {"type": "straight", "steps": 12},
                     {"type": "standing", "duration_s": 1.0}]}
CONFIG = FilterConfig(acc_noise_mps2_per_sqrt_hz=0.02, gyro_noise_radps_per_sqrt_hz=0.002)


@pytest.fixture(scope="module")
def walk():
    sim = simulate(SimulationConfig(scenario_from_dict(WALK, "walk"), WALK, "xsens_mtw", {},
                                    100.0, 1))
    accel, gyro = sim.imu["linear_acceleration"], sim.imu["angular_velocity"]
    stance = ConditionVoteDetector(variant="retarded").detect(accel, gyro, 100.0).mask
    return sim.imu.t_s - sim.imu.t_s[0], accel, gyro, stance


def touchdown_scale(walk) -> np.ndarray:
    """λ after each sample, from the configured filter stepped in Python: the mean of
    νᵀ·P_v⁻¹·ν / 3 (ν = −v̂ before the ZUPT) over the first sample of each stance after
    the one the filter is aligned on; 1 before the first."""
    t, accel, gyro, stance = walk
    ekf = ZuptEkf.aligned(CONFIG, accel[:100], gyro[:100])
    nis, scale, was_stance = [], np.ones(len(t)), True
    for k in range(len(t)):
        ekf.predict(accel[k], gyro[k], t[k] - t[k - 1] if k else 0.0)
        if stance[k]:
            if not was_stance:
                v, P_v = ekf.v, ekf.P[VELOCITY:VELOCITY + 3, VELOCITY:VELOCITY + 3]
                nis.append(v @ np.linalg.solve(P_v, v) / 3)
            ekf.zupt()
        was_stance = bool(stance[k])
        scale[k] = np.mean(nis) if nis else 1.0
    return scale


def test_estimates_are_the_configured_filters_and_the_covariance_is_scaled(walk):
    t, accel, gyro, stance = walk
    configured = run(t, accel, gyro, stance, CONFIG, slice(0, 100))
    scaled = run(t, accel, gyro, stance, replace(CONFIG, covariance_scale="innovations"),
                 slice(0, 100))
    for name in ("position", "velocity", "attitude", "bias", "variance", "position_cov",
                 "velocity_cov"):
        np.testing.assert_array_equal(getattr(scaled, name), getattr(configured, name))
    np.testing.assert_array_equal(configured.covariance_scale, 1.0)
    scale = touchdown_scale(walk)
    assert len(np.unique(scale)) > 10, "every touchdown moves λ"
    # the xsens_mtw errors are 10× below the configured noise and the simulated stance is
    # still: the swings' velocity errors are far smaller than predicted
    assert scale[-1] < 0.2
    np.testing.assert_allclose(scaled.covariance_scale, scale, rtol=1e-9, atol=0)


def test_the_pose_odometry_and_velocity_are_published_scaled_the_strides_are_not(walk):
    t, accel, gyro, stance = walk
    config = replace(CONFIG, covariance_scale="innovations")
    out = run(t, accel, gyro, stance, config, slice(0, 100))
    stamps = np.round(t * 1e9).astype(np.int64)
    foot = FootRun(stamps, stance, np.zeros(len(t)), 0, out)
    batches = output_batches(foot)
    every, scale = np.arange(len(t)), out.covariance_scale
    pose = batches[topics.FOOT_POSE].take(every)["pose.covariance"].reshape(-1, 6, 6)
    np.testing.assert_allclose(pose[:, :3, :3], scale[:, None, None] * out.position_cov,
                               rtol=1e-12, atol=0)
    np.testing.assert_allclose(np.diagonal(pose[:, 3:, 3:], axis1=1, axis2=2),
                               scale[:, None] * out.variance[:, ATTITUDE:ATTITUDE + 3],
                               rtol=1e-12, atol=0)
    odometry = batches[topics.FOOT_ODOMETRY].take(every)["pose.covariance"]
    np.testing.assert_array_equal(odometry.reshape(-1, 6, 6), pose)
    twist = batches[topics.FOOT_VELOCITY].take(every)["twist.covariance"].reshape(-1, 6, 6)
    np.testing.assert_allclose(twist[:, :3, :3], scale[:, None, None] * out.velocity_cov,
                               rtol=1e-12, atol=0)
    strides = StrideTracker().push(stamps, stance, out)
    assert strides
    for stride in strides:
        k = int(np.searchsorted(stamps, stride.stamp_ns))
        np.testing.assert_array_equal(np.reshape(stride.covariance_m2, (3, 3)),
                                      out.position_cov[k])


def test_with_bias_states_the_biases_share_is_published_as_it_is(walk):
    """15 states: the estimates and P are the configured filter's; the biases' share Pb
    (compiled_filter.bias_share) lies within P, the vertical position's grows over the
    walk (what piles up over the strides with one sign), and the published covariance is
    λ·(P − Pb) + Pb."""
    t, accel, gyro, stance = walk
    biased = replace(CONFIG, bias_model="random_walk", init_acc_bias_sigma_mps2=0.002,
                     acc_bias_noise_mps2_per_sqrt_s=1e-5)
    configured = run(t, accel, gyro, stance, biased, slice(0, 100))
    out = run(t, accel, gyro, stance, replace(biased, covariance_scale="innovations"),
              slice(0, 100))
    for name in ("position", "velocity", "attitude", "bias", "variance", "position_cov",
                 "velocity_cov", "bias_variance", "bias_position_cov"):
        np.testing.assert_array_equal(getattr(out, name), getattr(configured, name))
    assert np.all(out.bias_variance >= 0)
    assert np.all(out.bias_variance <= out.variance * (1 + 1e-9))
    vertical = out.bias_position_cov[:, 2, 2]
    assert vertical[-1] > vertical[len(t) // 2] > vertical[len(t) // 4] > 0
    stamps = np.round(t * 1e9).astype(np.int64)
    batches = output_batches(FootRun(stamps, stance, np.zeros(len(t)), 0, out))
    pose = batches[topics.FOOT_POSE].take(np.arange(len(t)))["pose.covariance"]
    scale = out.covariance_scale[:, None, None]
    np.testing.assert_allclose(
        pose.reshape(-1, 6, 6)[:, :3, :3],
        scale * (out.position_cov - out.bias_position_cov) + out.bias_position_cov,
        rtol=1e-12, atol=0)


def test_the_scale_carries_over_blocks(walk):
    """The live node's blocks give the offline run's covariances (λ and the last sample's
    stance carried in the state)."""
    t, accel, gyro, stance = walk
    config = replace(CONFIG, covariance_scale="innovations")
    whole = run(t, accel, gyro, stance, config, slice(0, 100))
    ekf = ZuptEkf.aligned(config, accel[:100], gyro[:100])
    dt = np.concatenate(([0.0], np.diff(t)))
    parts = [ekf.run_block(accel[a:a + 37], gyro[a:a + 37], dt[a:a + 37], stance[a:a + 37])
             for a in range(0, len(t), 37)]
    np.testing.assert_array_equal(np.concatenate([p.covariance_scale for p in parts]),
                                  whole.covariance_scale)


def test_covariance_scale_is_checked():
    with pytest.raises(ValueError, match="covariance_scale must be one of"):
        FilterConfig(covariance_scale="inflated")
