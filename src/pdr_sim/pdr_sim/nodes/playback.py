"""Timed publishing of serialized messages: the shared engine of ``bag_play`` and
``imu_sim``.

Parameters it declares on its node:
    rate (float, 1.0): speed factor over the message log times; 0 publishes as fast as
        the subscribers keep up (reliable delivery, waiting for acknowledgements every
        ``ack_every`` messages).
    clock (bool, false): also publish ``/clock`` (rosgraph_msgs/Clock) at each log time.
    wait_for_subscribers (int, 0): before publishing, wait until every publisher has this
        many subscribers (a start handshake: nothing goes out before discovery).
    wait_for_topics (str[], none): before publishing, also wait until each of these graph
        topics has a subscriber: the recorder of a launch file (pdr_sim/launch/
        replay.launch.xml), which subscribes to an output once its node publishes it, so
        that nothing is played before the graph downstream listens.
    wait_timeout_s (float, 30.0): give up waiting after this long.
    ack_every (int, 100): with rate 0, messages between acknowledgement waits.

Publishers are reliable and transient-local (depth 1000): a subscriber whose side of
discovery completes after the publisher already counts it still gets the first messages.
Messages go out as raw CDR, so subscribers receive them bit for bit.
"""
from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterable

import rclpy
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from pdr_core import topics as bag_topics
from pdr_core.errors import InputError
from pdr_core.io.bag import RawMessage
from pdr_core.ros.node_main import check_params_files, use_fast_acks
from pdr_core.ros.node_params import declare
from pdr_core.ros.ros_types import message_class

RELIABLE = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)
_NS = 1_000_000_000


def run_player(name: str, make_node: Callable[[], Node], args: list[str] | None) -> None:
    """``main`` of a player node: fast acknowledgements, init, ``node.run()`` as exit status
    (2 for bad parameters, 130 on interrupt), clean shutdown."""
    use_fast_acks()
    status = 1
    node = None
    try:
        check_params_files(args)
        rclpy.init(args=args)
        node = make_node()
        status = node.run()
    except (ValueError, InputError) as exc:
        print(f"{name}: error: {exc}", file=sys.stderr)
        status = 2
    except (KeyboardInterrupt, ExternalShutdownException):
        status = 130
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    sys.exit(status)


class Playback:
    """Publishes a time-ordered stream of :class:`RawMessage` from ``node``."""

    def __init__(self, node: Node) -> None:
        self.node = node
        self.rate = declare(node, "rate", 1.0, "playback speed [x real time]; 0: as fast as "
                            "the subscribers keep up")
        self.clock = declare(node, "clock", False, "also publish /clock")
        self.wait_for_subscribers = declare(node, "wait_for_subscribers", 0, "wait until every "
                                            "publisher has this many subscribers")
        self.wait_for_topics = (node.declare_parameter(
            "wait_for_topics", Parameter.Type.STRING_ARRAY).value or [])
        self.wait_timeout_s = declare(node, "wait_timeout_s", 30.0,
                                      "give up waiting after this long [s]")
        self.ack_every = max(1, declare(node, "ack_every", 100, "with rate 0, messages "
                                        "between acknowledgement waits"))
        self.published = 0
        self.publishers: dict = {}
        self.clock_pub = None
        if self.rate < 0:
            raise ValueError(f"rate must be >= 0, got {self.rate}")

    def advertise(self, topic_types: dict[str, str]) -> None:
        """Create a publisher per bag topic (published relative to the namespace)."""
        self.publishers = {t: self.node.create_publisher(message_class(msgtype),
                                                         bag_topics.graph_name(t), RELIABLE)
                           for t, msgtype in topic_types.items()}
        if self.clock:
            self.clock_pub = self.node.create_publisher(message_class("rosgraph_msgs/msg/Clock"),
                                                        bag_topics.CLOCK, RELIABLE)

    def wait_for_subscribers_or_timeout(self) -> bool:
        """True once every publisher has its subscribers and every topic of
        ``wait_for_topics`` one (or none are required)."""
        deadline = time.monotonic() + self.wait_timeout_s
        while missing := self.missing_subscribers():
            if time.monotonic() > deadline:
                self.node.get_logger().error(f"no subscriber(s) after {self.wait_timeout_s} s: "
                                             f"{', '.join(missing)}")
                return False
            time.sleep(0.01)
        return True

    def missing_subscribers(self) -> list[str]:
        """What the start handshake still waits for, in words."""
        missing = [f"{self.wait_for_subscribers} on {bag_topics.graph_name(topic)}"
                   for topic, pub in self.publishers.items()
                   if pub.get_subscription_count() < self.wait_for_subscribers]
        return missing + [f"1 on {topic}" for topic in self.wait_for_topics
                          if self.node.count_subscribers(topic) < 1]

    def wait_acked(self) -> None:
        for pub in self.publishers.values():
            pub.wait_for_all_acked(Duration(seconds=self.wait_timeout_s))

    def publish(self, messages: Iterable[RawMessage]) -> None:
        """Publish every message at its log time scaled by ``rate`` (exceptions of the
        iterator propagate after what came before was published)."""
        clock_msg = message_class("rosgraph_msgs/msg/Clock")() if self.clock_pub else None
        start_wall = start_log = None
        for message in messages:
            if start_log is None:
                start_wall, start_log = time.monotonic(), message.log_time_ns
            if self.rate > 0:
                delay = (start_wall + (message.log_time_ns - start_log) / _NS / self.rate
                         - time.monotonic())
                if delay > 0:
                    time.sleep(delay)
            if self.clock_pub is not None:
                clock_msg.clock.sec, clock_msg.clock.nanosec = divmod(message.log_time_ns, _NS)
                self.clock_pub.publish(clock_msg)
            self.publishers[message.topic].publish(message.data)
            self.published += 1
            if self.rate == 0 and self.published % self.ack_every == 0:
                self.wait_acked()
