"""The foot navigator on a whole recording: input checks, alignment, filter, outputs.

:func:`navigate` takes an ``imu/data`` batch and returns a :class:`FootRun`; the message
batches of the outputs (``pdr/foot/pose``, ``velocity``, ``odometry``, ``stance``) come
from :func:`output_batches`, the path's from :func:`step_path`, ``/tf`` and ``/tf_static``
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
from pdr_core.batch import LazyBatch, MessageBatch
from pdr_core.errors import InputError
from pdr_core.frames import BASE_FRAME, MAP_FRAME, SENSOR_FRAME
from pdr_core.imu_checks import check_units, clean_samples
from pdr_core.msgtypes import (
    ODOMETRY,
    POSE_WITH_COVARIANCE_STAMPED,
    TWIST_WITH_COVARIANCE_STAMPED,
)
from pdr_core.nav_path import encode_path
from pdr_core.odometry import (
    ANGULAR,
    LINEAR,
    UNKNOWN_VARIANCE,
    odometry_fields,
)
from pdr_core.odometry import tf_batches as pose_tf
from pdr_core.rotations import quaternion_from_orthonormal
from pdr_ins_ekf.config import RunConfig
from pdr_ins_ekf.kernel_data import ATTITUDE, AXES
from pdr_ins_ekf.zero_velocity import sample_rate_hz
from pdr_ins_ekf.zupt_ekf import FilterOutput, SmoothedOutput, run, smooth

STANCE = "pdr_msgs/msg/Stance"
IMU_GRAPH = topics.graph_name(topics.IMU_DATA)     # the input errors name


@dataclass
class FootRun:
    """Result of :func:`navigate` over the kept samples (stamps ``stamp_ns``)."""

    stamp_ns: np.ndarray
    stance: np.ndarray
    statistic: np.ndarray
    detector: int
    output: FilterOutput
    counts: dict[str, int] = field(default_factory=dict)
    smoothed: SmoothedOutput | None = None


def alignment_window(stance: np.ndarray, t_s: np.ndarray, min_s: float) -> slice:
    """The first stationary run lasting at least ``min_s`` seconds."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], stance.astype(int), [0]))))
    for start, stop in zip(edges[::2], edges[1::2], strict=True):
        if t_s[stop - 1] - t_s[start] >= min_s:
            return slice(int(start), int(stop))
    raise InputError(IMU_GRAPH, f"no stationary period of {min_s:g} s to align on")


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
    check_units(accel, gyro)
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
    return FootRun(stamp_ns[start:], result.mask[start:], result.statistic[start:],
                   result.detector, output, counts, smoothed)


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
    its velocity in ``base_frame``) and ``stance`` with covariances, built block by block
    as they are written."""
    out, n = run_.output, len(run_.stamp_ns)

    def pose_covariance(index: slice) -> np.ndarray:
        cov = np.zeros((len(out.position[index]), 6, 6))
        cov[:, LINEAR, LINEAR] = out.position_cov[index]
        cov[:, ANGULAR, ANGULAR] = (out.variance[index, ATTITUDE:ATTITUDE + AXES, None]
                                    * np.eye(3))
        return cov

    def pose(index: slice) -> dict[str, np.ndarray]:
        return {"pose.pose.position": out.position[index],
                "pose.pose.orientation": quaternion_from_orthonormal(out.attitude[index]),
                "pose.covariance": pose_covariance(index).reshape(-1, 36)}

    def velocity(index: slice) -> dict[str, np.ndarray]:
        cov = np.zeros((len(out.velocity[index]), 6, 6))
        cov[:, LINEAR, LINEAR] = out.velocity_cov[index]
        cov[:, ANGULAR, ANGULAR] = np.eye(3) * UNKNOWN_VARIANCE  # rate not estimated
        return {"twist.twist.linear": out.velocity[index],
                "twist.twist.angular": np.zeros((len(cov), 3)),
                "twist.covariance": cov.reshape(-1, 36)}

    def odometry(index: slice) -> dict[str, np.ndarray]:
        c = out.attitude[index]                 # C_b^n: the velocity to the body, Cᵀ·v
        return odometry_fields(
            base_frame, out.position[index], quaternion_from_orthonormal(c),
            pose_covariance(index), np.einsum("nji,nj->ni", c, out.velocity[index]),
            np.einsum("nji,njk,nkl->nil", c, out.velocity_cov[index], c))

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
    sensor_frame``, the identity, at the first (pdr_core.odometry)."""
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


def step_path(run_: FootRun, frame: str = MAP_FRAME) -> tuple[int, bytes]:
    """The ``pdr/foot/path`` (CDR) of the whole run, one pose per step (at each stance
    onset), stamped with the last sample."""
    onsets = np.flatnonzero(run_.stance[1:] & ~run_.stance[:-1]) + 1
    stamp = int(run_.stamp_ns[-1])
    return stamp, pose_path(run_.stamp_ns[onsets], run_.output.position[onsets],
                            run_.output.attitude[onsets], stamp, frame)


def pose_path(stamp_ns: np.ndarray, position: np.ndarray, attitude: np.ndarray,
              path_stamp_ns: int, frame: str) -> bytes:
    """A nav_msgs/Path (CDR) of the poses at ``stamp_ns`` (N,) [ns]: positions (N, 3) [m]
    and attitudes C_b^n (N, 3, 3), all in ``frame``, the Path stamped ``path_stamp_ns``."""
    poses = MessageBatch("geometry_msgs/msg/PoseStamped", stamp_ns, frame, {
        "pose.position": position, "pose.orientation": quaternion_from_orthonormal(attitude)})
    return encode_path(poses, path_stamp_ns, frame)
