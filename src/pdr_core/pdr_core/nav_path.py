"""nav_msgs/Path to and from a PoseStamped MessageBatch.

A Path carries a sequence of PoseStamped, so it has no fixed CDR layout; it is built and
read through ``rosbags`` message objects (one per pose). Paths are published per step
or per smoothed segment, far below the IMU rate.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from pdr_core.batch import MessageBatch
from pdr_core.msgtypes import PATH, POSE_STAMPED, typestore

_NS = 1_000_000_000


def _header(stamp_ns: int, frame_id: str) -> Any:
    types = typestore().types
    sec, nanosec = divmod(int(stamp_ns), _NS)
    return types["std_msgs/msg/Header"](
        stamp=types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec), frame_id=frame_id)


def path_message(poses: MessageBatch, stamp_ns: int, frame_id: str) -> Any:
    """A rosbags ``nav_msgs/Path`` from a PoseStamped batch (``pose.position``,
    ``pose.orientation`` as x, y, z, w), stamped ``stamp_ns`` in ``frame_id``."""
    types = typestore().types
    point, quat = types["geometry_msgs/msg/Point"], types["geometry_msgs/msg/Quaternion"]
    pose_t, stamped_t = types["geometry_msgs/msg/Pose"], types[POSE_STAMPED]
    items = [
        stamped_t(header=_header(t, f),
                  pose=pose_t(position=point(x=p[0], y=p[1], z=p[2]),
                              orientation=quat(x=q[0], y=q[1], z=q[2], w=q[3])))
        for t, f, p, q in zip(poses.stamp_ns.tolist(), poses.frame_id.tolist(),
                              poses["pose.position"].tolist(), poses["pose.orientation"].tolist(),
                              strict=True)]
    return types[PATH](header=_header(stamp_ns, frame_id), poses=items)


def path_poses(msg: Any) -> MessageBatch:
    """The poses of a rosbags ``nav_msgs/Path`` as a PoseStamped batch."""
    poses = msg.poses
    stamps = [p.header.stamp.sec * _NS + p.header.stamp.nanosec for p in poses]
    return MessageBatch(
        POSE_STAMPED, np.array(stamps, np.int64), np.array([p.header.frame_id for p in poses], str),
        {"pose.position": np.array([[p.pose.position.x, p.pose.position.y, p.pose.position.z]
                                    for p in poses], float).reshape(-1, 3),
         "pose.orientation": np.array([[p.pose.orientation.x, p.pose.orientation.y,
                                        p.pose.orientation.z, p.pose.orientation.w]
                                       for p in poses], float).reshape(-1, 4)})
