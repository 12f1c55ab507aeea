"""Benchmark: is the ``nav_msgs/Odometry`` covariance honest? (issue 42, acceptance 3)

Run on purpose (``./ws python test/benchmarks/bench_odometry_nees.py [runs] [--pocket]``),
not in CI (``--pocket``: the simulated pocket walks alone). For each simulated walk,
``runs`` seeds (default 20) of the simulator's sensor errors; each run's navigator
output is packed as the ``pdr/foot/odometry`` or ``pdr/pocket/odometry`` messages are
(pdr_ins_ekf.offline.output_batches, pdr_pocket.messages.step_batches), and its
covariance judged against the truth with the normalised estimation error squared,
ε = eᵀ·P⁻¹·e (Bar-Shalom et al. 2001, Section 5.4.2):

- the foot (every second of the walk): the position error (3 dof) and the attitude
  error, the rotation vector of R̂·Rᵀ in the map frame (3 dof); on the scenarios as
  written (a still stance) and on level walks as long in the ``walk`` gait (a stance
  that lands and rolls, as a real foot's);
- the pocket (every step, from the first): the horizontal position error (2 dof) against
  the sum of the true strides up to that step (the runs whose step count is the truth's),
  the x, y block of the odometry's pose covariance; the sensor simulated is the default
  configuration's (``calibrated_phone``, not ``IMU``: a phone's configuration holds a
  phone's magnetometer offset, which the MTw's simulation has not), the stride line told
  calibrated (the simulated walker walks it exactly).

With the shared data beside the repository (``../shared/data``, or ``PDR_SHARED_DATA``),
the same for the foot on the real pyshoe VICON trials (imported as bags/README.md
imports its sample, the shipped configuration): the position NEES every second against
the VICON position, each trial's mean and the share of seconds inside the one-run 95 %
band of 3 dof; against the filter's covariance alone, and with the truth's own error
added to it (:func:`truth_covariance`: the VICON marker's spread while the IMU stands
still, and its lever arm from the IMU).

The navigators start at their own origin and with their configured heading (the heading
is unobservable): the foot's NEES are pdr_core.evaluation.consistency's, the reports' (both paths
from their start, the estimate turned onto the truth where it is first 0.8 m from its
start, pdr_core.evaluation.metrics.alignment_yaw, its covariance and attitude turned with it), at
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
# name: (scenario, its level walk in the `walk` gait instead, IMU rate [Hz]): the
# scenarios' strides are Zampella et al.'s pattern, whose stance is exactly still; the
# `walk` gait's foot lands with an impact and rolls about the heel and the ball
# (pdr_sim.foot_gaits, docs/simulator.md), sampled at the pyshoe trials' 200 Hz (at 100 Hz
# the impact's integration error dominates the touchdown innovations)
FOOT_WALKS = {"foot_walk (1 min)": (str(ROOT / "bags" / "foot_walk.yaml"), False, 100.0),
              "long_mixed_walk": ("long_mixed_walk", False, 100.0),
              "walk gait, as long as foot_walk, 200 Hz": (
                  str(ROOT / "bags" / "foot_walk.yaml"), True, 200.0),
              "walk gait, as long as long_mixed_walk, 200 Hz": ("long_mixed_walk", True, 200.0)}
POCKET_WALKS = {"h1_rectangle": "h1_rectangle", "pocket_walk (4 min)":
                str(ROOT / "bags" / "pocket_walk.yaml")}
IMU = "xsens_mtw"
SHARED = Path(os.environ.get("PDR_SHARED_DATA", ROOT.parent / "shared" / "data"))
VICON_COLUMNS = ["--time-col", "t_s", "--acc-cols", "acc_x_mps2,acc_y_mps2,acc_z_mps2",
                 "--gyro-cols", "gyr_x_radps,gyr_y_radps,gyr_z_radps", "--pos-cols",
                 "gt_x_m,gt_y_m,gt_z_m", "--pos-axes=-x,y,z"]
# The VICON marker sits off the IMU; its offset r is not published. A few centimetres
# (docs/foot_ins.md, "Covariance honesty": σ per body axis of the assumed offset)
MARKER_LEVER_SIGMA_M = 0.03
STILL_MIN_S = 0.1       # detected stances at least this long show the truth's own spread


def foot_run(args: tuple[str, bool, float, int]) -> tuple[np.ndarray, np.ndarray]:
    """Position and attitude NEES at every second of one seed's foot walk: the scenario
    ``args[0]``, or with ``args[1]`` its level walk in the ``walk`` gait
    (pdr_sim.foot_trajectory.level_walk_like), at ``args[2]`` Hz, seed ``args[3]``."""
    from pdr_core import topics
    from pdr_core.evaluation.consistency import attitude_nees, checkpoints, position_nees
    from pdr_core.evaluation.metrics import alignment_yaw, truth_at, truth_orientation_at
    from pdr_ins_ekf.config import load_run_config
    from pdr_ins_ekf.offline import navigate, output_batches
    from pdr_sim.foot_trajectory import level_walk_like
    from pdr_sim.scenario import load_scenario, scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    scenario, data = load_scenario(args[0])
    if args[1]:
        data = level_walk_like(scenario, data)
        scenario = scenario_from_dict(data, data["name"])
    sim = simulate(SimulationConfig(scenario, data, IMU, {}, args[2], args[3]))
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
    configuration is made for (its ``imu_profile``), and the simulated walker walks the
    shipped stride line exactly, so the navigator is told the line is the person's
    (``step_length.calibrated``)."""
    from dataclasses import replace

    from pdr_core import topics
    from pdr_core.evaluation.consistency import nees
    from pdr_pocket.config import PocketConfig
    from pdr_pocket.messages import step_batches
    from pdr_pocket.navigator import PocketNavigator
    from pdr_pocket.samples import Samples
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    config = PocketConfig()
    config = replace(config, step_length=replace(config.step_length, calibrated=True))
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


def truth_covariance(run, truth: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The covariance (K, 3, 3) [m²] of the VICON truth's own error at the checkpoints
    ``at``, both paths taken from their start (the truth minus its first sample), in the
    estimate's map frame (position_nees turns it with the estimate's):

    - the marker's jitter: the truth moves while the IMU stands still (marker
      reconstruction, swapped markers): its variance per axis about each detected stance
      of ``STILL_MIN_S`` or more, measured on the trial, twice (start and checkpoint);
    - the lever arm: the marker sits at r from the IMU, so the truth is the IMU's position
      plus C·r, and from the start it carries (C(t) − C(0))·r; with r unknown, isotropic
      of σ ``MARKER_LEVER_SIGMA_M`` per axis, its covariance is σ²·D·Dᵀ, D = C(t) − C(0)
      (the estimated attitude, off the true one by a degree or so)."""
    t = (run.stamp_ns - run.stamp_ns[0]) * 1e-9
    edges = np.flatnonzero(np.diff(np.concatenate(([0], run.stance.astype(int), [0]))))
    spread = [truth[a:b] - truth[a:b].mean(axis=0)
              for a, b in zip(edges[::2], edges[1::2], strict=True)
              if t[b - 1] - t[a] >= STILL_MIN_S]
    jitter = 2 * np.diag(np.mean(np.concatenate(spread) ** 2, axis=0))
    turn = run.output.attitude[at] - run.output.attitude[0]
    return jitter + MARKER_LEVER_SIGMA_M ** 2 * turn @ turn.transpose(0, 2, 1)


def vicon_trial(csv: Path) -> tuple[np.ndarray, np.ndarray]:
    """Position NEES every second of one real VICON trial (shipped configuration): against
    the published covariance, and against it plus the truth's (:func:`truth_covariance`)."""
    from pdr_core import topics
    from pdr_core.evaluation.consistency import checkpoints, position_nees
    from pdr_core.evaluation.metrics import truth_at
    from pdr_core.io.bag import BagReader
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
    cov = cov.reshape(-1, 6, 6)[:, :3, :3]
    truth = truth_at(pose, run.stamp_ns)
    return (position_nees(run.output.position, truth, at, cov)[0],
            position_nees(run.output.position, truth, at,
                          cov + truth_covariance(run, truth, at))[0])


def vicon_table() -> None:
    trials = sorted((SHARED / "foot" / "pyshoe_vicon").glob("*.csv"))
    if not trials:
        print(f"\n(no VICON trials at {SHARED}: the real-data table is left out)")
        return
    low, high = chi2.ppf([0.025, 0.975], 3)
    print(f"\nfoot on the real pyshoe VICON trials: position NEES every second (3 dof; one "
          f"run's 95 % band [{low:.2f}, {high:.2f}]), against the published covariance "
          f"and against it plus the truth's own (truth_covariance)\n")
    print("| trial | seconds | mean NEES | mean NEES / 3 | with the truth's: mean NEES / 3 | "
          "median NEES / 3 | seconds inside |\n|---|---:|---:|---:|---:|---:|---:|")
    with ProcessPoolExecutor(2) as pool:
        for csv, (alone, values) in zip(trials, pool.map(vicon_trial, trials), strict=True):
            inside = np.mean((values >= low) & (values <= high))
            print(f"| {csv.stem} | {len(values)} | {alone.mean():.1f} | {alone.mean() / 3:.2f} "
                  f"| {values.mean() / 3:.2f} | {np.median(values) / 3:.2f} | "
                  f"{100 * inside:.0f} % |", flush=True)


XIO_ARGS = ["--time-col", "Time (s)", "--drop-duplicates", "--acc-unit", "g", "--gyro-unit",
            "deg/s", "--acc-cols", "Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)",
            "--gyro-cols", "Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s)"]


def xio_loop() -> None:
    """The foot on the x-io short_walk loop (it ends where it starts): the NEES of the end
    point's error against its covariance (3 dof, one sample)."""
    from pdr_core import topics
    from pdr_core.evaluation.consistency import nees
    from pdr_core.io.bag import BagReader
    from pdr_ins_ekf.config import load_run_config
    from pdr_ins_ekf.offline import navigate, output_batches

    csv = SHARED / "foot" / "xio_gait_tracking" / "short_walk.csv"
    if not csv.exists():
        return
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([str(ROOT / "ws"), "pdr-sim", "import-csv", str(csv), *XIO_ARGS,
                        "--out", f"{tmp}/bag"], check=True, capture_output=True)
        imu = BagReader(f"{tmp}/bag").read("/imu/data")
    run = navigate(imu, load_run_config())
    last = np.array([len(run.stamp_ns) - 1])
    cov = output_batches(run)[topics.FOOT_ODOMETRY].take(last)["pose.covariance"].reshape(6, 6)
    error = run.output.position[-1] - run.output.position[0]
    low, high = chi2.ppf([0.025, 0.975], 3)
    value = nees(error[None], cov[None, :3, :3])[0]
    print(f"\nfoot on the x-io short_walk loop: end-point error {np.linalg.norm(error):.2f} m, "
          f"σ {np.sqrt(np.trace(cov[:3, :3])):.2f} m, NEES {value:.1f} (3 dof; one sample's "
          f"95 % band [{low:.2f}, {high:.2f}])")


def oxiod_table() -> None:
    """The pocket's orientation filter (the default configuration, whose attitude
    covariance pdr/pocket/odometry carries) on the real OxIOD phones against the Vicon
    attitude: pdr-pocket attitude's consistency, the whole attitude (3 dof, the heading
    aligned at the start) and the tilt (2 dof)."""
    from bench_attitude_peers import oxiod_sequences

    from pdr_core.evaluation.attitude_metrics import tilt_error
    from pdr_core.evaluation.consistency import attitude_consistency
    from pdr_pocket.compiled_orientation_data import ATT_ROWS
    from pdr_pocket.config import PocketConfig
    from pdr_pocket.orientation import OrientationFilter

    sequences = oxiod_sequences([])
    if not sequences:
        return
    print("\npocket orientation filter on the real OxIOD phones (Vicon attitude): NEES per "
          "degree of freedom once a second\n")
    print("| sequence | seconds | attitude NEES/dof | tilt NEES/dof | attitude, object offset "
          "removed | tilt, offset removed | band | tilt error RMS (offset removed) |\n"
          "|---|---:|---:|---:|---:|---:|---|---:|")
    for name, (t, gyro, accel, mag, truth) in sequences.items():
        estimate = OrientationFilter(PocketConfig().orientation).run(t, gyro, accel, mag)
        cov = estimate.covariance[:, ATT_ROWS, ATT_ROWS]
        figures = attitude_consistency(t, estimate.attitude, cov, truth)
        mounted = truth @ object_offset(estimate.attitude, truth).T
        offset_removed = attitude_consistency(t, estimate.attitude, cov, mounted)
        tilt = [np.degrees(np.sqrt(np.mean(tilt_error(estimate.attitude, c) ** 2)))
                for c in (truth, mounted)]
        band = figures["attitude"]["band_per_dof"]
        print(f"| {name} | {figures['attitude']['samples']} | "
              f"{figures['attitude']['nees_per_dof']:.2f} | {figures['tilt']['nees_per_dof']:.2f} "
              f"| {offset_removed['attitude']['nees_per_dof']:.2f} | "
              f"{offset_removed['tilt']['nees_per_dof']:.2f} | [{band[0]:.2f}, {band[1]:.2f}] | "
              f"{tilt[0]:.2f}° / {tilt[1]:.2f}° |", flush=True)


def object_offset(estimate: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """The fixed rotation (3, 3) from the Vicon object's axes to the phone's that best
    turns the truth's vertical seen in the body frame onto the estimate's over the whole
    sequence (Wahba's problem, scipy's align_vectors): the truth's own error, the object
    "a few degrees off the phone's axes" (docs/pocket.md), which no filter can see."""
    from scipy.spatial.transform import Rotation

    rotation, _ = Rotation.align_vectors(estimate[:, 2, :], truth[:, 2, :])
    return rotation.as_matrix()


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
    args = [a for a in sys.argv[1:] if a != "--pocket"]
    pocket_only = "--pocket" in sys.argv[1:]
    runs = int(args[0]) if args else 20
    from pdr_pocket.config import PocketConfig

    print(f"NEES of the odometry covariance, {runs} seeds per walk; sensors simulated: the "
          f"foot {IMU}, the pocket {PocketConfig().orientation.imu_profile}\n")
    print("| walk | part | runs | dof | mean ANEES | 95 % band | checkpoints inside | "
          "final ANEES |\n|---|---|---:|---:|---:|---|---:|---:|")
    with ProcessPoolExecutor(2) as pool:
        for name, walk in ({} if pocket_only else FOOT_WALKS).items():
            results = list(pool.map(foot_run, [(*walk, seed) for seed in range(runs)]))
            print(row(f"foot: {name}", "position", [r[0] for r in results], 3), flush=True)
            print(row(f"foot: {name}", "attitude", [r[1] for r in results], 3), flush=True)
        for name, walk in POCKET_WALKS.items():
            results = [r for r in pool.map(pocket_run, [(walk, seed) for seed in range(runs)])
                       if r is not None]
            print(row(f"pocket: {name}", "position (horizontal)", results, 2), flush=True)
    if pocket_only:
        return
    vicon_table()
    xio_loop()
    oxiod_table()


if __name__ == "__main__":
    main()
