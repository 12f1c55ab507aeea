"""Vectorised MCAP I/O of fixed-size messages: appends to a rosbags writer, and reads
through the chunk and message indexes.

rosbags writes one message at a time, about 4 µs each in Python, which made writing the
full-rate outputs of an hour of 200 Hz data the slowest part of ``pdr-ekf run``. Here the
MCAP Message records of many messages are built with NumPy and handed to rosbags'
``McapWriter`` chunk by chunk, with its own chunking (a chunk is closed after the message
that takes it past 1 MiB, by :func:`close_chunk`, rosbags' own with the message index
built by NumPy), so the file is byte-identical to writing the same messages one by one in
the same order (tested in ``test_bag.py``, with and without zstd).

This relies on rosbags 0.11.9 (pinned in ``tools/constraints.txt``): the pending chunk of
``McapWriter`` (``chunk.bio``, ``chunk.msgs``, its time bounds), its file-wide time bounds,
``channel_stats``, ``bio``, ``chunks``, ``compression`` and ``compressor``, and
``Writer``'s ``counts`` and time bounds. An upgrade that
changes them fails that test.

Reading (:func:`read_rows`) takes the summary of the ``mcap`` library's SeekingReader
and gathers one channel's messages from each chunk with NumPy, by the offsets of its
MessageIndex records (MCAP specification: records are opcode, uint64 length, content).
"""
from __future__ import annotations

import struct
from collections import defaultdict
from io import BytesIO
from typing import Any

import lz4.frame
import numpy as np
import zstandard

CHUNK_LIMIT = 2**20  # rosbags closes a chunk once its records pass this many bytes
OPCODE_MESSAGE, OPCODE_CHUNK, OPCODE_MESSAGE_INDEX = 0x05, 0x06, 0x07


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
            close_chunk(storage)


def _string(text: str) -> bytes:
    data = text.encode()
    return struct.pack("<I", len(data)) + data


def _record(opcode: int, content: bytes) -> bytes:
    return struct.pack("<BQ", opcode, len(content)) + content


def close_chunk(storage: Any) -> None:
    """rosbags' ``McapWriter.close_chunk`` with the MessageIndex records built by NumPy
    (rosbags writes each (time, offset) pair with two Python calls): the Chunk record,
    one MessageIndex per channel in the order the channels first appear, and the
    ChunkIndex kept for the summary; then a new, empty pending chunk."""
    chunk = storage.chunk
    records = chunk.bio.getvalue()
    compressed = storage.compressor(records)
    chunk_start = storage.bio.tell()
    storage.bio.write(_record(OPCODE_CHUNK, struct.pack(
        "<QQQI", chunk.message_start_time, chunk.message_end_time, len(records), 0)
        + _string(storage.compression) + struct.pack("<Q", len(compressed)) + compressed))
    chunk_end = storage.bio.tell()
    offsets = []
    for channel, entries in chunk.msgs.items():
        offsets.append(struct.pack("<HQ", channel, storage.bio.tell()))
        pairs = np.asarray(entries, dtype="<u8").reshape(-1, 2)
        storage.bio.write(_record(OPCODE_MESSAGE_INDEX, struct.pack(
            "<HI", channel, pairs.nbytes) + pairs.tobytes()))
    index = BytesIO()  # positioned at its end: rosbags takes tell() as its length
    index.write(struct.pack("<QQQQI", chunk.message_start_time, chunk.message_end_time,
                            chunk_start, chunk_end - chunk_start, 10 * len(offsets))
                + b"".join(offsets) + struct.pack("<Q", storage.bio.tell() - chunk_end)
                + _string(storage.compression)
                + struct.pack("<QQ", len(compressed), len(records)))
    storage.chunks.append(index)
    storage.chunk = type(chunk)(2**63 - 1, 0, BytesIO(), defaultdict(list))


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


def _chunk_records(stream: Any, index: Any) -> np.ndarray:
    """The uncompressed records of the chunk of a ChunkIndex, as uint8."""
    stream.seek(index.chunk_start_offset)
    raw = stream.read(index.chunk_length)
    # opcode, record length, start and end time, uncompressed size and CRC: 37 bytes
    name_len = int.from_bytes(raw[37:41], "little")
    compression = raw[41:41 + name_len].decode()
    at = 41 + name_len + 8
    data = raw[at:at + index.compressed_size]
    if compression == "zstd":
        data = zstandard.ZstdDecompressor().decompress(
            data, max_output_size=index.uncompressed_size)
    elif compression == "lz4":
        data = lz4.frame.decompress(data)
    elif compression:
        raise ValueError(f"unknown chunk compression {compression!r}")
    return np.frombuffer(data, np.uint8)


def _message_index(stream: Any, offset: int) -> np.ndarray:
    """(log time, offset in the chunk's records) pairs (n, 2) of a MessageIndex record."""
    stream.seek(offset)
    head = stream.read(15)  # opcode, record length, channel id, array byte length
    size = int.from_bytes(head[11:15], "little")
    return np.frombuffer(stream.read(size), "<u8").reshape(-1, 2)


def _gather(values: np.ndarray, starts: np.ndarray, width: int) -> np.ndarray:
    return values[starts[:, None] + np.arange(width)]


def read_rows(stream: Any, summary: Any, channel_id: int) -> tuple[np.ndarray, np.ndarray]:
    """Log times (n,) [ns] and serialized messages (n, size) uint8 of one channel of an
    indexed MCAP file, in log-time order (ties in file order), through its chunk and
    message indexes. Raises ValueError if the messages differ in size (then read them
    one by one)."""
    times, rows = [], []
    for index in summary.chunk_indexes:
        if channel_id not in index.message_index_offsets:
            continue
        entries = _message_index(stream, index.message_index_offsets[channel_id])
        if not len(entries):
            continue
        records = _chunk_records(stream, index)
        offsets = entries[:, 1].astype(np.int64)
        lengths = _gather(records, offsets + 1, 8).copy().view("<u8").ravel()
        if np.any(lengths != lengths[0]):
            raise ValueError("messages of different sizes")
        times.append(entries[:, 0].astype(np.int64))
        rows.append(_gather(records, offsets + 31, int(lengths[0]) - 22))
    if not rows:
        return np.zeros(0, np.int64), np.zeros((0, 0), np.uint8)
    if len({r.shape[1] for r in rows}) > 1:
        raise ValueError("messages of different sizes")
    log_time, data = np.concatenate(times), np.concatenate(rows)
    order = np.argsort(log_time, kind="stable")
    return log_time[order], data[order]
