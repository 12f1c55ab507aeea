"""Benchmark: the foot navigator offline and the live node's callback.

Run on purpose (``make bench``), not in CI.

1. ``pdr-ekf run`` core (detector, alignment, filter) on simulated 200 Hz foot data, in
   IMU samples/s (issue 4 target: >= 180,000 samples/s on 1 h of data).
2. The streaming navigator behind ``zupt_ekf``: median and 99th-percentile time per
   sample (the node keeps up with 1 kHz if the p99 stays below 1 ms).
"""
from __future__ import annotations

import time

import numpy as np

from pdr_ins_ekf.config import RunConfig
from pdr_ins_ekf.offline import navigate
from pdr_ins_ekf.streaming import StreamingNavigator
from pdr_sim.scenario import scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate


def walk(minutes: float, rate_hz: float):
    steps = int(minutes * 60 / 1.2)
    data = {"segments": [{"type": "standing", "duration_s": 2.0},
                         {"type": "straight", "steps": steps}]}
    return simulate(SimulationConfig(scenario_from_dict(data, "walk"), data, "xsens_mtw", {},
                                     rate_hz, 1)).imu


def main() -> None:
    imu = walk(5.0, 200.0)
    start = time.perf_counter()
    navigate(imu, RunConfig())
    offline = time.perf_counter() - start
    navigator = StreamingNavigator(RunConfig())
    per_sample = np.empty(len(imu))
    accel, gyro = imu["linear_acceleration"], imu["angular_velocity"]
    for k in range(len(imu)):
        t0 = time.perf_counter()
        navigator.push(int(imu.stamp_ns[k]), accel[k], gyro[k])
        per_sample[k] = time.perf_counter() - t0
    print(f"{'measure':<46}{'value':>14}")
    print(f"{'offline navigate (5 min at 200 Hz)':<46}{len(imu) / offline:>10,.0f} /s")
    print(f"{'streaming push, median':<46}{np.median(per_sample) * 1e6:>11.0f} us")
    print(f"{'streaming push, p99':<46}{np.percentile(per_sample, 99) * 1e6:>11.0f} us")
    print(f"{'sustainable input rate (1 / p99)':<46}{1 / np.percentile(per_sample, 99):>10,.0f} Hz")
    print("targets: >= 180,000 samples/s offline; p99 < 1000 us for 1 kHz input")


if __name__ == "__main__":
    main()
