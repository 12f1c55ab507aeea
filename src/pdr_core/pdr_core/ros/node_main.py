"""The ``main()`` every estimator node shares: init, spin, clean shutdown.

rclpy is imported inside the function, so that pdr_core stays importable (and testable)
without ROS; only node modules call this.
"""
from __future__ import annotations

import itertools
import os
import sys
from collections.abc import Callable
from pathlib import Path

import yaml

from pdr_core.config_files import shipped_config_dir
from pdr_core.errors import InputError

SHUTDOWN_POLL_S = 0.5
"""The longest the executor waits before it checks whether the node was shut down [s]."""


def use_fast_acks() -> None:
    """Point Fast DDS at the shipped profile of 5 ms heartbeats
    (config/fast_acks_fastdds.xml) unless the user chose a profile already; call before
    ``rclpy.init``. With the default 3 s heartbeats a reliable writer learns of an
    acknowledgement only at its next heartbeat: ``bag_play`` at rate 0 and the nodes'
    acknowledged slices (pdr_core.ros.backlog.publish_acked) then wait, and the
    ``bags/pocket_walk`` graph took 60 s instead of 4 s."""
    profile = shipped_config_dir("pdr_core") / "fast_acks_fastdds.xml"
    os.environ.setdefault("FASTRTPS_DEFAULT_PROFILES_FILE", str(profile))


def spin_node(name: str, make_node: Callable, args: list[str] | None = None) -> None:
    """Fast acknowledgements (:func:`use_fast_acks`), rclpy.init, spin the node
    ``make_node()`` until shutdown, exit: status 2 with one
    line ``NAME: error: ...`` when its configuration is refused (InputError, and a
    ``--params-file`` that is no ROS parameter file: :func:`check_params_files`), 0 on SIGINT,
    SIGTERM or an external shutdown. rclpy's signal handler shuts the context down at
    once, so a callback running at that moment may fail to publish on it: an error raised
    once the context is no longer ok is part of the shutdown, not a failure (seen as a
    rare exit status 1 of pocket_pdr on SIGINT in the tests). The executor waits at most
    :data:`SHUTDOWN_POLL_S` at a time and checks the context in between: a node left
    waiting after its context was shut down (pocket_pdr and zupt_ekf, rarely, kept
    spinning after a SIGINT in the fresh-clone runs until a second one) then exits."""
    import rclpy
    from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor

    node = None
    status = 0
    use_fast_acks()
    try:
        check_params_files(args)
        rclpy.init(args=args)
        node = make_node()
        executor = SingleThreadedExecutor()
        executor.add_node(node)
        while rclpy.ok():
            executor.spin_once(timeout_sec=SHUTDOWN_POLL_S)
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


def check_params_files(args: list[str] | None) -> None:
    """Refuse, in one line (InputError), a ``--params-file`` of the ROS arguments (``args``,
    or the command line's) that is no ROS parameter file: a mapping of node names (and
    namespaces) to ``ros__parameters``. rcl's own refusal of one is a traceback, and the
    usual cause is a navigator configuration given where a parameter file goes."""
    argv = sys.argv[1:] if args is None else args
    for flag, path in itertools.pairwise(argv):
        if flag != "--params-file":
            continue
        try:
            content = yaml.safe_load(Path(path).read_text())
        except (OSError, yaml.YAMLError) as exc:
            raise InputError(f"--params-file {path}", f"cannot be read: {exc}") from None
        if not _parameter_tree(content):
            raise InputError(f"--params-file {path}", (
                "not a ROS parameter file (it needs NODE_NAME: ros__parameters: ..., as "
                "each package's config/*_params.yaml or zupt_ekf.yaml); a navigator or "
                f"estimator configuration is passed as -p config:={path}"))


def _parameter_tree(node) -> bool:
    """A mapping whose every branch reaches ``ros__parameters`` (a mapping) through node
    names and namespaces, as rcl reads a parameter file."""
    return isinstance(node, dict) and bool(node) and all(
        isinstance(value, dict) if key == "ros__parameters" else _parameter_tree(value)
        for key, value in node.items())
