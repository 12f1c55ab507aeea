"""What ``ros2 bag info BAG`` prints, from a bag's metadata (no file access: the reading is
in ``bag_verbs``).

Copies rosbag2's ``rosbag2_py/src/rosbag2_py/format_bag_metadata.cpp`` as Jazzy 0.26.6
and later has it (9-digit fractions, topics sorted by name, the ``Service:`` lines of
service recording; ros2/rosbag2 #1804 backported to Jazzy), printed by ``print`` (one
newline after the text): a first empty line, labels padded to 19 columns, further files
and topics indented by 19 spaces (services by 21), sizes in B/KiB/MiB/GiB/TiB (1024 base,
no decimal for bytes, one otherwise), times as the local date ``%b %e %Y %H:%M:%S.<ns>``
with the seconds since the epoch in brackets, an empty ROS distro as ``unknown``. Topics
``.../_service_event`` of a type ``..._Event`` are service events: listed as services
(``Service: /name | Type: pkg/srv/T | Event Count: N | ...``), not counted in Messages.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

INDENT = 19                          # the longest label ("Topic information: ")
SIZE_UNITS = ("B", "KiB", "MiB", "GiB", "TiB")
SERVICE_EVENT_SUFFIX = "/_service_event"
SERVICE_EVENT_TYPE_SUFFIX = "_Event"
_NS = 1_000_000_000


@dataclass(frozen=True)
class TopicCount:
    """One topic of a bag: name, type, message count, serialization format."""

    name: str
    type: str
    count: int
    serialization_format: str = "cdr"

    @property
    def is_service_event(self) -> bool:
        """rosbag2_cpp ``is_service_event_topic``: ``/srv/_service_event`` of ``..._Event``."""
        return (len(self.name) > len(SERVICE_EVENT_SUFFIX)
                and self.name.endswith(SERVICE_EVENT_SUFFIX)
                and len(self.type) > len(SERVICE_EVENT_TYPE_SUFFIX)
                and self.type.endswith(SERVICE_EVENT_TYPE_SUFFIX))


@dataclass(frozen=True)
class BagSummary:
    """What ``ros2 bag info`` shows: file names, total size [bytes], storage, ROS distro,
    first message time and span [ns since the epoch, ns], message count, topics."""

    files: list[str]
    size_bytes: int
    storage_id: str
    ros_distro: str
    start_ns: int
    duration_ns: int
    message_count: int
    topics: list[TopicCount]


def from_metadata(info: dict, size_bytes: int) -> BagSummary:
    """The summary of a ``metadata.yaml``'s ``rosbag2_bagfile_information`` mapping;
    KeyError or TypeError when a field is missing."""
    topics = [TopicCount(t["topic_metadata"]["name"], t["topic_metadata"]["type"],
                         int(t["message_count"]),
                         t["topic_metadata"].get("serialization_format") or "")
              for t in info["topics_with_message_count"] or []]
    return BagSummary([str(f) for f in info["relative_file_paths"] or []], size_bytes,
                      info["storage_identifier"], info.get("ros_distro") or "",
                      int(info["starting_time"]["nanoseconds_since_epoch"]),
                      int(info["duration"]["nanoseconds"]), int(info["message_count"]),
                      topics)


def size_text(size_bytes: int) -> str:
    """``format_file_size``: ``612 B``, ``2.4 MiB``."""
    size, unit = float(size_bytes), 0
    while size >= 1024 and unit < len(SIZE_UNITS) - 1:
        size /= 1024
        unit += 1
    return f"{size:.{0 if unit == 0 else 1}f} {SIZE_UNITS[unit]}"


def seconds_text(ns: int) -> str:
    """``format_duration``'s ``time_in_sec``: whole seconds, a dot, 9 digits of ns."""
    seconds = int(ns / _NS)                 # std::chrono::duration_cast truncates
    return f"{seconds}.{ns - seconds * _NS:09d}"


def time_text(ns: int) -> str:
    """``format_time_point``: ``Nov 14 2023 22:13:20.000000000 (1700000000.000000000)``
    in the local time zone."""
    local = time.localtime(int(ns / _NS))
    fraction = seconds_text(ns).split(".")[1]
    return (f"{time.strftime('%b %e %Y', local)} {time.strftime('%H:%M:%S', local)}"
            f".{fraction} ({seconds_text(ns)})")


def _indented(lines: list[str], spaces: int) -> str:
    """The first line as is, the others indented; an empty list is an empty line."""
    return "\n".join([lines[0], *(" " * spaces + line for line in lines[1:])]
                     if lines else [""])


def info_text(bag: BagSummary) -> str:
    """The text ``ros2 bag info`` passes to ``print``: it ends with ``Service information: ``
    and no newline when the bag has no service events, after their lines otherwise."""
    topics = sorted((t for t in bag.topics if not t.is_service_event), key=lambda t: t.name)
    services = sorted((t for t in bag.topics if t.is_service_event), key=lambda t: t.name)
    topic_lines = [f"Topic: {t.name} | Type: {t.type} | Count: {t.count} | "
                   f"Serialization Format: {t.serialization_format}" for t in topics]
    service_lines = [f"Service: {t.name.removesuffix(SERVICE_EVENT_SUFFIX)} | "
                     f"Type: {t.type.removesuffix(SERVICE_EVENT_TYPE_SUFFIX)} | "
                     f"Event Count: {t.count} | "
                     f"Serialization Format: {t.serialization_format}" for t in services]
    end_ns = bag.start_ns + bag.duration_ns
    text = "\n".join([
        "",
        f"{'Files:':<{INDENT}}{_indented(bag.files, INDENT)}",
        f"{'Bag size:':<{INDENT}}{size_text(bag.size_bytes)}",
        f"{'Storage id:':<{INDENT}}{bag.storage_id}",
        f"{'ROS Distro:':<{INDENT}}{bag.ros_distro or 'unknown'}",
        f"{'Duration:':<{INDENT}}{seconds_text(bag.duration_ns)}s",
        f"{'Start:':<{INDENT}}{time_text(bag.start_ns)}",
        f"{'End:':<{INDENT}}{time_text(end_ns)}",
        f"{'Messages:':<{INDENT}}{bag.message_count - sum(t.count for t in services)}",
        f"Topic information: {_indented(topic_lines, INDENT)}",
        f"{'Service:':<{INDENT}}{len(services)}",
        "Service information: ",
    ])
    if not services:
        return text
    return text + _indented(service_lines, INDENT + 2) + "\n"
