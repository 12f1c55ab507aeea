"""``ros2 bag play/record`` refuse what pdr_sim's bag_play and bag_record cannot do, in
words that name this stand-in, before anything is executed; an option of rosbag2's that
the stand-in lacks is argparse's error with the same note."""
from __future__ import annotations

import argparse

import pytest

from pdr_ros2.bag_verbs import NO_TOPICS, bag_play, bag_record
from pdr_ros2.command import parser


def play(**given) -> str:
    options = {"bag_path": "bags/pocket_walk", "topics": None, "rate": 1.0, "clock": None,
               "ros_args": None}
    return bag_play(argparse.Namespace(**{**options, **given}))


def test_play_refuses_a_clock_rate_and_a_negative_rate():
    assert play(clock="40").startswith("--clock 40: this stand-in (NOT ros2cli) publishes "
                                       "/clock at each message's time only")
    assert play(rate=-1.0).startswith("Invalid rate -1.0: this stand-in takes a factor >= 0")


def record(**given) -> str:
    options = {"topics_positional": ["/a"], "topics": None, "output": None, "ros_args": None}
    return bag_record(argparse.Namespace(**{**options, **given}))


def test_record_needs_topics_and_a_new_output(tmp_path):
    assert record(topics_positional=[]) == NO_TOPICS
    assert record(output=str(tmp_path)) == \
        f"[ERROR] [ros2bag]: Output folder '{tmp_path}' already exists."


def test_the_parsed_options_are_the_ones_the_verbs_read():
    args = parser().parse_args(["bag", "record", "/a", "--topics", "/b", "-o", "out",
                                "--ros-args", "-p", "max_messages:=5"])
    assert (args.topics_positional, args.topics, args.output, args.ros_args) == \
        (["/a"], ["/b"], "out", ["-p", "max_messages:=5"])
    args = parser().parse_args(["bag", "play", "bag", "--topics", "/a", "/b", "-r", "0",
                                "--clock"])
    assert (args.bag_path, args.topics, args.rate, args.clock) == ("bag", ["/a", "/b"], 0.0,
                                                                  True)


def test_an_option_of_rosbag2_that_the_stand_in_lacks_is_refused_naming_it(capsys):
    with pytest.raises(SystemExit) as exited:
        parser().parse_args(["bag", "record", "-a"])
    assert exited.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1] == (
        "ros2: error: unrecognized arguments: -a (this ros2 is the pdr stack's stand-in, NOT "
        "ros2cli, with fewer options: -h lists what it takes)")
