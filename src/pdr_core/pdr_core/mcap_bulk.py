"""Vectorised appends of fixed-size messages to a rosbags MCAP writer.

rosbags writes one message at a time, about 4 µs each in Python, which made writing the
full-rate outputs of an hour of 200 Hz data the slowest part of ``pdr-ekf run``. Here the
MCAP Message records of many messages are built with NumPy and handed to rosbags'
``McapWriter`` chunk by chunk, with its own chunking (a chunk is closed after the message
that takes it past 1 MiB), so the file is byte-identical to writing the same messages one
by one in the same order (tested in ``test_bag.py``).

This relies on rosbags 0.11.9 (pinned in ``tools/constraints.txt``): the pending chunk of
``McapWriter`` (``chunk.bio``, ``chunk.msgs``, its time bounds), its file-wide time bounds
and ``channel_stats``, and ``Writer``'s ``counts`` and time bounds. An upgrade that
changes them fails that test.
"""
from __future__ import annotations

from typing import Any

import numpy as np

CHUNK_LIMIT = 2**20  # rosbags closes a chunk once its records pass this many bytes
OPCODE_MESSAGE = 0x05


def _record_dtype(payload: int) -> np.dtype:
    """An MCAP Message record with a payload of ``payload`` bytes, packed."""
    return np.dtype([("opcode", "u1"), ("length", "<u8"), ("channel", "<u2"),
                     ("sequence", "<u4"), ("log_time", "<u8"), ("publish_time", "<u8"),
                     ("data", "u1", (payload,))])


def merged_order(stamps: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(stream, index) of every message of the time-sorted ``stamps`` streams in the
    order of ``heapq.merge`` by time: equal times go stream by stream, in stream order."""
    stream = np.concatenate([np.full(len(s), i) for i, s in enumerate(stamps)])
    index = np.concatenate([np.arange(len(s)) for s in stamps])
    order = np.lexsort((index, stream, np.concatenate(stamps)))
    return stream[order], index[order]


def append(writer: Any, connections: list[Any], stamps: list[np.ndarray],
           rows: list[np.ndarray]) -> None:
    """Append to an open rosbags ``Writer`` (MCAP storage, no per-message compression)
    the messages of several streams merged by log time: stream i goes to
    ``connections[i]``, its log times ``stamps[i]`` (n_i,) [ns] non-decreasing, its
    serialized messages the rows of ``rows[i]`` (n_i, size_i) uint8."""
    storage = writer.storage
    stream, index = merged_order(stamps)
    sizes = np.array([_record_dtype(r.shape[1]).itemsize for r in rows])[stream]
    ends = np.cumsum(sizes)
    first, base = 0, 0
    while first < len(stream):
        start = storage.chunk.bio.tell()
        over = int(np.searchsorted(ends, base + CHUNK_LIMIT - start, side="right"))
        last = min(over + 1, len(stream))
        _write_chunk(writer, connections, stamps, rows, stream[first:last],
                     index[first:last], ends[first:last] - base - sizes[first:last])
        base = ends[last - 1]
        first = last
        if storage.chunk.bio.tell() > CHUNK_LIMIT:
            storage.close_chunk()


def _write_chunk(writer: Any, connections: list[Any], stamps: list[np.ndarray],
                 rows: list[np.ndarray], stream: np.ndarray, index: np.ndarray,
                 offsets: np.ndarray) -> None:
    """Messages (stream, index) at byte ``offsets`` from the chunk's current end."""
    storage = writer.storage
    chunk = storage.chunk
    start = chunk.bio.tell()
    total = int(offsets[-1]) + _record_dtype(rows[stream[-1]].shape[1]).itemsize
    buffer = np.empty(total, np.uint8)
    present, first = np.unique(stream, return_index=True)
    for i in present[np.argsort(first)]:  # rosbags indexes channels as they first appear
        connection = connections[i]
        mine = stream == i
        picked = index[mine]
        times = stamps[i][picked].astype(np.uint64)
        dtype = _record_dtype(rows[i].shape[1])
        records = np.empty(len(picked), dtype)
        records["opcode"] = OPCODE_MESSAGE
        records["length"] = dtype.itemsize - 9
        records["channel"] = connection.id
        records["sequence"] = 0
        records["log_time"] = times
        records["publish_time"] = times
        records["data"] = rows[i][picked]
        at = offsets[mine]
        buffer[at[:, None] + np.arange(dtype.itemsize)] = records.view(np.uint8).reshape(
            len(picked), dtype.itemsize)
        chunk.msgs[connection.id].extend(zip(times.tolist(), (at + start).tolist(),
                                             strict=True))
        low, high = int(times.min()), int(times.max())
        chunk.message_start_time = min(chunk.message_start_time, low)
        chunk.message_end_time = max(chunk.message_end_time, high)
        storage.message_start_time = min(storage.message_start_time, low)
        storage.message_end_time = max(storage.message_end_time, high)
        storage.channel_stats[connection.id] += len(picked)
        writer.counts[connection.id] += len(picked)
        writer.min_timestamp = min(writer.min_timestamp, low)
        writer.max_timestamp = max(writer.max_timestamp, high)
    chunk.bio.write(buffer.tobytes())
