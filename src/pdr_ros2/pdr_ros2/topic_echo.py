"""``ros2 topic echo TOPIC [--once] [--csv]`` as ros2cli's ``ros2topic/verb/echo.py``
prints it: each message as YAML followed by a ``---`` line, or as one CSV line
(pdr_core.ros.message_yaml). The type is the one the graph gives the topic (its exact
name); the QoS starts from ``sensor_data`` and asks for reliable, or transient local, when
every publisher offers it (``choose_qos``), so a late ``--once`` on a transient-local
topic prints the oldest message its publisher keeps.

Not supported: a type argument, --field, --filter, --no-arr, --no-str, --flow-style,
--raw, --timeout, -i, the QoS options, the report of lost messages.
"""
from __future__ import annotations

from pdr_core.ros.message_yaml import SEPARATOR, message_csv, message_yaml
from pdr_core.ros.ros_types import message_class
from pdr_ros2.graph import graph_node, topic_types

NO_TYPE = "Could not determine the type for the passed topic"
SOME_RELIABLE = ("Some, but not all, publishers are offering QoSReliabilityPolicy.RELIABLE. "
                 "Falling back to QoSReliabilityPolicy.BEST_EFFORT as it will connect to all "
                 "publishers")
SOME_TRANSIENT_LOCAL = ("Some, but not all, publishers are offering "
                        "QoSDurabilityPolicy.TRANSIENT_LOCAL. Falling back to "
                        "QoSDurabilityPolicy.VOLATILE as it will connect to all publishers")


def topic_echo(args) -> str | None:
    """Print the messages of ``args.topic_name`` until Ctrl-C (the first only, under
    ``--once``); ros2cli's error text when the graph has no type for it."""
    import rclpy
    from rclpy.task import Future

    truncate_length = None if args.full_length else args.truncate_length
    with graph_node(args.spin_time) as node:
        types = topic_types(node, args.topic_name)
        if not types:
            return NO_TYPE
        printed = Future()

        def show(msg) -> None:
            if args.csv:
                print(message_csv(msg, truncate_length), flush=True)
            else:
                print(message_yaml(msg, truncate_length), end=SEPARATOR + "\n", flush=True)
            printed.set_result(True)

        node.create_subscription(message_class(types[0]), args.topic_name, show,
                                 echo_qos(node, args.topic_name))
        if args.once:
            rclpy.spin_until_future_complete(node, printed)
        else:
            rclpy.spin(node)
    return None


def echo_qos(node, topic: str):
    """ros2cli's ``choose_qos`` without QoS options: ``sensor_data`` (best effort,
    volatile, depth 5), made reliable (transient local) when every publisher of ``topic``
    is; a mixed graph is said on stdout, as ros2cli does."""
    from rclpy.qos import (
        DurabilityPolicy,
        QoSProfile,
        ReliabilityPolicy,
        qos_profile_sensor_data,
    )

    offered = [info.qos_profile for info in node.get_publishers_info_by_topic(topic)]
    qos = QoSProfile(history=qos_profile_sensor_data.history,
                     depth=qos_profile_sensor_data.depth,
                     reliability=qos_profile_sensor_data.reliability,
                     durability=qos_profile_sensor_data.durability)
    if not offered:
        return qos
    reliable = [p.reliability == ReliabilityPolicy.RELIABLE for p in offered]
    transient = [p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in offered]
    if any(reliable) and not all(reliable):
        print(SOME_RELIABLE)
    if any(transient) and not all(transient):
        print(SOME_TRANSIENT_LOCAL)
    qos.reliability = (ReliabilityPolicy.RELIABLE if all(reliable)
                       else ReliabilityPolicy.BEST_EFFORT)
    qos.durability = (DurabilityPolicy.TRANSIENT_LOCAL if all(transient)
                      else DurabilityPolicy.VOLATILE)
    return qos
