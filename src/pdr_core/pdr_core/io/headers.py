"""std_msgs/Header stamps for the nodes: nanoseconds to and from ``sec``/``nanosec``
(time comes from message stamps, never the wall clock)."""
from __future__ import annotations

NS_PER_S = 1_000_000_000


def time_ns(time) -> int:
    """A builtin_interfaces/Time [ns] (a header's stamp, a request's)."""
    return time.sec * NS_PER_S + time.nanosec


def set_time(time, stamp: int) -> None:
    """Fill a builtin_interfaces/Time with a stamp [ns]."""
    time.sec, time.nanosec = divmod(int(stamp), NS_PER_S)


def stamp_ns(msg) -> int:
    """A stamped message's ``header.stamp`` [ns]."""
    return time_ns(msg.header.stamp)


def set_header(header, stamp: int, frame_id: str) -> None:
    """Fill a std_msgs/Header with a stamp [ns] and a frame."""
    set_time(header.stamp, stamp)
    header.frame_id = frame_id
