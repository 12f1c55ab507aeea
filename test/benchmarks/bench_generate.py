"""Benchmark: simulating one hour of 100 Hz foot-mounted IMU data with every error source.

Run on purpose (``make bench``), not in CI. Prints a table of the stages and the overall
rate in samples per second; the target of issue 3 is >= 1,000,000 samples/s on the
project's 2-core machine. Writing the bag is measured separately (it is I/O, not
simulation).
"""
from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from pdr_core.bag import write_batches
from pdr_core.imu_profiles import profile
from pdr_sim.scenario import scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

SCENARIO = {
    "name": "one_hour",
    "seed": 1,
    "variation": {"length_m": 0.05, "swing_s": 0.02, "stance_s": 0.02},
    "environment": {"latitude_deg": 48.15, "magnetic_field": {
        "preset": "munich", "distortion": "table_3_3",
        # the template of 003_05973562addf7331.txt, Fig. 3.12: four streetlights, one car
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


def main() -> None:
    scenario = scenario_from_dict(SCENARIO, "benchmark")
    config = SimulationConfig(scenario, SCENARIO, "consumer_phone", EVERY_ERROR, 100.0, 1)
    errors = profile(config.imu, config.imu_overrides)
    simulate(config, errors)  # warm-up (imports, caches)
    runs = []
    for _ in range(3):
        start = time.perf_counter()
        sim = simulate(config, errors)
        runs.append(time.perf_counter() - start)
    n = len(sim.imu)
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        write_batches(Path(tmp) / "bag", {"/imu/data": sim.imu, "/imu/mag": sim.mag,
                                          "/ground_truth/pose": sim.pose})
        write_s = time.perf_counter() - start
    best = min(runs)
    print(f"{'stage':<34}{'seconds':>10}{'samples/s':>14}")
    print(f"{'simulate (best of 3)':<34}{best:>10.3f}{n / best:>14,.0f}")
    print(f"{'simulate (median of 3)':<34}{np.median(runs):>10.3f}{n / np.median(runs):>14,.0f}")
    print(f"{'write bag (3 topics)':<34}{write_s:>10.3f}{n / write_s:>14,.0f}")
    print(f"samples: {n:,} ({sim.trajectory.t[-1] / 3600:.2f} h at 100 Hz); target >= 1,000,000 "
          f"samples/s: {'met' if n / best >= 1e6 else 'NOT met'}")


if __name__ == "__main__":
    main()
