"""``ros2 topic`` and its verbs (``ros2topic/verb/list.py``, ``echo.py``, ``hz.py``,
``info.py``)."""
from __future__ import annotations

import argparse

from pdr_core.ros.message_yaml import ECHO_TRUNCATE_LENGTH
from pdr_core.ros.reception_rate import DEFAULT_WINDOW
from pdr_ros2.cli_parsers import graph_verb, verbs
from pdr_ros2.graph import topic_list
from pdr_ros2.topic_echo import topic_echo
from pdr_ros2.topic_hz import topic_hz
from pdr_ros2.topic_info import topic_info

HZ_SUMMARY = ("Print the average receiving rate to screen.\n\nnote:\n  This rate reflects the "
              "receiving rate on subscription, which might be affected by platform resources "
              "and QoS configuration, and may not exactly match the publisher's rate.")


def add(commands) -> None:
    """The ``topic`` command's parsers."""
    topic_verbs = verbs(commands, "topic", "Various topic related sub-commands")
    listing = graph_verb(topic_verbs, "list", "Output a list of available topics", topic_list)
    listing.add_argument("-t", "--show-types", action="store_true",
                         help="Additionally show the topic type")
    echo = graph_verb(topic_verbs, "echo", "Output messages from a topic", topic_echo)
    echo.add_argument("topic_name", help="Name of the ROS topic to listen to (e.g. '/chatter')")
    echo.add_argument("--csv", action="store_true",
                      help="Output all recursive fields separated by commas")
    echo.add_argument("--once", action="store_true",
                      help="Print the first message received and then exit.")
    echo.add_argument("--full-length", "-f", action="store_true",
                      help="Output all elements for arrays, bytes, and strings")
    echo.add_argument("--truncate-length", "-l", type=int, default=ECHO_TRUNCATE_LENGTH,
                      help=f"The length to truncate arrays, bytes, and string to "
                           f"(default: {ECHO_TRUNCATE_LENGTH})")
    hz = graph_verb(topic_verbs, "hz", "Print the average receiving rate to screen", topic_hz)
    hz.description = HZ_SUMMARY
    hz.formatter_class = argparse.RawDescriptionHelpFormatter
    hz.add_argument("topic_name", help="Name of the ROS topic to listen to (e.g. '/chatter')")
    hz.add_argument("--window", "-w", dest="window_size", type=positive_int,
                    default=DEFAULT_WINDOW, metavar="WINDOW",
                    help=f"window size, in # of messages, for calculating rate "
                         f"(default: {DEFAULT_WINDOW})")
    info = graph_verb(topic_verbs, "info", "Print information about a topic", topic_info)
    info.add_argument("topic_name", help="Name of the ROS topic to get info (e.g. '/chatter')")
    info.add_argument("--verbose", "-v", action="store_true",
                      help="Prints detailed information like the node name, node namespace, "
                           "topic type, GUID and QoS Profile of the publishers and subscribers "
                           "to this topic")


def positive_int(text: str) -> int:
    """``--window``'s value: an integer > 0 (ros2cli's ``positive_int``)."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value <= 0:
        raise argparse.ArgumentTypeError("value must be a positive integer")
    return value
