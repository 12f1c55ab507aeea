"""Benchmark: the pocket navigator on the simulated walks, one table (docs/pocket.md's
"before and after" of issue 28). Run on purpose
(``python test/benchmarks/bench_pocket_sim.py [SEED ...]``, default seed 0), not in CI.

For H1, H2, H3, UP/DW and the building walk, with the Xsens MTw errors and the shipped
configuration: the steps against the true gait cycles (found, missed, false; a true step
is found when one detection falls within its cycle), the activities right, the distance
error % (Muñoz Díaz 2016, Table 4.4: total estimated over total true), the largest riser
error % over the flights (Table 4.5) and the highest and final floor, estimated (true).
"""
from __future__ import annotations

import sys

import numpy as np

from pdr_pocket.config import PocketConfig
from pdr_pocket.navigator import PocketNavigator
from pdr_pocket.run_report import match_steps, riser_errors
from pdr_pocket.samples import Samples
from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

WALKS = ("h1_rectangle", "h2_rectangle_speeds", "h3_museum", "up_dw", "building")


def row(name: str, seed: int) -> str:
    _, data = load_pocket_scenario(name)
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, name), data, "xsens_mtw",
                                    {}, 100.0, seed, placement="pocket"))
    config = PocketConfig()
    navigator = PocketNavigator(config)
    out = navigator.process(Samples(sim.trajectory.t, sim.imu["linear_acceleration"],
                                    sim.imu["angular_velocity"], sim.mag["magnetic_field"]))
    truth = sim.model.true_steps
    match = match_steps(np.array([s.t for s in out.steps]), truth.end_s, truth.duration)
    found = match >= 0
    labels = np.array([s.activity for s in out.steps], dtype=int)[match[found]]
    distance = 100 * (sum(s.length for s in out.steps) / truth.length.sum() - 1)
    risers = [abs(f["error_pct"]) for f in riser_errors(
        navigator.staircases, sim.truth["/ground_truth/step"], truth.end_s)
        if f["error_pct"] is not None]
    height = np.cumsum(sim.truth["/ground_truth/step"]["vertical_displacement"])
    floor = config.stairs.floor_height_m
    true_floors = (f"{int(np.round(max(height.max(), 0) / floor))} / "
                   f"{int(np.round(height[-1] / floor))}")
    cells = [name, f"{len(out.steps)} ({len(truth.end_s)})", str(int((~found).sum())),
             str(len(out.steps) - int(found.sum())),
             f"{int((labels == truth.activity[found]).sum())} of {len(truth.end_s)}",
             f"{distance:+.3f}",
             f"{max(risers):.3f} ({len(risers)})" if risers else "—",
             f"{max((s.floor for s in out.steps), default=0)} / "
             f"{out.steps[-1].floor if out.steps else 0} ({true_floors})"]
    return "| " + " | ".join(cells) + " |"


def main() -> int:
    seeds = [int(a) for a in sys.argv[1:]] or [0]
    for seed in seeds:
        print(f"seed {seed}\n")
        print("| walk | steps (true) | missed | false | activities right | distance % | "
              "risers, largest error % (flights) | highest / final floor (true) |")
        print("|---" * 8 + "|")
        for name in WALKS:
            print(row(name, seed), flush=True)
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
