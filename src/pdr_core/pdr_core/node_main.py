"""The ``main()`` every estimator node shares: init, spin, clean shutdown.

rclpy is imported inside the function, so that pdr_core stays importable (and testable)
without ROS; only node modules call this.
"""
from __future__ import annotations

import sys
from collections.abc import Callable

from pdr_core.errors import InputError


def spin_node(name: str, make_node: Callable, args: list[str] | None = None) -> None:
    """rclpy.init, spin the node ``make_node()`` until shutdown, exit: status 2 with one
    line ``NAME: error: ...`` when its configuration is refused (InputError), 0 on SIGINT,
    SIGTERM or an external shutdown. rclpy's signal handler shuts the context down at
    once, so a callback running at that moment may fail to publish on it: an error raised
    once the context is no longer ok is part of the shutdown, not a failure (seen as a
    rare exit status 1 of pocket_pdr on SIGINT in the tests)."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    rclpy.init(args=args)
    node = None
    status = 0
    try:
        node = make_node()
        rclpy.spin(node)
    except InputError as exc:
        print(f"{name}: error: {exc}", file=sys.stderr)
        status = 2
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except Exception:
        if rclpy.ok():
            raise
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    sys.exit(status)
