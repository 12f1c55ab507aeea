"""Benchmark: the batched Monte-Carlo engines (issue 6, acceptance 4).

Run on purpose (``make bench``), not in CI.

1. Pure INS: 1,000 runs of a 100 s walk at 100 Hz, all four error sources of
   Zampella et al. 2011, Table I, one at a time (target: each under 60 s).
2. ZUPT EKF: the study of Zampella et al. 2011, section IV-B, 100 runs × 1,000 strides at
   100 Hz after 10 s standing (about 12 M samples), XSens MTi noise, limited window
   (target: under 3 minutes).
"""
from __future__ import annotations

import time

from pdr_ins_ekf.studies.ekf_montecarlo import XSENS_MTI, ekf_study, estimator_detector, filter_for
from pdr_ins_ekf.studies.montecarlo import SOURCES, NoiseLevels, ins_study, straight_walk

LEVELS = {"acc_noise": 0.01, "gyro_noise": 1e-3, "acc_bias": 0.01, "gyro_bias": 1e-3}


def main() -> None:
    rows = []
    walk = straight_walk(83, 100.0)  # 99.6 s
    ins_study(walk, NoiseLevels.only("acc_noise", 0.01), 2)  # compile
    for source in SOURCES:
        start = time.perf_counter()
        ins_study(walk, NoiseLevels.only(source, LEVELS[source]), 1000)
        seconds = time.perf_counter() - start
        rows.append((f"pure INS, {source}, 1000 runs × {walk.t_s[-1]:.0f} s",
                     1000 * len(walk.t_s), seconds, 60.0))
    walk = straight_walk(1000, 100.0, rest_s=10.0)
    detector, config = estimator_detector("ekf_limited"), filter_for(XSENS_MTI)
    ekf_study(straight_walk(5, 100.0, rest_s=10.0), XSENS_MTI, 2, detector, config)  # compile
    start = time.perf_counter()
    ekf_study(walk, XSENS_MTI, 100, detector, config)
    seconds = time.perf_counter() - start
    rows.append(("ZUPT EKF (15 states), all errors, 100 runs × 1000 strides",
                 100 * len(walk.t_s), seconds, 180.0))
    print("| study | samples | time [s] | samples/s | target [s] |\n|---|---:|---:|---:|---:|")
    for name, samples, seconds, target in rows:
        print(f"| {name} | {samples:,} | {seconds:.1f} | {samples / seconds:,.0f} | "
              f"{target:.0f} {'met' if seconds < target else 'MISSED'} |")


if __name__ == "__main__":
    main()
