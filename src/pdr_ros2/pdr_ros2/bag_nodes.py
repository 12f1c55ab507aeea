"""``ros2 bag play`` and ``ros2 bag record`` as the workspace's own nodes: the arguments of
pdr_sim's ``bag_play`` and ``bag_record`` (their ``-p name:=value`` parameters) for the
options of rosbag2's ``ros2bag/ros2bag/verb/play.py`` and ``record.py`` that they can
honour. Values are YAML (rcl parses ``-p`` values so): strings single-quoted, so that a
path like ``2024`` or ``on`` stays a string.
"""
from __future__ import annotations

from datetime import datetime

DEFAULT_BAG_PREFIX = "rosbag2_"        # ros2bag/verb/record.py: datetime.now().strftime(...)
DEFAULT_BAG_TIME = "%Y_%m_%d-%H_%M_%S"


def quoted(text: str) -> str:
    """``text`` as a single-quoted YAML scalar (a quote doubled)."""
    return "'" + text.replace("'", "''") + "'"


def parameter(name: str, value: str | list[str] | float | bool) -> list[str]:
    """``['-p', 'name:=value']`` with the value as YAML: a quoted string, a flow list of
    quoted strings, ``true``/``false``, a number."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, str):
        text = quoted(value)
    elif isinstance(value, list):
        text = "[" + ", ".join(map(quoted, value)) + "]"
    else:
        text = repr(float(value))
    return ["-p", f"{name}:={text}"]


def play_arguments(bag: str, topics: list[str], rate: float, clock: bool,
                   start_offset_s: float = 0.0, duration_s: float = 0.0) -> list[str]:
    """bag_play's ROS arguments: the bag, its topics (all when empty), the rate factor
    (0: as fast as the subscribers acknowledge, this stand-in's), /clock, and the part
    played (from ``start_offset_s``, for ``duration_s`` [s]; 0: to the end), when set."""
    arguments = ["--ros-args", *parameter("bag", bag), *parameter("rate", rate)]
    arguments += parameter("topics", topics) if topics else []
    arguments += parameter("start_offset_s", start_offset_s) if start_offset_s else []
    arguments += parameter("playback_duration_s", duration_s) if duration_s else []
    return arguments + (parameter("clock", True) if clock else [])


def record_arguments(out: str, topics: list[str]) -> list[str]:
    """bag_record's ROS arguments: the output bag directory and the graph topics."""
    return ["--ros-args", *parameter("out", out), *parameter("topics", topics)]


def default_bag_name(now: datetime) -> str:
    """rosbag2's name of a bag recorded without ``-o``: ``rosbag2_2026_12_07-11_20_05``
    (local time)."""
    return DEFAULT_BAG_PREFIX + now.strftime(DEFAULT_BAG_TIME)
