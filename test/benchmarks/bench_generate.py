"""Benchmark: simulating IMU data with every error source, foot and pocket placements.

Run on purpose (``make bench``), not in CI. Prints a table with the best and median of
five runs in samples per second:
- the foot: one hour at 100 Hz, every sensor error source in a homogeneous field and with
  five iron cylinders perturbing the field as well (issue 3's target: >= 1,000,000
  samples/s on the project's 2-core machine);
- the pocket: the 22-minute Theresienhöhe walk at 100 Hz with every error source, the
  whole run from the scenario (gait plan, pitch spline, truth steps and landmarks
  included; issue 15's target: >= 1,000,000 samples/s).
Writing the bag is measured separately (it is I/O, not simulation).
"""
from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

import numpy as np

from pdr_core.io.bag import write_batches
from pdr_core.sensors.imu_profiles import profile
from pdr_sim.pocket_scenario import load_pocket_scenario
from pdr_sim.simulation import SimulationConfig, scenario_of, simulate

SCENARIO = {
    "name": "one_hour",
    "seed": 1,
    "variation": {"length_m": 0.05, "swing_s": 0.02, "stance_s": 0.02},
    "environment": {"latitude_deg": 48.15, "magnetic_field": {
        "preset": "munich", "distortion": "table_3_3",
        # the template of Muñoz Díaz 2016, Fig. 3.12: four streetlights, one car
        "cylinders": [{"east_m": 10.0 * i, "north_m": 3.0, "radius_m": 0.3} for i in range(4)]
        + [{"east_m": 15.0, "north_m": -6.0, "radius_m": 2.0}]}},
    "segments": [{"type": "standing", "duration_s": 10.0}]
    + [{"type": "straight", "steps": 100},
       {"type": "curve", "steps": 20, "radius_m": 5.0, "direction": "left"},
       {"type": "turn", "angle_deg": 90, "duration_s": 1.5},
       {"type": "curve", "steps": 20, "radius_m": 5.0, "direction": "right"}] * 21,
}
EVERY_ERROR = {  # consumer_phone has scale, misalignment, GM bias, saturation, quantisation
    "gyro": {"rrw_deg_per_s_per_sqrt_h": 0.05},
    "accel": {"random_walk_mps2_per_sqrt_h": 0.01},
    "mag": {"scale_factor_ppm": 5000.0, "misalignment_mrad": 5.0},
}


def time_simulation(data: dict, repeats: int = 5,
                    placement: str = "foot") -> tuple[float, float, object]:
    """Best and median wall time [s] of ``simulate`` on a scenario mapping, and a result."""
    scenario = scenario_of(data, "benchmark", placement)
    config = SimulationConfig(scenario, data, "consumer_phone", EVERY_ERROR, 100.0, 1,
                              placement=placement)
    errors = profile(config.imu, config.imu_overrides)
    simulate(config, errors)  # warm-up (imports, caches)
    runs = []
    for _ in range(repeats):
        start = time.perf_counter()
        sim = simulate(config, errors)
        runs.append(time.perf_counter() - start)
    return min(runs), float(np.median(runs)), sim


def main() -> None:
    homogeneous = {**SCENARIO, "environment": {**SCENARIO["environment"], "magnetic_field": {
        "preset": "munich", "distortion": "table_3_3"}}}
    rows = []
    for name, data in (("every error source, homogeneous field", homogeneous),
                       ("+ 5 iron cylinders (Eq. 3.29)", SCENARIO)):
        best, median, sim = time_simulation(data)
        n = len(sim.imu)
        rows.append((f"simulate: {name}", best, median, n))
    _, pocket = load_pocket_scenario("theresienhoehe")
    best, median, pocket_sim = time_simulation(pocket, placement="pocket")
    rows.append(("pocket: Theresienhöhe 22 min, every error source", best, median,
                 len(pocket_sim.imu)))
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        write_batches(Path(tmp) / "bag", {"/imu/data": sim.imu, "/imu/mag": sim.mag,
                                          "/ground_truth/pose": sim.pose})
        write_s = time.perf_counter() - start
    print(f"{'stage':<50}{'best s':>8}{'median s':>10}{'samples/s (best)':>18}"
          f"{'samples/s (median)':>20}")
    for name, best, median, count in rows:
        print(f"{name:<50}{best:>8.3f}{median:>10.3f}{count / best:>18,.0f}"
              f"{count / median:>20,.0f}")
    print(f"{'write bag (3 topics, not simulation)':<50}{write_s:>8.3f}{'':>10}"
          f"{n / write_s:>18,.0f}")
    print(f"samples: foot {n:,} ({sim.trajectory.t[-1] / 3600:.2f} h at 100 Hz), pocket "
          f"{len(pocket_sim.imu):,}; {os.cpu_count()} CPUs; target >= 1,000,000 samples/s")


if __name__ == "__main__":
    main()
