"""Node ``bag_play``: publishes the messages of a bag with their recorded timing.

Parameters (``--ros-args -p name:=value`` or ``--params-file config/bag_play.yaml``):
    bag (str, required): bag directory or .mcap file.
    rate (float, 1.0): playback speed factor; 0 publishes as fast as the subscribers keep
        up (reliable delivery, waiting for acknowledgements every ``ack_every`` messages).
    topics (str[], all): bag topics to play, e.g. ``['/imu/data']``.
    clock (bool, false): also publish ``/clock`` (rosgraph_msgs/Clock) at each log time.
    wait_for_subscribers (int, 0): before playing, wait until every publisher has this
        many subscribers (a start handshake; no message goes out before discovery).
    wait_timeout_s (float, 30.0): give up waiting after this long (exit status 1).
    ack_every (int, 100): with rate 0, messages between acknowledgement waits.

Messages are published as the raw CDR bytes of the bag, so the subscribers receive them
bit for bit. Bag topics are absolute (``/imu/data``) and are published relative to the
node's namespace (``imu/data``). A damaged bag is played up to the damage; then the node
reports it and exits with status 1.
"""
from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import rclpy
from ament_index_python.packages import get_package_share_directory
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from pdr_core import topics as bag_topics
from pdr_core.bag import BagReader
from pdr_core.errors import InputError
from pdr_sim.nodes.ros_types import message_class

# Transient local: a subscriber whose side of discovery completes after the player's side
# (the player already counts it) still gets the first messages from the writer's history.
RELIABLE = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)
_NS = 1_000_000_000


class BagPlayer(Node):
    """Publishes one bag; :meth:`play` returns the process exit status."""

    def __init__(self) -> None:
        super().__init__("bag_play")
        self.bag_path = self.declare_parameter("bag", "").value
        self.rate = float(self.declare_parameter("rate", 1.0).value)
        self.topic_filter = (self.declare_parameter("topics", Parameter.Type.STRING_ARRAY).value
                             or [])
        self.clock = bool(self.declare_parameter("clock", False).value)
        self.wait_for_subscribers = int(self.declare_parameter("wait_for_subscribers", 0).value)
        self.wait_timeout_s = float(self.declare_parameter("wait_timeout_s", 30.0).value)
        self.ack_every = max(1, int(self.declare_parameter("ack_every", 100).value))
        self.published = 0

    def play(self) -> int:
        if not self.bag_path:
            self.get_logger().error("parameter 'bag' is required (-p bag:=PATH)")
            return 2
        if self.rate < 0:
            self.get_logger().error(f"rate must be >= 0, got {self.rate}")
            return 2
        try:
            reader = BagReader(self.bag_path)
            wanted = [bag_topics.bag_name(t) for t in self.topic_filter] or sorted(reader.topics)
            reader.require_topics(wanted)
        except InputError as exc:
            self.get_logger().error(str(exc))
            return 2
        publishers = {t: self.create_publisher(message_class(reader.topics[t]),
                                               bag_topics.graph_name(t), RELIABLE)
                      for t in wanted}
        clock_pub = None
        if self.clock:
            clock_pub = self.create_publisher(message_class("rosgraph_msgs/msg/Clock"),
                                              bag_topics.CLOCK, RELIABLE)
        if not self._wait_for_subscribers(list(publishers.values())):
            return 1
        try:
            self._publish_all(reader, wanted, publishers, clock_pub)
        except InputError as exc:
            self._wait_acked(publishers.values())
            self.get_logger().error(f"published {self.published} messages, then stopped: {exc}")
            return 1
        self._wait_acked(publishers.values())
        self.get_logger().info(f"published {self.published} messages from {self.bag_path}")
        return 0

    def _wait_for_subscribers(self, publishers: list) -> bool:
        if self.wait_for_subscribers <= 0:
            return True
        deadline = time.monotonic() + self.wait_timeout_s
        while min(p.get_subscription_count() for p in publishers) < self.wait_for_subscribers:
            if time.monotonic() > deadline:
                self.get_logger().error(
                    f"no {self.wait_for_subscribers} subscriber(s) after {self.wait_timeout_s} s")
                return False
            time.sleep(0.01)
        return True

    def _wait_acked(self, publishers) -> None:
        for pub in publishers:
            pub.wait_for_all_acked(Duration(seconds=self.wait_timeout_s))

    def _publish_all(self, reader: BagReader, wanted: list[str], publishers: dict,
                     clock_pub) -> None:
        clock_msg = message_class("rosgraph_msgs/msg/Clock")() if clock_pub else None
        start_wall = start_log = None
        for message in reader.raw_messages(wanted):
            if start_log is None:
                start_wall, start_log = time.monotonic(), message.log_time_ns
            if self.rate > 0:
                delay = start_wall + (message.log_time_ns - start_log) / _NS / self.rate \
                    - time.monotonic()
                if delay > 0:
                    time.sleep(delay)
            if clock_pub is not None:
                clock_msg.clock.sec, clock_msg.clock.nanosec = divmod(message.log_time_ns, _NS)
                clock_pub.publish(clock_msg)
            publishers[message.topic].publish(message.data)
            self.published += 1
            if self.rate == 0 and self.published % self.ack_every == 0:
                self._wait_acked(publishers.values())


def _use_fast_heartbeats() -> None:
    """Point Fast DDS at bag_play's profile unless the user chose a profile already."""
    profile = Path(get_package_share_directory("pdr_sim")) / "config" / "bag_play_fastdds.xml"
    os.environ.setdefault("FASTRTPS_DEFAULT_PROFILES_FILE", str(profile))


def main(args: list[str] | None = None) -> None:
    _use_fast_heartbeats()
    rclpy.init(args=args)
    node = BagPlayer()
    status = 1
    try:
        status = node.play()
    except (KeyboardInterrupt, ExternalShutdownException):
        status = 130
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    sys.exit(status)


if __name__ == "__main__":
    main()
