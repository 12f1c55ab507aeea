"""Benchmark: pdr-pocket's navigator beside a textbook pocket navigator, side by side.

Run on purpose (``make bench``, which installs the peers of tools/requirements-bench.in),
not in CI. The textbook navigator is what a user writes in an afternoon:

- footfalls: peaks of the specific force's norm, low-passed at 3 Hz (second-order
  Butterworth, both ways), at least 0.3 s apart and 1 m/s² prominent
  (``scipy.signal.find_peaks``);
- step length: Weinberg's, K·(max − min)^¼ of that norm between footfalls (Weinberg,
  "Using the ADXL202 in pedometer and personal navigation applications", 2002), with the
  population K = 0.47 m;
- heading: VQF's 6D attitude (``vqf``; Laidig and Seel 2023), the sensor's yaw averaged
  over each footfall (no heading at all without a gyroscope).

On every shared real pocket recording (../shared/data, or PDR_SHARED_DATA) and on
simulated walks with truth (front pocket, back pocket, stairs), in one run. Columns:
footfall error, the steps labelled stairs on level walks, the final floor, and where there
is a position truth (the simulated walks) the 2D ARMSE and the final error [m] of the
report (heading aligned on the first 0.8 m). Prints a Markdown table (docs/pocket.md has
it).

``--heading [--seeds N]`` (issue 40) prints instead the heading of the orientation filter
beside VQF's 6D heading on simulated walks without a magnetometer, per IMU profile
(``xsens_mtw``, ``consumer_phone``): Theresienhöhe (Muñoz Díaz 2016, Fig. 5.7, 22 min,
three laps with stops) and 20 minutes of walking without a stop, front pocket, seeds 1 to
N (default 5). The heading error δψ is the vertical component of the attitude error
(the navigation-frame rotation C·C_trueᵀ, what the filter's P[ATT_UP, ATT_UP] describes);
every filter starts from the true yaw (ours drawn about it with σ 1°, VQF's frame turned
onto the truth over the first second). Columns: median over seeds of the final |δψ| and
of its RMS over the walk [°], and for ours the mean NEES δψ²/σ_ψ² against its 95 %
interval for N walks. Rows: ours with the thesis' bias model and the shipped values
before issue 40 (``imu_profile: xsens_mtw``, ``bias_model: thesis``: "today"), ours
with the allan bias model and the profile's noise (``imu_profile`` = the sensor's), the
same without ZARU (config/pocket_pdr_no_mag.yaml's updates), and VQF 6D (its rest and
motion bias estimation on).

``--textbook-bag BAG --out DIR`` runs the textbook navigator on a bag, as its user would
write it, the yardstick for ``pdr-pocket run``'s speed (issue 53): ``imu/data`` (and
``imu/mag`` when the bag has it, which ``pdr-pocket run`` reads too; VQF 6D leaves it
unused) through rosbags' ``AnyReader``, deserialised message by message as rosbags'
documentation shows, then :func:`textbook`, and the steps written to ``DIR/steps.csv`` (t
[s from the first sample], x, y [m]). This mode imports nothing of this repository's
packages, so its time is the textbook's own; time it beside ``pdr-pocket run BAG --out
OUT`` (e.g. with ``/usr/bin/time -v``).
"""
from __future__ import annotations

import argparse
import itertools
import os
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from scipy.signal import butter, filtfilt, find_peaks
from scipy.spatial.transform import Rotation

# This repository's packages are imported where they are used: --textbook-bag pays for the
# textbook's imports only.
if TYPE_CHECKING:
    from pdr_pocket.orientation_config import OrientationConfig

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(os.environ.get("PDR_SHARED_DATA", ROOT.parent / "shared" / "data")) / "pocket"
G = 9.80665
WEINBERG_K_M = 0.47
BOARD = ("norm_thigh_1", "fast_thigh_1", "jog_thigh_1", "tug_thigh_1", "s_up_thigh_1",
         "s_down_thigh_1", "s_both_thigh_1")
LEVEL = {"norm_thigh_1", "fast_thigh_1", "jog_thigh_1", "tug_thigh_1", "oxford"}


def board(name: str, gyroscope: bool = True):
    from pdr_core.io.csv_import import CsvImuFormat, import_csv

    fmt = CsvImuFormat(time_col="time", acc_cols=("accel_x", "accel_y", "accel_z"),
                       gyro_cols=("gyro_x", "gyro_y", "gyro_z") if gyroscope else (),
                       mag_cols=("mag_x", "mag_y", "mag_z"), mag_unit="ut")
    result = import_csv(DATA / "thigh_revalew" / name / "imu.csv", fmt)
    truth = len((DATA / "thigh_revalew" / name / "step_times.csv").read_text().split()) - 1
    return result.imu, result.mag, truth


def oxford():
    from pdr_core.io.csv_import import CsvImuFormat, import_csv

    csv = next((DATA / "oxford_step_counter").glob("user1_frontpocket_*.csv"))
    fmt = CsvImuFormat(time_col="0", time_unit="ns", acc_cols=("1", "2", "3"), header=False)
    return import_csv(csv, fmt).imu, None, 327


def recordings() -> dict:
    out = {name: board(name) for name in BOARD}
    out |= {f"{name} (no gyro)": board(name, False) for name in ("norm_thigh_1", "fast_thigh_1")}
    out["oxford"] = oxford()
    return out


def simulated() -> dict:
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    out = {}
    for label, scenario, carried in (("H1, front pocket", "h1_rectangle", "front_pocket"),
                                     ("H1, back pocket", "h1_rectangle", "back_pocket"),
                                     ("UP/DW, front pocket", "up_dw", "front_pocket")):
        _, data = load_pocket_scenario(scenario)
        data = {**data, "carried": carried}
        out[label] = simulate(SimulationConfig(pocket_scenario_from_dict(data, label), data,
                                               "xsens_mtw", {}, 100.0, 1, placement="pocket"))
    return out


def textbook(t, gyro, accel):
    """Footfall times [s] and positions (N + 1, 3) of the textbook navigator."""
    rate = (len(t) - 1) / (t[-1] - t[0])
    b, a = butter(2, 3.0 / (rate / 2))
    norm = filtfilt(b, a, np.linalg.norm(accel, axis=1))
    peaks, _ = find_peaks(norm, distance=max(1, int(0.3 * rate)), prominence=1.0)
    if gyro is not None:
        from vqf import VQF
        quat = VQF(1.0 / rate).updateBatch(np.ascontiguousarray(gyro),
                                           np.ascontiguousarray(accel))["quat6D"]
        yaw = np.unwrap(Rotation.from_quat(quat[:, [1, 2, 3, 0]]).as_euler("ZYX")[:, 0])
    else:
        yaw = np.zeros(len(t))
    edges = np.r_[0, peaks]
    steps = [(WEINBERG_K_M * (norm[i:j + 1].max() - norm[i:j + 1].min()) ** 0.25,
              yaw[i:j + 1].mean()) for i, j in itertools.pairwise(edges)]
    moves = np.array([[s * np.cos(h), s * np.sin(h), 0.0] for s, h in steps]).reshape(-1, 3)
    return t[peaks], np.vstack([np.zeros(3), np.cumsum(moves, axis=0)])


def ours(t, gyro, accel, mag=None):
    """Step times [s], positions (N + 1, 3), footfalls and the navigator's steps."""
    from pdr_pocket.config import PocketConfig
    from pdr_pocket.navigator import PocketNavigator
    from pdr_pocket.samples import Samples

    navigator = PocketNavigator(PocketConfig())
    out = navigator.process(Samples(t, accel, gyro, mag))
    positions = np.vstack([np.zeros(3), *(s.position for s in out.steps)])
    return np.array([s.t for s in out.steps]), positions, navigator.footfalls, out.steps


def row(name, truth_footfalls, ours_run, book, truth_positions=None, level=True) -> str:
    from pdr_core.evaluation.metrics import error_report
    from pdr_pocket.config import PocketConfig

    t_ours, p_ours, footfalls, steps = ours_run
    t_book, p_book = book
    stairs = sum(s.activity in (2, 3) for s in steps)
    floor = int(np.round(p_ours[-1, 2] / PocketConfig().stairs.floor_height_m))
    cells = [name, f"{100 * (footfalls - truth_footfalls) / truth_footfalls:+.1f} %",
             f"{100 * (len(t_book) - truth_footfalls) / truth_footfalls:+.1f} %",
             f"{stairs} of {len(steps)}" if level else "—", "0" if level else "—",
             f"{floor:+d}", "+0"]
    if truth_positions is not None:
        for times, positions in ((t_ours, p_ours), (t_book, p_book)):
            truth = truth_positions(np.r_[0.0, times])
            report = error_report(np.r_[0.0, times], positions, truth)
            cells += [f"{report['armse_2d_m']:.2f}", f"{report['final_error_m']:.2f}"]
    else:
        cells += ["—"] * 4
    return "| " + " | ".join(cells) + " |"


NO_STOP_WALK = Path(__file__).with_name("no_stop_walk.yaml")
HEADING_PROFILES = ("xsens_mtw", "consumer_phone")
INITIAL_YAW_SIGMA_DEG = 1.0


def heading_filters(profile: str) -> dict[str, OrientationConfig | None]:
    """The filters of the heading table for a sensor of ``profile`` (None: VQF 6D): the
    default filter and the thesis' (the Allan bias model), each with and without its rest
    update, none reading the magnetometer."""
    from pdr_pocket.orientation_config import EkfConfig, OrientationConfig, Updates

    no_mag = Updates(absolute_magnetic=False, differential_magnetic=False, compass=False)
    thesis = OrientationConfig(filter="thesis", imu_profile=profile, updates=no_mag)
    return {"ekf": OrientationConfig(imu_profile=profile),
            "ekf, no rest": OrientationConfig(imu_profile=profile, ekf=EkfConfig(rest=False)),
            "thesis": thesis,
            "thesis, no ZARU": replace(thesis, updates=replace(no_mag, zaru=False)),
            "VQF 6D": None}


def heading_walk(name: str, profile: str, seed: int):
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    data = load_pocket_scenario(NO_STOP_WALK if name == "no stop" else "theresienhoehe")[1]
    data = {**data, "carried": "front_pocket"}
    return simulate(SimulationConfig(pocket_scenario_from_dict(data, name), data, profile, {},
                                     100.0, seed, placement="pocket"))


def heading_error(sim, config: OrientationConfig | None, seed: int
                  ) -> tuple[np.ndarray, np.ndarray | None]:
    """δψ [rad] per sample (N,) and its variance σ_ψ² (N,) (None for VQF)."""
    from pdr_pocket.compiled_orientation_data import ATT_UP
    from pdr_pocket.orientation import OrientationFilter

    gyro = np.ascontiguousarray(sim.imu["angular_velocity"])
    accel = np.ascontiguousarray(sim.imu["linear_acceleration"])
    truth = sim.trajectory.attitude
    if config is None:
        from vqf import VQF

        quat = VQF(1.0 / 100.0).updateBatch(gyro, accel)["quat6D"]
        estimate = Rotation.from_quat(quat[:, [1, 2, 3, 0]])
        offset = np.mean((estimate[:100] * truth[:100].inv()).as_rotvec()[:, 2])
        estimate = Rotation.from_rotvec([0.0, 0.0, -offset]) * estimate
        return (estimate * truth.inv()).as_rotvec()[:, 2], None
    drawn = np.random.default_rng(seed).standard_normal() * INITIAL_YAW_SIGMA_DEG
    start = float(np.degrees(truth[0].as_euler("ZYX")[0]) + drawn)
    est = OrientationFilter(replace(config, initial_yaw_deg=start,
                                    initial_yaw_sigma_deg=INITIAL_YAW_SIGMA_DEG)).run(
        sim.trajectory.t, gyro, accel)
    error = (Rotation.from_matrix(est.attitude) * truth.inv()).as_rotvec()[:, 2]
    return error, est.covariance[:, ATT_UP, ATT_UP]


def heading_table(seeds: int) -> None:
    from pdr_core.maths.chi2 import chi2_quantile

    tail = chi2_quantile(0.025, seeds) / seeds, chi2_quantile(0.975, seeds) / seeds
    print(f"Heading without a magnetometer, seeds 1-{seeds}: median final |δψ| and RMS [°], "
          f"mean NEES (95 % interval {tail[0]:.2f}-{tail[1]:.2f})\n")
    print("| walk | IMU | filter | final [°] | RMS [°] | NEES |\n|---|---|---|---:|---:|---:|")
    for walk, profile in itertools.product(("Theresienhöhe", "no stop"), HEADING_PROFILES):
        filters = heading_filters(profile)
        figures = {name: [] for name in filters}
        for seed in range(1, seeds + 1):
            sim = heading_walk(walk, profile, seed)
            for name, config in filters.items():
                error, variance = heading_error(sim, config, seed)
                figures[name].append((abs(np.degrees(error[-1])),
                                      np.degrees(np.sqrt(np.mean(error**2))),
                                      np.nan if variance is None else
                                      np.mean(error**2 / variance)))
        for name, rows in figures.items():
            rows = np.array(rows)
            nees = "—" if np.isnan(rows[0, 2]) else f"{rows[:, 2].mean():.2f}"
            print(f"| {walk} | {profile} | {name} | {np.median(rows[:, 0]):.1f} | "
                  f"{np.median(rows[:, 1]):.1f} | {nees} |", flush=True)


def read_imu_bag(bag: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
    """``imu/data`` of a rosbag2 bag as its user reads it with rosbags (``AnyReader``, one
    message deserialised at a time): t [s from the first message] (N,), the angular rate
    [rad/s] and the specific force [m/s²] (N, 3) each, and ``imu/mag`` [T] (M, 3) when the
    bag has it (else None)."""
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    stamps, gyro, accel, mag = [], [], [], []
    with AnyReader([bag], default_typestore=get_typestore(Stores.ROS2_JAZZY)) as reader:
        wanted = [c for c in reader.connections if c.topic in ("/imu/data", "/imu/mag")]
        for connection, _, raw in reader.messages(connections=wanted):
            msg = reader.deserialize(raw, connection.msgtype)
            if connection.topic == "/imu/mag":
                field = msg.magnetic_field
                mag.append((field.x, field.y, field.z))
                continue
            stamps.append(msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
            w, f = msg.angular_velocity, msg.linear_acceleration
            gyro.append((w.x, w.y, w.z))
            accel.append((f.x, f.y, f.z))
    stamps = np.array(stamps)
    return ((stamps - stamps[0]) * 1e-9, np.array(gyro), np.array(accel),
            np.array(mag) if mag else None)


def textbook_bag(bag: Path, out: Path) -> None:
    """``--textbook-bag``: :func:`textbook` on ``bag``, its steps (t [s], x, y [m]) in
    ``out/steps.csv``."""
    t, gyro, accel, _ = read_imu_bag(bag)      # VQF 6D leaves the magnetometer out
    times, positions = textbook(t, gyro, accel)
    out.mkdir(parents=True, exist_ok=True)
    np.savetxt(out / "steps.csv", np.column_stack([times, positions[1:, :2]]), delimiter=",",
               header="t_s,x_m,y_m", comments="", fmt="%.6f")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--heading", action="store_true",
                        help="the heading table against VQF 6D instead (issue 40)")
    parser.add_argument("--seeds", type=int, default=5, help="--heading: seeds 1 to N")
    parser.add_argument("--textbook-bag", type=Path, metavar="BAG",
                        help="instead, the textbook navigator alone on BAG (rosbags, VQF, "
                             "scipy): its steps in --out DIR/steps.csv")
    parser.add_argument("--out", type=Path, metavar="DIR", help="--textbook-bag's output")
    args = parser.parse_args()
    if args.textbook_bag:
        if args.out is None:
            parser.error("--textbook-bag needs --out DIR")
        textbook_bag(args.textbook_bag, args.out)
        return 0
    if args.heading:
        heading_table(args.seeds)
        return 0
    peers_table()
    return 0


def peers_table() -> None:
    """The Markdown table of the module docstring, printed row by row."""
    from pdr_core.evaluation.metrics import truth_at
    from pdr_pocket.inputs import pocket_inputs

    print("| walk | footfalls, ours | textbook | stairs steps on a level walk, ours | "
          "textbook | final floor, ours | textbook | ARMSE 2D [m], ours | final error [m], "
          "ours | ARMSE, textbook | final error, textbook |")
    print("|---" * 11 + "|")
    if DATA.is_dir():
        for name, (imu, mag, truth) in recordings().items():
            inputs = pocket_inputs(imu, mag)
            print(row(name, truth, ours(inputs.t, inputs.gyro_or_none, inputs.accel, inputs.mag),
                      textbook(inputs.t, inputs.gyro_or_none, inputs.accel),
                      level=name.split(" ")[0] in LEVEL), flush=True)
    else:
        print(f"({DATA} missing: the real recordings are left out)", file=sys.stderr)
    for name, sim in simulated().items():
        inputs = pocket_inputs(sim.batches["/imu/data"], sim.batches["/imu/mag"])
        truth_pose = sim.batches["/ground_truth/pose"]
        t0 = int(sim.batches["/imu/data"].stamp_ns[0])
        steps = sim.model.true_steps

        def truth_positions(times, pose=truth_pose, t0=t0):
            return truth_at(pose, t0 + np.round(np.asarray(times) * 1e9).astype(np.int64))

        print(row(name, 2 * len(steps.length),
                  ours(inputs.t, inputs.gyro, inputs.accel, inputs.mag),
                  textbook(inputs.t, inputs.gyro, inputs.accel), truth_positions,
                  level="UP" not in name), flush=True)


if __name__ == "__main__":
    sys.exit(main())
