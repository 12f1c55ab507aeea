"""Benchmark (issue 30, acceptance 4): the stance detectors' cost live, at 1 kHz input.

Run on purpose (``python test/benchmarks/bench_zero_velocity.py``), not in CI. For each
detector of the shipped configurations, on a minute of the long mixed walk simulated at
1 kHz (``xsens_mtw``):

- the detector alone, in process, as the live node calls it for one new sample: one
  ``detect`` over the sample's context (``context(rate)`` samples before and after);
- the streaming navigator behind ``zupt_ekf``, the sample pushed one at a time (the
  detector, the alignment search and the filter step).

Each: the median and the 99th percentile of the time per sample (target: p99 < 1 ms,
so that a node keeps up with 1 kHz), in one table.
"""
from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from pdr_ins_ekf.config import load_run_config
from pdr_ins_ekf.streaming import StreamingNavigator
from pdr_ins_ekf.zero_velocity import AdaptiveShoeDetector
from pdr_sim.scenario import load_scenario
from pdr_sim.simulation import SimulationConfig, simulate

RATE_HZ = 1000.0
SECONDS = 60.0


def walk():
    """The first minute of the long mixed walk at 1 kHz: stamps [ns], force, rate."""
    scenario, data = load_scenario("long_mixed_walk")
    imu = simulate(SimulationConfig(scenario, data, "xsens_mtw", {}, RATE_HZ, 0)).imu
    keep = slice(0, int(SECONDS * RATE_HZ))
    return imu.stamp_ns[keep], imu["linear_acceleration"][keep], imu["angular_velocity"][keep]


def detector_alone(detector, accel: np.ndarray, gyro: np.ndarray) -> np.ndarray:
    """Seconds per sample of one ``detect`` over each sample's context."""
    left, right = detector.context(RATE_HZ)
    times = []
    for k in range(left, len(accel) - right):
        window = slice(k - left, k + right + 1)
        start = time.perf_counter()
        detector.detect(accel[window], gyro[window], RATE_HZ)
        times.append(time.perf_counter() - start)
    return np.array(times)


def streaming(config, stamps: np.ndarray, accel: np.ndarray, gyro: np.ndarray) -> np.ndarray:
    """Seconds per sample pushed one at a time into the streaming navigator."""
    navigator = StreamingNavigator(config)
    times = np.empty(len(stamps))
    for k in range(len(stamps)):
        start = time.perf_counter()
        navigator.push(int(stamps[k]), accel[k], gyro[k])
        times[k] = time.perf_counter() - start
    return times


def main() -> None:
    stamps, accel, gyro = walk()
    shipped = load_run_config()
    configs = {"adaptive_shoe": replace(shipped, detector=AdaptiveShoeDetector()),
               f"shipped ({type(shipped.detector).__name__})": shipped}
    print(f"{SECONDS:.0f} s of the long mixed walk at {RATE_HZ:.0f} Hz\n")
    print("| detector | context [samples] | alone, median [us] | alone, p99 [us] "
          "| streaming push, median [us] | streaming push, p99 [us] |")
    print("|---|---|---|---|---|---|")
    for name, config in configs.items():
        streaming(config, stamps[:3000], accel[:3000], gyro[:3000])   # compile the filter
        alone = detector_alone(config.detector, accel, gyro)
        pushed = streaming(config, stamps, accel, gyro)
        left, right = config.detector.context(RATE_HZ)
        print(f"| {name} | {left} + {right} | {np.median(alone) * 1e6:.0f} "
              f"| {np.percentile(alone, 99) * 1e6:.0f} | {np.median(pushed) * 1e6:.0f} "
              f"| {np.percentile(pushed, 99) * 1e6:.0f} |", flush=True)
    print("\ntarget: p99 < 1000 us per sample at 1 kHz")


if __name__ == "__main__":
    main()
