"""bag_play and bag_record as separate ROS processes (issue 2, acceptance 2 and 4)."""
from __future__ import annotations

import signal
import time

import numpy as np
import pytest

from pdr_core.io.bag import BagReader
from pdr_core.io.msgtypes import IMU
from wstest import imu_bag, log_text, play

pytestmark = pytest.mark.ros


def record(procs, out, topics="[imu/data]"):
    return procs.start("bag_record", "--ros-args", "-p", f"out:={out}", "-p", f"topics:={topics}",
                       name="record")


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


def test_a_bag_cut_short_is_played_up_to_the_damage_or_refused_when_strict(procs, tmp_path):
    """Issue 19: the readable part is played, with a warning naming the file and how much;
    ``strict:=true`` refuses the bag."""
    bag, out = tmp_path / "in", tmp_path / "out"
    batch = imu_bag(bag, 12000)
    mcap = bag / "in.mcap"
    data = mcap.read_bytes()
    mcap.write_bytes(data[: int(len(data) * 0.7)])
    refused = play(procs, bag, "rate:=0.0", "strict:=true")
    assert refused.returncode == 2 and str(mcap) in refused.stderr
    assert "refused (--strict" in refused.stderr
    recorder = record(procs, out)
    played = play(procs, bag, "rate:=0.0")
    assert played.returncode == 0, played.stderr
    line = [s for s in played.stderr.splitlines() if "cut short or unindexed" in s]
    assert len(line) == 1 and str(mcap) in line[0]
    published = int(played.stderr.split("published ")[1].split()[0])
    assert 12000 * 0.4 < published < 12000 * 0.7
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
