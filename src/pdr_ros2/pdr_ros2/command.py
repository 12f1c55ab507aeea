"""The ``ros2`` console script: ros2cli's syntax for the verbs this workspace offers.

It steps aside first: when another ``ros2`` (not a pdr_ros2 one) is on the PATH, a real
ROS 2 install's, it is executed with the same arguments, so ``./ws ros2 ...`` (which finds
this script in install/) and a PATH on which this one comes first still run the real one.

Each command's parser is in its module (``cli_run``, ``cli_node``, ...). As ros2cli's main,
an error is one line on stderr and exit status 1, Ctrl-C exit status 2 (SIGINT).
"""
from __future__ import annotations

import argparse
import os
import shutil
import signal
import sys
from pathlib import Path

from pdr_ros2 import cli_bag, cli_launch, cli_node, cli_param, cli_run, cli_service, cli_topic
from pdr_ros2.cli_parsers import StandInParser

DESCRIPTION = """\
ros2 of the pdr stack: NOT ros2cli. A stand-in for a workspace whose ROS 2 comes from
PyPI wheels (rclpy without ros2cli), with ros2cli's syntax and output format for:
  ros2 run PKG EXE [args]
  ros2 launch PKG FILE [name:=value ...] (XML or YAML launch files)
  ros2 node list
  ros2 topic list [-t]
  ros2 topic echo TOPIC [--once] [--csv]
  ros2 topic hz TOPIC [--window N]
  ros2 topic info TOPIC [-v]
  ros2 service list [-t]
  ros2 service call SERVICE TYPE [VALUES]
  ros2 param list [NODE] [--param-type]
  ros2 param get NODE PARAM
  ros2 param set NODE PARAM VALUE
  ros2 param dump NODE
  ros2 bag info BAG
  ros2 bag play BAG [--topics T ...] [-r RATE] [--clock]
  ros2 bag record [-o OUT] TOPIC ...
Where a real ros2 is on the PATH, that one runs instead of this one."""
SHIM_FOLDER = "lib/pdr_ros2"       # where colcon installs this script (setup.cfg)
COMMANDS = (cli_run, cli_launch, cli_node, cli_topic, cli_service, cli_param,
            cli_bag)   # in the order -h lists them


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


def parser() -> argparse.ArgumentParser:
    """The argparse tree: one module per command, each adding its own verbs."""
    top = StandInParser(prog="ros2", description=DESCRIPTION,
                        formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = top.add_subparsers(title="commands", metavar="COMMAND", required=True)
    for command in COMMANDS:
        command.add(commands)
    return top
