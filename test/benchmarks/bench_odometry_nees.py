"""Benchmark: is the ``nav_msgs/Odometry`` covariance honest? (issue 42, acceptance 3)

Run on purpose (``./ws python test/benchmarks/bench_odometry_nees.py [runs]``), not in
CI. For each simulated walk, ``runs`` seeds (default 20) of the simulator's sensor
errors; each run's navigator output is packed as the ``pdr/foot/odometry`` or
``pdr/pocket/odometry`` messages are (pdr_ins_ekf.offline.output_batches,
pdr_pocket.messages.step_batches), and its covariance judged against the truth with the
normalised estimation error squared, ε = eᵀ·P⁻¹·e (Bar-Shalom et al. 2001, Section
5.4.2):

- the foot (every second of the walk): the position error (3 dof) and the attitude
  error, the rotation vector of R̂·Rᵀ in the map frame (3 dof);
- the pocket (every step, from the first): the horizontal position error (2 dof) against
  the sum of the true strides up to that step (the runs whose step count is the truth's),
  the x, y block of the odometry's pose covariance; the sensor simulated is the default
  configuration's (``calibrated_phone``, not ``IMU``: a phone's configuration holds a
  phone's magnetometer offset, which the MTw's simulation has not).

With the shared data beside the repository (``../shared/data``, or ``PDR_SHARED_DATA``),
the same for the foot on the real pyshoe VICON trials (imported as bags/README.md
imports its sample, the shipped configuration): the position NEES every second against
the VICON position, each trial's mean and the share of seconds inside the one-run 95 %
band of 3 dof.

The navigators start at their own origin and with their configured heading (the heading
is unobservable): the foot's NEES are pdr_core.consistency's, the reports' (both paths
from their start, the estimate turned onto the truth where it is first 0.8 m from its
start, pdr_core.metrics.alignment_yaw, its covariance and attitude turned with it), at
the first sample of each second. The pocket's are against the true strides, from the
origin both start at.

Per walk and part: the mean over the checkpoints of the average NEES over the runs
(ANEES), its 95 % band for ``runs`` runs, χ²(runs·dof)/runs at 2.5 % and 97.5 %, and the
share of checkpoints inside it. A covariance that is honest keeps the ANEES inside;
above it the navigator is overconfident, below it pessimistic.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from scipy.stats import chi2

ROOT = Path(__file__).resolve().parents[2]
FOOT_WALKS = {"foot_walk (1 min)": str(ROOT / "bags" / "foot_walk.yaml"),
              "long_mixed_walk": "long_mixed_walk"}
POCKET_WALKS = {"h1_rectangle": "h1_rectangle", "pocket_walk (4 min)":
                str(ROOT / "bags" / "pocket_walk.yaml")}
IMU = "xsens_mtw"
SHARED = Path(os.environ.get("PDR_SHARED_DATA", ROOT.parent / "shared" / "data"))
VICON_COLUMNS = ["--time-col", "t_s", "--acc-cols", "acc_x_mps2,acc_y_mps2,acc_z_mps2",
                 "--gyro-cols", "gyr_x_radps,gyr_y_radps,gyr_z_radps", "--pos-cols",
                 "gt_x_m,gt_y_m,gt_z_m", "--pos-axes=-x,y,z"]


def foot_run(args: tuple[str, int]) -> tuple[np.ndarray, np.ndarray]:
    """Position and attitude NEES at every second of one seed's foot walk."""
    from pdr_core import topics
    from pdr_core.consistency import attitude_nees, checkpoints, position_nees
    from pdr_core.metrics import alignment_yaw, truth_at, truth_orientation_at
    from pdr_ins_ekf.config import load_run_config
    from pdr_ins_ekf.offline import navigate, output_batches
    from pdr_sim.scenario import load_scenario
    from pdr_sim.simulation import SimulationConfig, simulate

    scenario, data = load_scenario(args[0])
    sim = simulate(SimulationConfig(scenario, data, IMU, {}, 100.0, args[1]))
    run = navigate(sim.imu, load_run_config(imu_profile=IMU))
    at = checkpoints((run.stamp_ns - run.stamp_ns[0]) * 1e-9)
    pose = output_batches(run)[topics.FOOT_ODOMETRY].take(at)
    cov = pose["pose.covariance"].reshape(-1, 6, 6)
    truth = truth_at(sim.pose, run.stamp_ns)
    return (position_nees(run.output.position, truth, at, cov[:, :3, :3])[0],
            attitude_nees(pose["pose.pose.orientation"], cov[:, 3:, 3:],
                          truth_orientation_at(sim.pose, run.stamp_ns[at]),
                          alignment_yaw(run.output.position, truth)))


def pocket_run(args: tuple[str, int]) -> np.ndarray | None:
    """Horizontal position NEES at every step of one seed's pocket walk (None: another
    step count than the truth's). The sensor simulated is the one the default
    configuration is made for (its ``imu_profile``)."""
    from pdr_core import topics
    from pdr_core.consistency import nees
    from pdr_pocket.config import PocketConfig
    from pdr_pocket.messages import step_batches
    from pdr_pocket.navigator import PocketNavigator
    from pdr_pocket.samples import Samples
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    config = PocketConfig()
    _, data = load_pocket_scenario(args[0])
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, args[0]), data,
                                    config.orientation.imu_profile, {}, 100.0, args[1],
                                    placement="pocket"))
    out = PocketNavigator(config).process(Samples(
        sim.trajectory.t, sim.imu["linear_acceleration"], sim.imu["angular_velocity"],
        sim.mag["magnetic_field"]))
    truth = sim.model.true_steps
    if len(out.steps) != len(truth.length):
        return None
    odometry = step_batches(out, sim.imu.stamp_ns)[topics.POCKET_ODOMETRY]
    cov = odometry["pose.covariance"].reshape(-1, 6, 6)[:, :2, :2]
    true_position = np.cumsum(np.column_stack([truth.length * np.cos(truth.heading),
                                               truth.length * np.sin(truth.heading)]), axis=0)
    return nees(odometry["pose.pose.position"][:, :2] - true_position, cov)


def vicon_trial(csv: Path) -> np.ndarray:
    """Position NEES every second of one real VICON trial (shipped configuration)."""
    from pdr_core import topics
    from pdr_core.bag import BagReader
    from pdr_core.consistency import checkpoints, position_nees
    from pdr_core.metrics import truth_at
    from pdr_ins_ekf.config import load_run_config
    from pdr_ins_ekf.offline import navigate, output_batches

    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([str(ROOT / "ws"), "pdr-sim", "import-csv", str(csv), *VICON_COLUMNS,
                        "--out", f"{tmp}/bag"], check=True, capture_output=True)
        reader = BagReader(f"{tmp}/bag")
        imu, pose = reader.read("/imu/data"), reader.read("/ground_truth/pose")
    run = navigate(imu, load_run_config())
    at = checkpoints((run.stamp_ns - run.stamp_ns[0]) * 1e-9)
    cov = output_batches(run)[topics.FOOT_ODOMETRY].take(at)["pose.covariance"]
    return position_nees(run.output.position, truth_at(pose, run.stamp_ns), at,
                         cov.reshape(-1, 6, 6)[:, :3, :3])[0]


def vicon_table() -> None:
    trials = sorted((SHARED / "foot" / "pyshoe_vicon").glob("*.csv"))
    if not trials:
        print(f"\n(no VICON trials at {SHARED}: the real-data table is left out)")
        return
    low, high = chi2.ppf([0.025, 0.975], 3)
    print(f"\nfoot on the real pyshoe VICON trials: position NEES every second (3 dof; one "
          f"run's 95 % band [{low:.2f}, {high:.2f}])\n")
    print("| trial | seconds | mean NEES | median NEES | seconds inside |\n"
          "|---|---:|---:|---:|---:|")
    with ProcessPoolExecutor(2) as pool:
        for csv, values in zip(trials, pool.map(vicon_trial, trials), strict=True):
            inside = np.mean((values >= low) & (values <= high))
            print(f"| {csv.stem} | {len(values)} | {values.mean():.1f} | "
                  f"{np.median(values):.1f} | {100 * inside:.0f} % |", flush=True)


def row(walk: str, part: str, values: list[np.ndarray], dof: int) -> str:
    """A table row: ANEES over runs at each checkpoint, judged against its band."""
    runs = len(values)
    length = min(len(v) for v in values)
    anees = np.mean([v[:length] for v in values], axis=0)
    low, high = chi2.ppf([0.025, 0.975], runs * dof) / runs
    inside = np.mean((anees >= low) & (anees <= high))
    return (f"| {walk} | {part} | {runs} | {dof} | {np.mean(anees):.2f} | "
            f"[{low:.2f}, {high:.2f}] | {100 * inside:.0f} % | {anees[-1]:.2f} |")


def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    print(f"NEES of the odometry covariance, {IMU}, {runs} seeds per walk\n")
    print("| walk | part | runs | dof | mean ANEES | 95 % band | checkpoints inside | "
          "final ANEES |\n|---|---|---:|---:|---:|---|---:|---:|")
    with ProcessPoolExecutor(2) as pool:
        for name, walk in FOOT_WALKS.items():
            results = list(pool.map(foot_run, [(walk, seed) for seed in range(runs)]))
            print(row(f"foot: {name}", "position", [r[0] for r in results], 3), flush=True)
            print(row(f"foot: {name}", "attitude", [r[1] for r in results], 3), flush=True)
        for name, walk in POCKET_WALKS.items():
            results = [r for r in pool.map(pocket_run, [(walk, seed) for seed in range(runs)])
                       if r is not None]
            print(row(f"pocket: {name}", "position (horizontal)", results, 2), flush=True)
    vicon_table()


if __name__ == "__main__":
    main()
