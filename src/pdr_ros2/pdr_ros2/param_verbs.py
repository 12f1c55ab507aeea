"""``ros2 param list/get/set/dump``: rclpy's AsyncParameterClient on the CLI's hidden node
(``graph.graph_node``), the text from ``param_text``.

As ros2cli's ``ros2param/ros2param/verb/{list,get,set,dump}.py``: the node is looked up
among the graph's nodes first (``Node not found``), waited for as ``set``/``dump`` do
(``ros2node.api.wait_for_node``). Without ros2cli's daemon, which has seen the graph
already, a verb naming a node waits for it up to ``--spin-time`` (0.5 s) plus
``--timeout`` (NODE_WAIT_S, 4 s; ``list``/``get``, which have no ``--timeout``, as long)
and goes on as soon as it is seen; ``list`` without a node spins ``--spin-time`` for discovery. Each
service is waited for 5 s (``Wait for service timed out``, ros2param/api). ``set`` types
VALUE by YAML (rclpy.parameter.get_parameter_value, what ros2param imports) and reports
the node's answer: ``Set parameter successful`` on stdout, ``Setting parameter failed: <reason>``
as the error (exit 1 here; ros2cli prints it on stderr and exits 0).
"""
from __future__ import annotations

import time

from pdr_ros2.graph import graph_node, node_names
from pdr_ros2.param_text import dump_text, get_text, list_lines, python_value

SERVICE_TIMEOUT_S = 5.0       # ros2param/api: client.wait_for_service(timeout_sec=5.0)
# How long a verb waits for the node it names [s] (set/dump: --timeout's default; ros2cli's
# is 1 s, with a daemon that has seen the graph already): a new participant of Fast DDS
# sees a node 0-2.8 s after its start (measured on an idle pocket_pdr, 2 cores).
NODE_WAIT_S = 4
NODE_NOT_FOUND = "Node not found"
NOT_SET = "Parameter not set"
NO_SERVICE = "Wait for service timed out"


class ParamError(Exception):
    """A failure in ros2param's words; the verb returns its text (exit 1)."""


def absolute_name(node_name: str) -> str:
    """``ros2node.api.get_absolute_node_name``: ``pocket_pdr`` -> ``/pocket_pdr``."""
    return node_name if node_name.startswith("/") else "/" + node_name


def spin_until(node, ready, timeout_s: float) -> bool:
    """True once ``ready()`` holds, spinning ``node`` in steps of 0.05 s up to
    ``timeout_s`` [s] (``ros2node.api.wait_for_node``'s loop)."""
    import rclpy

    deadline = time.monotonic() + timeout_s
    while not ready():
        if time.monotonic() >= deadline:
            return False
        rclpy.spin_once(node, timeout_sec=0.05)
    return True


def client_for(node, node_name: str, wait_s: float):
    """An AsyncParameterClient of ``node_name`` with its services up; ParamError when the
    node is not in the graph after ``wait_s`` [s] or its services do not appear."""
    from rclpy.parameter_client import AsyncParameterClient

    full_name = absolute_name(node_name)
    if not spin_until(node, lambda: full_name in node_names(node), wait_s):
        raise ParamError(NODE_NOT_FOUND)
    client = AsyncParameterClient(node, full_name)
    if not spin_until(node, client.services_are_ready, SERVICE_TIMEOUT_S):
        raise ParamError(NO_SERVICE)
    return client


def answer(node, future):
    """The response of a service call, spinning ``node`` for it up to SERVICE_TIMEOUT_S."""
    import rclpy

    rclpy.spin_until_future_complete(node, future, timeout_sec=SERVICE_TIMEOUT_S)
    if not future.done():
        raise ParamError(f"No answer from the node's parameter service in "
                         f"{SERVICE_TIMEOUT_S} s")
    if future.result() is None:
        raise ParamError(f"Exception while calling service: {future.exception()}")
    return future.result()


def param_list(args) -> str | None:
    """``ros2 param list [NODE] [--param-type]``: each node's sorted names, under a
    ``/node:`` line when no NODE is given (every node with parameter services)."""
    try:
        with graph_node(0.0 if args.node_name else args.spin_time) as node:
            if args.node_name:
                nodes = [absolute_name(args.node_name)]
            else:
                services = {name for name, _ in node.get_service_names_and_types()}
                nodes = sorted(n for n in node_names(node) if f"{n}/list_parameters" in services)
            for full_name in nodes:
                client = client_for(node, full_name, args.spin_time + NODE_WAIT_S)
                lines = parameter_lines(node, client, args.param_type)
                shown = lines if args.node_name else [f"{full_name}:", *lines]
                if shown:
                    print("\n".join(shown))
    except ParamError as error:
        return str(error)
    return None


def parameter_lines(node, client, with_types: bool) -> list[str]:
    """One node's ``param list`` lines, typed by ``describe_parameters`` when asked."""
    names = list(answer(node, client.list_parameters()).result.names)
    if not with_types:
        return list_lines(names)
    described = answer(node, client.describe_parameters(names)).descriptors
    return list_lines(names, {d.name: d.type for d in described})


def param_get(args) -> str | None:
    """``ros2 param get NODE NAME [--hide-type]``: ``Double value is: 0.25``."""
    try:
        with graph_node(0.0) as node:
            client = client_for(node, args.node_name, args.spin_time + NODE_WAIT_S)
            values = answer(node, client.get_parameters([args.parameter_name])).values
        if not values:
            return NOT_SET
        print(get_text(values[0], args.hide_type))
    except (ParamError, ValueError) as error:
        return str(error)
    return None


def param_set(args) -> str | None:
    """``ros2 param set NODE NAME VALUE``: the node's verdict."""
    from rcl_interfaces.msg import Parameter
    from rclpy.parameter import get_parameter_value

    parameter = Parameter(name=args.parameter_name,
                          value=get_parameter_value(string_value=args.value))
    try:
        with graph_node(0.0) as node:
            client = client_for(node, args.node_name, args.spin_time + args.timeout)
            [result] = answer(node, client.set_parameters([parameter])).results
    except ParamError as error:
        return str(error)
    verdict = "Set parameter successful" if result.successful else "Setting parameter failed"
    verdict += f": {result.reason}" if result.reason else ""
    if not result.successful:
        return verdict
    print(verdict)
    return None


def param_dump(args) -> str | None:
    """``ros2 param dump NODE``: the node's parameters as a params file on stdout."""
    full_name = absolute_name(args.node_name)
    try:
        with graph_node(0.0) as node:
            client = client_for(node, full_name, args.spin_time + args.timeout)
            names = sorted(answer(node, client.list_parameters()).result.names)
            values = answer(node, client.get_parameters(names)).values
    except ParamError as error:
        return str(error)
    print(dump_text(full_name, {name: python_value(value)
                                for name, value in zip(names, values, strict=True)}))
    return None
