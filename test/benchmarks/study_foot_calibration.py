"""Study (issue 57, acceptance 1 and 2): the foot INS calibrates the pocket's lines.

Run on purpose, not in CI (about 3 minutes on 2 cores):

    ./ws python test/benchmarks/study_foot_calibration.py [--seeds 10] [--workers 2]
        [--out out/study_foot_calibration]

Three persons whose lines differ from the population's (the shipped configuration's
a_H = 0.025 m/°, b_H = 0.42 m and the stairs lines of Section 4.3.1) as much as the
thesis' persons do (1.2–9.6 % of the distance, its Table 4.4), 10 seeds each. Per person
and seed, with the commands a user types:

1. ``pdr-sim generate --placement pocket --with-foot`` of ``two_imu_walk`` (level, 10 min)
   or ``two_imu_stairs`` (11 min, three lines), the person's lines set, strides deviating
   from them step by step (2.5 %, not centred);
2. ``pdr-ekf run`` on the foot's topics and ``pdr-pocket run`` on the pocket's;
3. ``pdr-pocket calibrate-step --foot --pocket``: the person's lines;
4. a second walk of the same person, phone alone (``h2_rectangle_speeds`` level, 7 min at
   2.5 and 4.8 km/h; ``up_dw`` with stairs, risers of 15 to 21 cm), another seed:
   ``pdr-pocket run`` with the population's lines (before) and ``--step-calibration``
   (after): the distance error against the true strides and each flight's riser error.

Prints a row per person and walk and writes OUT/runs.csv (a row per run), OUT/summary.md
and OUT/study.png (docs/img/foot_calibration_study.png).
"""
from __future__ import annotations

import argparse
import csv
import json
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # test/: wstest

from pdr_core import topics
from pdr_core.evaluation.parallel import on_one_thread
from pdr_sim.pocket_scenario import PersonSpec
from wstest import cli

# the persons: lines as far from the population's as the thesis' persons are
PERSONS = {
    "short strides": {"a_h_m_per_deg": 0.025, "b_h_m": 0.35, "b_u_cm": -10.5,
                      "b_d_cm": -22.0},
    "long strides": {"a_h_m_per_deg": 0.026, "b_h_m": 0.50, "b_u_cm": -6.5,
                     "b_d_cm": -17.0},
    "flat slope": {"a_h_m_per_deg": 0.022, "b_h_m": 0.52, "b_u_cm": -7.5,
                   "b_d_cm": -21.0},
}
WALKS = {"level": ("two_imu_walk", "h2_rectangle_speeds"),
         "stairs": ("two_imu_stairs", "up_dw")}
SECOND_SEED_OFFSET = 1000
FOOT = topics.FOOT_NAMESPACE


def _cli(prog: str, *args) -> str:
    """A CLI run in this process (wstest.cli); its stdout, or RuntimeError with its
    stderr."""
    done = cli(prog, *args)
    if done.returncode:
        raise RuntimeError(f"{prog} {' '.join(map(str, args))}: {done.stderr}")
    return done.stdout


def _person_sets(person: dict, seed: int) -> list[str]:
    """``--set`` options: the walk's seed and the person's lines."""
    values = {"seed": seed, **{f"person.{key}": value for key, value in person.items()}}
    return [word for key, value in values.items() for word in ("--set", f"{key}={value}")]


def one_run(person_name: str, walk: str, seed: int) -> dict:
    """Steps 1-4 of the module docstring for one person, walk kind and seed."""
    person = PERSONS[person_name]
    calibration, second = WALKS[walk]
    with tempfile.TemporaryDirectory(prefix="study57_") as tmp:
        work = Path(tmp)
        _cli("pdr-sim", "generate", "--placement", "pocket", "--scenario", calibration,
             "--with-foot", "--seed", seed, *_person_sets(person, seed), "--out",
             work / "pair")
        _cli("pdr-ekf", "run", work / "pair", "--out", work / "foot",
             "--imu-topic", FOOT + topics.IMU_DATA,
             "--truth-topic", FOOT + topics.GROUND_TRUTH_POSE,
             "--stance-truth-topic", FOOT + topics.GROUND_TRUTH_STANCE)
        _cli("pdr-pocket", "run", work / "pair", "--out", work / "pocket")
        _cli("pdr-pocket", "calibrate-step", "--foot", work / "foot", "--pocket",
             work / "pocket", "--out", work / "fit.yaml")
        fit = yaml.safe_load((work / "fit.yaml").read_text())
        second_seed = seed + SECOND_SEED_OFFSET
        _cli("pdr-sim", "generate", "--placement", "pocket", "--scenario", second,
             "--seed", second_seed, *_person_sets(person, second_seed), "--out",
             work / "second")
        _cli("pdr-pocket", "run", work / "second", "--out", work / "before")
        _cli("pdr-pocket", "run", work / "second", "--step-calibration",
             work / "fit.yaml", "--out", work / "after")
        _cli("pdr-pocket", "run", work / "second", "--step-calibration",
             _own_lines(person, work / "own.yaml"), "--out", work / "own")
        before, after, own = (json.loads((work / name / "report.json").read_text())
                              for name in ("before", "after", "own"))
    row = {"person": person_name, "walk": walk, "seed": seed,
           "true_b_h_m": person["b_h_m"], "true_a_h_m_per_deg": person["a_h_m_per_deg"],
           "b_h_m": fit["step_length"]["b_h_m"],
           "a_h_m_per_deg": fit["step_length"]["a_h_m_per_deg"],
           "level_pairs": (fit["fit"]["level"] or {}).get("pairs", 0),
           "distance_error_before_pct": before["distance_error_pct"],
           "distance_error_after_pct": after["distance_error_pct"],
           "distance_error_own_pct": own["distance_error_pct"],
           "steps_off_the_line": _off_the_line(after, walk)}
    row["offset_error_cm"] = 100.0 * (row["b_h_m"] - person["b_h_m"])
    if walk == "stairs":
        for line, key in (("up", "u"), ("down", "d")):
            row[f"b_{key}_cm"] = fit["stairs"][f"b_{key}_cm"]
            row[f"{line}_offset_error_cm"] = row[f"b_{key}_cm"] - person[f"b_{key}_cm"]
            row[f"a_{key}_cm_per_deg"] = fit["stairs"][f"a_{key}_cm_per_deg"]
            row[f"{line}_pairs"] = (fit["fit"][line] or {}).get("pairs", 0)
        row["riser_error_before_pct"] = _riser_error(before)
        row["riser_error_after_pct"] = _riser_error(after)
        row["riser_error_own_pct"] = _riser_error(own)
    return row


def _own_lines(person: dict, path: Path) -> Path:
    """A saved fit holding the person's own (true) lines: what a perfect calibration
    would give, the floor of each figure."""
    from pdr_pocket.saved_lines import FitStats, LineEstimate, SavedFit, write_fit

    exact = FitStats(1, ((0.0, 0.0), (0.0, 0.0)), 0.0)
    up = (PersonSpec.a_u_cm_per_deg, person["b_u_cm"])
    down = (PersonSpec.a_d_cm_per_deg, person["b_d_cm"])
    lines = {"level": LineEstimate(person["a_h_m_per_deg"], person["b_h_m"], exact),
             "up": LineEstimate(*up, exact), "down": LineEstimate(*down, exact)}
    return write_fit(path, SavedFit(lines, 1.0, {}, {"person": "the simulated truth"}))


def _off_the_line(report: dict, walk: str) -> int:
    """The second walk's steps whose stride the level line did not give, where a
    calibration of it cannot act: another model while the placement was unknown, and on
    a level walk the steps taken for stairs."""
    by_line = report["placement"]["cycles_by_model"].get("pitch", 0)
    on_stairs = report["activities"]["upstairs"] + report["activities"]["downstairs"]
    return int(report["steps"] - by_line) + (on_stairs if walk == "level" else 0)


def _riser_error(report: dict) -> float:
    """The mean |riser error| [%] over the second walk's flights."""
    errors = [abs(f["error_pct"]) for f in report["staircase_riser_error_pct"]
              if f["error_pct"] is not None]
    return float(np.mean(errors)) if errors else float("nan")


def _summary(rows: list[dict]) -> list[str]:
    """A row per person and walk: the largest offset errors, the distance error of the
    second walk (mean, and the largest in brackets) with the population's lines, the
    fitted ones and the person's own, the largest difference the fit makes against the
    person's own lines (the calibration's share of the error), the mean riser errors, and
    how many runs had steps the level line did not measure."""
    lines = ["| person | walk | runs | level offset error, max [cm] | up, down offset "
             "error, max [cm] | distance error: population's lines [%] | fitted [%] | "
             "person's own [%] | fitted − own, max [%] | riser error: population's [%] | "
             "fitted [%] | own [%] | runs with steps off the line |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for walk in WALKS:
        for person in PERSONS:
            runs = [r for r in rows if r["person"] == person and r["walk"] == walk]
            if not runs:
                continue
            cells = [f"{max(abs(r['offset_error_cm']) for r in runs):.2f}", "—"]
            for which in ("before", "after", "own"):
                d = np.array([r[f"distance_error_{which}_pct"] for r in runs])
                cells.append(f"{d.mean():+.2f} ({np.abs(d).max():.2f})")
            calibration = max(abs(r["distance_error_after_pct"] - r["distance_error_own_pct"])
                              for r in runs)
            cells += [f"{calibration:.2f}"] + ["—"] * 3
            if walk == "stairs":
                cells[1] = ", ".join(f"{max(abs(r[f'{line}_offset_error_cm']) for r in runs):.2f}"
                                     for line in ("up", "down"))
                cells[6:9] = [f"{np.mean([r[f'riser_error_{w}_pct'] for r in runs]):.2f}"
                              for w in ("before", "after", "own")]
            off = sum(1 for r in runs if r["steps_off_the_line"])
            lines.append(f"| {person} | {walk} | {len(runs)} | " + " | ".join(cells)
                         + f" | {off} |")
    return lines


def plot(rows: list[dict], path: Path) -> Path:
    """The second walks' distance errors per run (the population's lines, the fitted ones,
    the person's own) and, for the stairs walks, the riser errors: a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), width_ratios=(2, 1))
    groups = [(walk, person) for walk in WALKS for person in PERSONS]
    colours = {"before": "tab:red", "after": "tab:blue", "own": "tab:green"}
    names = {"before": "population's lines", "after": "fitted by the foot INS",
             "own": "the person's own"}
    for which, offset in (("before", -0.2), ("after", 0.0), ("own", 0.2)):
        for g, (walk, person) in enumerate(groups):
            values = [r[f"distance_error_{which}_pct"] for r in rows
                      if r["walk"] == walk and r["person"] == person]
            axes[0].scatter(np.full(len(values), g + offset), values, s=12,
                            color=colours[which], label=names[which] if g == 0 else None)
            if walk == "stairs":
                risers = [r[f"riser_error_{which}_pct"] for r in rows
                          if r["walk"] == walk and r["person"] == person]
                axes[1].scatter(np.full(len(risers), g - len(PERSONS) + offset), risers, s=12,
                                color=colours[which])
    axes[0].axhspan(-1.0, 1.0, color="0.9", zorder=0)
    axes[0].set_xticks(range(len(groups)), [f"{p}\n{w}" for w, p in groups], fontsize=8)
    axes[0].set_ylabel("second walk's distance error [%]")
    axes[0].set_title("the phone alone on a second walk (band: ±1 %)")
    axes[0].legend(fontsize=8)
    axes[1].set_xticks(range(len(PERSONS)), list(PERSONS), fontsize=8)
    axes[1].set_ylabel("mean |riser error| over the flights [%]")
    axes[1].set_title("risers of up_dw (15-21 cm)")
    fig.suptitle("The foot INS calibrates the pocket's lines (issue 57): three persons, "
                 f"{len({r['seed'] for r in rows})} seeds each")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=10)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--walks", nargs="+", choices=list(WALKS), default=list(WALKS))
    p.add_argument("--out", type=Path, default=Path("out/study_foot_calibration"))
    args = p.parse_args(argv)
    tasks = [(person, walk, seed) for walk in args.walks for person in PERSONS
             for seed in range(1, args.seeds + 1)]
    rows = []
    with ProcessPoolExecutor(args.workers) as pool:
        futures = [pool.submit(on_one_thread, one_run, *task) for task in tasks]
        for done, future in enumerate(futures, 1):
            row = future.result()
            rows.append(row)
            print(f"[{done}/{len(tasks)}] {row['person']}, {row['walk']}, seed {row['seed']}: "
                  f"offset {row['offset_error_cm']:+.2f} cm, distance "
                  f"{row['distance_error_before_pct']:+.2f} % -> "
                  f"{row['distance_error_after_pct']:+.2f} %", file=sys.stderr, flush=True)
    args.out.mkdir(parents=True, exist_ok=True)
    keys = sorted({k for r in rows for k in r}, key=lambda k: list(rows[-1]).index(k)
                  if k in rows[-1] else 99)
    with (args.out / "runs.csv").open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=keys)
        writer.writeheader()
        writer.writerows(rows)
    table = _summary(rows)
    (args.out / "summary.md").write_text("\n".join(table) + "\n")
    print("\n".join(table))
    print(f"plot: {plot(rows, args.out / 'study.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
