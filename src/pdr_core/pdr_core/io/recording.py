"""A bag written as it is recorded, so that a crash loses at most the last second.

:class:`RecordingBag` is what ``bag_record`` writes with. Unlike
:class:`pdr_core.io.bag.BagWriter` (a finished product, renamed into place only when
complete), it writes at its final path from the start, as rosbag2's MCAP storage does:

- messages go into the open MCAP chunk of rosbags' writer; the chunk is written to the
  file (with its message index) when it fills (1 MiB) or when :meth:`flush_if_due` finds
  it older than ``flush_interval_s``, then flushed and fsync'ed;
- ``metadata.yaml`` is written at the start and rewritten (atomically) at every flush with
  the topics and counts so far;
- :meth:`close` writes the summary and the index, and rosbags' final ``metadata.yaml``.

After a SIGKILL or a power cut the file holds every flushed chunk; readers recover it
(:class:`pdr_core.io.bag.BagReader` warns how much) and ``pdr-sim repair`` rebuilds its index.
The flush uses rosbags' MCAP storage writer's ``close_chunk`` and file object (rosbags is
pinned in ``constraints.txt``). The flush interval is wall-clock (monotonic) time: it
bounds what a crash can lose, whatever the data's own stamps.
"""
from __future__ import annotations

import os
import shutil
import time
from pathlib import Path
from typing import Any

import yaml
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.rosbag2.metadata import dump_qos_v9

from pdr_core.errors import InputError
from pdr_core.io.msgtypes import typestore

BAG_VERSION = 9


class RecordingBag:
    """Writes messages at ``path`` (a new rosbag2 directory) as they come; module
    docstring. Raises InputError for an existing ``path`` unless ``overwrite`` (then it is
    removed first), OSError when the disk fails."""

    def __init__(self, path: str | Path, flush_interval_s: float = 1.0,
                 overwrite: bool = False) -> None:
        self.path = Path(path)
        if self.path.exists() and not overwrite:
            raise InputError(self.path, "output exists already (remove it, or -p "
                                        "overwrite:=true replaces it)")
        if self.path.is_dir():
            shutil.rmtree(self.path)
        elif self.path.exists():
            self.path.unlink()
        if not flush_interval_s > 0:
            raise InputError("flush_interval_s", f"must be > 0, got {flush_interval_s}")
        self.flush_interval_s = flush_interval_s
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._writer = Writer(self.path, version=BAG_VERSION, storage_plugin=StoragePlugin.MCAP)
        self._writer.open()
        self._connections: dict[str, Any] = {}
        self._last_flush = time.monotonic()
        self.flushes = 0
        self.bytes_written = 0
        self._write_metadata()

    def write_raw(self, topic: str, msgtype: str, log_time_ns: int, data: bytes) -> None:
        """Append one serialized message; flush when the open chunk is due."""
        if topic not in self._connections:
            self._connections[topic] = self._writer.add_connection(
                topic, msgtype, typestore=typestore())
        self._writer.write(self._connections[topic], int(log_time_ns), data)
        self.flush_if_due()

    def flush_if_due(self) -> None:
        """Flush when the last flush is ``flush_interval_s`` old (or a chunk filled)."""
        storage = self._writer.storage
        if storage is None:
            return
        filled = storage.bio.tell() > self.bytes_written
        if filled or time.monotonic() - self._last_flush >= self.flush_interval_s:
            self.flush()

    def flush(self) -> None:
        """Write the open chunk, sync the file and rewrite metadata.yaml."""
        storage = self._writer.storage
        if storage.chunk.bio.tell():
            storage.close_chunk()
        storage.bio.flush()
        os.fsync(storage.bio.fileno())
        self.bytes_written = storage.bio.tell()
        self._write_metadata()
        self._last_flush = time.monotonic()
        self.flushes += 1

    def close(self) -> None:
        """Write the summary, the index and the final metadata.yaml."""
        if self._writer.storage is not None:
            self._writer.close()
            self.bytes_written = sum(f.stat().st_size for f in self.path.glob("*.mcap"))

    @property
    def message_count(self) -> int:
        return sum(self._writer.counts.values())

    def _write_metadata(self) -> None:
        """metadata.yaml of what is flushed so far, replaced atomically."""
        w = self._writer
        start = w.min_timestamp if w.counts and self.message_count else 0
        duration = max(0, w.max_timestamp - start)
        name = f"{self.path.name}.mcap"
        info = {
            "version": BAG_VERSION, "storage_identifier": "mcap",
            "relative_file_paths": [name], "duration": {"nanoseconds": duration},
            "starting_time": {"nanoseconds_since_epoch": start},
            "message_count": self.message_count,
            "topics_with_message_count": [
                {"topic_metadata": {"name": c.topic, "type": c.msgtype,
                                    "serialization_format": c.ext.serialization_format,
                                    "offered_qos_profiles": dump_qos_v9(
                                        c.ext.offered_qos_profiles),
                                    "type_description_hash": c.digest},
                 "message_count": w.counts[c.id]} for c in w.connections],
            "compression_format": "", "compression_mode": "",
            "files": [{"path": name, "starting_time": {"nanoseconds_since_epoch": start},
                       "duration": {"nanoseconds": duration},
                       "message_count": self.message_count}],
            "custom_data": None, "ros_distro": "rosbags"}
        tmp = self.path / "metadata.yaml.tmp"
        tmp.write_text(yaml.safe_dump({"rosbag2_bagfile_information": info}))
        tmp.replace(self.path / "metadata.yaml")
