"""``ros2 run PKG EXE [args]``: execute ``<prefix of PKG>/lib/PKG/EXE`` in place of this
process (ros2run starts it as a child and searches lib/PKG's sub-folders too); its errors
are ros2run's: ``Package 'PKG' not found``, ``No executable found``."""
from __future__ import annotations

import argparse
import os


def add(commands) -> None:
    """The ``run`` command's parser."""
    run_cmd = commands.add_parser("run", help="Run a package specific executable")
    run_cmd.add_argument("package_name", help="Name of the ROS package")
    run_cmd.add_argument("executable_name", help="Name of the executable")
    run_cmd.add_argument("argv", nargs=argparse.REMAINDER,
                         help="Pass arbitrary arguments to the executable")
    run_cmd.set_defaults(verb=run)


def executable_path(package: str, executable: str) -> str:
    """``<prefix>/lib/PACKAGE/EXECUTABLE``; ValueError with ros2run's words when the
    package or the executable is missing."""
    from ament_index_python.packages import PackageNotFoundError, get_package_prefix

    try:
        prefix = get_package_prefix(package)
    except PackageNotFoundError:
        raise ValueError(f"Package '{package}' not found") from None
    path = os.path.join(prefix, "lib", package, executable)
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        raise ValueError("No executable found")
    return path


def run(args) -> str:
    """``ros2 run``: execute PKG's EXE with the remaining arguments (returns an error)."""
    try:
        path = executable_path(args.package_name, args.executable_name)
    except ValueError as error:
        return str(error)
    os.execv(path, [path, *args.argv])
