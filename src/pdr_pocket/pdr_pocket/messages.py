"""The pocket navigator's outputs as messages, one packing for the live node
(``pocket_pdr``) and the bag ``pdr-pocket run`` writes.

- :func:`step_batches`: ``pdr/pocket/step`` (pdr_msgs/Step), ``pdr/pocket/pose``
  (geometry_msgs/PoseWithCovarianceStamped, the thigh's attitude and the position with
  its covariance) and ``pdr/pocket/odometry`` (nav_msgs/Odometry, the same pose with the
  attitude's covariance too) at each step's confirmation, stamped with the IMU sample
  that confirmed it (:func:`step_stamps`), from :func:`step_fields`, :func:`pose_fields`
  and :func:`odometry_step_fields`;
- :func:`path_batch`: the steps' poses for ``pdr/pocket/path``;
- :func:`attitude_batches`: ``pdr/pocket/attitude`` (sensor_msgs/Imu with orientation and
  its covariance, REP-145) and ``pdr/pocket/gyro_bias`` (geometry_msgs/Vector3Stamped) at
  every sample;
- :func:`stride_lines_fields`: ``pdr/pocket/stride_lines`` (pdr_msgs/StrideLines), the
  person's lines a :class:`~pdr_pocket.line_calibration.StrideCalibrator` fitted.
"""
from __future__ import annotations

import numpy as np

from pdr_core import topics
from pdr_core.frames import BASE_FRAME, MAP_FRAME, SENSOR_FRAME
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import (
    IMU,
    ODOMETRY,
    POSE_STAMPED,
    POSE_WITH_COVARIANCE_STAMPED,
    STEP,
    VECTOR3_STAMPED,
)
from pdr_core.io.odometry import ANGULAR, odometry_fields, tf_batches
from pdr_core.maths.rotations import quaternion_from_orthonormal
from pdr_pocket.compiled_orientation_data import ATT_ROWS
from pdr_pocket.inputs import PocketInputs
from pdr_pocket.line_calibration import LINES, REASONS, StrideCalibrator
from pdr_pocket.orientation import AttitudeEstimate
from pdr_pocket.records import NavigatorOutput, StepRecord


def step_stamps(steps: list[StepRecord], stamp_ns: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The IMU stamp [ns] of the sample that confirmed each step."""
    confirms = np.array([s.t_confirm for s in steps])
    return stamp_ns[np.clip(np.searchsorted(t, confirms), 0, len(t) - 1)]


def step_fields(steps: list[StepRecord]) -> dict[str, np.ndarray]:
    return {"index": np.array([s.index for s in steps], np.uint32),
            "length": np.array([s.length for s in steps]),
            "vertical_displacement": np.array([s.vertical_displacement for s in steps]),
            "heading": np.array([s.heading for s in steps]),
            "pitch_max": np.array([s.pitch_max for s in steps]),
            "pitch_min": np.array([s.pitch_min for s in steps]),
            "pitch_amplitude": np.array([s.pitch_amplitude for s in steps]),
            "duration": np.array([s.duration for s in steps]),
            "activity": np.array([s.activity for s in steps], np.uint8),
            "ride": np.array([s.ride for s in steps], np.uint8),
            "ride_height": np.array([s.ride_height for s in steps])}


def pose_fields(steps: list[StepRecord], attitude: np.ndarray) -> dict[str, np.ndarray]:
    """Position and covariance (x, y, z block; orientation variances unknown: −1 on the
    diagonal per REP-145 would be read as "no orientation", so the attitude filter's are
    not repeated here and the block is left 0) and the sensor attitude (N, 3, 3)."""
    cov = np.zeros((len(steps), 6, 6))
    cov[:, :3, :3] = np.reshape([s.covariance for s in steps], (-1, 3, 3))
    return {"pose.pose.position": np.array([s.position for s in steps]).reshape(-1, 3),
            "pose.pose.orientation": quaternion_from_orthonormal(attitude),
            "pose.covariance": cov.reshape(-1, 36)}


def odometry_step_fields(steps: list[StepRecord], attitude: np.ndarray,
                         attitude_covariance: np.ndarray, base_frame: str = BASE_FRAME
                         ) -> dict[str, np.ndarray]:
    """nav_msgs/Odometry of ``base_frame`` at each step: the pose of :func:`pose_fields`
    with the position covariance for a fusion node (StepRecord.odometry_covariance, where
    a step has it; pdr_pocket.position), the orientation filter's attitude covariance
    (N, 3, 3) [rad²] in its rotation block, and the twist: the step's mean velocity
    (StepRecord.velocity, the stride over the cycle's duration along its heading) and its
    covariance, turned from the map frame into ``base_frame`` (REP-105: the twist is the
    child frame's), whose orientation is the sensor attitude C (N, 3, 3) of the pose:
    v_b = Cᵀ·v_n, Σ_b = Cᵀ·Σ_n·C. The angular rate is not given
    (pdr_core.io.odometry.UNKNOWN_VARIANCE), nor a velocity a step does not know (a run read
    back from its bag)."""
    pose = pose_fields(steps, attitude)
    cov = pose["pose.covariance"].reshape(-1, 6, 6)
    cov[:, :3, :3] = np.reshape([s.covariance if s.odometry_covariance is None
                                 else s.odometry_covariance for s in steps], (-1, 3, 3))
    cov[:, ANGULAR, ANGULAR] = attitude_covariance
    velocity = velocity_covariance = None
    if steps and all(s.velocity is not None for s in steps):
        turn = np.transpose(attitude, (0, 2, 1))
        velocity = np.einsum("nij,nj->ni", turn, [s.velocity for s in steps])
        velocity_covariance = turn @ np.array([s.velocity_covariance for s in steps]) @ attitude
    return odometry_fields(base_frame, pose["pose.pose.position"],
                           pose["pose.pose.orientation"], cov, velocity, velocity_covariance)


def _step_samples(out: NavigatorOutput, stamp_ns: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The stamps [ns] and sample indices of the steps' confirmations."""
    t = out.attitude.t
    at = np.clip(np.searchsorted(t, [s.t_confirm for s in out.steps]), 0, len(t) - 1)
    return step_stamps(out.steps, stamp_ns, t), at


def step_batches(out: NavigatorOutput, stamp_ns: np.ndarray, base_frame: str = BASE_FRAME
                 ) -> dict[str, MessageBatch]:
    steps = out.steps
    stamps, at = _step_samples(out, stamp_ns)
    attitude = out.attitude.attitude[at]
    return {topics.POCKET_STEP: MessageBatch(STEP, stamps, MAP_FRAME, step_fields(steps)),
            topics.POCKET_POSE: MessageBatch(POSE_WITH_COVARIANCE_STAMPED, stamps, MAP_FRAME,
                                             pose_fields(steps, attitude)),
            topics.POCKET_ODOMETRY: MessageBatch(ODOMETRY, stamps, MAP_FRAME, odometry_step_fields(
                steps, attitude, out.attitude.covariance[at][:, ATT_ROWS, ATT_ROWS], base_frame))}


def path_batch(steps: list[StepRecord], stamps: np.ndarray) -> MessageBatch:
    """The steps' poses as a PoseStamped batch for ``pdr/pocket/path``."""
    quat = np.zeros((len(steps), 4))
    quat[:, 2], quat[:, 3] = np.sin([s.heading / 2 for s in steps]), \
        np.cos([s.heading / 2 for s in steps])
    return MessageBatch(POSE_STAMPED, stamps, MAP_FRAME, {
        "pose.position": np.array([s.position for s in steps]).reshape(-1, 3),
        "pose.orientation": quat})


def step_tf(out: NavigatorOutput, stamp_ns: np.ndarray) -> dict[str, MessageBatch]:
    """A bag's ``/tf`` (``map → base_link`` at each step, the pose of ``pdr/pocket/pose``)
    and ``/tf_static`` (``base_link → imu_link``; pdr_core.io.odometry.tf_batches); none
    without a step."""
    if not out.steps:
        return {}
    stamps, at = _step_samples(out, stamp_ns)
    position = np.array([s.position for s in out.steps]).reshape(-1, 3)
    quaternion = quaternion_from_orthonormal(out.attitude.attitude[at])
    return tf_batches(stamps, MAP_FRAME, BASE_FRAME, SENSOR_FRAME,
                      lambda index: (position[index], quaternion[index]))


def step_positions(steps: list[StepRecord]) -> np.ndarray:
    """The origin and each step's position (N + 1, 3) [m], map frame."""
    return np.vstack([np.zeros(3), *(s.position for s in steps)])


def attitude_batches(inputs: PocketInputs, estimate: AttitudeEstimate,
                     gyro_noise_var: float, frame: str = SENSOR_FRAME
                     ) -> dict[str, MessageBatch]:
    """``pdr/pocket/attitude`` and ``pdr/pocket/gyro_bias`` at every sample, stamped in the
    sensor's ``frame``."""
    n = len(inputs.t)
    cov = estimate.covariance
    rate_cov = cov[:, 3:, 3:] + np.eye(3) * gyro_noise_var
    attitude = MessageBatch(IMU, inputs.stamp_ns, frame, {
        "orientation": quaternion_from_orthonormal(estimate.attitude),
        "orientation_covariance": cov[:, :3, :3].reshape(n, 9),
        "angular_velocity": inputs.gyro - estimate.bias,
        "angular_velocity_covariance": rate_cov.reshape(n, 9),
        "linear_acceleration": inputs.accel,
        "linear_acceleration_covariance": inputs.accel_covariance})
    bias = MessageBatch(VECTOR3_STAMPED, inputs.stamp_ns, frame,
                        {"vector": estimate.bias})
    return {topics.POCKET_ATTITUDE: attitude, topics.POCKET_GYRO_BIAS: bias}


def stride_lines_fields(calibrator: StrideCalibrator) -> dict[str, object]:
    """The fields of one pdr_msgs/StrideLines but its header: per line of
    :data:`~pdr_pocket.line_calibration.LINES` (``level_``, ``up_``, ``down_``) the slope,
    offset, covariance of [slope, offset] (4 values, row-major; the prior's before any pair),
    pairs and residual σ (NaN before any pair), in the lines' units (level m/deg and m,
    stairs cm/deg and cm); the refusals by reason (every one of
    :data:`~pdr_pocket.line_calibration.REASONS`, in that order) and λ."""
    fields: dict[str, object] = {}
    for name in LINES:
        fit = calibrator.fits[name]
        fields.update({f"{name}_slope": fit.slope, f"{name}_offset": fit.offset,
                       f"{name}_covariance": [float(v) for v in fit.covariance.ravel()],
                       f"{name}_pairs": fit.pairs,
                       f"{name}_residual_sigma": fit.residual_sigma})
    fields["refused_reasons"] = list(REASONS)
    fields["refused_counts"] = [calibrator.refused[reason] for reason in REASONS]
    fields["forgetting"] = calibrator.settings.forgetting
    return fields
