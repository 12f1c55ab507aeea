"""Benchmark (issue 19): an hour of 200 Hz foot data through the graph, and the recorder
at 2 kHz. Run on purpose (``python test/benchmarks/bench_soak.py [--minutes M]``), not in
CI; it takes about ten minutes and prints two tables.

1. Soak: ``bag_play`` (rate ×10) → ``zupt_ekf`` → ``bag_record`` as three processes on
   an hour of simulated foot walking (``long_mixed_walk`` repeated, Xsens MTi errors,
   200 Hz). Reported: the samples played, the poses recorded against the poses expected
   (every sample but the detector's look-ahead), the resident memory of ``zupt_ekf``
   and ``bag_record`` a minute in and at the end (flat within 10 % expected), and the
   recorder's bytes written against the messages it received.
2. Recorder: ``bag_play`` at 2 kHz in real time → ``bag_record`` (1 s flushes): messages
   played against recorded, and the wall time.
"""
from __future__ import annotations

import argparse
import math
import signal
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from pdr_core import topics
from pdr_core.io.bag import BagReader, write_batches
from pdr_ins_ekf.config import load_run_config
from wstest import Processes, imu_bag, log_text, wait_for_log

SOAK_RATE = 10.0
DOMAIN = 91


def hour_of_walking(path: Path, minutes: float) -> int:
    """``long_mixed_walk``'s walking repeated past ``minutes`` (each repeat is about 4.7
    min), simulated at 200 Hz and cut to ``minutes``; the number of imu/data samples
    written."""
    from pdr_sim.scenario import load_scenario, scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    _, data = load_scenario("long_mixed_walk")
    once = data["segments"][1:]
    repeats = math.ceil(minutes / 4.5)
    data = {**data, "segments": [data["segments"][0], *once * repeats]}
    sim = simulate(SimulationConfig(scenario_from_dict(data, "soak"), data, "xsens_mti", {},
                                    200.0, 0))
    imu = sim.batches[topics.IMU_DATA]
    imu = imu.take(slice(0, min(len(imu), round(minutes * 60 * 200))))
    write_batches(path, {topics.IMU_DATA: imu})
    return len(imu)


def rss_mb(pid: int) -> float:
    """Resident memory of a process [MB] (/proc; ``./ws`` execs the node, so a Popen's pid
    is the node's)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return float("nan")


def recorded_bytes(proc) -> str:
    line = [s for s in log_text(proc).splitlines() if "recorded" in s]
    return line[-1].split("recorded ", 1)[1] if line else "(no summary logged)"


def soak(folder: Path, minutes: float) -> None:
    procs = Processes(DOMAIN, folder)
    try:
        bag = folder / "hour"
        print(f"simulating {minutes:g} min of 200 Hz foot walking ...", file=sys.stderr)
        samples = hour_of_walking(bag, minutes)
        lag = load_run_config().detector.context(200.0)[1]
        recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={folder / 'rec'}",
                               "-p", "topics:=[pdr/foot/pose]", name="record")
        node = procs.start("zupt_ekf", "--ros-args", "-p", "imu_durability:=transient_local",
                           name="zupt_ekf")
        wait_for_log(recorder, "recording /pdr/foot/pose")
        player = procs.start("bag_play", "--ros-args", "-p", f"bag:={bag}", "-p",
                             f"rate:={SOAK_RATE}", "-p", "wait_for_subscribers:=1", name="play")
        start = time.monotonic()
        time.sleep(60.0)
        early = rss_mb(node.pid), rss_mb(recorder.pid)
        player.wait(timeout=3600)
        expected = samples - lag
        deadline = time.monotonic() + 300
        while time.monotonic() < deadline and not _settled(folder / "rec"):
            pass
        wall = time.monotonic() - start
        late = rss_mb(node.pid), rss_mb(recorder.pid)
        procs.stop(recorder, signal.SIGINT)
        procs.stop(node, signal.SIGINT)
        poses = len(BagReader(folder / "rec").read("/pdr/foot/pose"))
        print(f"\nsoak: {samples} samples ({samples / 200 / 60:.1f} min at 200 Hz), "
              f"bag_play at x{SOAK_RATE:g}, {wall:.0f} s wall")
        print(f"{'':<24}{'expected':>10}{'recorded':>10}{'dropped':>9}")
        print(f"{'poses (zupt_ekf)':<24}{expected:>10}{poses:>10}{expected - poses:>9}")
        print(f"{'resident memory [MB]':<24}{'1 min in':>10}{'at end':>10}{'change':>9}")
        for name, a, b in (("zupt_ekf", early[0], late[0]), ("bag_record", early[1], late[1])):
            print(f"{name:<24}{a:>10.1f}{b:>10.1f}{100 * (b / a - 1):>8.1f}%")
        print(f"bag_record: {recorded_bytes(recorder)}")
    finally:
        procs.cleanup()


def _settled(bag: Path) -> bool:
    """True when the recording has stopped growing for 10 s (the node is done)."""
    size = sum(f.stat().st_size for f in bag.glob("*.mcap"))
    time.sleep(10.0)
    return size == sum(f.stat().st_size for f in bag.glob("*.mcap"))


def recorder_2khz(folder: Path, seconds: float = 60.0) -> None:
    procs = Processes(DOMAIN, folder)
    try:
        n = int(seconds * 2000)
        imu_bag(folder / "fast", n, rate_hz=2000.0)
        recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={folder / 'fast_rec'}",
                               "-p", "topics:=[imu/data]", name="record_fast")
        start = time.monotonic()
        played = procs.run("bag_play", "--ros-args", "-p", f"bag:={folder / 'fast'}", "-p",
                           "wait_for_subscribers:=1", timeout=seconds * 10)
        wall = time.monotonic() - start
        time.sleep(2.0)
        procs.stop(recorder, signal.SIGINT)
        got = len(BagReader(folder / "fast_rec").read("/imu/data"))
        print(f"\nrecorder at 2 kHz ({seconds:g} s in real time, play exit {played.returncode}):"
              f" {n} played, {got} recorded, {n - got} dropped, {wall:.1f} s wall; "
              f"{recorded_bytes(recorder)}")
    finally:
        procs.cleanup()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--minutes", type=float, default=60.0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        soak(Path(tmp), args.minutes)
        recorder_2khz(Path(tmp))
