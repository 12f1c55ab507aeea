"""bag_play's part of a bag (``start_offset_s``, ``playback_duration_s``): the messages
from the offset after the first one, for the duration of log time."""
from pdr_core.io.bag import RawMessage
from pdr_sim.nodes.bag_play import in_window

NS = 1_000_000_000


def messages(times_s):
    return [RawMessage("/imu/data", "sensor_msgs/msg/Imu", int(5 * NS + t * NS), b"")
            for t in times_s]


def played(offset_s, duration_s):
    return [(m.log_time_ns - 5 * NS) / NS
            for m in in_window(iter(messages([0, 0.5, 1, 1.5, 2, 2.5])), offset_s, duration_s)]


def test_the_whole_bag_by_default():
    assert played(0, 0) == [0, 0.5, 1, 1.5, 2, 2.5]


def test_from_the_offset_for_the_duration_half_open():
    assert played(1, 0) == [1, 1.5, 2, 2.5]
    assert played(0.5, 1) == [0.5, 1]
    assert played(0, 1) + played(1, 0) == played(0, 0)     # two parts make the whole


def test_an_offset_past_the_end_plays_nothing():
    assert played(10, 0) == []
