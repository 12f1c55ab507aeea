"""The launch front ends' substitutions, ``$(name args...)`` in an attribute's text.

Those the project's launch files use, as ROS 2 launch evaluates them (``launch`` and
``launch_ros``'s ``substitutions/``): ``$(var NAME)`` (a launch argument or ``let``),
``$(find-pkg-share PKG)``, ``$(find-pkg-prefix PKG)``, ``$(env NAME [DEFAULT])`` and
``$(dirname)`` (the folder of the launch file being read). Substitutions nest:
``$(find-pkg-share $(var package))``. Any other name is refused with its name; a launch
file that parses here therefore also runs with the real ``ros2 launch``.
"""
from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass

OPEN = "$("
CLOSE = ")"


class LaunchError(ValueError):
    """A launch file this runner cannot run: the text says where and why."""


@dataclass(frozen=True)
class Scope:
    """What a substitution reads: the launch configurations (``arg`` and ``let``
    values) and the folder of the file being read."""

    variables: Mapping[str, str]
    folder: str


def substitute(text: str, scope: Scope) -> str:
    """``text`` with every ``$(...)`` replaced by its value (innermost first)."""
    out, rest = [], text
    while (start := rest.find(OPEN)) >= 0:
        end = closing(rest, start)
        out.append(rest[:start])
        inner = substitute(rest[start + len(OPEN):end], scope)
        out.append(evaluate(inner.split(), scope, text))
        rest = rest[end + len(CLOSE):]
    out.append(rest)
    return "".join(out)


def closing(text: str, start: int) -> int:
    """The index of the ``)`` closing the ``$(`` at ``start`` (nested ones counted)."""
    depth = 0
    for index in range(start, len(text)):
        if text.startswith(OPEN, index):
            depth += 1
        elif text[index] == CLOSE:
            depth -= 1
            if depth == 0:
                return index
    raise LaunchError(f"unclosed substitution in {text!r}")


def evaluate(words: list[str], scope: Scope, text: str) -> str:
    """One substitution's value: ``words`` are its name and arguments."""
    if not words or words[0] not in SUBSTITUTIONS:
        raise LaunchError(f"unknown substitution {words[0] if words else ''!r} in {text!r} "
                          f"(supported: {', '.join(sorted(SUBSTITUTIONS))})")
    name, *args = words
    expected, function = SUBSTITUTIONS[name]
    if len(args) not in expected:
        raise LaunchError(f"$({name}) takes {' or '.join(map(str, expected))} argument(s), "
                          f"got {len(args)} in {text!r}")
    return function(scope, *args)


def variable(scope: Scope, name: str) -> str:
    """``$(var NAME)``: a launch configuration; an unknown one is an error, as in launch."""
    try:
        return scope.variables[name]
    except KeyError:
        raise LaunchError(f"launch configuration '{name}' does not exist") from None


def package_share(scope: Scope, package: str) -> str:
    """``$(find-pkg-share PKG)``: the package's share folder (ament index)."""
    return os.path.join(package_prefix(scope, package), "share", package)


def package_prefix(scope: Scope, package: str) -> str:
    """``$(find-pkg-prefix PKG)``: the package's install prefix (ament index)."""
    from ament_index_python.packages import PackageNotFoundError, get_package_prefix

    try:
        return get_package_prefix(package)
    except PackageNotFoundError:
        raise LaunchError(f"package '{package}' not found") from None


def environment(scope: Scope, name: str, *default: str) -> str:
    """``$(env NAME [DEFAULT])``: an unset variable without a default is an error."""
    if name in os.environ:
        return os.environ[name]
    if default:
        return default[0]
    raise LaunchError(f"environment variable '{name}' does not exist")


def folder(scope: Scope) -> str:
    """``$(dirname)``: the folder of the launch file being read."""
    return scope.folder


SUBSTITUTIONS: dict[str, tuple[tuple[int, ...], Callable[..., str]]] = {
    "var": ((1,), variable),
    "find-pkg-share": ((1,), package_share),
    "find-pkg-prefix": ((1,), package_prefix),
    "env": ((1, 2), environment),
    "dirname": ((0,), folder),
}
