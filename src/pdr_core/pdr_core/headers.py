"""std_msgs/Header stamps for the nodes: nanoseconds to and from ``sec``/``nanosec``
(time comes from message stamps, never the wall clock)."""
from __future__ import annotations

NS_PER_S = 1_000_000_000


def stamp_ns(msg) -> int:
    """A stamped message's ``header.stamp`` [ns]."""
    return msg.header.stamp.sec * NS_PER_S + msg.header.stamp.nanosec


def set_header(header, stamp: int, frame_id: str) -> None:
    """Fill a std_msgs/Header with a stamp [ns] and a frame."""
    header.stamp.sec, header.stamp.nanosec = divmod(int(stamp), NS_PER_S)
    header.frame_id = frame_id
