"""``ros2 launch PKG FILE [name:=value ...]`` (or ``ros2 launch PATH [name:=value ...]``)
as ``ros2launch`` takes it: FILE is looked for under ``share/PKG`` and its sub-folders
(one match, or an error), the arguments are ``name:=value``; ``-s`` prints the file's
arguments. The file is read by :mod:`pdr_ros2.launch_description` (XML or YAML front
end) and run by :mod:`pdr_ros2.launch_runner`."""
from __future__ import annotations

import os
from pathlib import Path
from xml.etree import ElementTree

from pdr_ros2.launch_description import load_root, read_launch
from pdr_ros2.launch_runner import SIGKILL_TIMEOUT_S, SIGTERM_TIMEOUT_S, LaunchRunner
from pdr_ros2.launch_substitutions import LaunchError

ASSIGN = ":="
TIMEOUTS = {"sigterm_timeout": SIGTERM_TIMEOUT_S, "sigkill_timeout": SIGKILL_TIMEOUT_S}


def add(commands) -> None:
    """The ``launch`` command's parser."""
    parsed = commands.add_parser("launch", help="Run a launch file",
                                 description="Run a launch file (XML or YAML front end)")
    parsed.add_argument("-s", "--show-args", "--show-arguments", action="store_true",
                        help="Show arguments that may be given to the launch file")
    parsed.add_argument("package_name", help="Name of the ROS package which contains the "
                                             "launch file, or the launch file's path")
    parsed.add_argument("launch_file_name", nargs="?",
                        help="Name of the launch file")
    parsed.add_argument("launch_arguments", nargs="*",
                        help="Arguments to the launch file; '<name>:=<value>'")
    parsed.set_defaults(verb=launch)


def launch(args) -> str | None:
    """Run (or, under ``-s``, describe) the launch file; an error's text, or None."""
    try:
        path, arguments = launch_file(args)
        if args.show_args:
            print(arguments_text(path))
            return None
        timeouts = {name: float(arguments.pop(name, default))
                    for name, default in TIMEOUTS.items()}
        described = read_launch(path, arguments)
    except (LaunchError, ValueError) as error:
        return str(error)
    status = LaunchRunner(described.processes, timeouts["sigterm_timeout"],
                          timeouts["sigkill_timeout"]).run()
    return None if status == 0 else status


def launch_file(args) -> tuple[Path, dict[str, str]]:
    """The launch file's path and the ``name:=value`` arguments, as ros2launch reads the
    command line: a first argument that is a file is the launch file itself."""
    words = [args.launch_file_name] if args.launch_file_name else []
    if os.path.isfile(args.package_name):
        path = Path(args.package_name)
    elif not words:
        raise LaunchError(f"'{args.package_name}' is not a file; give a package and a launch "
                          "file name")
    else:
        path = share_file(args.package_name, words.pop(0))
    return path, launch_arguments([*words, *args.launch_arguments])


def launch_arguments(words: list[str]) -> dict[str, str]:
    """``name:=value`` words as a mapping; ros2launch's error for any other word."""
    arguments = {}
    for word in words:
        name, assign, value = word.partition(ASSIGN)
        if not (assign and name):
            raise LaunchError(f"malformed launch argument '{word}', expected format "
                              f"'<name>{ASSIGN}<value>'")
        arguments[name] = value
    return arguments


def share_file(package: str, file_name: str) -> Path:
    """The one file named ``file_name`` under the package's share folder."""
    from ament_index_python.packages import (
        PackageNotFoundError,
        get_package_share_directory,
    )

    try:
        share = get_package_share_directory(package)
    except PackageNotFoundError:
        raise LaunchError(f"Package '{package}' not found") from None
    found = sorted(Path(folder) / name for folder, _, names in os.walk(share)
                   for name in names if name == file_name)
    if not found:
        raise LaunchError(f"file '{file_name}' was not found in the share directory of "
                          f"package '{package}' which is at '{share}'")
    if len(found) > 1:
        raise LaunchError(f"Multiple launch files with the same name: "
                          f"{', '.join(map(str, found))}")
    return found[0]


def arguments_text(path: Path) -> str:
    """``-s``: the ``<arg>`` elements the file declares (not those of its includes), as
    ros2launch prints them."""
    declared = list(declared_arguments(load_root(path)))
    if not declared:
        return "No arguments."
    lines = [f"Arguments (pass arguments as '<name>{ASSIGN}<value>'):", ""]
    for element in declared:
        lines += [f"    '{element.get('name')}':",
                  f"        {element.get('description') or 'no description given'}",
                  f"        (default: '{element.get('default')}')" if "default" in element.attrib
                  else "        (required)", ""]
    return "\n".join(lines)


def declared_arguments(parent: ElementTree.Element):
    """The ``<arg>`` declarations under ``parent`` (an ``<include>``'s are values)."""
    for child in parent:
        if child.tag == "arg":
            yield child
        elif child.tag != "include":
            yield from declared_arguments(child)
