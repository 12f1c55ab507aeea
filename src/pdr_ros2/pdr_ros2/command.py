"""The ``ros2`` console script: ros2cli's syntax for the verbs this workspace offers.

It steps aside first: when another ``ros2`` (not a pdr_ros2 one) is on the PATH, a real
ROS 2 install's, it is executed with the same arguments, so ``./ws ros2 ...`` (which finds
this script in install/) and a PATH on which this one comes first still run the real one.

``ros2 run PKG EXE [args]`` executes ``<prefix of PKG>/lib/PKG/EXE`` in place of this
process (ros2run starts it as a child and searches lib/PKG's sub-folders too); its errors
are ros2run's: ``Package 'PKG' not found``, ``No executable found``. As ros2cli's main,
an error is one line on stderr and exit status 1, Ctrl-C exit status 2 (SIGINT).
"""
from __future__ import annotations

import argparse
import os
import shutil
import signal
import sys
from pathlib import Path

from pdr_core.ros.message_yaml import ECHO_TRUNCATE_LENGTH
from pdr_ros2.graph import DISCOVERY_S, node_list, topic_list
from pdr_ros2.topic_echo import topic_echo

DESCRIPTION = """\
ros2 of the pdr stack: NOT ros2cli. A stand-in for a workspace whose ROS 2 comes from
PyPI wheels (rclpy without ros2cli), with ros2cli's syntax and output format for:
  ros2 run PKG EXE [args]
  ros2 node list
  ros2 topic list [-t]
  ros2 topic echo TOPIC [--once] [--csv]
Where a real ros2 is on the PATH, that one runs instead of this one."""
SHIM_FOLDER = "lib/pdr_ros2"       # where colcon installs this script (setup.cfg)


def main(argv: list[str] | None = None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    real = real_ros2()
    if real is not None:
        os.execv(real, [real, *argv])
    args = parser().parse_args(argv)
    try:
        error = args.verb(args)
    except KeyboardInterrupt:
        sys.exit(signal.SIGINT)
    sys.exit(error)


def real_ros2() -> str | None:
    """The first ``ros2`` on the PATH that is not a pdr_ros2 script, or None."""
    for folder in os.environ.get("PATH", "").split(os.pathsep):
        found = shutil.which("ros2", path=folder)
        if found and not Path(found).resolve().parent.as_posix().endswith(SHIM_FOLDER):
            return found
    return None


def run(args) -> str:
    """``ros2 run``: execute PKG's EXE with the remaining arguments (returns an error)."""
    from ament_index_python.packages import PackageNotFoundError, get_package_prefix

    try:
        prefix = get_package_prefix(args.package_name)
    except PackageNotFoundError:
        return f"Package '{args.package_name}' not found"
    path = os.path.join(prefix, "lib", args.package_name, args.executable_name)
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        return "No executable found"
    os.execv(path, [path, *args.argv])


def parser() -> argparse.ArgumentParser:
    top = argparse.ArgumentParser(prog="ros2", description=DESCRIPTION,
                                  formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = top.add_subparsers(title="commands", metavar="COMMAND", required=True)
    run_cmd = commands.add_parser("run", help="Run a package specific executable")
    run_cmd.add_argument("package_name", help="Name of the ROS package")
    run_cmd.add_argument("executable_name", help="Name of the executable")
    run_cmd.add_argument("argv", nargs=argparse.REMAINDER,
                         help="Pass arbitrary arguments to the executable")
    run_cmd.set_defaults(verb=run)
    node_verbs = verbs(commands, "node", "Various node related sub-commands")
    graph_verb(node_verbs, "list", "Output a list of available nodes", node_list)
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
    return top


def verbs(commands, name: str, summary: str):
    """A command (``node``, ``topic``) and the sub-parsers of its verbs."""
    command = commands.add_parser(name, help=summary, description=summary)
    return command.add_subparsers(title="verbs", metavar="VERB", required=True)


def graph_verb(verb_parsers, name: str, summary: str, function) -> argparse.ArgumentParser:
    """A verb that asks the graph, with ros2cli's ``--spin-time``."""
    verb = verb_parsers.add_parser(name, help=summary, description=summary)
    verb.add_argument("--spin-time", type=float, default=DISCOVERY_S,
                      help="Spin time in seconds to wait for discovery")
    verb.set_defaults(verb=function)
    return verb
