"""Benchmark (issue 45): why adaptive SHOE fails on the pyshoe VICON trial that climbs,
and the simulated stairs walk that fails the same way (docs/foot_ins.md, "The foot on
real stairs").

Run on purpose (``./ws python test/benchmarks/bench_stairs.py [FIGURE.png]``), not in CI.

1. The real trial (``2018-02-09-11-19-39.csv`` of the shared data, when it is there): the
   zero-velocity truth from the VICON foot position (pdr_ins_ekf.studies.stance_study:
   speed below 0.05 m/s), then adaptive SHOE without the valley-depth rule
   (``depth_min: 1``, the detector before issue 45) and with it (the shipped 70): the
   detections on a moving foot, each with the statistic, the span's floor and peak and
   their ratio, the true rests missed, and the ARMSE of ``pdr-ekf run``'s filter.
2. The simulator's ``stairs_slow`` (200 Hz, ``xsens_mtw``, seeds 1-3) and its matched
   level walk (``--level-walk``): the same figures and the ARMSE ratio to the level walk.
3. The figure (default docs/img/stairs_statistic.png): the statistic and both
   thresholds over a swing of each, side by side.
"""
from __future__ import annotations

import os
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.ndimage import maximum_filter1d, minimum_filter1d

from pdr_core import topics
from pdr_core.evaluation.metrics import error_report, truth_at
from pdr_ins_ekf.config import load_run_config
from pdr_ins_ekf.offline import navigate
from pdr_ins_ekf.studies.plots import stance_statistic_png
from pdr_ins_ekf.studies.stance_study import (
    false_stances,
    missed_stances,
    zero_velocity_truth,
)
from pdr_ins_ekf.zero_velocity import samples_of
from pdr_sim.foot_trajectory import level_walk_like
from pdr_sim.scenario import load_scenario, scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

ROOT = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("PDR_SHARED_DATA", ROOT.parent / "shared" / "data"))
CLIMB = SHARED / "foot" / "pyshoe_vicon" / "2018-02-09-11-19-39.csv"
SHIPPED = load_run_config(None)
DETECTORS = {"adaptive SHOE before (depth_min 1)": replace(SHIPPED.detector, depth_min=1.0),
             "with the valley depth (depth_min 70)": SHIPPED.detector}


class Recording:
    """Stamps [ns], specific force, rate and true positions of one recording."""

    def __init__(self, stamp_ns, accel, gyro, position, title: str) -> None:
        self.stamp_ns, self.accel, self.gyro, self.position = stamp_ns, accel, gyro, position
        self.title = title
        self.t_s = (stamp_ns - stamp_ns[0]) * 1e-9
        self.rate_hz = 1.0 / float(np.median(np.diff(self.t_s)))


def real_climb() -> Recording:
    data = np.genfromtxt(CLIMB, delimiter=",", names=True)
    stamp = np.round(data["t_s"] * 1e9).astype(np.int64)
    axes = ("x", "y", "z")
    return Recording(stamp, np.column_stack([data[f"acc_{a}_mps2"] for a in axes]),
                     np.column_stack([data[f"gyr_{a}_radps"] for a in axes]),
                     np.column_stack([-data["gt_x_m"], data["gt_y_m"], data["gt_z_m"]]),
                     "pyshoe VICON 2018-02-09-11-19-39 (real)")


def simulated(seed: int, level: bool = False) -> Recording:
    scenario, data = load_scenario("stairs_slow")
    if level:
        data = level_walk_like(scenario, data)
        scenario = scenario_from_dict(data, data["name"])
    sim = simulate(SimulationConfig(scenario, data, "xsens_mtw", {}, 200.0, seed))
    imu, pose = sim.batches[topics.IMU_DATA], sim.batches[topics.GROUND_TRUTH_POSE]
    return Recording(imu.stamp_ns, imu["linear_acceleration"], imu["angular_velocity"],
                     truth_at(pose, imu.stamp_ns), f"stairs_slow, seed {seed} (simulated)"
                     + (", its level walk" if level else ""))


def armse(recording: Recording, detector) -> float:
    """ARMSE 3-D [m] of the shipped filter with ``detector``."""
    from pdr_core.io.batch import MessageBatch
    from pdr_core.io.msgtypes import IMU

    imu = MessageBatch(IMU, recording.stamp_ns, "imu_link", {
        "linear_acceleration": recording.accel, "angular_velocity": recording.gyro})
    run = navigate(imu, replace(SHIPPED, detector=detector))
    keep = np.searchsorted(recording.stamp_ns, run.stamp_ns)
    t = recording.t_s[keep] - recording.t_s[keep[0]]
    return error_report(t, run.output.position, recording.position[keep])["armse_3d_m"]


def report(recording: Recording) -> dict[str, np.ndarray]:
    """Prints the detectors' figures on a recording; returns their stance masks."""
    at_rest, speed = zero_velocity_truth(recording.t_s, recording.position)
    print(f"\n## {recording.title}: {recording.t_s[-1]:.0f} s, at rest {at_rest.mean():.0%}")
    masks = {}
    for label, detector in DETECTORS.items():
        stance = detector.detect(recording.accel, recording.gyro, recording.rate_hz)
        masks[label] = stance.mask
        wrong = false_stances(recording.t_s, stance.mask, at_rest, speed, stance.statistic,
                              recording.gyro, detector)
        missed = missed_stances(recording.t_s, stance.mask, at_rest)
        print(f"\n{label}: ARMSE {armse(recording, detector):.3f} m; {len(wrong)} "
              f"detections on a moving foot, {len(missed)} rests of 0.1 s or more missed")
        if wrong:
            print("| t [s] | samples | least speed [m/s] | T | floor | peak | depth | "
                  "max rate [rad/s] |\n|---:|---:|---:|---:|---:|---:|---:|---:|")
        for w in wrong[:12]:
            print(f"| {w.t_s:.2f} | {w.samples} | {w.least_speed_mps:.3f} | "
                  f"{w.statistic:.3g} | {w.floor:.3g} | {w.peak:.3g} | {w.depth:.0f} | "
                  f"{w.rate_radps:.2f} |")
    return masks


def panel(recording: Recording, masks: dict, window: tuple[float, float]) -> dict:
    """The figure's panel of a recording between ``window`` [s]."""
    detector = SHIPPED.detector
    statistic = detector.detect(recording.accel, recording.gyro, recording.rate_hz).statistic
    span = samples_of(detector.span_s, recording.rate_hz)
    floor = minimum_filter1d(statistic, span, mode="nearest")
    peak = maximum_filter1d(statistic, span, mode="nearest")
    before = np.clip(detector.threshold_factor * floor, detector.threshold_min,
                     detector.threshold_max)
    after = np.where(peak >= detector.depth_min * floor, before, detector.threshold_min)
    part = (recording.t_s >= window[0]) & (recording.t_s <= window[1])
    labels = list(DETECTORS)
    return {"title": recording.title, "t_s": recording.t_s[part],
            "statistic": statistic[part],
            "at_rest": zero_velocity_truth(recording.t_s, recording.position)[0][part],
            "thresholds": {"threshold before": before[part],
                           "threshold with the depth rule": after[part]},
            "stance": {f"stance: {labels[0]}": masks[labels[0]][part],
                       f"stance: {labels[1]}": masks[labels[1]][part]}}


def main(figure: Path) -> None:
    panels = []
    if CLIMB.exists():
        climb = real_climb()
        panels.append(panel(climb, report(climb), (13.0, 20.5)))
    else:
        print(f"(no {CLIMB}: the real trial is not run)")
    for seed in (1, 2, 3):
        walk = simulated(seed)
        masks = report(walk)
        level = simulated(seed, level=True)
        ratios = [armse(walk, d) / armse(level, d) for d in DETECTORS.values()]
        print(f"\nARMSE over the matched level walk's: before {ratios[0]:.1f}, with the "
              f"depth rule {ratios[1]:.2f}")
        if seed == 1:
            panels.append(panel(walk, masks, (5.0, 12.5)))
    stance_statistic_png(panels, figure)
    print(f"\nwrote {figure}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs" / "img" /
         "stairs_statistic.png")
