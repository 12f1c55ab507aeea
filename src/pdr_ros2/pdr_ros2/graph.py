"""The CLI's node on the graph and what it lists: ``ros2 node list``, ``ros2 topic list``,
``ros2 service list``.

As ros2cli without its daemon (``ros2cli/node/direct.py``): a hidden node
``_ros2cli_<pid>``, without parameter services, spun for ``--spin-time`` (0.5 s) so that
discovery has seen the graph before it is asked. Names starting with ``_`` (hidden) are
left out of the lists, as ros2cli does without ``-a``.
"""
from __future__ import annotations

import os
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager, suppress

NODE_NAME_PREFIX = "_ros2cli"     # ros2cli's name for its own (hidden) node
DISCOVERY_S = 0.5                 # ros2cli's DirectNode DEFAULT_TIMEOUT (--spin-time)
HIDDEN_PREFIX = "_"
DUPLICATE_NODES_WARNING = ("WARNING: Be aware that there are nodes in the graph that share "
                           "an exact name, which can have unintended side effects.")


@contextmanager
def graph_node(spin_time: float = DISCOVERY_S, name: str | None = None) -> Iterator:
    """A hidden rclpy node in ``$ROS_DOMAIN_ID`` (``name``, by default ``_ros2cli_<pid>``),
    after ``spin_time`` [s] of discovery; rclpy shut down on leaving. Ctrl-C is a
    KeyboardInterrupt whichever of Python and rclpy's signal handler takes it first (rclpy's
    shuts the context down, and a spin then raises ExternalShutdownException)."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    rclpy.init()
    try:
        node = rclpy.create_node(name or f"{NODE_NAME_PREFIX}_{os.getpid()}",
                                 start_parameter_services=False)
        deadline = time.monotonic() + spin_time
        while (left := deadline - time.monotonic()) > 0:
            rclpy.spin_once(node, timeout_sec=left)
        yield node
    except ExternalShutdownException:
        raise KeyboardInterrupt from None
    finally:
        # Ctrl-C: rclpy's signal handler may shut the context down between try_shutdown's
        # look and its call, which then raises RCLError (a RuntimeError), "rcl_shutdown
        # already called": the context is shut down either way
        with suppress(RuntimeError):
            rclpy.try_shutdown()


def topic_types(node, topic: str) -> list[str]:
    """The types the graph gives ``topic`` (its exact name, hidden or not); [] if none."""
    return dict(node.get_topic_names_and_types()).get(topic, [])


def node_list(args) -> None:
    """``ros2 node list``: the nodes' full names, sorted, one a line; a warning on stderr
    when two share a name."""
    with graph_node(args.spin_time) as node:
        names = node_names(node)
    if len(set(names)) < len(names):
        print(DUPLICATE_NODES_WARNING, file=sys.stderr)
    if names:
        print(*sorted(names), sep="\n")


def node_names(node) -> list[str]:
    """The full names of the graph's nodes that are not hidden, as rclpy lists them."""
    return [full_name(name, namespace)
            for name, namespace in node.get_node_names_and_namespaces()
            if not name.startswith(HIDDEN_PREFIX)]


def full_name(name: str, namespace: str) -> str:
    """``/ns/name`` from a node's name and namespace (``/`` or ``/ns``)."""
    return namespace + ("" if namespace.endswith("/") else "/") + name


def topic_list(args) -> None:
    """``ros2 topic list [-t]``: the topics, one a line, with ``[type, ...]`` under -t."""
    with graph_node(args.spin_time) as node:
        print_names(node.get_topic_names_and_types(), args.show_types)


def service_list(args) -> None:
    """``ros2 service list [-t]`` (``ros2service/verb/list.py``): the services, one a line,
    with ``[type, ...]`` under -t."""
    with graph_node(args.spin_time) as node:
        print_names(node.get_service_names_and_types(), args.show_types)


def print_names(names_and_types: list[tuple[str, list[str]]], show_types: bool) -> None:
    """The names that are not hidden, sorted, one a line, each followed by
    `` [type, ...]`` when ``show_types``."""
    from rclpy.topic_or_service_is_hidden import topic_or_service_is_hidden

    for name, types in sorted(names_and_types):
        if not topic_or_service_is_hidden(name):
            print(f"{name} [{', '.join(types)}]" if show_types else name)
