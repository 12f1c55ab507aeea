"""The summary of a dataset run: ``summary.csv`` and ``summary.md``.

One line per recording: its dataset, the navigator that ran (chosen by ``auto`` or
given), status, wall time, the failure's reason; what the walk was, truth or not
(:data:`WALK_COLUMNS`: pdr_eval.walk_figures, the warnings' count and the first
warning); the manifest's known figures against the run's (:data:`KNOWN_SCORES`); and
every figure of :data:`TRUTH_FIGURES` its report has. Then per dataset the median, mean
and maximum of each number over the recordings that have it. The status is ``done``,
``kept`` (an earlier run's report), ``failed``, or ``not a pocket walk`` for a run of the
pocket navigator that found the phone in no pocket (its report's placement), whose
figures are no walk's. The truth figures are those of docs/reports.md that a report has
against a truth (a pose, true steps, floors or the stance truth) for ``pdr-ekf run`` and
``pdr-pocket run``, the smoothed path's, the drift's and the consistency's (the NEES of
the position and attitude, pdr_core.evaluation.consistency) included where a report has them;
test_pdr_eval.py checks the list against that page.
"""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from pdr_eval.job import Outcome
from pdr_pocket.placement import NOT_IN_POCKET

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
    *(f"consistency.{part}.{name}" for part in ("position_3d", "position_2d", "attitude")
      for name in ("samples", "nees", "nees_per_dof")),
)
STATISTICS = {"median": np.median, "mean": np.mean, "max": np.max}
LINE_COLUMNS = ("recording", "dataset", "navigator", "status", "seconds", "error")
WALK_NUMBERS = ("steps", "footfalls", "distance_m", "final_floor", "warnings")
WALK_COLUMNS = ("steps", "footfalls", "distance_m", "final_floor", "placement", "barometer",
                "warnings", "first_warning")
# the manifest's known figure, the run's figure scored against it, the error and its %
# (the distance's named apart from the report's distance_error_pct against true strides)
KNOWN_SCORES = (("true_footfalls", "footfalls", "footfall_error", "footfall_error_pct"),
                ("true_steps", "steps", "step_error", "step_error_pct"),
                ("true_distance_m", "distance_m", "known_distance_error_m",
                 "known_distance_error_pct"))
NOT_A_POCKET_WALK = "not a pocket walk"
WALKED = ("done", "kept")           # the statuses of a walk, scored and summarised


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
    if outcome.report is None:
        return "failed"
    eval_ = outcome.report.get("eval", {})
    if eval_.get("navigator") == "pocket" and \
            eval_.get("walk", {}).get("placement") == NOT_IN_POCKET:
        return NOT_A_POCKET_WALK
    return "kept" if outcome.skipped else "done"


def walk_cells(report: dict | None) -> dict:
    """The :data:`WALK_COLUMNS` of a report (all None for a failed run)."""
    if report is None:
        return dict.fromkeys(WALK_COLUMNS)
    warnings = report.get("eval", {}).get("warnings", [])
    return {**{c: report.get("eval", {}).get("walk", {}).get(c) for c in WALK_COLUMNS},
            "warnings": len(warnings), "first_warning": warnings[0] if warnings else ""}


def known_scores(known: dict[str, float], walk: dict) -> dict:
    """Each known figure, the run's error against it and that error in % of it (None
    where the manifest does not give it or the run has no figure)."""
    cells = {}
    for column, found, score, pct in KNOWN_SCORES:
        true, value = known.get(column), walk.get(found)
        error = None if true is None or value is None else float(value) - true
        cells |= {column: true, score: error,
                  pct: None if error is None or not true else 100 * error / true}
    return cells


def lines(outcomes: list[Outcome]) -> tuple[list[str], list[dict]]:
    """The numbers to summarise per dataset (the walk's, the known figures' scores and
    the truth figures any report has), and a row per recording (``LINE_COLUMNS``,
    ``WALK_COLUMNS``, the scores and the truth figures)."""
    given = {column for o in outcomes for column, _ in o.recording.known}
    known = [n for column, _, *scores in KNOWN_SCORES if column in given
             for n in (column, *scores)]
    names = [n for n in TRUTH_FIGURES
             if any(o.report is not None and figure(o.report, n) is not None for o in outcomes)]
    rows = []
    for o in outcomes:
        report = o.report
        row = {"recording": o.recording.name, "dataset": o.recording.dataset,
               "navigator": o.recording.navigator if report is None
               else report.get("eval", {}).get("navigator", o.recording.navigator),
               "status": status(o), "seconds": round(o.seconds, 2), "error": o.error}
        if row["status"] == NOT_A_POCKET_WALK:
            row["error"] = f"{NOT_IN_POCKET}: {report['placement'].get('why', '')}"
        row |= walk_cells(report)
        scores = known_scores(dict(o.recording.known),
                              row if row["status"] in WALKED else {})
        row |= {n: scores[n] for n in known}
        row |= {n: (None if report is None else figure(report, n)) for n in names}
        rows.append(row)
    return [*WALK_NUMBERS, *known, *names], rows


def per_dataset(names: list[str], rows: list[dict]) -> list[dict]:
    """Per dataset and statistic: the figures over the walks (status done or kept) that
    have them; ``recordings``: those walks."""
    out = []
    for dataset in sorted({r["dataset"] for r in rows}):
        mine = [r for r in rows if r["dataset"] == dataset and r["status"] in WALKED]
        for label, statistic in STATISTICS.items():
            row = {"dataset": dataset, "statistic": label, "recordings": len(mine)}
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
                                               *names, "placement", "barometer",
                                               "first_warning"], extrasaction="ignore")
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
    aside = sum(r["status"] == NOT_A_POCKET_WALK for r in rows)
    warned = [r for r in rows if r["warnings"]]
    text = (f"# Dataset run: {len(rows)} recordings, {len(failed)} failed, {aside} not "
            "pocket walks\n\n## Per dataset\n\n"
            + _table(["dataset", "statistic", "recordings", *names], stats)
            + "\n## Per recording\n\n"
            + _table(["recording", "dataset", "navigator", "status", "seconds", "placement",
                      "barometer", *names], rows))
    if warned:
        text += "\n## First warnings\n\n" + _table(["recording", "warnings", "first_warning"],
                                                    warned)
    if aside:
        text += "\n## Not pocket walks\n\n" + _table(
            ["recording", "error"], [r for r in rows if r["status"] == NOT_A_POCKET_WALK])
    if failed:
        text += "\n## Failed\n\n" + _table(["recording", "error"], failed)
    return text
