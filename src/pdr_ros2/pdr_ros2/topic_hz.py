"""``ros2 topic hz TOPIC [--window N]`` as ros2cli's ``ros2topic/verb/hz.py`` (Jazzy) prints
it: every second of messages, the rate at which they arrive, their shortest and longest
interval and its standard deviation over the last N intervals
(pdr_core.ros.reception_rate), until Ctrl-C.

As ros2cli: a topic the graph does not have yet is waited for (polled every 0.1 s) after
``WARNING: topic [TOPIC] does not appear to be published yet``; the subscription is
``sensor_data``'s (best effort, volatile, depth 5), taking the raw bytes (no decoding).
Unlike ros2cli, reception times are of a monotonic clock (ros2cli takes the node's clock,
ROS time); ``--filter``, ``--wall-time`` and ``--use-sim-time`` are not supported.
"""
from __future__ import annotations

import time

from pdr_core.ros.reception_rate import ReceptionRate
from pdr_core.ros.ros_types import message_class
from pdr_ros2.graph import graph_node, topic_types

NOT_PUBLISHED = "WARNING: topic [{}] does not appear to be published yet"
POLL_S = 0.1        # ros2cli's wait between two looks at the graph for the topic [s]


def topic_hz(args) -> None:
    """Print ``args.topic_name``'s reception rate every second of messages until Ctrl-C."""
    import rclpy
    from rclpy.qos import qos_profile_sensor_data

    with graph_node(args.spin_time) as node:
        types = published_types(node, args.topic_name)
        rate = ReceptionRate(args.window_size)
        node.create_subscription(message_class(types[0]), args.topic_name,
                                 lambda _raw: rate.received(time.monotonic_ns()),
                                 qos_profile_sensor_data, raw=True)
        while rclpy.ok():
            rclpy.spin_once(node)
            report = rate.report()
            if report is not None:
                print(report.text(), flush=True)
    raise KeyboardInterrupt     # only Ctrl-C ends it: rclpy's handler shut the context down


def published_types(node, topic: str) -> list[str]:
    """``topic``'s types, once the graph has it (said on stdout when it has not yet)."""
    types = topic_types(node, topic)
    if not types:
        print(NOT_PUBLISHED.format(topic), flush=True)
    while not types:
        time.sleep(POLL_S)
        types = topic_types(node, topic)
    return types
