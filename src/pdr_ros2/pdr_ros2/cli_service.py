"""``ros2 service`` and its verbs (``ros2service/verb/list.py``, ``call.py``)."""
from __future__ import annotations

from pdr_ros2.cli_parsers import graph_verb, verb, verbs
from pdr_ros2.graph import service_list
from pdr_ros2.service_call import service_call


def add(commands) -> None:
    """The ``service`` command's parsers."""
    service_verbs = verbs(commands, "service", "Various service related sub-commands")
    listing = graph_verb(service_verbs, "list", "Output a list of available services",
                         service_list)
    listing.add_argument("-t", "--show-types", action="store_true",
                         help="Additionally show the service type")
    call = verb(service_verbs, "call", "Call a service", service_call)
    call.add_argument("service_name",
                      help="Name of the ROS service to call to (e.g. '/add_two_ints')")
    call.add_argument("service_type", help="Type of the ROS service (e.g. 'std_srvs/srv/Empty')")
    call.add_argument("values", nargs="?", default="{}",
                      help="Values to fill the service request with in YAML format (e.g. "
                           "'{a: 1, b: 2}'), otherwise the service request will be published "
                           "with default values")
