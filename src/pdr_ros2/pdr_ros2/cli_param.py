"""``ros2 param`` and its verbs (ros2cli's ``ros2param/ros2param/verb/*.py`` arguments)."""
from __future__ import annotations

from pdr_ros2.cli_parsers import graph_verb, verbs
from pdr_ros2.param_verbs import NODE_WAIT_S, param_dump, param_get, param_list, param_set


def add(commands) -> None:
    """The ``param`` command's parsers."""
    param_verbs = verbs(commands, "param", "Various param related sub-commands")
    listing = graph_verb(param_verbs, "list", "Output a list of available parameters",
                         param_list)
    listing.add_argument("node_name", nargs="?", help="Name of the ROS node")
    listing.add_argument("--param-type", action="store_true",
                         help="Print parameter types with parameter names")
    get = graph_verb(param_verbs, "get", "Get parameter", param_get)
    get.add_argument("node_name", help="Name of the ROS node")
    get.add_argument("parameter_name", help="Name of the parameter")
    get.add_argument("--hide-type", action="store_true", help="Hide the type information")
    setting = graph_verb(param_verbs, "set", "Set parameter", param_set)
    setting.add_argument("node_name", help="Name of the ROS node")
    setting.add_argument("parameter_name", help="Name of the parameter")
    setting.add_argument("value", help="Value of the parameter")
    add_timeout(setting)
    dump = graph_verb(param_verbs, "dump",
                      "Show all of the parameters of a node in a YAML file format", param_dump)
    dump.add_argument("node_name", help="Name of the ROS node")
    add_timeout(dump)


def add_timeout(parser) -> None:
    """ros2param's ``--timeout N`` of set and dump (its default 1 s there)."""
    parser.add_argument("--timeout", metavar="N", type=int, default=NODE_WAIT_S,
                        help="Wait for N seconds until node becomes available "
                             "(default %(default)s sec; ros2cli's 1 sec)")
