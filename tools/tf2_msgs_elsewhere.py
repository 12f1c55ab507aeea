"""Where a tf2_msgs outside this workspace is, if there is one (issue 42).

tf2_msgs is not among the PyPI wheels, so src/tf2_msgs builds its TFMessage; but a
tf2_msgs installed elsewhere (a ROS install, or a wheel in the venv) must be the one used.
tools/bootstrap.sh runs this with the venv's Python and the venv on AMENT_PREFIX_PATH, and
skips src/tf2_msgs when it prints a location:

    python tools/tf2_msgs_elsewhere.py WORKSPACE

prints the first tf2_msgs found outside WORKSPACE/install and WORKSPACE/build (a previous
build of ours is not "elsewhere"): a prefix on AMENT_PREFIX_PATH whose ament index lists
it, else the folder of a ``tf2_msgs`` Python package with a ``msg`` subpackage on this
Python's path. It prints nothing when there is none. Nothing is imported.
"""
from __future__ import annotations

import os
import sys
from collections.abc import Iterable
from pathlib import Path

MARKER = Path("share", "ament_index", "resource_index", "packages", "tf2_msgs")
MODULE = Path("tf2_msgs", "msg", "__init__.py")


def ours(workspace: Path) -> list[Path]:
    """The folders a build of the workspace's own tf2_msgs lives in."""
    root = workspace.resolve()
    return [root / "install", root / "build"]


def inside(path: Path, folders: list[Path]) -> bool:
    resolved = path.resolve()
    return any(resolved.is_relative_to(folder) for folder in folders)


def elsewhere(ament_prefix_path: Iterable[str], python_path: Iterable[str],
              workspace: Path) -> Path | None:
    """The first tf2_msgs outside the workspace's install and build folders: an ament
    prefix that registers it, else a Python path entry that holds ``tf2_msgs/msg``."""
    excluded = ours(workspace)
    for entry in ament_prefix_path:
        prefix = Path(entry)
        if entry and (prefix / MARKER).is_file() and not inside(prefix, excluded):
            return prefix
    for entry in python_path:
        folder = Path(entry or os.curdir)
        module = folder / MODULE
        if module.is_file() and not inside(folder, excluded) and not inside(module, excluded):
            return folder / "tf2_msgs"
    return None


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    found = elsewhere(os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep),
                      sys.path[1:], Path(argv[0]))
    if found is not None:
        print(found)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
