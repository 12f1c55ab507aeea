"""A navigator's pose for a fusion node and a viewer (REP-105; issue 42): the fields of
``nav_msgs/Odometry`` and of the ``/tf`` and ``/tf_static`` transforms, as batches the
vectorised codec encodes (pdr_core.io.cdr), written to bags and published alike.

- :func:`odometry_fields`: the pose with its covariance in ``map``, the twist in the
  child frame (REP-105: ``twist`` is expressed in ``child_frame_id``) with its
  covariance, unknown parts marked by :data:`UNKNOWN_VARIANCE`;
- :func:`transform_batch`: ``parent → child`` per pose (``/tf``);
- :func:`tf_batches`: a bag's ``/tf`` and ``/tf_static``; :func:`truth_tf`: a recording's,
  from its true poses;
- :func:`static_batch`: the identity ``base_frame → sensor_frame`` (``/tf_static``): the
  navigators' body is the IMU's, so the messages stamped in the sensor frame (the
  attitude, the gyro bias, ``imu/data``) are placed with no setting changed.

Pose covariance: row-major 6×6 over (x, y, z, rotation about x, y, z of the parent frame)
[m², rad²], as geometry_msgs/PoseWithCovariance; twist covariance over (vx, vy, vz, ωx, ωy,
ωz) of the child frame [m²/s², rad²/s²].
"""
from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pdr_core import topics
from pdr_core.frames import BASE_FRAME, SENSOR_FRAME, TRUTH_FRAME
from pdr_core.io.batch import LazyBatch, MessageBatch
from pdr_core.io.msgtypes import TF_MESSAGE

# the variance of a part of a covariance the navigator does not estimate (the rates, a
# velocity it has no state for): large, so a fusion node gives it no weight, and not −1,
# which REP-145 reserves for a message without the part
UNKNOWN_VARIANCE = 1e6
LINEAR, ANGULAR = slice(0, 3), slice(3, 6)
IDENTITY_XYZW = np.array([0.0, 0.0, 0.0, 1.0])


def odometry_fields(child_frame: str, position: np.ndarray, quaternion_xyzw: np.ndarray,
                    pose_covariance: np.ndarray, velocity_child: np.ndarray | None = None,
                    velocity_covariance: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The fields of N nav_msgs/Odometry (pdr_core.io.cdr names): the position [m] (N, 3) and
    orientation (N, 4, x y z w) in the parent frame, the pose covariance (N, 6, 6), and
    the velocity [m/s] (N, 3) in ``child_frame`` with its covariance (N, 3, 3), or none
    (zero, every twist variance :data:`UNKNOWN_VARIANCE`). The angular rate is not given
    (zero, its variance unknown)."""
    n = len(position)
    twist_cov = np.zeros((n, 6, 6))
    twist_cov[:, ANGULAR, ANGULAR] = np.eye(3) * UNKNOWN_VARIANCE
    if velocity_child is None:
        velocity_child = np.zeros((n, 3))
        twist_cov[:, LINEAR, LINEAR] = np.eye(3) * UNKNOWN_VARIANCE
    else:
        twist_cov[:, LINEAR, LINEAR] = velocity_covariance
    return {"child_frame_id": np.full(n, child_frame),
            "pose.pose.position": position, "pose.pose.orientation": quaternion_xyzw,
            "pose.covariance": np.reshape(pose_covariance, (n, 36)),
            "twist.twist.linear": velocity_child, "twist.twist.angular": np.zeros((n, 3)),
            "twist.covariance": twist_cov.reshape(n, 36)}


def transform_fields(child_frame: str, position: np.ndarray, quaternion_xyzw: np.ndarray
                     ) -> dict[str, np.ndarray]:
    """The fields of N tf2_msgs/TFMessage of one transform each: ``child_frame``'s pose
    in the batch's frame, position [m] (N, 3) and orientation (N, 4, x y z w)."""
    return {"transforms.child_frame_id": np.full(len(position), child_frame),
            "transforms.transform.translation": position,
            "transforms.transform.rotation": quaternion_xyzw}


def transform_batch(stamp_ns: np.ndarray, parent: str, child: str, position: np.ndarray,
                    quaternion_xyzw: np.ndarray) -> MessageBatch:
    """``parent → child`` at each stamp [ns], for ``/tf``."""
    return MessageBatch(TF_MESSAGE, stamp_ns, parent,
                        transform_fields(child, position, quaternion_xyzw))


def static_batch(stamp_ns: int, base_frame: str, sensor_frame: str) -> MessageBatch:
    """The identity ``base_frame → sensor_frame`` stamped ``stamp_ns`` [ns], for
    ``/tf_static``."""
    return transform_batch(np.array([stamp_ns], np.int64), base_frame, sensor_frame,
                           np.zeros((1, 3)), IDENTITY_XYZW[None])


def tf_batches(stamp_ns: np.ndarray, map_frame: str, base_frame: str, sensor_frame: str,
               poses: Callable[[slice], tuple[np.ndarray, np.ndarray]],
               child_frame: str | None = None) -> dict[str, LazyBatch | MessageBatch]:
    """A bag's ``/tf``, ``map_frame → child_frame`` (default ``base_frame``) at each stamp
    [ns] with the position [m] and quaternion (x, y, z, w) ``poses`` gives for a slice of
    them (built block by block as written), and its ``/tf_static``, ``base_frame →
    sensor_frame`` (:func:`static_batch`, at the first stamp)."""
    child = base_frame if child_frame is None else child_frame
    return {topics.TF: LazyBatch(TF_MESSAGE, stamp_ns, map_frame,
                                 lambda index: transform_fields(child, *poses(index))),
            topics.TF_STATIC: static_batch(int(stamp_ns[0]), base_frame, sensor_frame)}


def truth_tf(pose: MessageBatch) -> dict[str, LazyBatch | MessageBatch]:
    """A recording's ``/tf`` and ``/tf_static`` from its true poses (geometry_msgs/
    PoseStamped of the IMU in the map frame): ``map → ground_truth`` at each
    (pdr_core.frames.TRUTH_FRAME, apart from the estimates' ``base_link``, so a recording
    and a navigator's bag open together), and ``base_link → imu_link``, the frame of
    ``imu/data``, as the navigators' bags give it."""
    return tf_batches(pose.stamp_ns, str(pose.frame_id[0]), BASE_FRAME, SENSOR_FRAME,
                      lambda index: (pose["pose.position"][index],
                                     pose["pose.orientation"][index]), TRUTH_FRAME)
