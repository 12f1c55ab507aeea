"""``ros2 bag`` and its verbs: rosbag2's ``ros2bag/ros2bag/verb/{info,play,record}.py``
arguments that the workspace's bag tools honour; ``--ros-args ...`` (this stand-in's)
passes the rest to the bag_play or bag_record node (e.g. ``-p wait_for_subscribers:=1``)."""
from __future__ import annotations

import argparse

from pdr_ros2.bag_verbs import bag_info, bag_play, bag_record
from pdr_ros2.cli_parsers import verb, verbs


def add(commands) -> None:
    """The ``bag`` command's parsers."""
    bag_verbs = verbs(commands, "bag", "Various rosbag related sub-commands")
    info = verb(bag_verbs, "info", "Print information about a bag to the screen", bag_info)
    info.add_argument("bag_path", help="Bag to open (a directory, or an .mcap file)")
    play = verb(bag_verbs, "play", "Play back ROS data from a bag (pdr_sim's bag_play)",
                bag_play)
    play.add_argument("bag_path", help="Bag to open (a directory, or an .mcap file)")
    play.add_argument("--topics", nargs="+", metavar="TOPIC",
                      help="Topics to replay, separated by space (default: all)")
    play.add_argument("-r", "--rate", type=float, default=1.0,
                      help="Rate at which to play back messages; this stand-in's 0: as "
                           "fast as the subscribers acknowledge (default %(default)s)")
    play.add_argument("--clock", nargs="?", const=True, metavar="HZ",
                      help="Publish to /clock at each message's time (no HZ in this "
                           "stand-in)")
    play.add_argument("--start-offset", type=float, default=0.0, metavar="SECONDS",
                      help="Start the playback this many seconds into the bag (from its "
                           "first played message)")
    play.add_argument("--playback-duration", type=float, default=0.0, metavar="SECONDS",
                      help="Playback duration, in seconds (0: to the end)")
    add_ros_args(play, "bag_play")
    record = verb(bag_verbs, "record", "Record ROS data to a bag (pdr_sim's bag_record)",
                  bag_record)
    record.add_argument("topics_positional", nargs="*", metavar="TOPIC",
                        help="Space-delimited list of topics to record")
    record.add_argument("--topics", nargs="+", metavar="TOPIC",
                        help="Space-delimited list of topics to record")
    record.add_argument("-o", "--output",
                        help="Destination of the bagfile to create, defaults to a timestamped "
                             "folder in the current directory")
    add_ros_args(record, "bag_record")


def add_ros_args(parser, node: str) -> None:
    """This stand-in's ``--ros-args ...``: the remaining arguments go to ``node``."""
    parser.add_argument("--ros-args", nargs=argparse.REMAINDER, metavar="ARG",
                        help=f"NOT in ros2cli: further ROS arguments of pdr_sim's {node} "
                             "node, e.g. -p name:=value")
