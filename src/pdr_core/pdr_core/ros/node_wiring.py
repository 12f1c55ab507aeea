"""The start-up line of a node: the names it subscribes to, publishes, serves and calls,
resolved (namespace and remappings applied), so a graph wired wrong shows itself in the
first lines of the log. Duck-typed on rclpy's ``Node`` (no rclpy import here)."""
from __future__ import annotations

# what rclpy creates on every node
RCLPY_PUBLISHERS = frozenset({"/parameter_events", "/rosout"})
RCLPY_SERVICES = ("/describe_parameters", "/get_parameters", "/get_parameter_types",
                  "/list_parameters", "/set_parameters", "/set_parameters_atomically",
                  "/get_type_description")


def wiring(node) -> str:
    """"subscribes A, B; publishes C; serves D; calls E": the node's own endpoints with
    their resolved names, each list sorted, empty ones left out."""
    services = [node.resolve_service_name(s.srv_name) for s in node.services]
    lists = (("subscribes", [s.topic_name for s in node.subscriptions]),
             ("publishes", [p.topic_name for p in node.publishers
                            if p.topic_name not in RCLPY_PUBLISHERS]),
             ("serves", [s for s in services if not s.endswith(RCLPY_SERVICES)]),
             ("calls", [node.resolve_service_name(c.srv_name) for c in node.clients]))
    return "; ".join(f"{verb} {', '.join(sorted(names))}" for verb, names in lists if names)
