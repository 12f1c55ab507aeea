"""Shared argparse shapes of the ``ros2`` commands: a command with its verbs, a verb that
asks the graph (ros2cli's ``--spin-time``)."""
from __future__ import annotations

import argparse

from pdr_ros2.graph import DISCOVERY_S


def verbs(commands, name: str, summary: str):
    """A command (``node``, ``topic``, ...) and the sub-parsers of its verbs."""
    command = commands.add_parser(name, help=summary, description=summary)
    return command.add_subparsers(title="verbs", metavar="VERB", required=True)


def verb(verb_parsers, name: str, summary: str, function) -> argparse.ArgumentParser:
    """A verb that runs ``function(args)``; its return value is the error text, or None."""
    parsed = verb_parsers.add_parser(name, help=summary, description=summary)
    parsed.set_defaults(verb=function)
    return parsed


def graph_verb(verb_parsers, name: str, summary: str, function) -> argparse.ArgumentParser:
    """A verb that asks the graph, with ros2cli's ``--spin-time``."""
    parsed = verb(verb_parsers, name, summary, function)
    parsed.add_argument("--spin-time", type=float, default=DISCOVERY_S,
                        help="Spin time in seconds to wait for discovery")
    return parsed
