"""Benchmark: the nearest against the multi-hypothesis association of revisits (issues 32, 55).

Run on purpose (``make bench``, or ``python test/benchmarks/bench_association.py
[--seeds N] [--config shipped|thesis ...] [--scenario ...] [--imu PROFILE] [--zaru]
[--bias-model allan|thesis] [--jobs N] [--no-speed]``), not in CI. Prints:

1. Seeds, one table per walk and per ``--config`` (default both, shipped first): the
   Theresienhöhe walk (Muñoz Díaz 2016, Fig. 5.7) and the corridor grid (pdr_sim's
   ``corridor_grid``), a phone in the pocket with ``xsens_mtw`` errors (or ``--imu``'s
   profile) and the gyro biases of Muñoz Díaz 2016, Table 6.1 (a 0.05 °/s z bias), the
   navigator with the orientation filter's noise of the sensor's profile (``imu_profile``:
   xsens_mtw for the Xsens and the thesis' tables) and

   - ``shipped``: config/pocket_pdr.yaml (its filter, bias model and rest update) with
     the magnetometer off (issue 55's setting);
   - ``thesis``: config/pocket_pdr_no_mag.yaml (``--zaru``: with the zero-rate update on)
     with the allan bias model (``--bias-model thesis``: Eq. (3.11) as written, the
     file's own setting, issue 40);

   over seeds 1 to N: per seed, the final position error without corrections, with the
   nearest association's (``pdr-pocket run --drift online``'s loop, in process) and with
   the multi-hypothesis one's, each with its associations right and wrong against the
   simulator's truth and its ratio to the uncorrected error; then the totals, the medians
   of the final errors and of uncorrected/corrected, and the seeds whose corrected end is
   more than 5 % worse than the uncorrected one (issue 55's acceptance: none).
2. Speed: the time per landmark of the multi-hypothesis association against the number
   of hypotheses kept, k, on the corridor grid's steps (seed 1, no corrections fed back),
   with what it associated.
"""
from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace

import numpy as np

from pdr_pocket.samples import Samples

SCENARIOS = ("theresienhoehe", "corridor_grid")
BIAS = {"gyro": {"bias_deg_per_s": [-0.1, 0.1, 0.05]}}
K_VALUES = (1, 2, 4, 8, 16, 32)


def simulated(scenario: str, seed: int, imu: str = "xsens_mtw"):
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    _, data = load_pocket_scenario(scenario)
    return simulate(SimulationConfig(pocket_scenario_from_dict(data, scenario), data,
                                     imu, BIAS, 100.0, seed, placement="pocket"))


def navigator_config(zaru: bool = False, imu: str = "xsens_mtw", bias_model: str = "allan",
                     setting: str = "thesis"):
    """``thesis``: config/pocket_pdr_no_mag.yaml with ``zaru`` and ``bias_model``;
    ``shipped``: config/pocket_pdr.yaml (its filter, its bias model, its rest update) with
    the magnetometer off (``ekf.field`` and the thesis filter's magnetic updates).
    Either with the orientation filter's noise of ``imu``'s profile."""
    from pdr_pocket.config import default_config_path, load_pocket_config

    profile = "consumer_phone" if imu == "consumer_phone" else "xsens_mtw"
    if setting == "shipped":
        config = load_pocket_config(default_config_path())
        o = config.orientation
        return replace(config, orientation=replace(
            o, imu_profile=profile, ekf=replace(o.ekf, field=False),
            updates=replace(o.updates, absolute_magnetic=False,
                            differential_magnetic=False)))
    config = load_pocket_config(default_config_path().with_name("pocket_pdr_no_mag.yaml"))
    orientation = config.orientation
    return replace(config, orientation=replace(
        orientation, updates=replace(orientation.updates, zaru=zaru),
        imu_profile=profile, bias_model=bias_model))


def truth_of(sim, log) -> dict:
    from pdr_drift.drift_report import truth_report

    record = [{"id": m.id, "revisit_of": m.revisit_of} for m in sim.model.landmarks]
    return truth_report(log, sim.truth["/ground_truth/landmarks"], record,
                        int(sim.imu.stamp_ns[0]))


def one_seed(job: tuple[str, int, str, bool, str, str]) -> tuple[str, int, list]:
    """(scenario, seed, [(final error [m], right, wrong) alone, nearest, multi])."""
    from pdr_drift.config import DriftConfig
    from pdr_pocket.drift_loop import navigate_online

    scenario, seed, imu, zaru, bias_model, setting = job
    sim = simulated(scenario, seed, imu)
    steps = sim.model.true_steps
    end = np.array([np.sum(steps.length * np.cos(steps.heading)),
                    np.sum(steps.length * np.sin(steps.heading))])
    samples = Samples(sim.trajectory.t, sim.imu["linear_acceleration"],
                      sim.imu["angular_velocity"], sim.mag["magnetic_field"])
    row = []
    for association, apply in (("nearest", False), ("nearest", True),
                               ("multi_hypothesis", True)):
        _, out, log = navigate_online(navigator_config(zaru, imu, bias_model, setting),
                                      DriftConfig(association=association),
                                      samples, apply=apply)
        report = truth_of(sim, log)
        row.append((float(np.linalg.norm(out.steps[-1].position[:2] - end)),
                    report["associations_correct"] if apply else 0,
                    report["associations_wrong"] if apply else 0))
    return scenario, seed, row


def seeds_table(seeds: int, imu: str, zaru: bool, bias_model: str = "allan",
                setting: str = "thesis", scenarios: tuple[str, ...] = SCENARIOS,
                workers: int = 2) -> None:
    tasks = [(scenario, seed, imu, zaru, bias_model, setting) for scenario in scenarios
             for seed in range(1, seeds + 1)]
    with ProcessPoolExecutor(workers) as pool:
        results = list(pool.map(one_seed, tasks))
    label = ("config/pocket_pdr.yaml, no magnetometer" if setting == "shipped" else
             f"config/pocket_pdr_no_mag.yaml{', ZARU' if zaru else ''}, bias model "
             f"{bias_model}")
    for scenario in scenarios:
        rows = [(seed, row) for s, seed, row in results if s == scenario]
        print(f"\n{scenario}, {imu}, {label}: final position error [m] (associations "
              "right/wrong; corrected/uncorrected)")
        print("| seed | uncorrected | nearest | multi-hypothesis |\n|---:|---:|---:|---:|")
        for seed, ((alone, _, _), (near, nr, nw), (multi, mr, mw)) in rows:
            print(f"| {seed} | {alone:.2f} | {near:.2f} ({nr}/{nw}; {near / alone:.2f}) | "
                  f"{multi:.2f} ({mr}/{mw}; {multi / alone:.2f}) |")
        table = np.array([[r[0][0], r[1][0], r[2][0], r[1][1], r[1][2], r[2][1], r[2][2]]
                          for _, r in rows])
        print(f"| all | median {np.median(table[:, 0]):.2f} | median "
              f"{np.median(table[:, 1]):.2f} ({table[:, 3].sum():.0f}/"
              f"{table[:, 4].sum():.0f}) | median {np.median(table[:, 2]):.2f} "
              f"({table[:, 5].sum():.0f}/{table[:, 6].sum():.0f}) |")
        print(f"median of uncorrected/corrected: nearest "
              f"{np.median(table[:, 0] / table[:, 1]):.2f}, multi-hypothesis "
              f"{np.median(table[:, 0] / table[:, 2]):.2f}; seeds whose corrected end is "
              f"more than 5 % worse: nearest {int(np.sum(table[:, 1] > 1.05 * table[:, 0]))},"
              f" multi-hypothesis {int(np.sum(table[:, 2] > 1.05 * table[:, 0]))} "
              f"(worst ratio {np.max(table[:, 2] / table[:, 0]):.2f})")


def speed_table() -> None:
    from pdr_drift.config import DriftConfig
    from pdr_drift.drift_log import DriftLog
    from pdr_drift.estimator import DriftEstimator
    from pdr_pocket.drift_loop import navigate_online, step_sample

    sim = simulated("corridor_grid", 1)
    _, out, _ = navigate_online(navigator_config(), DriftConfig(), Samples(
        sim.trajectory.t, sim.imu["linear_acceleration"], sim.imu["angular_velocity"],
        sim.mag["magnetic_field"]), apply=False)
    steps = [step_sample(s) for s in out.steps]
    base = DriftConfig(association="multi_hypothesis")
    print("\nmulti-hypothesis association on the corridor grid's steps (seed 1, "
          f"{len(steps)} steps)")
    print("| k | landmarks | ms per landmark | µs per step without one | right/wrong |\n"
          "|---:|---:|---:|---:|---:|")
    for k in K_VALUES:
        estimator = DriftEstimator(replace(base, hypotheses_k=k), feedback=False)
        log, with_mark, without = DriftLog(), [], []
        for step in steps:
            start = time.perf_counter()
            result = estimator.push(step)
            (with_mark if result.landmarks else without).append(time.perf_counter() - start)
            log.landmarks += result.landmarks
            log.drifts += result.drifts
        log.drifts += estimator.finish().drifts
        report = truth_of(sim, log)
        print(f"| {k} | {len(with_mark)} | {1e3 * np.mean(with_mark):.2f} | "
              f"{1e6 * np.median(without):.0f} | {report['associations_correct']}/"
              f"{report['associations_wrong']} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20, help="seeds 1 to N per scenario")
    parser.add_argument("--imu", default="xsens_mtw",
                        help="the IMU error profile (pdr_core.sensors.imu_profiles), with the "
                             "biases of Table 6.1")
    parser.add_argument("--zaru", action="store_true",
                        help="the navigator's zero-rate update on (pocket_pdr.yaml's default)")
    parser.add_argument("--bias-model", default="allan", choices=("allan", "thesis"),
                        help="the orientation filter's bias model (default allan; thesis: "
                             "Eq. (3.11) as written, pocket_pdr_no_mag.yaml's own)")
    parser.add_argument("--config", nargs="+", default=["shipped", "thesis"],
                        choices=("shipped", "thesis"),
                        help="the navigator's settings, a table each (default both, shipped "
                             "first): shipped, config/pocket_pdr.yaml with the magnetometer "
                             "off; thesis, config/pocket_pdr_no_mag.yaml (--zaru, "
                             "--bias-model apply to it)")
    parser.add_argument("--scenario", nargs="+", default=list(SCENARIOS), choices=SCENARIOS,
                        help="the walks (default both)")
    parser.add_argument("--jobs", type=int, default=2, help="processes (default 2)")
    parser.add_argument("--no-speed", action="store_true", help="the seeds table only")
    args = parser.parse_args()
    if not args.no_speed:
        speed_table()
    for setting in args.config:
        seeds_table(args.seeds, args.imu, args.zaru, args.bias_model, setting,
                    tuple(args.scenario), args.jobs)


if __name__ == "__main__":
    main()
