"""Every module of pdr_core is named in its package's index (issue 56): the docstring of
each package's ``__init__.py`` lists its modules and sub-packages, one line each, so a
newcomer finds a module from the index, and a module added without its line fails here."""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

import pdr_core

TOP = Path(pdr_core.__file__).resolve().parent
PACKAGES = sorted(p.parent for p in TOP.rglob("__init__.py") if "__pycache__" not in p.parts)
# an index line: a module's name, two spaces or more, the first words of what it is
ENTRY = re.compile(r"^ {2,8}([a-z][a-z0-9_]*) {2,}\S", re.MULTILINE)


def indexed(package: Path) -> set[str]:
    """The names an index lists: the first word of each of its entry lines."""
    module = ast.parse((package / "__init__.py").read_text())
    docstring = ast.get_docstring(module, clean=False) or ""
    return set(ENTRY.findall(docstring))


def members(package: Path) -> set[str]:
    """A package's modules and sub-packages."""
    return ({p.stem for p in package.glob("*.py") if p.stem != "__init__"}
            | {p.name for p in package.iterdir() if (p / "__init__.py").is_file()})


def test_pdr_core_has_sub_packages_to_index():
    assert len(PACKAGES) > 5


@pytest.mark.parametrize("package", PACKAGES, ids=lambda p: p.relative_to(TOP.parent).as_posix())
def test_every_module_is_named_in_its_package_index_and_no_other_name(package):
    assert indexed(package) == members(package)


def test_the_entry_pattern_reads_names_not_descriptions():
    index = ("Modules:\n    bag           Reading and writing bags\n"
             "                  in MCAP storage.\n  Messages and bags\n")
    assert ENTRY.findall(index) == ["bag"]
