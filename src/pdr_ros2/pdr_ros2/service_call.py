"""``ros2 service call SERVICE TYPE [VALUES]`` as ros2cli's ``ros2service/verb/call.py``
(Jazzy) does it: the request filled from VALUES, a YAML mapping of its fields (``{}``:
the defaults; pdr_core.ros.message_fields), sent once, and printed as
``requester: making request: <repr of the request>``, a blank line, ``response:``, the
response's repr and a blank line (the generated classes' ``__repr__``). A service that is
not there yet is waited for, after ``waiting for service to become available...``.

Errors in ros2cli's words: ``The passed service type is invalid``, ``The passed type is
not a service``, ``Failed to populate field: <why>``; a VALUES text that is not YAML is
one too (ros2cli stops with a traceback). The request is filled before the node starts,
its setters checking sizes and ranges (``check_fields=True``), so that a bad value is
a ``Failed to populate field`` and not a failed serialization.
Not supported: ``--rate``, ``--stdin``, ``auto``/``now`` stamps, the QoS options.
"""
from __future__ import annotations

from typing import Any

from pdr_core.ros.message_fields import FIELD_ERRORS, set_message_fields, yaml_values
from pdr_core.ros.ros_types import message_class
from pdr_ros2.graph import NODE_NAME_PREFIX, graph_node

INVALID_TYPE = "The passed service type is invalid"
NOT_A_SERVICE = "The passed type is not a service"
WAITING = "waiting for service to become available..."


def service_call(args) -> str | None:
    """Call ``args.service_name`` once with the request of ``args.values``; print the
    request and the response (returns the error text, or None)."""
    try:
        service, request = filled_request(args.service_type, args.values)
    except ValueError as error:
        return str(error)
    parts = args.service_type.split("/")
    return call_once(service, request, args.service_name,
                     f"{NODE_NAME_PREFIX}_requester_{parts[0]}_{parts[-1]}")


def filled_request(service_type: str, values: str) -> tuple[Any, Any]:
    """The service class of ``service_type`` and its request filled from the YAML text
    ``values``; ValueError with ros2cli's words when either cannot be."""
    service = service_class(service_type)
    request = service.Request(check_fields=True)
    try:
        set_message_fields(request, yaml_values(values))
    except FIELD_ERRORS as error:
        raise ValueError(f"Failed to populate field: {error}") from None
    return service, request


def call_once(service: Any, request: Any, service_name: str, node_name: str) -> str | None:
    """Send ``request`` to ``service_name`` from a node ``node_name``, once the service is
    there, and print the request and the response (returns the error text, or None)."""
    import rclpy

    with graph_node(0.0, node_name) as node:
        client = node.create_client(service, service_name)
        if not client.service_is_ready():
            print(WAITING, flush=True)
            client.wait_for_service()
        print(f"requester: making request: {request!r}\n", flush=True)
        future = client.call_async(request)
        rclpy.spin_until_future_complete(node, future)
        if future.result() is None:
            return f"Exception while calling service: {future.exception()!r}"
        print(f"response:\n{future.result()!r}\n")
    return None


def service_class(service_type: str) -> Any:
    """The generated class of ``pkg/srv/Name`` (or ``pkg/Name``); ValueError in ros2cli's
    words when it is not found or is no service."""
    parts = service_type.split("/")
    if len(parts) == 2:
        parts.insert(1, "srv")
    try:
        service = message_class("/".join(parts))
    except (AttributeError, ImportError, ValueError):
        raise ValueError(INVALID_TYPE) from None
    if not (hasattr(service, "Request") and hasattr(service, "Response")):
        raise ValueError(NOT_A_SERVICE)
    return service
