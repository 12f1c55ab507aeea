"""``--help`` of every CLI and every subcommand (issue 29): exit 0 without a traceback, no
RST markup, text for every option, every default shown with its unit, and no citation of
a file the repository does not hold.

The subcommands are found from each CLI's own parser, so a new one is tested too. The
top-level commands run as the installed executables (install/PKG/lib/PKG/PROG, what
``./ws pdr-pocket --help`` runs once built), the subcommands by their CLI's ``main`` in
the test's process (wstest.cli).
"""
from __future__ import annotations

import argparse
import importlib
import re
import subprocess

import pytest

from wstest import CLIS, ROOT, cli, installed

RST_MARKUP = re.compile(r"``|`|:(class|func|meth|data|mod|attr):")
# Option names that carry their unit (--rest-s, --floor-height-m, --field-norm-ut)
UNIT_SUFFIX = re.compile(r"-(s|m|hz|ut|mps|ns|deg)$")


def subcommands(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()):
    """(path, parser) of ``parser`` and of every subcommand below it."""
    yield path, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from subcommands(sub, (*path, name))


COMMANDS = [(prog, path, sub) for prog, module in CLIS.items()
            for path, sub in subcommands(importlib.import_module(module).parser())]


def run_help(prog: str, path: tuple[str, ...]) -> subprocess.CompletedProcess:
    if path:
        return cli(prog, *path, "--help")
    return subprocess.run([installed(prog), "--help"], capture_output=True, text=True,
                          timeout=120, cwd=ROOT)


def entries(text: str) -> dict[str, str]:
    """The help text of each argument in ``text``, by its first option string (or its
    name for a positional): everything from its line to the next argument's."""
    found: dict[str, str] = {}
    key = None
    for line in text.splitlines():
        if re.match(r"^  \S", line):
            key = line.split()[0].rstrip(",")
            found[key] = line.strip()[len(line.split()[0]):]
        elif key is not None and line.startswith("   "):
            found[key] += " " + line.strip()
        elif not line.startswith("    "):
            key = None
    return found


@pytest.mark.parametrize("prog, path, sub", COMMANDS,
                         ids=[" ".join((prog, *path)) for prog, path, _ in COMMANDS])
def test_help(prog, path, sub):
    result = run_help(prog, path)
    assert result.returncode == 0, result.stderr
    assert result.stderr == "" and "Traceback" not in result.stdout
    assert not RST_MARKUP.search(result.stdout), RST_MARKUP.search(result.stdout)
    assert "INTERFACES.md" not in result.stdout, "not in the repository: docs/reports.md"
    assert result.stdout.startswith(f"usage: {' '.join((prog, *path))} ")
    texts = entries(result.stdout)
    for action in sub._actions:
        if isinstance(action, argparse._SubParsersAction):
            continue
        key = action.option_strings[0] if action.option_strings else \
            action.metavar or action.dest
        name = action.option_strings[-1] if action.option_strings else key
        assert action.help, f"{prog} {' '.join(path)} {name}: no help text"
        text = texts[key]
        # the invocation (option and metavar) is followed by words of its own
        words = text.replace(str(action.metavar or action.dest.upper()), "", 1)
        assert re.search(r"[a-z]{3}", words), f"{name}: no text in --help: {text!r}"
        meaningful = action.default not in (None, False, (), [], argparse.SUPPRESS)
        if action.option_strings and action.nargs != 0 and meaningful:
            assert "default" in text, f"{name}: default {action.default!r} not shown: {text}"
        if isinstance(action.default, float):
            assert "[" in text or UNIT_SUFFIX.search(name) or "dimensionless" in text, \
                f"{name}: default {action.default} without its unit: {text}"


def test_import_csv_help_shows_every_unit_and_its_default():
    text = " ".join(run_help("pdr-sim", ("import-csv",)).stdout.split())
    for shown in ("unit of the time column: s, ms, us (µs) or ns (default: s)",
                  "(m/s²), or g (9.80665 m/s²) (default: mps2)",
                  "radps or rad/s, degps or deg/s (default: radps)",
                  "ut (µT), nt (nT), t (T) or gauss (G) (default: ut)",
                  "unit of the position columns: m, cm or mm (default: m)",
                  "added to every stamp [s] (default: 0.0)", "--force"):
        assert shown in text, shown


def test_pocket_help_no_longer_fails_on_percent_signs():
    """The defect as reported: ``./ws pdr-pocket --help`` ended in ValueError: incomplete
    format (an unescaped % in two subcommands' help)."""
    result = run_help("pdr-pocket", ())
    assert result.returncode == 0 and "ValueError" not in result.stderr
    assert "undetected and false steps in percent" in " ".join(result.stdout.split())


# The one flag vocabulary: --overwrite replaces an existing output, --force accepts data
# that fail a plausibility check
WRITES_A_BAG = {("pdr-sim", "generate"), ("pdr-sim", "import-csv"), ("pdr-sim", "import-oxiod"),
                ("pdr-sim", "import-phone"), ("pdr-sim", "repair"),
                ("pdr-pocket", "run"), ("pdr-pocket", "attitude"), ("pdr-ekf", "run"),
                ("pdr-drift", "run"), ("pdr-eval",),
                ("pdr-sim", "export-csv"), ("pdr-pocket", "evaluate")}   # a CSV, a JSON
CHECKS_PLAUSIBILITY = {("pdr-sim", "import-csv"), ("pdr-sim", "import-phone"), ("pdr-sim", "allan"),
                       ("pdr-pocket", "calibrate-mag")}
OTHER_SPELLINGS = re.compile(r"^(-f|-y|--yes|--replace|--clobber|--force-\w+|--accept\w*|"
                             r"--allow\w*|--no-check\w*|--skip-check\w*|--unsafe)$")


def test_one_flag_vocabulary():
    for prog, path, sub in COMMANDS:
        flags = {flag for action in sub._actions for flag in action.option_strings}
        where = " ".join((prog, *path))
        assert not {f for f in flags if OTHER_SPELLINGS.match(f)}, where
        assert ("--overwrite" in flags) == ((prog, *path) in WRITES_A_BAG), where
        assert ("--force" in flags) == ((prog, *path) in CHECKS_PLAUSIBILITY), where
