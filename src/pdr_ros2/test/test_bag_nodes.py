"""The bag_play and bag_record arguments of ``ros2 bag play/record`` (their parameters:
pdr_sim/nodes/bag_play.py, playback.py, bag_record.py), and rosbag2's default bag name
(``ros2bag/ros2bag/verb/record.py``: ``datetime.now().strftime('rosbag2_%Y_%m_%d-%H_%M_%S')``)."""
from __future__ import annotations

from datetime import datetime

import yaml

from pdr_ros2.bag_nodes import default_bag_name, play_arguments, quoted, record_arguments


def test_play_passes_bag_rate_topics_and_clock_as_yaml_parameters():
    assert play_arguments("bags/pocket_walk", ["/imu/data", "/imu/mag"], 0.0, True) == [
        "--ros-args", "-p", "bag:='bags/pocket_walk'", "-p", "rate:=0.0",
        "-p", "topics:=['/imu/data', '/imu/mag']", "-p", "clock:=true"]


def test_play_of_every_topic_leaves_the_topics_out():
    assert play_arguments("b", [], 2, False) == ["--ros-args", "-p", "bag:='b'", "-p",
                                                 "rate:=2.0"]


def test_play_passes_the_part_played_only_when_it_is_set():
    assert play_arguments("b", [], 0, False, 270.0, 60.5)[-4:] == [
        "-p", "start_offset_s:=270.0", "-p", "playback_duration_s:=60.5"]


def test_record_passes_out_and_topics():
    assert record_arguments("out/x", ["pdr/pocket/step"]) == [
        "--ros-args", "-p", "out:='out/x'", "-p", "topics:=['pdr/pocket/step']"]


def test_quoted_values_read_back_as_the_same_strings():
    for text in ("2024", "on", "it's: #here", "[a]"):
        assert yaml.safe_load(quoted(text)) == text


def test_a_bag_recorded_without_a_name_is_named_as_rosbag2_names_it():
    assert default_bag_name(datetime(2026, 12, 7, 9, 5, 3)) == "rosbag2_2026_12_07-09_05_03"
