"""``ros2 topic`` and its verbs."""
from __future__ import annotations

from pdr_core.ros.message_yaml import ECHO_TRUNCATE_LENGTH
from pdr_ros2.cli_parsers import graph_verb, verbs
from pdr_ros2.graph import topic_list
from pdr_ros2.topic_echo import topic_echo


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
