"""Benchmark: the pocket orientation filter beside the peers a user would pick instead.

Run on purpose (``make bench``, which installs the peers of tools/requirements-bench.in),
not in CI. In one run, on the same samples:

- ours: pdr_pocket's default filter (``filter: ekf``, pdr_pocket.compiled_attitude) with
  the magnetometer (9D) and without it (``ekf: {field: false}``, 6D), and the thesis'
  unscented filter as shipped before issue 53 (config/pocket_pdr_thesis.yaml);
- VQF (``vqf``: Laidig and Seel 2023) 9D and 6D, with its rest and motion bias estimation;
- x-io Fusion (``imufusion``: its AHRS and its gyroscope bias algorithm) with and
  without the magnetometer.

Two tables:

1. **Real phones** (issue 53): the OxIOD sequences of ../shared/data/attitude/oxiod (or
   PDR_SHARED_DATA), and any more given as arguments (``--oxiod DIR ...``, each a folder
   of OxIOD's synchronised ``imuK.csv``/``viK.csv`` pairs or a pair's file), read with
   pdr_core.io.oxiod. Columns per sequence and filter: the heading error's RMS, mean and
   final value [°] (pdr_core.evaluation.attitude_metrics: the truth's most level body axis, relative
   to its first 2 s, so that a filter with and one without an absolute heading are scored
   alike), the tilt error's RMS [°] (the Vicon object sits a few degrees off the phone's
   axes: a floor every filter shares), the largest gyro-bias estimate [°/s] and samples
   per second. Then the median and mean over the sequences.
2. **Simulated walks**: the indoor loops of a phone in the pocket (pdr-sim's
   ``indoor_loops``, ``calibrated_phone``, seeds 1-5), Theresienhöhe with an Xsens MTw
   and 20 minutes without a stop with the thesis' Table 3.2 errors: the same columns.

``--plot DIR`` also writes, per shared sequence, a figure of the heading error over time
for every filter with the field's norm and dip and what our filter did with each reading
(docs/pocket.md, "Heading on real phones").
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core.evaluation.attitude_metrics import heading_error, tilt_error
from pdr_core.io.oxiod import import_oxiod
from pdr_pocket.config import load_pocket_config
from pdr_pocket.orientation import FIELD_JUDGEMENTS, OrientationFilter
from pdr_pocket.orientation_config import EkfConfig, OrientationConfig

ROOT = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("PDR_SHARED_DATA", ROOT.parent / "shared" / "data"))
OXIOD = SHARED / "attitude" / "oxiod"
NO_STOP = Path(__file__).with_name("no_stop_walk.yaml")
G = 9.80665
THESIS = load_pocket_config(ROOT / "src" / "pdr_pocket" / "config" /
                            "pocket_pdr_thesis.yaml").orientation


def ours(config: OrientationConfig):
    def run(t, gyr, acc, mag):
        est = OrientationFilter(config).run(t, gyr, acc, mag)
        return est.attitude, est.bias
    return run


def vqf(nine: bool):
    def run(t, gyr, acc, mag):
        from vqf import VQF

        out = VQF(float(np.median(np.diff(t)))).updateBatch(gyr, acc, mag * 1e6 if nine
                                                            else None)
        quat = out["quat9D" if nine else "quat6D"]
        return Rotation.from_quat(quat[:, [1, 2, 3, 0]]).as_matrix(), out["bias"]
    return run


def fusion(nine: bool):
    def run(t, gyr, acc, mag):
        import imufusion

        rate = 1.0 / float(np.median(np.diff(t)))
        ahrs, bias = imufusion.Ahrs(), imufusion.Bias()
        settings = imufusion.AhrsSettings()
        settings.sample_rate = rate
        ahrs.set_settings(settings)
        bias_settings = imufusion.BiasSettings()
        bias_settings.sample_rate = rate
        bias.set_settings(bias_settings)
        gyr_deg, acc_g, mag_ut = np.degrees(gyr), acc / G, mag * 1e6
        quats, offsets = np.empty((len(gyr), 4)), np.empty((len(gyr), 3))
        for k in range(len(gyr)):
            corrected = bias.update(gyr_deg[k])
            if nine:
                ahrs.update(corrected, acc_g[k], mag_ut[k])
            else:
                ahrs.update_no_magnetometer(corrected, acc_g[k])
            quats[k] = ahrs.get_quaternion()
            offsets[k] = bias.get_offset()
        return Rotation.from_quat(quats[:, [1, 2, 3, 0]]).as_matrix(), np.radians(offsets)
    return run


def filters() -> dict:
    default = OrientationConfig()
    return {"ours 9D": ours(default),
            "ours 6D": ours(replace(default, ekf=EkfConfig(field=False))),
            "thesis filter (before)": ours(THESIS),
            "VQF 9D": vqf(True), "VQF 6D": vqf(False),
            "x-io Fusion 9D": fusion(True), "x-io Fusion 6D": fusion(False)}


def scored(run, t, gyr, acc, mag, truth) -> dict:
    start = time.perf_counter()
    attitude, bias = run(t, gyr, acc, mag)
    seconds = time.perf_counter() - start
    heading = np.degrees(heading_error(t, attitude, truth))
    return {"heading": heading, "rms": float(np.sqrt(np.mean(heading**2))),
            "mean": float(heading.mean()), "final": float(heading[-1]),
            "tilt": float(np.degrees(np.sqrt(np.mean(tilt_error(attitude, truth) ** 2)))),
            "bias": float(np.degrees(np.abs(bias).max())), "rate": len(t) / seconds}


def oxiod_sequences(extra: list[Path]) -> dict[str, tuple]:
    """name -> (t, gyro, accel, mag, truth C_b^n) of the shared sequences and ``extra``."""
    folders = sorted(p for p in OXIOD.iterdir() if p.is_dir()) if OXIOD.is_dir() else []
    if not folders:
        print(f"({OXIOD} missing: the shared sequences are left out)", file=sys.stderr)
    out = {}
    for folder in [*folders, *extra]:
        seq = import_oxiod(folder)
        t = (seq.imu.stamp_ns - seq.imu.stamp_ns[0]) * 1e-9
        mag = seq.mag["magnetic_field"] if seq.mag is not None else np.full((len(t), 3), np.nan)
        out[Path(folder).name] = (t, np.ascontiguousarray(seq.imu["angular_velocity"]),
                                  np.ascontiguousarray(seq.imu["linear_acceleration"]),
                                  np.ascontiguousarray(mag),
                                  Rotation.from_quat(seq.pose["pose.orientation"]).as_matrix())
    return out


def simulated_walks() -> dict[str, tuple]:
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    walks = {}
    for seed in range(1, 6):
        _, data = load_pocket_scenario("indoor_loops")
        field = data["environment"]["magnetic_field"]
        data = {**data, "environment": {**data["environment"], "magnetic_field": {
            **field, "indoor": {**field.get("indoor", {}), "seed": seed}}}}
        walks[f"indoor loops, seed {seed}"] = ("indoor_loops", data, "calibrated_phone", seed)
    walks["Theresienhöhe (MTw)"] = ("theresienhoehe", load_pocket_scenario("theresienhoehe")[1],
                                    "xsens_mtw", 1)
    walks["20 min, no stop (Table 3.2)"] = ("no stop", load_pocket_scenario(NO_STOP)[1],
                                            "thesis_table_3_2", 1)
    out = {}
    for label, (name, data, imu, seed) in walks.items():
        sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, name), data, imu, {},
                                        100.0, seed, placement="pocket"))
        out[label] = (sim.trajectory.t, np.ascontiguousarray(sim.imu["angular_velocity"]),
                      np.ascontiguousarray(sim.imu["linear_acceleration"]),
                      np.ascontiguousarray(sim.mag["magnetic_field"]),
                      sim.trajectory.attitude.as_matrix())
    return out


def table(title: str, records: dict[str, tuple], plot: Path | None = None) -> None:
    print(f"\n{title}\n")
    print("| record | filter | heading RMS [°] | mean | final | tilt RMS [°] | "
          "largest bias [°/s] | samples/s |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    runs = filters()
    summary: dict[str, list[float]] = {name: [] for name in runs}
    for record, data in records.items():
        results = {}
        for name, run in runs.items():
            try:
                results[name] = r = scored(run, *data)
            except ImportError as exc:
                print(f"| {record} | {name} | not installed ({exc}) |")
                continue
            summary[name].append(r["rms"])
            print(f"| {record} | {name} | {r['rms']:.1f} | {r['mean']:+.1f} | "
                  f"{r['final']:+.1f} | {r['tilt']:.1f} | {r['bias']:.2f} | "
                  f"{r['rate']:,.0f} |", flush=True)
        if plot is not None:
            heading_figure(record, data, results, plot / f"heading_{record}.png")
    print("\n| filter | heading RMS, median [°] | mean |\n|---|---:|---:|")
    for name, values in summary.items():
        if values:
            print(f"| {name} | {np.median(values):.1f} | {np.mean(values):.1f} |")


def heading_figure(record: str, data: tuple, results: dict, path: Path) -> None:
    """The heading error of every filter against time, and below it the field in the
    truth's frame (norm and dip) with what ours did with each reading."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t, gyr, acc, mag, truth = data
    est = OrientationFilter(OrientationConfig()).run(t, gyr, acc, mag)
    field = np.einsum("nij,nj->ni", truth, mag) * 1e6
    norm = np.linalg.norm(field, axis=1)
    dip = np.degrees(np.arcsin(-field[:, 2] / norm))
    fig, ax = plt.subplots(3, 1, figsize=(12, 10), sharex=True)
    for name, r in results.items():
        ax[0].plot(t, r["heading"], lw=0.8, label=f"{name} ({r['rms']:.1f}° RMS)")
    ax[0].set(ylabel="heading error [°]", title=f"{record}: heading error of the most level "
              "axis, relative to the first 2 s")
    ax[0].legend(loc="upper left", fontsize=8, ncol=2)
    ax[1].plot(t, norm, color="k", lw=0.6)
    ax[1].set(ylabel="|B| [µT]", title="the field in the truth's frame")
    twin = ax[1].twinx()
    twin.plot(t, dip, color="tab:purple", lw=0.6)
    twin.set_ylabel("dip [°]", color="tab:purple")
    judged = est.field_judgement()
    colours = ("tab:green", "tab:red", "tab:grey")
    for i, (name, colour) in enumerate(zip(FIELD_JUDGEMENTS, colours, strict=True)):
        ax[2].fill_between(t, 0, 1, where=judged == i, color=colour, alpha=0.3, lw=0,
                           transform=ax[2].get_xaxis_transform(), label=name)
    ax[2].plot(t, np.degrees(est.bias), lw=0.8)
    ax[2].set(xlabel="t [s]", ylabel="our gyro bias [°/s]",
              title="our filter's gyro bias and what it did with each magnetometer reading")
    ax[2].legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--oxiod", type=Path, nargs="*", default=[],
                        help="more OxIOD sequences (folders or files of imuK/viK pairs)")
    parser.add_argument("--no-simulated", action="store_true",
                        help="leave out the simulated walks")
    parser.add_argument("--plot", type=Path, help="write the heading figures here")
    args = parser.parse_args()
    if args.plot:
        args.plot.mkdir(parents=True, exist_ok=True)
    OrientationFilter(OrientationConfig()).run(np.arange(50) * 0.01, np.zeros((50, 3)),
                                               np.tile([0.0, 0.0, G], (50, 1)))   # compiled
    table("Real phones: OxIOD, the Vicon attitude as truth", oxiod_sequences(args.oxiod),
          args.plot)
    if not args.no_simulated:
        table("Simulated walks", simulated_walks())
    return 0


if __name__ == "__main__":
    sys.exit(main())
