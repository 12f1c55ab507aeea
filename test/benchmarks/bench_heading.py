"""Benchmark: the heading on a 10-minute walk, one error source at a time (issue 30).

Run on purpose, not in CI (about 6 minutes each on the 2-core machine)::

    python test/benchmarks/bench_heading.py [--seeds 10] [--walk FILE] [--no-recorded]

The walk is ``heading_walk.yaml`` beside this file: ten laps of a 60 m loop, always
turning left (3,600° in all), 592 s, simulated at 400 Hz with the basic step pattern
(the foot still through every stance, turning in the swings); ``--walk
heading_walk_gait.yaml`` walks ten such laps with the walk gait of pdr_sim.foot_gaits
(heel strike, foot flat, heel-off, eversion, impacts) and turns in place at the
corners, 585 s. The IMU is the x-io NGIMU of the ``short_walk`` recording as
:data:`XIO_NGIMU` below (pdr_core has no x-io profile): white noise measured on the
recording's first 14 s at rest, the other errors of the order its class of calibrated
MEMS IMU has (assumed, marked so). Every row is the white noise plus one error source,
with the same white noise per seed in every row; the two "all" rows leave out the
what-ifs. Scale factors and misalignments are drawn per seed, like the turn-on biases.

Every column is a filter: ``foot_ekf.yaml`` as shipped (9 states) and with its
``filter`` keys changed as in :data:`FILTERS`. Stance, alignment and filter are those
of ``pdr-ekf run`` (:func:`pdr_ins_ekf.offline.navigate`), the runs of a row in one
parallel batch (:func:`pdr_ins_ekf.studies.ekf_montecarlo.ekf_batch`). Printed, as
Markdown: the median over seeds of the final heading error |ψ̂ − ψ| [°] at the end of
the walk, and of the final position error and ARMSE 3D [m] (pdr_core.evaluation.metrics, at
100 Hz; the start heading is known in simulation, so the estimate is not turned onto
the truth beyond the metric's own alignment on the first 0.8 m). Then, unless
``--no-recorded``, each filter on the recordings of ../shared/data: ARMSE 3D of the
seven pyshoe VICON trials and the x-io short_walk's loop gap.
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from pdr_core import units
from pdr_core.constants import earth_rate_enu
from pdr_core.evaluation.metrics import error_report, truth_at
from pdr_core.io.csv_import import CsvImuFormat, import_csv
from pdr_core.sensors.allan import gm_sigma_for_bias_instability
from pdr_core.sensors.imu_errors import ImuErrors, TriadErrors, corrupt
from pdr_ins_ekf.config import RunConfig, load_run_config
from pdr_ins_ekf.kernel_data import GYRO
from pdr_ins_ekf.offline import alignment_window, navigate
from pdr_ins_ekf.studies.ekf_montecarlo import detect_runs, ekf_batch
from pdr_ins_ekf.zupt_ekf import (
    initial_attitude,
    initial_covariance,
    kernel_params,
    record_samples,
)
from pdr_sim.foot_trajectory import sample_times
from pdr_sim.scenario import scenario_from_dict
from pdr_sim.signals import angular_rate
from pdr_sim.simulation import SimulationConfig, foot_model, simulate

WALK = Path(__file__).with_name("heading_walk.yaml")
ROOT = Path(__file__).resolve().parents[2]
DATA = Path(os.environ.get("PDR_SHARED_DATA", ROOT.parent / "shared" / "data")) / "foot"
RATE_HZ = 400.0
LATITUDE_DEG = 48.15
KEEP_EVERY = 4                  # the metrics at 100 Hz

# The x-io NGIMU (x-io Technologies), per axis, SI. Measured on short_walk.csv's first
# 14 s at rest: gyro white noise 0.0123 °/s/√Hz on its quietest axis (z; x and y see the
# foot sway), accelerometer 175 µg/√Hz; 1 % of its sample intervals are two samples long.
# Assumed (no NGIMU figure published): turn-on biases σ 0.2 °/s (the recording's rest
# means are 0.05-0.16 °/s) and 5 mg (x-io's x-IMU3 states ±5 mg at 1 g); in-run gyro bias
# 10 °/h bias instability with τ 100 s; scale factors σ 0.3 % and misalignments σ 3 mrad
# per axis left by the factory calibration.
GYRO_WHITE_RADPS_PER_SQRT_HZ = np.radians(0.0123)
ACCEL_WHITE_MPS2_PER_SQRT_HZ = units.ug_per_sqrt_hz_to_si(175.0)
XIO_NGIMU = {
    "gyro_bias_sigma_radps": np.radians(0.2),
    "accel_bias_sigma_mps2": units.mg_to_si(5.0),
    "gyro_bias_instability_radps": units.deg_per_h_to_si(10.0),
    "gyro_bias_correlation_s": 100.0,
    "scale_factor_sigma": 3e-3,
    "misalignment_sigma_rad": 3e-3,
    "dropped_fraction": 0.01,
}
GYRO_LAG_S = 1 / RATE_HZ        # what-if: the gyroscope one sample behind the accelerometer
GYRO_DRIFT_RADPS, GYRO_DRIFT_S = np.radians(0.05), 300.0   # what-if: a large in-run drift
CLOCK_ERROR = 3e-3              # what-if: stamps at the nominal 400 Hz, the sensor 0.3 % slow

# Each row: the white noise plus these sources.
SOURCES = {
    "white noise only": (),
    "gyro turn-on bias, z only": ("gyro_bias_z",),
    "gyro turn-on bias, x y z": ("gyro_bias",),
    "gyro in-run bias (Gauss–Markov)": ("gyro_in_run",),
    "gyro in-run bias, 0.05 °/s over 300 s (what-if)": ("gyro_drift",),
    "accelerometer turn-on bias": ("accel_bias",),
    "gyro scale factor, z only": ("scale_z",),
    "scale factors (gyro, accelerometer)": ("scale",),
    "misalignment (gyro, accelerometer)": ("misalignment",),
    "Earth rotation (48° N)": ("earth",),
    "timing: 1 % of samples dropped": ("dropped",),
    "timing: gyro 2.5 ms late (what-if)": ("lag",),
    "timing: nominal stamps, clock 0.3 % slow (what-if)": ("clock",),
    "all but the scale factors": ("gyro_bias", "gyro_in_run", "accel_bias", "misalignment",
                                  "earth", "dropped"),
    "all (but the what-ifs)": ("gyro_bias", "gyro_in_run", "accel_bias", "scale",
                               "misalignment", "earth", "dropped"),
}

# Column name -> the ``filter`` keys changed from the shipped foot_ekf.yaml.
FILTERS = {
    "9 states": {},
    "15 RW": {"bias_model": "random_walk"},
    "15 RW + ZARU": {"bias_model": "random_walk", "zaru": True},
    # ZARU in every detected stance, as before its innovation gate (zaru_gate_nis)
    "15 RW + ZARU ungated": {"bias_model": "random_walk", "zaru": True,
                             "zaru_gate_nis": 1e300},
    "15 GM + ZARU": {"bias_model": "gauss_markov", "zaru": True},
    # the 15 states that keep the VICON trials (docs/foot_ins.md, "Heading on long walks")
    "15 RW + ZARU 0.05": {"bias_model": "random_walk", "zaru": True, "zaru_sigma_radps": 0.05,
                          "init_gyro_bias_sigma_radps": 5e-4, "init_acc_bias_sigma_mps2": 0.01},
}


@dataclass(frozen=True)
class Truth:
    """The walk without sensor errors: stamps t (N,) [s], true rate and specific force
    (N, 3) in the body frame, the rate with the Earth's and one sample late, the truth
    positions (N, 3) and the final yaw [rad]."""

    t: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    earth_rate: np.ndarray
    gyro_late: np.ndarray
    position: np.ndarray
    final_yaw: float


def walk_truth(walk: Path = WALK) -> Truth:
    """The walk of a scenario file at RATE_HZ, without sensor errors."""
    data = yaml.safe_load(walk.read_text())
    scenario = scenario_from_dict(data, str(walk))
    sim = simulate(SimulationConfig(scenario, data, "ideal", {}, RATE_HZ, 0), ImuErrors())
    traj = sim.trajectory
    late = foot_model(scenario).at(np.maximum(traj.t - GYRO_LAG_S, 0.0))
    assert len(traj.t) == len(sample_times(foot_model(scenario).duration_s, RATE_HZ))
    return Truth(traj.t, sim.true_gyro, sim.true_accel,
                 traj.to_body(earth_rate_enu(LATITUDE_DEG)), angular_rate(late),
                 traj.position, float(traj.euler[-1, 2]))


def distortion(rng: np.random.Generator, parts: tuple[str, ...]) -> dict:
    """Scale factors and misalignments of one sensor for one seed (TriadErrors fields)."""
    fields = {}
    scale = rng.standard_normal(3) * XIO_NGIMU["scale_factor_sigma"]
    off = rng.standard_normal((3, 3)) * XIO_NGIMU["misalignment_sigma_rad"]
    if "scale" in parts:
        fields["scale_factor"] = tuple(scale)
    elif "scale_z" in parts:
        fields["scale_factor"] = (0.0, 0.0, scale[2])
    if "misalignment" in parts:
        np.fill_diagonal(off, 0.0)
        fields["misalignment"] = tuple(map(tuple, off))
    return fields


def measured(truth: Truth, parts: tuple[str, ...], seed: int
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Stamps (N,) [s], specific force and rate (N, 3) of one seed with these sources,
    and the mask (N,) of the samples kept (False: dropped).
    The white noise, the biases and the distortions each come from their own generator,
    so a source's draw is the same in every row that has it."""
    white, gyro_rng, accel_rng, shape_rng, drop_rng = np.random.default_rng(seed).spawn(5)
    z_only = (0.0, 0.0, XIO_NGIMU["gyro_bias_sigma_radps"])
    gyro_fields: dict = {"bias_sigma": z_only if "gyro_bias_z" in parts else
                         (XIO_NGIMU["gyro_bias_sigma_radps"],) * 3 if "gyro_bias" in parts
                         else (0.0,) * 3}
    if "gyro_in_run" in parts:
        sigma = gm_sigma_for_bias_instability(
            XIO_NGIMU["gyro_bias_instability_radps"], XIO_NGIMU["gyro_bias_correlation_s"],
            GYRO_WHITE_RADPS_PER_SQRT_HZ, 0.0)
        gyro_fields |= {"gm_sigma": (sigma,) * 3,
                        "gm_tau_s": (XIO_NGIMU["gyro_bias_correlation_s"],) * 3}
    if "gyro_drift" in parts:
        gyro_fields |= {"gm_sigma": (GYRO_DRIFT_RADPS,) * 3, "gm_tau_s": (GYRO_DRIFT_S,) * 3}
    accel_fields: dict = {"bias_sigma": (XIO_NGIMU["accel_bias_sigma_mps2"],) * 3
                          if "accel_bias" in parts else (0.0,) * 3}
    gyro_rng_shape, accel_rng_shape = shape_rng.spawn(2)
    gyro_fields |= distortion(gyro_rng_shape, parts)
    accel_fields |= distortion(accel_rng_shape, tuple(p for p in parts if p != "scale_z"))
    true_gyro = truth.gyro_late if "lag" in parts else truth.gyro
    if "earth" in parts:
        true_gyro = true_gyro + truth.earth_rate
    gyro = corrupt(true_gyro, TriadErrors(**gyro_fields), RATE_HZ, gyro_rng)
    accel = corrupt(truth.accel, TriadErrors(**accel_fields), RATE_HZ, accel_rng)
    noise = white.standard_normal((2, len(truth.t), 3)) * np.sqrt(RATE_HZ)
    gyro += noise[0] * GYRO_WHITE_RADPS_PER_SQRT_HZ
    accel += noise[1] * ACCEL_WHITE_MPS2_PER_SQRT_HZ
    t = truth.t * (1 + CLOCK_ERROR) if "clock" in parts else truth.t
    keep = np.ones(len(t), bool)
    if "dropped" in parts:   # single samples, never the first or last
        count = int(XIO_NGIMU["dropped_fraction"] * len(t))
        keep[drop_rng.choice(np.arange(1, len(t) - 1), count, replace=False)] = False
    return t, accel, gyro, keep


def filter_runs(config: RunConfig, t: np.ndarray, accel: np.ndarray, gyro: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``pdr-ekf run``'s stance, alignment and filter on runs sharing the stamps t (N,):
    accel, gyro (R, N, 3). The filter starts at the latest first sample of the runs'
    alignment windows (0 on this walk); each run aligns on its own window. Returns the
    kept sample indices (K,), positions (R, K, 3) and yaw (R, K) [rad]."""
    rate = (len(t) - 1) / (t[-1] - t[0])
    stance = detect_runs(config.detector, accel, gyro, rate)
    windows = [alignment_window(s, t, config.alignment_min_s) for s in stance]
    start = max(w.start for w in windows)
    c = config.filter
    yaw = np.radians(config.initial_yaw_deg)
    attitude = np.stack([initial_attitude(a[w.start:w.stop], yaw)
                         for a, w in zip(accel, windows, strict=True)])
    bias = np.zeros((len(accel), 6))
    bias[:, GYRO] = [g[w.start:w.stop].mean(axis=0) for g, w in zip(gyro, windows, strict=True)]
    keep = np.unique(np.r_[np.arange(0, len(t) - start, KEEP_EVERY), len(t) - start - 1])
    position, yaw_out, _, _ = ekf_batch(
        record_samples(t[start:], accel[:, start:], gyro[:, start:], stance[:, start:]),
        attitude, bias, initial_covariance(c), kernel_params(c), keep)
    return keep + start, position, yaw_out


def row_figures(truth: Truth, parts: tuple[str, ...], seeds: range,
                configs: dict[str, RunConfig]) -> dict[str, np.ndarray]:
    """Per filter: (seeds, 3) of |final yaw error| [°], final error and ARMSE 3D [m]."""
    runs = [measured(truth, parts, seed) for seed in seeds]
    groups = ([[i] for i in range(len(runs))] if "dropped" in parts
              else [list(range(len(runs)))])   # dropped samples: each seed its own stamps
    out = {}
    for name, config in configs.items():
        figures = np.empty((len(runs), 3))
        for group in groups:
            keep = runs[group[0]][3]
            t = runs[group[0]][0][keep]
            index, position, yaw = filter_runs(
                config, t, np.stack([runs[i][1][keep] for i in group]),
                np.stack([runs[i][2][keep] for i in group]))
            true_index = np.flatnonzero(keep)[index]
            truth_position = truth.position[true_index]
            for j, i in enumerate(group):
                report = error_report(t[index], position[j], truth_position)
                error = np.angle(np.exp(1j * (yaw[j, -1] - truth.final_yaw)))
                figures[i] = (abs(np.degrees(error)), report["final_error_m"],
                              report["armse_3d_m"])
        out[name] = figures
    return out


PYSHOE = ("2017-11-22-11-22-03", "2017-11-22-11-30-14", "2017-11-22-11-49-03",
          "2017-11-27-11-13-10", "2017-11-27-11-24-07", "2017-12-15-18-03-05",
          "2018-02-22-10-10-29")
PYSHOE_FORMAT = CsvImuFormat(   # as test/test_foot_real_data.py imports them
    time_col="t_s", acc_cols=("acc_x_mps2", "acc_y_mps2", "acc_z_mps2"),
    gyro_cols=("gyr_x_radps", "gyr_y_radps", "gyr_z_radps"),
    pos_cols=("gt_x_m", "gt_y_m", "gt_z_m"), pos_axes=("-x", "y", "z"))
XIO_FORMAT = CsvImuFormat(
    time_col="Time (s)", drop_duplicates=True, acc_unit="g", gyro_unit="degps",
    acc_cols=("Accelerometer X (g)", "Accelerometer Y (g)", "Accelerometer Z (g)"),
    gyro_cols=("Gyroscope X (deg/s)", "Gyroscope Y (deg/s)", "Gyroscope Z (deg/s)"))


def recorded_figures(configs: dict[str, RunConfig]) -> None:
    """Print, per filter, ARMSE 3D of the seven pyshoe VICON trials (mean, and the largest
    ratio to the first filter's) and the x-io short_walk's loop gap, as ``pdr-ekf run``
    gives them (../shared/data, or PDR_SHARED_DATA; skipped when missing)."""
    trials = [DATA / "pyshoe_vicon" / f"{name}.csv" for name in PYSHOE]
    loop = DATA / "xio_gait_tracking" / "short_walk.csv"
    if not all(p.is_file() for p in (*trials, loop)):
        print(f"\n(no recordings under {DATA}: skipped)")
        return
    vicon = [import_csv(p, PYSHOE_FORMAT) for p in trials]
    walk = import_csv(loop, XIO_FORMAT).imu
    print("\n| filter | VICON mean ARMSE [m] | worst trial against 9 states | per trial [m] | "
          "x-io loop gap [m] (horizontal, height) |\n|---|---:|---:|---|---:|")
    first = None
    for name, config in configs.items():
        armse = []
        for trial in vicon:
            run = navigate(trial.imu, config)
            t = (run.stamp_ns - run.stamp_ns[0]) * 1e-9
            armse.append(error_report(t, run.output.position,
                                      truth_at(trial.pose, run.stamp_ns))["armse_3d_m"])
        armse = np.array(armse)
        first = armse if first is None else first
        gap = navigate(walk, config).output.position[-1]
        print(f"| {name} | {armse.mean():.4f} | {100 * (armse / first - 1).max():+.0f} % | "
              f"{', '.join(f'{a:.3f}' for a in armse)} | {np.linalg.norm(gap):.3f} "
              f"({np.linalg.norm(gap[:2]):.3f}, {gap[2]:+.3f}) |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10, help="seeds 0..N-1 (default 10)")
    parser.add_argument("--walk", type=Path, default=WALK,
                        help="scenario file (default heading_walk.yaml; heading_walk_gait.yaml "
                             "beside it: the same laps with the walk gait's stance)")
    parser.add_argument("--no-recorded", action="store_true",
                        help="skip the recorded walks (VICON trials, x-io short_walk)")
    args = parser.parse_args()
    shipped = load_run_config()
    configs = {name: dataclasses.replace(shipped, filter=dataclasses.replace(
        shipped.filter, **changes)) for name, changes in FILTERS.items()}
    begin = time.perf_counter()
    truth = walk_truth(args.walk)
    seeds = range(args.seeds)
    table = {}
    for row, parts in SOURCES.items():
        table[row] = {k: np.median(v, axis=0) for k, v in
                      row_figures(truth, parts, seeds, configs).items()}
        print(f"  {row}: {time.perf_counter() - begin:.0f} s", flush=True)
    names = list(configs)
    distance = float(np.linalg.norm(np.diff(truth.position, axis=0), axis=1).sum())
    print(f"\n{args.walk.name}: {truth.t[-1]:.0f} s, {distance:.0f} m at {RATE_HZ:.0f} Hz, "
          f"turned {np.degrees(truth.final_yaw):.0f}°, median of seeds "
          f"0-{args.seeds - 1}\n")
    print("Final heading error |ψ̂ − ψ| [°]\n")
    print("| error source | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for row, cells in table.items():
        print(f"| {row} | " + " | ".join(f"{cells[n][0]:.2f}" for n in names) + " |")
    print("\nFinal position error / ARMSE 3D [m]\n")
    print("| error source | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for row, cells in table.items():
        print(f"| {row} | " + " | ".join(f"{cells[n][1]:.2f} / {cells[n][2]:.2f}"
                                         for n in names) + " |")
    if not args.no_recorded:
        recorded_figures(configs)
    print(f"\n{time.perf_counter() - begin:.0f} s")


if __name__ == "__main__":
    main()
