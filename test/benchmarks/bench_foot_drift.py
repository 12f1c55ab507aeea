"""Benchmark: the foot INS's heading with and without the landmark drift corrections
(issue 44, acceptance 1).

Run on purpose (``./ws python test/benchmarks/bench_foot_drift.py [seeds]``), not in CI:
the twenty-minute walk around a block with a z gyro warming by 0.05 °/s after the start
(pdr_ins_ekf.studies.drift_study), seeds 0 … seeds − 1 (default 10), one process per
core. Prints the final yaw and position errors per seed without and with
``--drift online``, their means, and the ratio of the mean yaw errors.

With the shared data beside the repository (``../shared/data``, or ``PDR_SHARED_DATA``),
then the real foot recordings (acceptance 3): the eight pyshoe VICON trials and the x-io
closed walk, imported as the tests import them (wstest), through ``pdr-ekf run`` with
config/foot_drift.yaml without and with ``--drift online`` (and the shipped foot_ekf.yaml
beside them): the ARMSE against the VICON (3-D), the x-io walk's end-to-start gap, and
the associations made.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from pdr_ins_ekf.studies.drift_study import drift_outcome

ROOT = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("PDR_SHARED_DATA", ROOT.parent / "shared" / "data"))
PYSHOE = ("2017-11-22-11-22-03", "2017-11-22-11-30-14", "2017-11-22-11-49-03",
          "2017-11-27-11-13-10", "2017-11-27-11-24-07", "2017-12-15-18-03-05",
          "2018-02-09-11-19-39", "2018-02-22-10-10-29")
PYSHOE_ARGS = ["--time-col", "t_s", "--acc-cols", "acc_x_mps2,acc_y_mps2,acc_z_mps2",
               "--gyro-cols", "gyr_x_radps,gyr_y_radps,gyr_z_radps",
               "--pos-cols", "gt_x_m,gt_y_m,gt_z_m", "--pos-axes=-x,y,z"]
XIO_ARGS = ["--time-col", "Time (s)", "--drop-duplicates",
            "--acc-cols", "Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)",
            "--gyro-cols", "Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s)",
            "--acc-unit", "g", "--gyro-unit", "deg/s"]
CONFIG = ROOT / "src" / "pdr_ins_ekf" / "config"
ESTIMATOR = ROOT / "src" / "pdr_drift" / "config" / "landmark_drift_foot.yaml"
RUNS = {"foot_ekf.yaml": ["--config", str(CONFIG / "foot_ekf.yaml")],
        "foot_drift.yaml": ["--config", str(CONFIG / "foot_drift.yaml")],
        "foot_drift.yaml --drift online": ["--config", str(CONFIG / "foot_drift.yaml"),
                                           "--drift", "online", "--drift-config",
                                           str(ESTIMATOR)]}


def real_trial(item: tuple[str, Path, list[str]]) -> tuple[str, dict]:
    """One recording imported and run three ways: its figures per run."""
    name, csv, import_args = item
    with tempfile.TemporaryDirectory() as folder:
        bag = Path(folder) / "bag"
        subprocess.run([str(ROOT / "ws"), "pdr-sim", "import-csv", str(csv), "--out", str(bag),
                        *import_args], check=True, capture_output=True)
        out = {}
        for label, args in RUNS.items():
            run = Path(folder) / label.replace(" ", "_")
            subprocess.run([str(ROOT / "ws"), "pdr-ekf", "run", str(bag), "--out", str(run),
                            *args], check=True, capture_output=True)
            report = json.loads((run / "report.json").read_text())
            out[label] = (report.get("armse_3d_m"), report.get("loop_gap_m"),
                          report.get("drift", {}).get("associations"))
        return name, out


def real_recordings() -> None:
    items = [(trial, SHARED / "foot" / "pyshoe_vicon" / f"{trial}.csv", PYSHOE_ARGS)
             for trial in PYSHOE]
    items.append(("x-io short walk", SHARED / "foot" / "xio_gait_tracking" / "short_walk.csv",
                  XIO_ARGS))
    if not all(csv.exists() for _, csv, _ in items):
        print(f"\n(no shared recordings under {SHARED}: the real trials are not run)")
        return
    with ProcessPoolExecutor() as pool:
        results = list(pool.map(real_trial, items))
    labels = list(RUNS)
    print("\n| recording | " + " | ".join(labels) + " | associations |\n|---|"
          + "---:|" * (len(labels) + 1))
    for name, out in results:
        figure = [out[label][1] if out[label][0] is None else out[label][0]
                  for label in labels]
        print(f"| {name} | " + " | ".join(f"{v:.3f}" for v in figure)
              + f" | {out[labels[-1]][2]} |")
    print("(ARMSE 3-D [m] against the VICON; the x-io walk: its end-to-start gap [m])")


def main(seeds: int) -> None:
    with ProcessPoolExecutor() as pool:
        outcomes = list(pool.map(drift_outcome, range(seeds)))
    print("| seed | final yaw error, uncorrected [°] | corrected [°] | final position error, "
          "uncorrected [m] | corrected [m] | corrections |\n|---:|---:|---:|---:|---:|---:|")
    for o in outcomes:
        print(f"| {o.seed} | {o.uncorrected_yaw_deg:.1f} | {o.corrected_yaw_deg:.1f} | "
              f"{o.uncorrected_position_m:.2f} | {o.corrected_position_m:.2f} | "
              f"{o.corrections} |")
    mean = {k: np.mean([getattr(o, k) for o in outcomes]) for k in (
        "uncorrected_yaw_deg", "corrected_yaw_deg", "uncorrected_position_m",
        "corrected_position_m", "corrections")}
    print(f"| mean | {mean['uncorrected_yaw_deg']:.1f} | {mean['corrected_yaw_deg']:.1f} | "
          f"{mean['uncorrected_position_m']:.2f} | {mean['corrected_position_m']:.2f} | "
          f"{mean['corrections']:.1f} |")
    worst = max(o.corrected_yaw_deg / o.uncorrected_yaw_deg for o in outcomes)
    print(f"\ncorrected / uncorrected final yaw error: mean "
          f"{mean['corrected_yaw_deg'] / mean['uncorrected_yaw_deg']:.3f}, worst seed "
          f"{worst:.3f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
    real_recordings()
