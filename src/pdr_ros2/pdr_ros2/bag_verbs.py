"""``ros2 bag info/play/record`` over the workspace's bag tools.

``info`` reads the bag with pdr_core.io.bag's BagReader (a missing bag, a file that is
not MCAP, a corrupt ``metadata.yaml``: one line naming the file, exit 1) and prints
``bag_info_text`` of its ``metadata.yaml``; a bare ``.mcap`` file, or a directory whose
recorder died before writing ``metadata.yaml``, is counted message by message (a bag cut
short: its readable part, with BagReader's warning on stderr). ``play`` and ``record``
execute pdr_sim's ``bag_play`` and ``bag_record`` nodes in place of this process
(``bag_nodes``), with whatever follows ``--ros-args`` passed on to them.
"""
from __future__ import annotations

import os
import sys
import warnings
from datetime import datetime
from pathlib import Path

import yaml

from pdr_ros2.bag_info_text import BagSummary, TopicCount, from_metadata, info_text
from pdr_ros2.bag_nodes import default_bag_name, play_arguments, record_arguments
from pdr_ros2.cli_run import executable_path

BAG_PACKAGE = "pdr_sim"
OUTPUT_EXISTS = "[ERROR] [ros2bag]: Output folder '{}' already exists."   # verb/record.py
NO_TOPICS = ("No topics to record: this stand-in (NOT ros2cli) records the topics named "
             "(-a, --regex, --services and the like are not supported)")


def bag_info(args) -> str | None:
    """``ros2 bag info BAG``: the summary, or the problem (one line)."""
    from pdr_core.errors import InputError, InputWarning
    from pdr_core.io.bag import BagReader

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InputWarning)
        try:
            reader = BagReader(args.bag_path)
            summary = bag_summary(reader)
        except InputError as error:
            return str(error)
    for warning in caught:
        print(f"warning: {warning.message}", file=sys.stderr)
    print(info_text(summary))
    return None


def bag_summary(reader) -> BagSummary:
    """The summary of a BagReader's bag: from its metadata.yaml, else counted."""
    from pdr_core.errors import InputError

    path = reader.path
    meta_path = path / "metadata.yaml"
    if not meta_path.is_file():
        return counted_summary(reader)
    try:
        info = yaml.safe_load(meta_path.read_text())["rosbag2_bagfile_information"]
        return from_metadata(info, directory_size(path))
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(meta_path, f"corrupt metadata.yaml ({exc!r})") from exc


def directory_size(path: Path) -> int:
    """rcutils_calculate_directory_size: the bytes of the files directly in ``path``."""
    return sum(entry.stat().st_size for entry in path.iterdir() if entry.is_file())


def counted_summary(reader) -> BagSummary:
    """The summary of a bag without metadata.yaml, from its messages."""
    counts = dict.fromkeys(reader.topics, 0)
    first = last = None
    for message in reader.raw_messages():
        counts[message.topic] += 1
        first = message.log_time_ns if first is None else min(first, message.log_time_ns)
        last = message.log_time_ns if last is None else max(last, message.log_time_ns)
    bare = not reader.path.is_dir()
    files = [str(reader.path)] if bare else [f.name for f in reader.files]
    size = reader.path.stat().st_size if bare else directory_size(reader.path)
    return BagSummary(files, size, "mcap", "", first or 0, (last or 0) - (first or 0),
                      sum(counts.values()),
                      [TopicCount(topic, reader.topics[topic], n) for topic, n in counts.items()])


def bag_play(args) -> str:
    """``ros2 bag play BAG``: bag_play in place of this process (returns an error)."""
    if args.clock is not None and args.clock is not True:
        return (f"--clock {args.clock}: this stand-in (NOT ros2cli) publishes /clock at each "
                "message's time only; give --clock without a rate")
    if args.rate < 0:
        return f"Invalid rate {args.rate}: this stand-in takes a factor >= 0 (0: as fast as "\
               "the subscribers acknowledge)"
    if args.start_offset < 0 or args.playback_duration < 0:
        return "--start-offset and --playback-duration take seconds >= 0"
    return run_node("bag_play", play_arguments(args.bag_path, args.topics or [], args.rate,
                                               args.clock is True, args.start_offset,
                                               args.playback_duration), args.ros_args)


def bag_record(args) -> str:
    """``ros2 bag record [-o OUT] TOPIC ...``: bag_record in place of this process; an
    existing OUT refused with ros2bag's words."""
    topics = [*args.topics_positional, *(args.topics or [])]
    if not topics:
        return NO_TOPICS
    out = args.output or default_bag_name(datetime.now())
    if os.path.isdir(out):
        return OUTPUT_EXISTS.format(out)
    return run_node("bag_record", record_arguments(out, topics), args.ros_args)


def run_node(executable: str, arguments: list[str], ros_args: list[str] | None) -> str:
    """Execute pdr_sim's ``executable`` with ``arguments`` and the user's ROS arguments;
    the error when it is not installed."""
    try:
        path = executable_path(BAG_PACKAGE, executable)
    except ValueError as error:
        return str(error)
    os.execv(path, [path, *arguments, *(ros_args or [])])
