"""The navigator does not depend on its research tooling: no module of pdr_ins_ekf outside
``studies/`` imports ``pdr_ins_ekf.studies``, except ``cli.py``, the ``pdr-ekf`` command that
registers the studies' subcommands beside ``run`` and ``evaluate``."""
from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "pdr_ins_ekf"
COMMAND = PACKAGE / "cli.py"


def imported_modules(source: Path) -> set[str]:
    """Every module named by an import statement of ``source`` (at any depth)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(source.read_text())):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return names


def navigator_modules() -> list[Path]:
    return [p for p in PACKAGE.rglob("*.py")
            if "studies" not in p.relative_to(PACKAGE).parts and p != COMMAND]


def test_studies_package_exists():
    assert (PACKAGE / "studies" / "__init__.py").is_file()
    assert {"montecarlo", "ekf_montecarlo", "zupt_error_model", "error_sweep",
            "mechanization_study"} <= {p.stem for p in (PACKAGE / "studies").glob("*.py")}


def test_navigator_never_imports_the_studies():
    offenders = {str(p.relative_to(PACKAGE)): sorted(m for m in imported_modules(p)
                                                     if m.startswith("pdr_ins_ekf.studies"))
                 for p in navigator_modules()}
    assert {k: v for k, v in offenders.items() if v} == {}
    assert len(offenders) >= 10  # the check saw the navigator's modules


def test_import_check_sees_an_offender(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("def f():\n    from pdr_ins_ekf.studies import montecarlo\n")
    assert "pdr_ins_ekf.studies.montecarlo" in imported_modules(bad)
