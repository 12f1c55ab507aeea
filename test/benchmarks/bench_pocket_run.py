"""Benchmark: ``pdr-pocket run`` end to end on an hour of 100 Hz pocket data, and the
position covariance's honesty over Monte-Carlo runs of H1.

Run on purpose (``make bench``), not in CI. Prints two tables:

1. Speed (issue 17, acceptance 9; issue 18, acceptance 7): an hour of simulated pocket
   walking (the 39-minute out-and-back and the Theresienhöhe block, 61 min in all, Xsens
   MTw errors, the shipped updates) written as a bag, then ``pdr-pocket run`` on it, alone,
   with ``--plot`` and with ``--drift online`` and ``offline``, as a child process: wall
   time, samples per second end to end (reading, navigating, writing the bag and the
   report) and the child's peak resident memory.
2. NEES (acceptance 5): 50 runs of H1 with different seeds; at the last step, the
   position error against the true route (the sum of the true strides) and the filter's
   covariance: the mean normalised estimation error squared with its 95 % band for the
   degrees of freedom the covariance has (2 on level ground: the vertical is exact).
"""
from __future__ import annotations

import resource
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from scipy.stats import chi2

from pdr_core import topics
from pdr_core.io.bag import write_batches
from pdr_pocket.samples import Samples

ROOT = Path(__file__).resolve().parents[2]
HOUR_SCENARIOS = ("out_and_back_39min", "theresienhoehe")
MC_RUNS = 50


def hour_bag(folder: Path) -> tuple[Path, int]:
    """The scenarios back to back in one bag, each shifted to start 10 ms after the
    previous one ends."""
    from dataclasses import replace

    from pdr_core.io.batch import MessageBatch
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    parts: dict[str, list[MessageBatch]] = {topics.IMU_DATA: [], topics.IMU_MAG: []}
    end = None
    for seed, name in enumerate(HOUR_SCENARIOS):
        _, data = load_pocket_scenario(name)
        sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, name), data,
                                        "xsens_mtw", {}, 100.0, seed, placement="pocket"))
        shift = 0 if end is None else end + 10_000_000 - int(sim.imu.stamp_ns[0])
        for topic in parts:
            batch = sim.batches[topic]
            parts[topic].append(replace(batch, stamp_ns=batch.stamp_ns + shift))
        end = int(parts[topics.IMU_DATA][-1].stamp_ns[-1])
    merged = {t: MessageBatch.concatenate(b) for t, b in parts.items()}
    path = folder / "hour"
    write_batches(path, merged)
    return path, len(merged[topics.IMU_DATA])


def timed_run(bag: Path, out: Path, *options: str) -> tuple[float, float]:
    """Wall time [s] and the child's peak resident memory [MB] of pdr-pocket run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    start = time.perf_counter()
    subprocess.run([str(ROOT / "ws"), "pdr-pocket", "run", str(bag), "--out", str(out),
                    *options], check=True, capture_output=True)
    wall = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return wall, max(peak, before) / 1024.0


def speed_table() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        print("simulating an hour of pocket walking ...", file=sys.stderr)
        bag, samples = hour_bag(folder)
        print(f"\n{'pdr-pocket run':<26}{'samples':>10}{'wall [s]':>10}{'samples/s':>12}"
              f"{'peak RSS [MB]':>15}")
        runs = {"bag and report": (), "with --plot": ("--plot",),
                "with --drift online": ("--drift", "online"),
                "with --drift offline": ("--drift", "offline")}
        for k, (label, options) in enumerate(runs.items()):
            wall, peak = timed_run(bag, folder / f"out{k}", *options)
            print(f"{label:<26}{samples:>10}{wall:>10.1f}{samples / wall:>12.0f}{peak:>15.0f}")


def final_nees(seed: int) -> tuple[float, int]:
    from pdr_pocket.config import PocketConfig
    from pdr_pocket.navigator import PocketNavigator
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    _, data = load_pocket_scenario("h1_rectangle")
    data = {**data, "seed": seed}
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, "h1"), data, "xsens_mtw",
                                    {}, 100.0, seed, placement="pocket"))
    out = PocketNavigator(PocketConfig()).process(Samples(
        sim.trajectory.t, sim.imu["linear_acceleration"], sim.imu["angular_velocity"],
        sim.mag["magnetic_field"]))
    steps = sim.model.true_steps
    true_end = np.array([np.sum(steps.length * np.cos(steps.heading)),
                         np.sum(steps.length * np.sin(steps.heading)),
                         np.sum(steps.vertical_displacement)])
    error = out.steps[-1].position - true_end
    cov = out.steps[-1].covariance
    dof = int(np.sum(np.diag(cov) > 1e-12))
    keep = np.diag(cov) > 1e-12
    return float(error[keep] @ np.linalg.solve(cov[np.ix_(keep, keep)], error[keep])), dof


def nees_table() -> None:
    with ProcessPoolExecutor(2) as pool:
        results = list(pool.map(final_nees, range(MC_RUNS)))
    nees = np.array([r[0] for r in results])
    dof = results[0][1]
    low, high = chi2.ppf([0.025, 0.975], dof * MC_RUNS) / MC_RUNS
    print(f"\nposition NEES at the end of H1, {MC_RUNS} runs ({dof} dof)")
    print(f"{'mean NEES':>10}{'95 % band':>18}{'median':>9}{'p90':>8}  consistent")
    print(f"{nees.mean():>10.2f}{f'[{low:.2f}, {high:.2f}]':>18}{np.median(nees):>9.2f}"
          f"{np.percentile(nees, 90):>8.2f}  {'yes' if low <= nees.mean() <= high else 'no'}")


if __name__ == "__main__":
    speed_table()
    nees_table()
