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

Reading (:func:`chunk_rows`) takes the summary of the ``mcap`` library's SeekingReader
and gathers the wanted channels' messages from each chunk with NumPy, by the offsets of
their MessageIndex records (MCAP specification: records are opcode, uint64 length, content).
"""
from __future__ import annotations

import struct
from collections import defaultdict
from collections.abc import Callable, Iterator
from io import BytesIO
from typing import Any

import lz4.frame
import numpy as np
import zstandard
from numpy.lib.stride_tricks import as_strided, sliding_window_view

CHUNK_LIMIT = 2**20  # rosbags closes a chunk once its records pass this many bytes
OPCODE_MESSAGE, OPCODE_CHUNK, OPCODE_MESSAGE_INDEX = 0x05, 0x06, 0x07


def _record_dtype(payload: int) -> np.dtype:
    """An MCAP Message record with a payload of ``payload`` bytes, packed."""
    return np.dtype([("opcode", "u1"), ("length", "<u8"), ("channel", "<u2"),
                     ("sequence", "<u4"), ("log_time", "<u8"), ("publish_time", "<u8"),
                     ("data", "u1", (payload,))])


def merged_order(stamps: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(stream, index) of every message of the time-sorted ``stamps`` streams in the
    order of ``heapq.merge`` by time: equal times go stream by stream, in stream order.
    Streams sharing one strictly increasing time base (the outputs of one filter) simply
    take turns."""
    first = stamps[0]
    if all(s is first or np.array_equal(s, first) for s in stamps[1:]) and np.all(
            np.diff(first) > 0):
        return (np.tile(np.arange(len(stamps)), len(first)),
                np.repeat(np.arange(len(first)), len(stamps)))
    stream = np.concatenate([np.full(len(s), i) for i, s in enumerate(stamps)])
    index = np.concatenate([np.arange(len(s)) for s in stamps])
    order = np.lexsort((index, stream, np.concatenate(stamps)))
    return stream[order], index[order]


def append(writer: Any, connections: list[Any], stamps: list[np.ndarray],
           encoders: list[Callable[[slice], np.ndarray]], sizes: list[int]) -> None:
    """Append to an open rosbags ``Writer`` (MCAP storage, no per-message compression)
    the messages of several streams merged by log time: stream i goes to
    ``connections[i]``, its log times ``stamps[i]`` (n_i,) [ns] non-decreasing, and
    ``encoders[i](messages)`` serializes a slice of its messages to the rows of a
    (m, ``sizes[i]``) uint8 array. Messages are encoded chunk by chunk (1 MiB), so that
    nothing of the size of the whole output is ever built."""
    storage = writer.storage
    stream, index = merged_order(stamps)
    record_sizes = np.array([_record_dtype(size).itemsize for size in sizes])[stream]
    ends = np.cumsum(record_sizes)
    first, base = 0, 0
    while first < len(stream):
        start = storage.chunk.bio.tell()
        over = int(np.searchsorted(ends, base + CHUNK_LIMIT - start, side="right"))
        last = min(over + 1, len(stream))
        _write_chunk(writer, connections, stamps, encoders, sizes, stream[first:last],
                     index[first:last], ends[first:last] - base - record_sizes[first:last])
        base = ends[last - 1]
        first = last
        if storage.chunk.bio.tell() > CHUNK_LIMIT:
            close_chunk(storage)
    _entries_as_tuples(storage.chunk)


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
    with chunk.bio.getbuffer() as records:      # the chunk's bytes, not copied
        compressed = storage.compressor(records)
        sizes = len(compressed), len(records)
        chunk_start = storage.bio.tell()
        content = struct.pack("<QQQI", chunk.message_start_time, chunk.message_end_time,
                              sizes[1], 0) \
            + _string(storage.compression) + struct.pack("<Q", sizes[0])
        storage.bio.write(struct.pack("<BQ", OPCODE_CHUNK, len(content) + sizes[0]) + content)
        storage.bio.write(compressed)           # the record's last field, not copied either
    chunk_end = storage.bio.tell()
    offsets = []
    for channel, entries in chunk.msgs.items():
        offsets.append(struct.pack("<HQ", channel, storage.bio.tell()))
        pairs = _entries_array(entries)
        storage.bio.write(_record(OPCODE_MESSAGE_INDEX, struct.pack(
            "<HI", channel, pairs.nbytes) + pairs.tobytes()))
    index = BytesIO()  # positioned at its end: rosbags takes tell() as its length
    index.write(struct.pack("<QQQQI", chunk.message_start_time, chunk.message_end_time,
                            chunk_start, chunk_end - chunk_start, 10 * len(offsets))
                + b"".join(offsets) + struct.pack("<Q", storage.bio.tell() - chunk_end)
                + _string(storage.compression) + struct.pack("<QQ", *sizes))
    storage.chunks.append(index)
    storage.chunk = type(chunk)(2**63 - 1, 0, BytesIO(), defaultdict(list))


def _write_chunk(writer: Any, connections: list[Any], stamps: list[np.ndarray],
                 encoders: list[Callable[[slice], np.ndarray]], sizes: list[int],
                 stream: np.ndarray, index: np.ndarray, offsets: np.ndarray) -> None:
    """Messages (stream, index) at byte ``offsets`` from the chunk's current end. The
    messages of one stream in a chunk are consecutive (the merge keeps each stream's
    order), so each stream is encoded as one slice."""
    storage = writer.storage
    chunk = storage.chunk
    start = chunk.bio.tell()
    buffer = np.empty(int(offsets[-1]) + _record_dtype(sizes[stream[-1]]).itemsize, np.uint8)
    present, first = np.unique(stream, return_index=True)
    for i in present[np.argsort(first)]:  # rosbags indexes channels as they first appear
        connection = connections[i]
        mine = stream == i
        picked = index[mine]
        times = stamps[i][picked].astype(np.uint64)
        dtype = _record_dtype(sizes[i])
        records = np.empty(len(picked), dtype)
        records["opcode"] = OPCODE_MESSAGE
        records["length"] = dtype.itemsize - 9
        records["channel"] = connection.id
        records["sequence"] = 0
        records["log_time"] = times
        records["publish_time"] = times
        records["data"] = encoders[i](slice(int(picked[0]), int(picked[-1]) + 1))
        at = offsets[mine]
        _place(buffer, at, records.view(np.uint8).reshape(len(picked), dtype.itemsize))
        chunk.msgs[connection.id].append(np.column_stack((times, at.astype(np.uint64) + start)))
        low, high = int(times.min()), int(times.max())
        chunk.message_start_time = min(chunk.message_start_time, low)
        chunk.message_end_time = max(chunk.message_end_time, high)
        storage.message_start_time = min(storage.message_start_time, low)
        storage.message_end_time = max(storage.message_end_time, high)
        storage.channel_stats[connection.id] += len(picked)
        writer.counts[connection.id] += len(picked)
        writer.min_timestamp = min(writer.min_timestamp, low)
        writer.max_timestamp = max(writer.max_timestamp, high)
    chunk.bio.write(buffer)


def _place(buffer: np.ndarray, at: np.ndarray, records: np.ndarray) -> None:
    """Copy the rows of ``records`` (k, size) to ``buffer[at[j]:at[j] + size]`` (records
    side by side: the rows do not overlap)."""
    view = _evenly_spaced_rows(buffer, at, records.shape[1])
    if view is None:
        sliding_window_view(buffer, records.shape[1], writeable=True)[at] = records
    else:
        view[:] = records


def _evenly_spaced_rows(buffer: np.ndarray, at: np.ndarray, width: int
                        ) -> np.ndarray | None:
    """The ``width`` bytes at each offset ``at`` of ``buffer`` as a (k, width) strided
    view (writeable if ``buffer`` is) when the offsets are evenly spaced and the rows do
    not overlap: one topic, or topics interleaved in a fixed pattern, the usual case.
    None otherwise."""
    step = int(at[1] - at[0]) if len(at) > 1 else width
    if step >= width and np.all(np.diff(at) == step):
        return as_strided(buffer[at[0]:], (len(at), width), (step, 1), writeable=True)
    return None


def _entries_as_tuples(chunk: Any) -> None:
    """Turn the (k, 2) arrays of message-index entries this module put in the pending
    chunk into rosbags' own (log time, offset) tuples, so that rosbags can close it."""
    for channel, entries in chunk.msgs.items():
        chunk.msgs[channel] = [tuple(pair) for pair in _entries_array(entries).tolist()]


def _entries_array(entries: list) -> np.ndarray:
    """A chunk's message-index entries of one channel, rosbags' (log time, offset) tuples
    and this module's (k, 2) arrays in any mix, as one (n, 2) little-endian uint64 array."""
    return np.concatenate([np.asarray(e, "<u8").reshape(-1, 2) for e in entries])


def _chunk_records(stream: Any, index: Any) -> np.ndarray:
    """The uncompressed records of the chunk of a ChunkIndex, as uint8."""
    stream.seek(index.chunk_start_offset)
    raw = stream.read(index.chunk_length)
    # opcode, record length, start and end time, uncompressed size and CRC: 37 bytes
    name_len = int.from_bytes(raw[37:41], "little")
    compression = raw[41:41 + name_len].decode()
    at = 41 + name_len + 8
    data = memoryview(raw)[at:at + index.compressed_size]    # not copied
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


def _rows(records: np.ndarray, at: np.ndarray, width: int) -> np.ndarray:
    """The ``width`` bytes at each offset ``at`` of ``records``, as a (k, width) array:
    a view when the offsets are evenly spaced, else gathered row by row (fancy indexing of
    the rows of a sliding-window view copies each row whole, about 14 times as fast as an
    index of every byte)."""
    view = _evenly_spaced_rows(records, at, width)
    return sliding_window_view(records, width)[at] if view is None else view


def chunk_rows(stream: Any, summary: Any, channel_ids: list[int]
               ) -> Iterator[tuple[int, np.ndarray, np.ndarray]]:
    """Per chunk of an indexed MCAP file, per channel of ``channel_ids`` that it holds
    (in that order): the channel id, its messages' log times (k,) [ns] and serialized
    messages (k, size) uint8, in the chunk's index order, through the chunk and message
    indexes; each chunk is read and decompressed once for all the channels. Raises
    ValueError if a channel's messages in a chunk differ in size (then read them one by
    one)."""
    for index in summary.chunk_indexes:
        held = {channel: _message_index(stream, index.message_index_offsets[channel])
                for channel in channel_ids if channel in index.message_index_offsets}
        held = {channel: entries for channel, entries in held.items() if len(entries)}
        if not held:
            continue
        records = _chunk_records(stream, index)
        for channel, entries in held.items():
            offsets = entries[:, 1].astype(np.int64)
            lengths = _rows(records, offsets + 1, 8).copy().view("<u8").ravel()
            if np.any(lengths != lengths[0]):
                raise ValueError("messages of different sizes")
            yield (channel, entries[:, 0].astype(np.int64),
                   _rows(records, offsets + 31, int(lengths[0]) - 22))
