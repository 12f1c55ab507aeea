"""bag_play and bag_record as separate ROS processes (issue 2, acceptance 2 and 4)."""
from __future__ import annotations

import signal
import time

import numpy as np
import pytest

from pdr_core.bag import BagReader, write_batches
from pdr_core.batch import MessageBatch
from pdr_core.msgtypes import IMU
from wstest import log_text

pytestmark = pytest.mark.ros


def imu_bag(path, n, rate_hz=200.0, seed=0):
    rng = np.random.default_rng(seed)
    stamps = 1_700_000_000_000_000_000 + np.round(np.arange(n) * 1e9 / rate_hz).astype(np.int64)
    cov = np.zeros((n, 9))
    cov[:, 0] = -1.0
    batch = MessageBatch(IMU, stamps, "imu_link", {
        "orientation": np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)),
        "orientation_covariance": cov,
        "angular_velocity": rng.normal(size=(n, 3)),
        "angular_velocity_covariance": rng.normal(size=(n, 9)),
        "linear_acceleration": rng.normal(size=(n, 3)) * 20,
        "linear_acceleration_covariance": rng.normal(size=(n, 9)),
    })
    write_batches(path, {"/imu/data": batch})
    return batch


def record(procs, out, topics="[imu/data]"):
    return procs.start("bag_record", "--ros-args", "-p", f"out:={out}", "-p", f"topics:={topics}",
                       name="record")


def play(procs, bag, *params):
    args = ["bag_play", "--ros-args", "-p", f"bag:={bag}", "-p", "wait_for_subscribers:=1"]
    for p in params:
        args += ["-p", p]
    return procs.run(*args)


def test_recorded_bag_equals_played_bag(procs, tmp_path):
    bag, out = tmp_path / "in", tmp_path / "out"
    imu_bag(bag, 2000)
    recorder = record(procs, out)
    played = play(procs, bag, "rate:=0.0")
    assert played.returncode == 0, played.stdout + played.stderr
    assert "published 2000 messages" in played.stderr
    assert procs.stop(recorder, signal.SIGINT) == 0, log_text(recorder)
    assert "recorded 2000 messages" in log_text(recorder)
    sent = [m.data for m in BagReader(bag).raw_messages()]
    got = list(BagReader(out).raw_messages())
    assert [m.data for m in got] == sent, "every message, bit for bit, in order"
    assert [m.log_time_ns for m in got] == [m.log_time_ns for m in BagReader(bag).raw_messages()]


def test_rate_factor_clock_and_sigterm(procs, tmp_path):
    bag, out = tmp_path / "in", tmp_path / "out"
    batch = imu_bag(bag, 400)
    recorder = record(procs, out, "[imu/data, /clock]")
    start = time.monotonic()
    played = play(procs, bag, "rate:=2.0", "clock:=true")
    assert played.returncode == 0, played.stdout + played.stderr
    wall = time.monotonic() - start
    assert wall >= 1.995 / 2.0, "400 samples at 200 Hz span 1.995 s: at rate 2, >= 1 s"
    assert procs.stop(recorder, signal.SIGTERM) == 0, log_text(recorder)
    reader = BagReader(out)
    assert reader.topics == {"/imu/data": IMU, "/clock": "rosgraph_msgs/msg/Clock"}
    np.testing.assert_array_equal(reader.read("/imu/data").stamp_ns, batch.stamp_ns)
    clocks = [m.clock.sec * 10**9 + m.clock.nanosec for _, m in reader.read_messages("/clock")]
    np.testing.assert_array_equal(clocks, batch.stamp_ns)


def test_corrupt_tail_is_played_up_to_the_damage(procs, tmp_path):
    bag, out = tmp_path / "in", tmp_path / "out"
    batch = imu_bag(bag, 12000)
    mcap = bag / "in.mcap"
    data = mcap.read_bytes()
    mcap.write_bytes(data[: int(len(data) * 0.7)])
    recorder = record(procs, out)
    played = play(procs, bag, "rate:=0.0")
    assert played.returncode == 1
    line = [s for s in played.stderr.splitlines() if "then stopped" in s]
    assert len(line) == 1 and str(mcap) in line[0] and "corrupt MCAP after" in line[0]
    published = int(line[0].split("published ")[1].split()[0])
    assert published > 12000 * 0.4
    assert procs.stop(recorder) == 0
    np.testing.assert_array_equal(BagReader(out).read("/imu/data").stamp_ns,
                                  batch.stamp_ns[:published])


@pytest.mark.parametrize("case", ["missing", "unknown_topic"])
def test_bad_bag_exits_nonzero_naming_the_problem(procs, tmp_path, case):
    bag = tmp_path / "in"
    if case == "missing":
        played = procs.run("bag_play", "--ros-args", "-p", f"bag:={bag}")
        expected = f"{bag}: no such bag"
    else:
        imu_bag(bag, 10)
        played = procs.run("bag_play", "--ros-args", "-p", f"bag:={bag}", "-p",
                           "topics:=[imu/mag]")
        expected = f"{bag}: no topic /imu/mag (the bag has: /imu/data)"
    assert played.returncode == 2
    assert expected in played.stderr


def test_recorder_refuses_existing_output(procs, tmp_path):
    imu_bag(tmp_path / "in", 10)
    result = procs.run("bag_record", "--ros-args", "-p", f"out:={tmp_path / 'in'}", "-p",
                       "topics:=[imu/data]")
    assert result.returncode == 2
    assert f"bag_record: error: {tmp_path / 'in'}: output exists already" in result.stderr
