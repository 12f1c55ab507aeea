"""The summary of a dataset run: ``summary.csv`` and ``summary.md``.

One line per recording (its dataset, navigator, status, wall time, the failure's reason,
and every figure of :data:`TRUTH_FIGURES` its report has), then per dataset the median,
mean and maximum of each figure over the recordings that have it. The figures are those
of docs/reports.md that a report has against a truth (a pose, true steps, floors or the
stance truth) for ``pdr-ekf run`` and ``pdr-pocket run``, the smoothed path's and the
drift's included where a report has them; test_pdr_eval.py checks the list against that
page.
"""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from pdr_eval.job import Outcome

TRUTH_FIGURES = (
    "final_error_m", "final_error_pct", "mean_error_3d_m", "armse_3d_m", "armse_2d_m",
    "within_step_rmse_m",
    "stance.samples", "stance.precision", "stance.recall", "stance.true_fraction",
    "stance.detected_fraction",
    "true_steps", "matched_steps", "missed_steps", "false_steps", "missed_pct", "false_pct",
    "activity_correct_pct", "true_step_distance_m", "distance_error_pct",
    "true_final_floor", "true_highest_floor", "floor_error", "highest_floor_error",
    "smoothed.final_error_m", "smoothed.final_error_pct", "smoothed.mean_error_3d_m",
    "smoothed.armse_3d_m", "smoothed.armse_2d_m", "smoothed.within_step_rmse_m",
    "drift.true_landmarks", "drift.landmarks_matched", "drift.missed_landmarks",
    "drift.false_landmarks", "drift.associations_correct", "drift.associations_wrong",
    "drift.uncorrected.final_yaw_error_deg", "drift.uncorrected.final_position_error_m",
    "drift.corrected.final_yaw_error_deg", "drift.corrected.final_position_error_m",
)
STATISTICS = {"median": np.median, "mean": np.mean, "max": np.max}
LINE_COLUMNS = ("recording", "dataset", "navigator", "status", "seconds", "error")


def figure(report: dict, name: str) -> float | None:
    """The number at the dotted ``name`` of a report (None: absent, null or not a
    number)."""
    value: object = report
    for key in name.split("."):
        if not isinstance(value, dict) or key not in value:
            return None
        value = value[key]
    return float(value) if isinstance(value, int | float) and not isinstance(value, bool) \
        else None


def status(outcome: Outcome) -> str:
    return "failed" if outcome.report is None else "kept" if outcome.skipped else "done"


def lines(outcomes: list[Outcome]) -> tuple[list[str], list[dict]]:
    """The figures any report has, and a row per recording (``LINE_COLUMNS`` and those)."""
    names = [n for n in TRUTH_FIGURES
             if any(o.report is not None and figure(o.report, n) is not None for o in outcomes)]
    rows = []
    for o in outcomes:
        row = {"recording": o.recording.name, "dataset": o.recording.dataset,
               "navigator": o.recording.navigator, "status": status(o),
               "seconds": round(o.seconds, 2), "error": o.error}
        row |= {n: (None if o.report is None else figure(o.report, n)) for n in names}
        rows.append(row)
    return names, rows


def per_dataset(names: list[str], rows: list[dict]) -> list[dict]:
    """Per dataset and statistic: the figures over the recordings that have them."""
    out = []
    for dataset in sorted({r["dataset"] for r in rows}):
        mine = [r for r in rows if r["dataset"] == dataset]
        for label, statistic in STATISTICS.items():
            row = {"dataset": dataset, "statistic": label,
                   "recordings": sum(r["status"] != "failed" for r in mine)}
            for n in names:
                values = [r[n] for r in mine if r[n] is not None]
                row[n] = float(statistic(values)) if values else None
            out.append(row)
    return out


def write_summary(outcomes: list[Outcome], out: Path) -> tuple[Path, Path]:
    """``out/summary.csv`` (the lines, then the per-dataset statistics) and
    ``out/summary.md`` (the same as two tables, failures with their reasons)."""
    names, rows = lines(outcomes)
    stats = per_dataset(names, rows)
    csv_path, md_path = out / "summary.csv", out / "summary.md"
    with csv_path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=[*LINE_COLUMNS, "statistic", "recordings",
                                               *names], extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
        writer.writerows({**s, "recording": "", "status": ""} for s in stats)
    md_path.write_text(_markdown(names, rows, stats))
    return csv_path, md_path


def _cell(value: object) -> str:
    if value is None:
        return "—"
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value).replace("|", "\\|")


def _table(columns: list[str], rows: list[dict]) -> str:
    head = f"| {' | '.join(columns)} |\n|{'---|' * len(columns)}\n"
    return head + "".join(f"| {' | '.join(_cell(r.get(c)) for c in columns)} |\n"
                          for r in rows)


def _markdown(names: list[str], rows: list[dict], stats: list[dict]) -> str:
    failed = [r for r in rows if r["status"] == "failed"]
    text = (f"# Dataset run: {len(rows)} recordings, {len(failed)} failed\n\n"
            "## Per dataset\n\n" + _table(["dataset", "statistic", "recordings", *names], stats)
            + "\n## Per recording\n\n"
            + _table(["recording", "dataset", "navigator", "status", "seconds", *names], rows))
    if failed:
        text += "\n## Failed\n\n" + _table(["recording", "error"], failed)
    return text
