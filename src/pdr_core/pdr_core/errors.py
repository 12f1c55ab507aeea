"""Errors for bad input, and how command-line tools report them.

Every problem with user input (a file, a topic, a column, a parameter) is raised as
:class:`InputError`, whose message is one line that names the source and the problem.
CLIs turn it into that line on stderr and exit status 2 (:func:`run_cli`).
"""
from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence


class InputError(Exception):
    """Input that cannot be used: ``source`` (a path, topic or key) and what is wrong."""

    def __init__(self, source: object, problem: str) -> None:
        self.source = str(source)
        self.problem = problem
        super().__init__(f"{self.source}: {problem}")


EXIT_INPUT_ERROR = 2


def run_cli(prog: str, main: Callable[[Sequence[str] | None], int],
            argv: Sequence[str] | None = None) -> int:
    """Run ``main(argv)``; an :class:`InputError` becomes one line on stderr and exit 2."""
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
