"""Benchmark (issue 29): the live pocket graph replaying the 39-minute walk as fast as it
is acknowledged. Run on purpose (``python test/benchmarks/bench_pocket_live.py``), not in
CI; it takes a few minutes and prints one table.

The walk: ``out_and_back_39min`` (Muñoz Díaz 2016, Section 3.4.2), a phone in the pocket,
100 Hz IMU and 50 Hz magnetometer, simulated once into a temporary bag. Rows:

1. ``pocket_pdr`` alone: ``bag_play rate:=0`` (it publishes as fast as its reliable
   subscribers acknowledge, every ``ack_every`` messages) → ``pocket_pdr``, the bench
   subscribing to ``pdr/pocket/step`` only (a few hundred messages). Time from the first
   message played to the last step received.
2. End to end: ``bag_play`` → ``pocket_pdr`` → ``bag_record`` of every output (attitude and
   gyro bias at every sample, step and pose at every step), then of the step and pose
   alone. Time until the recorder has every message.
3. The players alone: ``bag_play`` → ``bag_record`` of ``imu/data`` and ``imu/mag``, no
   navigator: what the transport costs.

Each row: wall time, IMU samples per second, and whether the steps (count and stamps)
equal ``pdr-pocket run``'s on the same bag.

A second table times the streaming navigator the node runs (pdr_pocket.streaming), in this
process, without the transport: its cost per IMU sample [µs] when the samples come one at
a time at the IMU's rate and are processed each at once (``block_s`` 0) or in blocks of
0.1 s or of the node's default ``block_s`` (0.25 s), and when a backlog comes in the
node's blocks of 400 (``MAX_BLOCK``, a bag played as fast as acknowledged). Issue 56's
target: at most 50 µs.
"""
from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from pdr_core import topics
from pdr_core.io.bag import BagReader, write_batches
from wstest import Processes, log_text, wait_for_log

DOMAIN = 92
SCENARIO = "out_and_back_39min"
PLAY = ["-p", "rate:=0.0", "-p", "wait_for_subscribers:=1"]
OUTPUTS = "[pdr/pocket/attitude, pdr/pocket/gyro_bias, pdr/pocket/step, pdr/pocket/pose]"
STEP_OUTPUTS = "[pdr/pocket/step, pdr/pocket/pose]"


def simulate_walk(path: Path) -> int:
    """The walk as a bag at ``path``; the number of imu/data samples."""
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    _, data = load_pocket_scenario(SCENARIO)
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, SCENARIO), data,
                                    "xsens_mtw", {}, 100.0, 0, placement="pocket"))
    write_batches(path, {t: sim.batches[t] for t in (topics.IMU_DATA, topics.IMU_MAG)})
    return len(sim.batches[topics.IMU_DATA])


def step_subscriber():
    """A node of this process subscribed to pdr/pocket/step: the node, its executor, the
    list the stamps [ns] received go to, and its context."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

    from pdr_msgs.msg import Step

    context = rclpy.Context()
    rclpy.init(context=context, domain_id=DOMAIN)
    node = rclpy.create_node("bench_steps", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    stamps: list[int] = []
    qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_subscription(Step, "pdr/pocket/step", lambda m: stamps.append(
        m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec), qos)
    return node, executor, stamps, context


def end_to_end(procs: Processes, bag: Path, out: Path, outputs: str, expected: int
               ) -> tuple[float, np.ndarray]:
    """``bag_play`` → ``pocket_pdr`` → ``bag_record`` of ``outputs`` until the recorder has
    ``expected`` messages: the wall time [s] from the first message played, and the stamps
    [ns] of the steps recorded."""
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={out}", "-p",
                           f"topics:={outputs}", "-p", f"max_messages:={expected}",
                           name=f"record_{out.name}")
    node = procs.start("pocket_pdr", "--ros-args", "-p", "imu_durability:=transient_local",
                       name=f"pocket_pdr_{out.name}")
    wait_for_log(recorder, "recording /pdr/pocket/pose", "recording /pdr/pocket/step")
    start = time.monotonic()
    procs.run("bag_play", "--ros-args", "-p", f"bag:={bag}", *PLAY, timeout=1800)
    assert recorder.wait(timeout=1800) == 0, log_text(recorder)
    seconds = time.monotonic() - start
    procs.stop(node)
    return seconds, BagReader(out).read("/pdr/pocket/step").stamp_ns


def streaming_cost(bag: Path, block: int, block_s: float) -> tuple[float, np.ndarray]:
    """The streaming navigator on ``bag`` pushed ``block`` IMU samples at a time, each
    block after the magnetometer readings up to its last: the wall time [µs] per IMU sample
    and the stamps [ns] of its steps."""
    from pdr_pocket.config import load_pocket_config
    from pdr_pocket.streaming import StreamingPocket

    reader = BagReader(bag)
    imu, mag = reader.read(topics.IMU_DATA), reader.read(topics.IMU_MAG)
    accel, gyro = imu["linear_acceleration"], imu["angular_velocity"]
    ends = np.searchsorted(mag.stamp_ns, imu.stamp_ns[block - 1::block], side="right")
    navigator = StreamingPocket(load_pocket_config(), block_s=block_s)
    processed, taken = [], 0
    start = time.perf_counter()
    for first, end in zip(range(0, len(imu), block), [*ends, len(mag)], strict=False):
        processed += navigator.push_mags(mag.stamp_ns[taken:end], mag["magnetic_field"][taken:end])
        taken = end
        part = slice(first, first + block)
        processed += navigator.push_imus(imu.stamp_ns[part], accel[part], gyro[part])
    processed += navigator.flush()
    seconds = time.perf_counter() - start
    stamps = [chunk.stamp_of(step.t_confirm) for chunk in processed for step in chunk.output.steps]
    return seconds / len(imu) * 1e6, np.array(stamps, np.int64)


def cost_table(bag: Path, reference: np.ndarray) -> None:
    """The streaming navigator's cost per sample, in this process (the module docstring)."""
    from pdr_pocket.streaming import BLOCK_S

    print("\n| streaming navigator, in process | µs per IMU sample | steps as offline |")
    print("|---|---|---|")
    for label, block, block_s in (("one sample at a time, each processed at once", 1, 0.0),
                                  ("one sample at a time, in blocks of 0.1 s", 1, 0.1),
                                  (f"one sample at a time, in blocks of {BLOCK_S:g} s "
                                   "(the node's default)", 1, BLOCK_S),
                                  ("a backlog, 400 samples a call", 400, 0.0)):
        cost, stamps = streaming_cost(bag, block, block_s)
        print(f"| {label} | {cost:.0f} | {np.array_equal(stamps, reference)} |", flush=True)


def row(label: str, samples: int, seconds: float, steps_equal: str) -> str:
    return f"| {label} | {seconds:.1f} | {samples / seconds:,.0f} | {steps_equal} |"


def main() -> int:
    import rclpy

    folder = Path(tempfile.mkdtemp(prefix="bench_pocket_live_"))
    procs = Processes(DOMAIN, folder)
    bag = folder / "walk"
    samples = simulate_walk(bag)
    offline = procs.run("pdr-pocket", "run", str(bag), "--out", str(folder / "offline"))
    assert offline.returncode == 0, offline.stderr
    reference = BagReader(folder / "offline").read("/pdr/pocket/step").stamp_ns
    print(f"{SCENARIO}: {samples} IMU samples, {len(reference)} steps offline\n")
    print("| graph | wall time [s] | IMU samples/s | steps as offline |")
    print("|---|---|---|---|")
    try:
        # 1. pocket_pdr alone
        node = procs.start("pocket_pdr", "--ros-args", "-p", "imu_durability:=transient_local",
                           name="pocket_pdr")
        wait_for_log(node, "configuration")
        sub, executor, stamps, context = step_subscriber()
        start = time.monotonic()
        player = procs.start("bag_play", "--ros-args", "-p", f"bag:={bag}", *PLAY,
                             name="play_1")
        last = start
        while len(stamps) < len(reference) and time.monotonic() - start < 900:
            before = len(stamps)
            executor.spin_once(timeout_sec=0.1)
            if len(stamps) > before:
                last = time.monotonic()
        player.wait(timeout=60)
        equal = np.array_equal(np.array(stamps), reference)
        print(row("`bag_play` → `pocket_pdr`", samples, last - start, str(equal)), flush=True)
        sub.destroy_node()
        rclpy.shutdown(context=context)
        procs.stop(node)
        # 2. end to end, every output recorded, then the per-step ones only
        for label, outputs, per_sample in (("", OUTPUTS, 2), (" (step, pose)", STEP_OUTPUTS, 0)):
            expected = per_sample * samples + 2 * len(reference)
            seconds, live = end_to_end(procs, bag, folder / f"live{per_sample}", outputs,
                                       expected)
            print(row(f"`bag_play` → `pocket_pdr` → `bag_record`{label}", samples, seconds,
                      str(np.array_equal(live, reference))), flush=True)
        # 3. the players alone
        recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={folder / 'copy'}",
                               "-p", "topics:=[imu/data, imu/mag]", "-p",
                               f"max_messages:={samples + len(BagReader(bag).read('/imu/mag'))}",
                               name="record_3")
        wait_for_log(recorder, "will record")
        start = time.monotonic()
        procs.run("bag_play", "--ros-args", "-p", f"bag:={bag}", *PLAY, timeout=1800)
        assert recorder.wait(timeout=1800) == 0, log_text(recorder)
        print(row("`bag_play` → `bag_record` (no navigator)", samples,
                  time.monotonic() - start, "—"), flush=True)
    finally:
        procs.cleanup()
    cost_table(bag, reference)
    return 0


if __name__ == "__main__":
    sys.exit(main())
