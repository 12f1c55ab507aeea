"""nav_msgs/Path to and from a PoseStamped MessageBatch.

A Path carries a sequence of PoseStamped, so it has no fixed CDR layout as a whole; it is
read through ``rosbags`` message objects (one per pose). :func:`encode_path` writes it
without them: when the poses share one frame_id, every pose after the first has the byte
layout of a stand-alone PoseStamped (:func:`pdr_core.io.cdr.encode_rows`), so a path of
every sample of a smoothed segment costs one vectorised encode.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from pdr_core.io import cdr
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import PATH, POSE_STAMPED, typestore

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


def encode_path(poses: MessageBatch, stamp_ns: int, frame_id: str) -> bytes:
    """The CDR of :func:`path_message` (byte for byte), vectorised over the poses.

    XCDR1 aligns each float64 to 8 bytes from the start of the payload. A stand-alone
    PoseStamped starts at payload offset 0; inside the Path, pose k > 0 starts where pose
    k − 1 ended, on a multiple of 8 too, so its bytes are the stand-alone message's without
    the 4-byte encapsulation header. Only the first pose, which follows the 4-byte pose
    count, may need a different padding before its float64s.
    """
    frames = np.unique(poses.frame_id)
    if len(frames) != 1:
        return cdr.encode_generic(path_message(poses, stamp_ns, frame_id))
    empty = cdr.encode_generic(typestore().types[PATH](header=_header(stamp_ns, frame_id),
                                                       poses=[]))
    rows = cdr.encode_rows(poses, str(frames[0]))[:, 4:]
    start = len(empty) - 4                      # payload offset of the first pose
    stamp_and_frame = 12 + len(str(frames[0]).encode()) + 1
    pad = -(start + stamp_and_frame) % 8
    first = rows[0]
    first_padded = np.concatenate([first[:stamp_and_frame], np.zeros(pad, np.uint8),
                                   first[-56:]])  # Point + Quaternion: 7 float64
    count = np.uint32(len(poses)).tobytes()
    return empty[:-4] + count + first_padded.tobytes() + rows[1:].tobytes()


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


def last_path(reader, topic: str) -> MessageBatch:
    """The poses of the last ``nav_msgs/Path`` on ``topic`` of a bag
    (:class:`pdr_core.io.bag.BagReader`): a navigator's path as it finally had it, the steps
    a correction ran again in their place (pocket_pdr publishes its path again then)."""
    *_, last = reader.raw_messages([topic])
    return path_poses(typestore().deserialize_cdr(last.data, last.msgtype))
