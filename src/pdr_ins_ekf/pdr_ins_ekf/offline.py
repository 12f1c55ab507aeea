"""The foot navigator on a whole recording: input checks, alignment, filter, outputs.

:func:`navigate` takes an ``imu/data`` batch and returns a :class:`FootRun`; the message
batches of the outputs (``pdr/foot/pose``, ``velocity``, ``odometry``, ``stance``) come
from :func:`output_batches`, the strides' (``pdr/foot/step``, ``pdr/foot/step_pose``) from
:func:`stride_batches`, the path's from :func:`step_path`, ``/tf`` and ``/tf_static``
from :func:`tf_batches`. Bad input never stops the run silently:

- samples with NaN/Inf are dropped and counted; so are stamps that do not increase;
- gaps longer than ``max_gap_s`` are propagated (the covariance grows with the gap) and
  counted;
- data in the wrong units is refused at alignment: a specific force at rest near 1
  (g instead of m/s²) or far from 9.81, or a gyroscope at rest above 0.2 rad/s (deg/s
  instead of rad/s, or a broken sensor).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.frames import BASE_FRAME, MAP_FRAME, SENSOR_FRAME
from pdr_core.io.batch import LazyBatch, MessageBatch
from pdr_core.io.msgtypes import (
    ODOMETRY,
    POSE_WITH_COVARIANCE_STAMPED,
    STEP,
    TWIST_WITH_COVARIANCE_STAMPED,
)
from pdr_core.io.nav_path import encode_path
from pdr_core.io.odometry import (
    ANGULAR,
    LINEAR,
    UNKNOWN_VARIANCE,
    odometry_fields,
)
from pdr_core.io.odometry import tf_batches as pose_tf
from pdr_core.maths.rotations import quaternion_from_orthonormal
from pdr_core.sensors.imu_checks import check_units, clean_samples
from pdr_ins_ekf.config import RunConfig
from pdr_ins_ekf.kernel_data import ATTITUDE, AXES
from pdr_ins_ekf.strides import Stride, StrideTracker
from pdr_ins_ekf.zero_velocity import sample_rate_hz
from pdr_ins_ekf.zupt_ekf import FilterOutput, SmoothedOutput, run, smooth

STANCE = "pdr_msgs/msg/Stance"
IMU_GRAPH = topics.graph_name(topics.IMU_DATA)     # the input errors name


@dataclass
class FootRun:
    """Result of :func:`navigate` over the kept samples (stamps ``stamp_ns``), with the
    strides (pdr_ins_ekf.strides)."""

    stamp_ns: np.ndarray
    stance: np.ndarray
    statistic: np.ndarray
    detector: int
    output: FilterOutput
    counts: dict[str, int] = field(default_factory=dict)
    smoothed: SmoothedOutput | None = None
    strides: list[Stride] = field(default_factory=list)


def alignment_window(stance: np.ndarray, t_s: np.ndarray, min_s: float) -> slice:
    """The first stationary run lasting at least ``min_s`` seconds."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], stance.astype(int), [0]))))
    for start, stop in zip(edges[::2], edges[1::2], strict=True):
        if t_s[stop - 1] - t_s[start] >= min_s:
            return slice(int(start), int(stop))
    raise InputError(IMU_GRAPH, f"no stationary period of {min_s:g} s to align on (a "
                                "foot-mounted IMU stands still at each stance; a phone in a "
                                "pocket is for `pdr-pocket run` or `pdr-eval --navigator "
                                "pocket`)")


def check_rest(accel: np.ndarray, gyro: np.ndarray) -> None:
    """Refuse an alignment window that is not at rest under 1 g."""
    f = float(np.linalg.norm(accel.mean(axis=0)))
    if not 8.8 < f < 10.8:
        raise InputError(IMU_GRAPH, f"specific force at rest is {f:.3f} m/s², expected 9.81")
    w = float(np.linalg.norm(gyro.mean(axis=0)))
    if w > 0.2:
        raise InputError(IMU_GRAPH, f"angular rate at rest is {w:.3f} rad/s: not at rest")


def navigate(imu: MessageBatch, config: RunConfig) -> FootRun:
    """Detect stance, align on the first stationary period and filter from there on."""
    keep, counts = clean_samples(imu)
    stamp_ns = imu.stamp_ns[keep]
    t = (stamp_ns - stamp_ns[0]) * 1e-9
    accel, gyro = imu["linear_acceleration"][keep], imu["angular_velocity"][keep]
    if len(t) < 10 or t[-1] <= 0:
        raise InputError(IMU_GRAPH, f"{len(t)} usable samples are too few")
    check_units(accel, gyro, t_s=t)
    result = config.detector.detect(accel, gyro, sample_rate_hz(stamp_ns))
    window = alignment_window(result.mask, t, config.alignment_min_s)
    check_rest(accel[window], gyro[window])
    start = window.start
    counts["before_alignment"] = start
    counts["gaps"] = int((np.diff(t) > config.max_gap_s).sum())
    aligned = slice(0, window.stop - start)
    args = (t[start:], accel[start:], gyro[start:], result.mask[start:], config.filter)
    yaw = np.radians(config.initial_yaw_deg)
    output = run(*args, aligned, yaw)
    smoothed = (None if config.smoother.mode == "none"
                else smooth(*args, config.smoother, aligned, yaw))
    strides = StrideTracker().push(stamp_ns[start:], result.mask[start:], output)
    return FootRun(stamp_ns[start:], result.mask[start:], result.statistic[start:],
                   result.detector, output, counts, smoothed, strides)


def stance_scores(run_: FootRun, truth: MessageBatch) -> dict[str, float | int | None]:
    """The detected stance against a stance truth (``ground_truth/stance``,
    pdr_msgs/Stance, e.g. the simulator's: true where the sensor's true velocity is
    zero), sample by sample over the navigated samples that have a truth at their stamp.

    ``precision``: share of the detected stance that is truly stationary (a ZUPT on a
    moving foot is the error that bends a path); ``recall``: share of the true stance
    detected; each None when its denominator is 0. ``true_fraction`` and
    ``detected_fraction``: shares of the compared samples; ``samples``: how many."""
    k = np.clip(np.searchsorted(truth.stamp_ns, run_.stamp_ns), 0, len(truth) - 1)
    matched = truth.stamp_ns[k] == run_.stamp_ns
    true = truth["stationary"][k[matched]].astype(bool)
    detected = run_.stance[matched].astype(bool)
    both = int(np.sum(true & detected))
    n = int(matched.sum())
    return {"samples": n,
            "precision": both / int(detected.sum()) if detected.any() else None,
            "recall": both / int(true.sum()) if true.any() else None,
            "true_fraction": float(true.mean()) if n else None,
            "detected_fraction": float(detected.mean()) if n else None}


def output_batches(run_: FootRun, frame: str = MAP_FRAME, base_frame: str = BASE_FRAME
                   ) -> dict[str, LazyBatch]:
    """``pdr/foot/pose``, ``velocity``, ``odometry`` (``base_frame``'s pose in ``frame``,
    its velocity in ``base_frame``) and ``stance`` with covariances (the filter's times
    its white noises' part times ``covariance_scale``, FilterOutput.published), built
    block by block as they are written."""
    out, n = run_.output, len(run_.stamp_ns)

    def pose_covariance(index: slice) -> np.ndarray:
        cov = np.zeros((len(out.position[index]), 6, 6))
        cov[:, LINEAR, LINEAR] = out.published(out.position_cov, out.bias_position_cov, index)
        attitude = out.published(out.variance, out.bias_variance, index)
        cov[:, ANGULAR, ANGULAR] = attitude[:, ATTITUDE:ATTITUDE + AXES, None] * np.eye(3)
        return cov

    def velocity_cov(index: slice) -> np.ndarray:
        return out.published(out.velocity_cov, out.bias_velocity_cov, index)

    def pose(index: slice) -> dict[str, np.ndarray]:
        return {"pose.pose.position": out.position[index],
                "pose.pose.orientation": quaternion_from_orthonormal(out.attitude[index]),
                "pose.covariance": pose_covariance(index).reshape(-1, 36)}

    def velocity(index: slice) -> dict[str, np.ndarray]:
        cov = np.zeros((len(out.velocity[index]), 6, 6))
        cov[:, LINEAR, LINEAR] = velocity_cov(index)
        cov[:, ANGULAR, ANGULAR] = np.eye(3) * UNKNOWN_VARIANCE  # rate not estimated
        return {"twist.twist.linear": out.velocity[index],
                "twist.twist.angular": np.zeros((len(cov), 3)),
                "twist.covariance": cov.reshape(-1, 36)}

    def odometry(index: slice) -> dict[str, np.ndarray]:
        c = out.attitude[index]                 # C_b^n: the velocity to the body, Cᵀ·v
        return odometry_fields(
            base_frame, out.position[index], quaternion_from_orthonormal(c),
            pose_covariance(index), np.einsum("nji,nj->ni", c, out.velocity[index]),
            np.einsum("nji,njk,nkl->nil", c, velocity_cov(index), c))

    detector = np.full(n, run_.detector, np.uint8)
    return {
        topics.FOOT_POSE: LazyBatch(POSE_WITH_COVARIANCE_STAMPED, run_.stamp_ns, frame, pose),
        topics.FOOT_VELOCITY: LazyBatch(TWIST_WITH_COVARIANCE_STAMPED, run_.stamp_ns, frame,
                                        velocity),
        topics.FOOT_ODOMETRY: LazyBatch(ODOMETRY, run_.stamp_ns, frame, odometry),
        topics.FOOT_STANCE: LazyBatch(STANCE, run_.stamp_ns, SENSOR_FRAME, lambda index: {
            "stationary": run_.stance[index], "statistic": run_.statistic[index],
            "detector": detector[index]}),
    }


def tf_batches(run_: FootRun, frame: str = MAP_FRAME, base_frame: str = BASE_FRAME,
               sensor_frame: str = SENSOR_FRAME) -> dict[str, LazyBatch | MessageBatch]:
    """``/tf``: ``frame → base_frame`` at every sample; ``/tf_static``: ``base_frame →
    sensor_frame``, the identity, at the first (pdr_core.io.odometry)."""
    out = run_.output
    return pose_tf(run_.stamp_ns, frame, base_frame, sensor_frame, lambda index: (
        out.position[index], quaternion_from_orthonormal(out.attitude[index])))


def smoothed_paths(run_: FootRun, frame: str = MAP_FRAME) -> list[tuple[int, bytes]]:
    """``pdr/foot/smoothed_path``: one Path (CDR) per smoother segment with every
    sample's smoothed pose, stamped (and logged) at the segment's last sample."""
    out = run_.smoothed
    paths, first = [], 0
    for end in out.segment_ends.tolist():
        part = slice(first, end + 1)
        stamp = int(run_.stamp_ns[end])
        paths.append((stamp, pose_path(run_.stamp_ns[part], out.position[part],
                                       out.attitude[part], stamp, frame)))
        first = end + 1
    return paths


def stride_batches(strides: list[Stride], frame: str = MAP_FRAME) -> dict[str, MessageBatch]:
    """``pdr/foot/step`` (pdr_msgs/Step) and ``pdr/foot/step_pose``
    (PoseWithCovarianceStamped: the position and attitude with their covariances) at each
    stride, stamped with its footfall (pdr_ins_ekf.strides)."""
    stamps = np.array([s.stamp_ns for s in strides], np.int64)
    pitch_max = np.array([s.pitch_max_rad for s in strides])
    pitch_min = np.array([s.pitch_min_rad for s in strides])
    cov = np.zeros((len(strides), 6, 6))
    cov[:, LINEAR, LINEAR] = np.reshape([s.covariance_m2 for s in strides], (-1, 3, 3))
    cov[:, ANGULAR, ANGULAR] = (np.reshape([s.attitude_variance_rad2 for s in strides],
                                           (-1, 3))[:, :, None] * np.eye(3))
    return {
        topics.FOOT_STEP: MessageBatch(STEP, stamps, frame, {
            "index": np.array([s.index for s in strides], np.uint32),
            "length": np.array([s.length_m for s in strides]),
            "vertical_displacement": np.array([s.vertical_m for s in strides]),
            "heading": np.array([s.heading_rad for s in strides]),
            "pitch_max": pitch_max, "pitch_min": pitch_min,
            "pitch_amplitude": pitch_max - pitch_min,
            "duration": np.array([s.duration_s for s in strides]),
            "activity": np.array([s.activity for s in strides], np.uint8),
            "ride": np.zeros(len(strides), np.uint8), "ride_height": np.zeros(len(strides))}),
        topics.FOOT_STEP_POSE: MessageBatch(POSE_WITH_COVARIANCE_STAMPED, stamps, frame, {
            "pose.pose.position": np.reshape([s.position_m for s in strides], (-1, 3)),
            "pose.pose.orientation": quaternion_from_orthonormal(
                np.reshape([s.attitude for s in strides], (-1, 3, 3))),
            "pose.covariance": cov.reshape(-1, 36)})}


def step_path(strides: list[Stride], stamp_ns: int, frame: str = MAP_FRAME) -> bytes:
    """The ``pdr/foot/path`` (CDR): the pose at each stride, stamped ``stamp_ns``."""
    return pose_path(np.array([s.stamp_ns for s in strides], np.int64),
                     np.reshape([s.position_m for s in strides], (-1, 3)),
                     np.reshape([s.attitude for s in strides], (-1, 3, 3)), stamp_ns, frame)


def pose_path(stamp_ns: np.ndarray, position: np.ndarray, attitude: np.ndarray,
              path_stamp_ns: int, frame: str) -> bytes:
    """A nav_msgs/Path (CDR) of the poses at ``stamp_ns`` (N,) [ns]: positions (N, 3) [m]
    and attitudes C_b^n (N, 3, 3), all in ``frame``, the Path stamped ``path_stamp_ns``."""
    poses = MessageBatch("geometry_msgs/msg/PoseStamped", stamp_ns, frame, {
        "pose.position": position, "pose.orientation": quaternion_from_orthonormal(attitude)})
    return encode_path(poses, path_stamp_ns, frame)
