"""Node ``bag_record``: writes topics of the ROS graph to an MCAP bag.

Parameters:
    out (str, required): output bag directory; it must not exist.
    topics (str[], required): graph topics to record, relative to the node's namespace
        (``imu/data``); stored in the bag as absolute names (``/imu/data``).
    max_messages (int, 0): stop after this many messages in all (0: until stopped).
    flush_interval_s (float, 1.0): the open chunk is written and synced at least this
        often (pdr_core.io.recording).

Each topic is subscribed once a publisher of it appears, with its type taken from the
graph and its reliability and durability matching the publishers'. Messages are stored
as received (raw CDR). The log time is the message's ``header.stamp`` when it has one, so
the bag replays in data time; messages without a header (``/clock``) are logged at
reception.

The bag is written at ``out`` as it goes (:class:`pdr_core.io.recording.RecordingBag`): a
SIGKILL or a power cut loses at most the last ``flush_interval_s``, and what is left is
read with a warning or repaired by ``pdr-sim repair``. SIGINT or SIGTERM stops recording:
messages already received are drained from the subscriptions and the bag is closed with
its summary and index. A write that fails (disk full, the directory gone) is logged, the
bag closed as far as it can be, and the node exits with status 1.
"""
from __future__ import annotations

import signal
import struct
import sys

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions

from pdr_core import topics as bag_topics
from pdr_core.errors import InputError
from pdr_core.io.msgtypes import typestore
from pdr_core.io.recording import RecordingBag
from pdr_core.ros.backlog import waiting_messages
from pdr_core.ros.node_main import check_params_files
from pdr_core.ros.node_params import declare
from pdr_core.ros.ros_types import message_class

_NS = 1_000_000_000
# messages taken from a subscription's queue per callback (pdr_core.ros.backlog)
BACKLOG_BLOCK = 1000
_HEADER = ("header", "std_msgs/msg/Header")


def known_type(msgtype: str) -> bool:
    """True when the typestore (ROS 2 Jazzy + pdr_msgs) can describe ``msgtype``."""
    return msgtype in typestore().fielddefs


def has_header(msgtype: str) -> bool:
    """True when the first field of ``msgtype`` is a std_msgs/Header."""
    _, fields = typestore().fielddefs[msgtype]
    return bool(fields) and (fields[0][0], fields[0][1][1]) == _HEADER


def header_stamp_ns(data: bytes) -> int:
    """``header.stamp`` in ns of a CDR message whose first field is a Header."""
    sec, nanosec = struct.unpack_from("<iI", data, 4)
    return sec * _NS + nanosec


def matching_qos(publishers: list) -> QoSProfile:
    """The strongest subscription QoS that every publisher of a topic is compatible with:
    reliable and transient local when all of them offer it (as ``ros2 bag record`` does)."""
    reliable = all(p.qos_profile.reliability == ReliabilityPolicy.RELIABLE for p in publishers)
    durable = all(p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
                  for p in publishers)
    return QoSProfile(
        history=HistoryPolicy.KEEP_ALL,
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if durable else DurabilityPolicy.VOLATILE)


class BagRecorder(Node):
    """Subscribes to the chosen topics as they appear and writes what arrives.

    Raises InputError for missing parameters or an existing output.
    """

    def __init__(self) -> None:
        super().__init__("bag_record")
        out = declare(self, "out", "", "output bag directory (required)")
        self.wanted = list(self.declare_parameter("topics", Parameter.Type.STRING_ARRAY).value
                           or [])
        self.max_messages = declare(self, "max_messages", 0, "stop after this many messages "
                                    "in all; 0: until stopped")
        flush_interval_s = declare(self, "flush_interval_s", 1.0,
                                   "write and sync the open chunk at least this often [s]")
        overwrite = declare(self, "overwrite", False, "replace an existing output")
        if not out:
            raise InputError("out", "parameter is required (-p out:=DIR)")
        if not self.wanted:
            raise InputError("topics", "parameter is required (-p topics:=[imu/data])")
        self.writer = RecordingBag(out, flush_interval_s, overwrite)
        self.count = 0
        self.failure: OSError | None = None
        self.subscribed: dict = {}      # graph topic -> its subscription
        self.discovery = self.create_timer(0.05, self._discover)
        limit = f"; stops after {self.max_messages} messages" if self.max_messages else ""
        self.get_logger().info(f"will record {', '.join(map(self.resolve_topic_name, self.wanted))}"
                               f" into {out}, each once a publisher appears{limit}")
        self.flusher = self.create_timer(flush_interval_s / 4, self._flush)

    def _discover(self) -> None:
        graph = dict(self.get_topic_names_and_types())
        for topic in self.wanted:
            if topic in self.subscribed:
                continue
            full = self.resolve_topic_name(topic)
            if full not in graph:
                continue
            msgtype = graph[full][0]
            if not known_type(msgtype):
                self.get_logger().error(f"cannot record {full}: type {msgtype} is not in the "
                                        "typestore (ROS 2 Jazzy and pdr_msgs)",
                                        throttle_duration_sec=10.0)
                continue
            qos = matching_qos(self.get_publishers_info_by_topic(full))
            self.subscribed[topic] = self.create_subscription(
                message_class(msgtype), topic,
                self._callback(topic, bag_topics.bag_name(topic), msgtype), qos, raw=True)
            self.get_logger().info(f"recording {full} ({msgtype})")

    def _callback(self, topic: str, bag_topic: str, msgtype: str):
        """The topic's callback: its message and the ones waiting behind it (up to
        BACKLOG_BLOCK, pdr_core.ros.backlog), written until done."""
        stamped = has_header(msgtype)

        def record(data: bytes) -> None:
            waiting = waiting_messages(self.subscribed[topic], BACKLOG_BLOCK)
            for message in (data, *waiting):
                if self.done:
                    return
                log_time = (header_stamp_ns(message) if stamped
                            else self.get_clock().now().nanoseconds)
                try:
                    self.writer.write_raw(bag_topic, msgtype, log_time, message)
                except OSError as exc:
                    self._failed(exc)
                    return
                self.count += 1

        return record

    def _flush(self) -> None:
        if self.failure is None:
            try:
                self.writer.flush_if_due()
            except OSError as exc:
                self._failed(exc)

    def _failed(self, exc: OSError) -> None:
        self.failure = exc
        self.get_logger().error(f"cannot write {self.writer.path}: {exc}; stopping after "
                                f"{self.count} messages")

    @property
    def done(self) -> bool:
        return self.failure is not None or 0 < self.max_messages <= self.count

    def drain(self, executor: SingleThreadedExecutor) -> None:
        """Take the messages already delivered to the subscriptions."""
        idle = 0
        while idle < 3:
            before = self.count
            executor.spin_once(timeout_sec=0.05)
            idle = idle + 1 if self.count == before else 0


def main(args: list[str] | None = None) -> None:
    try:
        check_params_files(args)
    except InputError as exc:
        print(f"bag_record: error: {exc}", file=sys.stderr)
        sys.exit(2)
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    stop = [False]

    def request_stop(signum, frame) -> None:
        stop[0] = True

    signal.signal(signal.SIGINT, request_stop)
    signal.signal(signal.SIGTERM, request_stop)
    try:
        node = BagRecorder()
    except InputError as exc:
        print(f"bag_record: error: {exc}", file=sys.stderr)
        rclpy.try_shutdown()
        sys.exit(2)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    try:
        while not stop[0] and not node.done:
            executor.spin_once(timeout_sec=0.1)
        if node.failure is None:
            node.drain(executor)
    finally:
        _close(node)
        node.destroy_node()
        rclpy.try_shutdown()
    if node.failure is not None:
        sys.exit(1)


def _close(node: BagRecorder) -> None:
    """Close the bag (as far as it can be after a failed write) and say what it holds."""
    try:
        node.writer.close()
    except OSError as exc:
        node.failure = node.failure or exc
        node.get_logger().error(f"cannot close {node.writer.path}: {exc}; what was flushed "
                                "is readable, and `pdr-sim repair` rebuilds its index")
        return
    node.get_logger().info(f"recorded {node.count} messages on {len(node.subscribed)} "
                           f"topics to {node.writer.path} ({node.writer.bytes_written} bytes)")


if __name__ == "__main__":
    main()
