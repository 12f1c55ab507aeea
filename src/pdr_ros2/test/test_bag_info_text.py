"""``ros2 bag info``'s text (rosbag2 ``rosbag2_py/src/rosbag2_py/format_bag_metadata.cpp``,
Jazzy 0.26.6+: 9-digit fractions, topics sorted by name, ``Service:`` lines) on the
repository's sample bags, in UTC, and the verb's errors (one line naming the file)."""
from __future__ import annotations

import argparse
import shutil
import time
from pathlib import Path

import pytest
import yaml

from pdr_ros2.bag_info_text import (
    BagSummary,
    TopicCount,
    from_metadata,
    info_text,
    seconds_text,
    size_text,
)
from pdr_ros2.bag_verbs import bag_info

BAGS = Path(__file__).resolve().parents[3] / "bags"
POCKET_WALK = """
Files:             pocket_walk.mcap
Bag size:          2.4 MiB
Storage id:        mcap
ROS Distro:        rosbags
Duration:          230.740000000s
Start:             Nov 14 2023 22:13:20.000000000 (1700000000.000000000)
End:               Nov 14 2023 22:17:10.740000000 (1700000230.740000000)
Messages:          46284
Topic information: Topic: /ground_truth/landmarks | Type: pdr_msgs/msg/Landmark | Count: 9 | \
Serialization Format: cdr
                   Topic: /ground_truth/pose | Type: geometry_msgs/msg/PoseStamped | \
Count: 11538 | Serialization Format: cdr
                   Topic: /ground_truth/step | Type: pdr_msgs/msg/Step | Count: 122 | \
Serialization Format: cdr
                   Topic: /imu/data | Type: sensor_msgs/msg/Imu | Count: 11538 | \
Serialization Format: cdr
                   Topic: /imu/mag | Type: sensor_msgs/msg/MagneticField | Count: 11538 | \
Serialization Format: cdr
                   Topic: /tf | Type: tf2_msgs/msg/TFMessage | Count: 11538 | \
Serialization Format: cdr
                   Topic: /tf_static | Type: tf2_msgs/msg/TFMessage | Count: 1 | \
Serialization Format: cdr
Service:           0
""" + "Service information: \n"         # one space after the colon, as rosbag2 writes it


@pytest.fixture
def utc(monkeypatch):
    """Local time is UTC during the test."""
    monkeypatch.setenv("TZ", "UTC")
    time.tzset()
    yield
    monkeypatch.undo()
    time.tzset()


def info(bag: Path, capsys) -> tuple[str | None, str, str]:
    """``ros2 bag info BAG``'s error, stdout and stderr."""
    error = bag_info(argparse.Namespace(bag_path=str(bag)))
    out, err = capsys.readouterr()
    return error, out, err


def test_pocket_walk_prints_rosbag2s_layout(utc, capsys):
    assert info(BAGS / "pocket_walk", capsys) == (None, POCKET_WALK, "")


def test_the_metadata_gives_every_figure():
    meta = yaml.safe_load((BAGS / "pocket_walk" / "metadata.yaml").read_text())
    bag = from_metadata(meta["rosbag2_bagfile_information"], 2_496_369)
    assert (bag.files, bag.storage_id, bag.ros_distro) == (["pocket_walk.mcap"], "mcap",
                                                          "rosbags")
    assert (bag.start_ns, bag.duration_ns, bag.message_count) == (1_700_000_000_000_000_000,
                                                                 230_740_000_000, 46284)
    assert TopicCount("/ground_truth/step", "pdr_msgs/msg/Step", 122, "cdr") in bag.topics


def test_a_bare_mcap_file_is_counted_message_by_message(utc, capsys):
    error, out, err = info(BAGS / "foot_walk" / "foot_walk.mcap", capsys)
    lines = out.splitlines()
    assert (error, err) == (None, "")
    assert lines[1] == f"Files:             {BAGS / 'foot_walk' / 'foot_walk.mcap'}"
    assert lines[2:6] == ["Bag size:          1.3 MiB", "Storage id:        mcap",
                          "ROS Distro:        unknown", "Duration:          60.940000000s"]
    assert lines[8] == "Messages:          30476"
    assert lines[9] == ("Topic information: Topic: /ground_truth/pose | Type: "
                        "geometry_msgs/msg/PoseStamped | Count: 6095 | Serialization Format: cdr")


def test_a_directory_without_metadata_is_counted_with_a_warning(tmp_path, capsys):
    shutil.copy(BAGS / "foot_walk" / "foot_walk.mcap", tmp_path)
    error, out, err = info(tmp_path, capsys)
    assert error is None and "\nMessages:          30476\n" in out
    assert "\nFiles:             foot_walk.mcap\n" in out
    assert err == (f"warning: {tmp_path}: no metadata.yaml: reading its MCAP files "
                   "(`pdr-sim repair` rebuilds it)\n")


def test_a_missing_or_corrupt_bag_is_one_line_naming_the_file(tmp_path, capsys):
    assert info(tmp_path / "nope", capsys) == (f"{tmp_path / 'nope'}: no such bag", "", "")
    bag = tmp_path / "bag"
    shutil.copytree(BAGS / "foot_walk", bag)
    text = (bag / "metadata.yaml").read_text()
    (bag / "metadata.yaml").write_text(text.replace("starting_time", "started"))
    error, out, _ = info(bag, capsys)
    assert error.startswith(f"{bag / 'metadata.yaml'}: corrupt metadata.yaml (KeyError(")
    assert "\n" not in error and out == ""
    (bag / "foot_walk.mcap").write_bytes(b"time,ax,ay,az\n")
    assert info(bag, capsys)[0].startswith(f"{bag / 'foot_walk.mcap'}: a CSV log, not a bag")


def test_service_events_are_listed_as_services_and_not_counted_as_messages(utc):
    bag = BagSummary(["a.mcap", "b.mcap"], 612, "mcap", "", 1_500_000_000, 2_000_000_001, 7,
                     [TopicCount("/z", "std_msgs/msg/Empty", 4),
                      TopicCount("/reset/_service_event", "std_srvs/srv/Trigger_Event", 3)])
    assert info_text(bag) == """
Files:             a.mcap
                   b.mcap
Bag size:          612 B
Storage id:        mcap
ROS Distro:        unknown
Duration:          2.000000001s
Start:             Jan  1 1970 00:00:01.500000000 (1.500000000)
End:               Jan  1 1970 00:00:03.500000001 (3.500000001)
Messages:          4
Topic information: Topic: /z | Type: std_msgs/msg/Empty | Count: 4 | Serialization Format: cdr
Service:           1
Service information: Service: /reset | Type: std_srvs/srv/Trigger | Event Count: 3 | \
Serialization Format: cdr
"""


def test_sizes_and_spans_as_rosbag2_writes_them():
    assert [size_text(n) for n in (0, 1023, 1024, 1536, 2_496_369, 3 * 1024**3, 2 * 1024**5)] \
        == ["0 B", "1023 B", "1.0 KiB", "1.5 KiB", "2.4 MiB", "3.0 GiB", "2048.0 TiB"]
    assert seconds_text(0) == "0.000000000" and seconds_text(61_000_000_007) == "61.000000007"
