"""Errors for bad input, and how command-line tools report them.

Every problem with user input (a file, a topic, a column, a parameter) is raised as
:class:`InputError`, whose message is one line that names the source and the problem.
CLIs turn it into that line on stderr and exit status 2 (:func:`run_cli`). Input used in
part is an :class:`InputWarning`, one line on stderr.
"""
from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Callable, Sequence


class InputError(Exception):
    """Input that cannot be used: ``source`` (a path, topic or key) and what is wrong."""

    def __init__(self, source: object, problem: str) -> None:
        self.source = str(source)
        self.problem = problem
        super().__init__(f"{self.source}: {problem}")


class InputWarning(UserWarning):
    """Input used in part (a recording cut short, read up to its damage): ``source`` and
    what was recovered. Raised with :func:`warnings.warn`; CLIs print it as one line."""

    def __init__(self, source: object, problem: str) -> None:
        self.source = str(source)
        self.problem = problem
        super().__init__(f"{self.source}: {problem}")


EXIT_INPUT_ERROR = 2


def run_cli(prog: str, main: Callable[[Sequence[str] | None], int],
            argv: Sequence[str] | None = None) -> int:
    """Run ``main(argv)``; an :class:`InputError` becomes one line on stderr and exit 2,
    an :class:`InputWarning` one line on stderr."""
    def show(message, category, *_args, **_kwargs) -> None:
        kind = "warning" if issubclass(category, InputWarning) else category.__name__
        print(f"{prog}: {kind}: {message}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = show
        warnings.simplefilter("always", InputWarning)
        try:
            return main(argv)
        except InputError as exc:
            print(f"{prog}: error: {exc}", file=sys.stderr)
            return EXIT_INPUT_ERROR


def dispatch(prog: str, parser: argparse.ArgumentParser,
             argv: Sequence[str] | None = None) -> None:
    """Parse ``argv`` and exit with the status of the chosen subcommand's ``func``."""
    def main(args: Sequence[str] | None) -> int:
        namespace = parser.parse_args(args)
        return namespace.func(namespace)

    sys.exit(run_cli(prog, main, argv))
