"""Benchmark (issue 30, acceptance 1): the foot navigator on the gaits beyond level walking.

Run on purpose, not in CI (about a minute)::

    python test/benchmarks/bench_gaits.py [--rates 100 200] [--seed 1] [--profile xsens_mtw]

For each gait scenario of pdr_sim (stairs up and down, stepping in place, crawling, side
and back steps, running) and the level walk of the same duration and seed
(``pdr-sim generate --level-walk``, :func:`pdr_sim.foot_trajectory.level_walk_like`),
simulated with the profile's sensor errors, the navigator of ``pdr-ekf run
--imu-profile PROFILE`` (:func:`pdr_ins_ekf.offline.navigate`): its ARMSE 3D against the
truth, the ratio to the level walk's (the issue's target: at most 2), and the stance
precision and recall against ``ground_truth/stance`` (:func:`pdr_ins_ekf.offline.stance_scores`).
Columns: the shipped configuration and the same with the ZARU in every detected stance
(``zaru_gate_nis: .inf``, as before the gate). Printed as Markdown.
"""
from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

from pdr_core import topics
from pdr_core.evaluation.metrics import error_report, truth_at
from pdr_ins_ekf.config import RunConfig, load_run_config
from pdr_ins_ekf.offline import navigate, stance_scores
from pdr_sim.foot_trajectory import level_walk_like
from pdr_sim.scenario import load_scenario
from pdr_sim.simulation import SimulationConfig, scenario_of, simulate

GAITS = ("stairs_up_down", "stepping_in_place", "crawling", "side_and_back_steps", "running")


def simulated(name: str, level: bool, profile: str, rate_hz: float, seed: int):
    """The gait scenario, or the level walk of its duration, simulated."""
    scenario, data = load_scenario(name)
    if level:
        data = level_walk_like(scenario, data)
        scenario = scenario_of(data, data["name"], "foot")
    return simulate(SimulationConfig(scenario, data, profile, {}, rate_hz, seed))


def scores(sim, config: RunConfig) -> tuple[float, dict]:
    """ARMSE 3D [m] and the stance scores of one run."""
    run = navigate(sim.imu, config)
    truth = truth_at(sim.pose, run.stamp_ns)
    armse = error_report((run.stamp_ns - run.stamp_ns[0]) * 1e-9, run.output.position,
                         truth)["armse_3d_m"]
    return armse, stance_scores(run, sim.batches[topics.GROUND_TRUTH_STANCE])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rates", type=float, nargs="+", default=[100.0, 200.0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--profile", default="xsens_mtw")
    args = parser.parse_args()
    shipped = load_run_config(imu_profile=args.profile)
    configs = {"shipped": shipped,
               "ZARU ungated": replace(shipped, filter=replace(shipped.filter,
                                                               zaru_gate_nis=np.inf))}
    print(f"\n{args.profile}, seed {args.seed}: ARMSE 3D [m] (ratio to the level walk)\n")
    print("| scenario | rate | " + " | ".join(configs) + " | stance precision | recall |")
    print("|---|---:|" + "---:|" * (len(configs) + 2))
    for rate in args.rates:
        for name in GAITS:
            gait = simulated(name, False, args.profile, rate, args.seed)
            level = simulated(name, True, args.profile, rate, args.seed)
            cells = []
            for config in configs.values():
                armse, stance = scores(gait, config)
                armse_level, _ = scores(level, config)
                cells.append(f"{armse:.3f} / {armse_level:.3f} ({armse / armse_level:.1f})")
            print(f"| {name} | {rate:.0f} Hz | " + " | ".join(cells)
                  + f" | {stance['precision']:.3f} | {stance['recall']:.3f} |", flush=True)


if __name__ == "__main__":
    main()
