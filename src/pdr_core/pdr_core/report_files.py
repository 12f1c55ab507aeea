"""The ``report.json`` of the ``run`` commands (fields: docs/reports.md), written and
printed one way: JSON indented by two spaces, one newline at the end.

- :func:`write_report`: ``DIRECTORY/report.json`` (a run's output folder, or the staging
  folder of its output bag);
- :func:`write_report_file`: a report to a file of its own name (``pdr-pocket evaluate
  --out``);
- :func:`print_report`: the same text on stdout.
"""
from __future__ import annotations

import json
from pathlib import Path

REPORT_NAME = "report.json"


def report_text(report: dict) -> str:
    """The report as the files hold it."""
    return json.dumps(report, indent=2) + "\n"


def write_report_file(path: str | Path, report: dict) -> Path:
    """``report`` written to ``path``; returns the path."""
    path = Path(path)
    path.write_text(report_text(report))
    return path


def write_report(directory: str | Path, report: dict) -> Path:
    """``report`` written to ``directory/report.json``; returns its path."""
    return write_report_file(Path(directory) / REPORT_NAME, report)


def print_report(report: dict) -> None:
    """``report`` on stdout, as the file holds it."""
    print(report_text(report), end="")
