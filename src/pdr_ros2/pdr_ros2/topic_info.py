"""``ros2 topic info TOPIC [-v]`` as ros2cli's ``ros2topic/verb/info.py`` (Jazzy) prints
it: the type, the publisher count and the subscription count, one a line; under -v each
line is followed by a blank line and each count by its endpoints, each as rclpy's
``TopicEndpointInfo.__str__`` gives it (node, type, type hash, GID, QoS) and a blank line.
A topic with several types prints the Python list of them. ``Unknown topic 'TOPIC'``
when the graph does not have it.
"""
from __future__ import annotations

from pdr_ros2.graph import graph_node, topic_types

UNKNOWN_TOPIC = "Unknown topic '{}'"


def topic_info(args) -> str | None:
    """Print what the graph has of ``args.topic_name``; ros2cli's error when nothing."""
    topic = args.topic_name
    with graph_node(args.spin_time) as node:
        types = topic_types(node, topic)
        if not types:
            return UNKNOWN_TOPIC.format(topic)
        line_end = "\n\n" if args.verbose else "\n"
        print(f"Type: {types[0] if len(types) == 1 else types}", end=line_end)
        ends = (("Publisher", node.count_publishers, node.get_publishers_info_by_topic),
                ("Subscription", node.count_subscribers, node.get_subscriptions_info_by_topic))
        for kind, count, endpoints in ends:
            print(f"{kind} count: {count(topic)}", end=line_end)
            if args.verbose:
                for endpoint in endpoints(topic):
                    print(endpoint, end=line_end)
    return None
