"""Errors for bad input, and how command-line tools report them.

Every problem with user input (a file, a topic, a column, a parameter) is raised as
:class:`InputError`, whose message is one line that names the source and the problem.
CLIs turn it into that line on stderr and exit status 2 (:func:`run_cli`). Input used in
part is an :class:`InputWarning`, one line on stderr.

Every CLI's parser is a :class:`CliParser` (:func:`cli_parser`): its ``--help`` and each
subcommand's show every option's default (:class:`DefaultsHelpFormatter`) and no RST
markup (:func:`plain_text`).
"""
from __future__ import annotations

import argparse
import re
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


# RST roles (:class:`x`, :func:`x`) and inline literals (``x``, `x`) of a docstring
_RST_ROLE = re.compile(r":[a-z]+:`~?([^`]+)`")
_RST_LITERAL = re.compile(r"``([^`]+)``|`([^`]+)`")


def plain_text(text: str) -> str:
    """``text`` (a docstring line) without RST markup: :func:`x` and ``x`` become x."""
    text = _RST_ROLE.sub(r"\1", text)
    return _RST_LITERAL.sub(lambda m: m.group(1) or m.group(2), text)


class DefaultsHelpFormatter(argparse.HelpFormatter):
    """argparse's formatter with each option's default after its help text, as
    ``(default: VALUE)``: not for flags (options without a value), defaults that mean
    "not given" (None, an empty sequence), nor where the text already names its default."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        default = action.default
        if (not action.option_strings or action.nargs == 0 or "default" in text
                or default is argparse.SUPPRESS or default is None or default == ()
                or default == []):
            return text
        shown = ",".join(map(str, default)) if isinstance(default, (list, tuple)) \
            else str(default)
        return f"{text} (default: {shown.replace('%', '%%')})"


class CliParser(argparse.ArgumentParser):
    """An argument parser whose subcommands' parsers are CliParsers too (argparse's
    ``add_subparsers`` makes them of the parser's class), formatted by
    :class:`DefaultsHelpFormatter`."""

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("formatter_class", DefaultsHelpFormatter)
        super().__init__(*args, **kwargs)


def cli_parser(prog: str, doc: str) -> CliParser:
    """The top-level parser of the CLI ``prog``, described by the first line of its
    module docstring ``doc`` as plain text."""
    return CliParser(prog=prog, description=plain_text(doc.strip().split("\n")[0]))
