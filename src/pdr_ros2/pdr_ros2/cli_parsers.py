"""Shared argparse shapes of the ``ros2`` commands: the parser whose errors name this
stand-in, a command with its verbs, a verb that asks the graph (ros2cli's
``--spin-time``)."""
from __future__ import annotations

import argparse

from pdr_ros2.graph import DISCOVERY_S

STAND_IN_NOTE = ("this ros2 is the pdr stack's stand-in, NOT ros2cli, with fewer options: -h "
                 "lists what it takes")


class StandInParser(argparse.ArgumentParser):
    """argparse's parser (usage, then ``ros2 ...: error: ...``, exit 2) whose error adds
    that this is not ros2cli, so that an option of the real CLI that ours lacks is
    refused in words that say why; its sub-parsers are of this class too."""

    def error(self, message: str):
        super().error(f"{message} ({STAND_IN_NOTE})")


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
