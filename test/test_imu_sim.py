"""imu_sim publishes live exactly what ``pdr-sim generate`` writes (issue 3, outputs)."""
from __future__ import annotations

import signal

import pytest

from pdr_core.io.bag import BagReader
from wstest import log_text

pytestmark = pytest.mark.ros
# what imu_sim publishes of the bag pdr-sim generate writes: the bag's /tf and /tf_static
# (the truth for a viewer, docs/nodes.md "TF and odometry") are the writer's
LIVE_TOPICS = ["/imu/data", "/imu/mag", "/ground_truth/pose"]


def stamp_and_topic(message):
    """Sort key: messages of one stamp on different topics may arrive in any order."""
    return message.log_time_ns, message.topic


def without_end_padding(message):
    """(topic, stamp, data) with the zero bytes that rmw's CDR serializer appends to
    align a message's end to 4 bytes (rosbags' serializer does not) removed: pdr_msgs/Step
    ends in a uint8 activity, never 0 in a step, and a float64 before it; the true
    pdr_msgs/Stance in its uint8 detector, 255 for the truth."""
    padded = message.topic.endswith(("/step", "/stance"))
    data = message.data.rstrip(b"\x00") if padded else message.data
    return message.topic, message.log_time_ns, data


def test_live_simulation_equals_offline_bag(procs, tmp_path):
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={tmp_path / 'live'}", "-p",
                           "topics:=[imu/data, imu/mag, ground_truth/pose, ground_truth/stance]",
                           name="record")
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
    expected = list(BagReader(tmp_path / "offline").raw_messages(
        [*LIVE_TOPICS, "/ground_truth/stance"]))
    assert len(got) == len(expected) == 4 * 6561
    assert [without_end_padding(m) for m in sorted(got, key=stamp_and_topic)] == \
        [without_end_padding(m) for m in sorted(expected, key=stamp_and_topic)]


def test_live_pocket_simulation_equals_offline_bag(procs, tmp_path):
    """The pocket placement: the same five topics, truth steps and landmarks included."""
    scenario = tmp_path / "short.yaml"
    scenario.write_text("segments: [{type: standing, duration_s: 2},\n"
                        "  {type: walk, distance_m: 12, speed_kmh: 4},\n"
                        "  {type: turn, angle_deg: 90, steps: 2},\n"
                        "  {type: stairs, direction: up, risers: 6, riser_m: 0.17},\n"
                        "  {type: standing, duration_s: 2}]\n")
    topics = "[imu/data, imu/mag, ground_truth/pose, ground_truth/step, ground_truth/landmarks]"
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={tmp_path / 'live'}", "-p",
                           f"topics:={topics}", name="record")
    live = procs.run("imu_sim", "--ros-args", "-p", "placement:=pocket", "-p",
                     f"scenario:={scenario}", "-p", "imu:=consumer_phone", "-p", "seed:=4",
                     "-p", "rate:=0.0", "-p", "wait_for_subscribers:=1")
    assert live.returncode == 0, live.stderr
    assert procs.stop(recorder, signal.SIGINT) == 0, log_text(recorder)
    offline = procs.run("pdr-sim", "generate", "--placement", "pocket", "--scenario",
                        str(scenario), "--imu", "consumer_phone", "--seed", "4", "--out",
                        str(tmp_path / "offline"))
    assert offline.returncode == 0, offline.stderr
    got = list(BagReader(tmp_path / "live").raw_messages())
    expected = list(BagReader(tmp_path / "offline").raw_messages(
        [*LIVE_TOPICS, "/ground_truth/step", "/ground_truth/landmarks"]))
    reader = BagReader(tmp_path / "offline")
    assert len(reader.read("/ground_truth/step")) > 10
    assert len(reader.read("/ground_truth/landmarks")) == 2     # the corner and the flight
    assert [without_end_padding(m) for m in sorted(got, key=stamp_and_topic)] == \
        [without_end_padding(m) for m in sorted(expected, key=stamp_and_topic)]


def test_bad_scenario_parameter_exits_2(procs):
    result = procs.run("imu_sim", "--ros-args", "-p", "scenario:=/nonexistent.yaml")
    assert result.returncode == 2
    assert "/nonexistent.yaml: no such scenario file" in result.stderr
