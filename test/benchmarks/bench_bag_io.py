"""Benchmark: bag I/O of an hour of 200 Hz foot data (720,000 samples).

Run on purpose (``make bench``), not in CI. Prints seconds and samples per second for
CDR encoding and decoding (pdr_core.io.cdr), writing a bag with imu/data and
ground_truth/pose, and reading imu/data back as a MessageBatch.
"""
from __future__ import annotations

import tempfile
import time
from pathlib import Path

from pdr_core.io import cdr
from pdr_core.io.bag import BagReader, write_batches
from pdr_sim.scenario import scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

HOUR = {"segments": [{"type": "standing", "duration_s": 5.0},
                     {"type": "straight", "steps": 2995}]}


def timed(function):
    start = time.perf_counter()
    result = function()
    return time.perf_counter() - start, result


def main() -> None:
    sim = simulate(SimulationConfig(scenario_from_dict(HOUR, "hour"), HOUR, "xsens_mtw", {},
                                    200.0, 1))
    n = len(sim.imu)
    rows = []
    seconds, raws = timed(lambda: cdr.encode(sim.imu))
    rows.append(("encode imu/data (vectorised CDR)", seconds))
    rows.append(("decode imu/data (vectorised CDR)",
                 timed(lambda: cdr.decode(sim.imu.msgtype, raws))[0]))
    with tempfile.TemporaryDirectory() as tmp:
        bag = Path(tmp) / "bag"
        rows.append(("write bag (imu/data + ground_truth/pose)", timed(lambda: write_batches(
            bag, {"/imu/data": sim.imu, "/ground_truth/pose": sim.pose}))[0]))
        rows.append(("read imu/data as a batch", timed(lambda: BagReader(bag).read(
            "/imu/data"))[0]))
    print(f"{'operation':<44}{'seconds':>9}{'samples/s':>13}")
    for name, seconds in rows:
        print(f"{name:<44}{seconds:>9.2f}{n / seconds:>13,.0f}")
    print(f"samples: {n:,} (1 h at 200 Hz)")


if __name__ == "__main__":
    main()
