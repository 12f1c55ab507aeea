"""Node ``bag_play``: publishes the messages of a bag with their recorded timing.

Parameters (``--ros-args -p name:=value`` or ``--params-file``):
    bag (str, required): bag directory or .mcap file.
    topics (str[], all): bag topics to play, e.g. ``['/imu/data']``.
    rate, clock, wait_for_subscribers, wait_timeout_s, ack_every: see
        :mod:`pdr_sim.nodes.playback`.

    strict (bool, false): refuse a bag cut short or without its index (exit status 2)
        instead of playing its readable part with a warning.
    start_offset_s (float, 0.0): skip the messages logged in the first this many seconds
        after the first played message (``ros2 bag play --start-offset``).
    playback_duration_s (float, 0.0): stop this many seconds of log time after the start
        offset; 0: at the end of the bag (``ros2 bag play --playback-duration``).

Bag topics are absolute (``/imu/data``) and are published relative to the node's
namespace (``imu/data``); the truth topics of a simulated bag (``ground_truth/pose``,
``stance``, ``step``, ``landmarks``) are played like any other. A bag cut short
(pdr_core.io.bag) is played up to its last complete chunk, with a warning saying how much;
damage inside an intact bag stops the playback there, reported, with exit status 1. Bad
parameters or an unreadable bag exit with status 2.
"""
from __future__ import annotations

import warnings
from collections.abc import Iterator

from rclpy.node import Node
from rclpy.parameter import Parameter

from pdr_core import topics as bag_topics
from pdr_core.errors import InputError, InputWarning
from pdr_core.io.bag import BagReader, RawMessage
from pdr_core.ros.node_params import declare
from pdr_sim.nodes.playback import Playback, run_player


class BagPlayer(Node):
    """Publishes one bag; :meth:`run` returns the process exit status."""

    def __init__(self) -> None:
        super().__init__("bag_play")
        self.bag_path = declare(self, "bag", "", "bag directory or .mcap file (required)")
        self.topic_filter = (self.declare_parameter("topics", Parameter.Type.STRING_ARRAY).value
                             or [])
        self.strict = declare(self, "strict", False, "refuse a bag cut short instead of "
                              "playing its readable part")
        self.start_offset_s = declare(self, "start_offset_s", 0.0, "skip the first this many "
                                      "seconds of log time [s]")
        self.duration_s = declare(self, "playback_duration_s", 0.0, "stop this many seconds "
                                  "of log time after the start offset; 0: at the end [s]")
        if self.start_offset_s < 0 or self.duration_s < 0:
            raise ValueError("start_offset_s and playback_duration_s must be >= 0, got "
                             f"{self.start_offset_s} and {self.duration_s}")
        self.playback = Playback(self)

    def run(self) -> int:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", InputWarning)
            status = self._play()
        for warning in caught:
            self.get_logger().warning(str(warning.message))
        return status

    def _play(self) -> int:
        if not self.bag_path:
            self.get_logger().error("parameter 'bag' is required (-p bag:=PATH)")
            return 2
        try:
            reader = BagReader(self.bag_path, strict=self.strict)
            wanted = [bag_topics.bag_name(t) for t in self.topic_filter] or sorted(reader.topics)
            reader.require_topics(wanted)
        except InputError as exc:
            self.get_logger().error(str(exc))
            return 2
        self.playback.advertise({t: reader.topics[t] for t in wanted})
        if not self.playback.wait_for_subscribers_or_timeout():
            return 1
        try:
            self.playback.publish(in_window(reader.raw_messages(wanted), self.start_offset_s,
                                            self.duration_s))
        except InputError as exc:
            self.playback.wait_acked()
            self.get_logger().error(
                f"published {self.playback.published} messages, then stopped: {exc}")
            return 1
        self.playback.wait_acked()
        self.get_logger().info(f"published {self.playback.published} messages "
                               f"from {self.bag_path}")
        return 0


def in_window(messages: Iterator[RawMessage], start_offset_s: float,
              duration_s: float) -> Iterator[RawMessage]:
    """The messages (in log-time order) from ``start_offset_s`` after the first one, for
    ``duration_s`` of log time (0: to the end) [s]."""
    first = None
    for message in messages:
        first = message.log_time_ns if first is None else first
        elapsed_s = (message.log_time_ns - first) / 1e9
        if elapsed_s < start_offset_s:
            continue
        if duration_s and elapsed_s >= start_offset_s + duration_s:
            return
        yield message


def main(args: list[str] | None = None) -> None:
    run_player("bag_play", BagPlayer, args)

if __name__ == "__main__":
    main()
