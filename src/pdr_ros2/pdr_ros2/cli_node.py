"""``ros2 node`` and its verbs."""
from __future__ import annotations

from pdr_ros2.cli_parsers import graph_verb, verbs
from pdr_ros2.graph import node_list


def add(commands) -> None:
    """The ``node`` command's parsers."""
    node_verbs = verbs(commands, "node", "Various node related sub-commands")
    graph_verb(node_verbs, "list", "Output a list of available nodes", node_list)
