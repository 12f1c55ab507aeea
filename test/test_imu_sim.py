"""imu_sim publishes live exactly what ``pdr-sim generate`` writes (issue 3, outputs)."""
from __future__ import annotations

import signal

import pytest

from pdr_core.bag import BagReader
from wstest import log_text

pytestmark = pytest.mark.ros


def stamp_and_topic(message):
    """Sort key: messages of one stamp on different topics may arrive in any order."""
    return message.log_time_ns, message.topic


def test_live_simulation_equals_offline_bag(procs, tmp_path):
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={tmp_path / 'live'}", "-p",
                           "topics:=[imu/data, imu/mag, ground_truth/pose]", name="record")
    live = procs.run("imu_sim", "--ros-args", "-p", "scenario:=square_loop", "-p",
                     "imu:=consumer_phone", "-p", "rate_hz:=200.0", "-p", "seed:=4", "-p",
                     "rate:=0.0", "-p", "wait_for_subscribers:=1")
    assert live.returncode == 0, live.stderr
    assert procs.stop(recorder, signal.SIGINT) == 0, log_text(recorder)
    offline = procs.run("pdr-sim", "generate", "--scenario", "square_loop", "--imu",
                        "consumer_phone", "--rate", "200", "--seed", "4", "--out",
                        str(tmp_path / "offline"))
    assert offline.returncode == 0, offline.stderr
    got = list(BagReader(tmp_path / "live").raw_messages())
    expected = list(BagReader(tmp_path / "offline").raw_messages())
    assert len(got) == len(expected) == 3 * 6561
    assert sorted(got, key=stamp_and_topic) == sorted(expected, key=stamp_and_topic)


def test_bad_scenario_parameter_exits_2(procs):
    result = procs.run("imu_sim", "--ros-args", "-p", "scenario:=/nonexistent.yaml")
    assert result.returncode == 2
    assert "/nonexistent.yaml: no such scenario file" in result.stderr
