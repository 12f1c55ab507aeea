"""Vectorised CDR codec for stamped messages of fixed layout.

Most high-rate messages of the stack (``sensor_msgs/Imu``, ``MagneticField``,
``FluidPressure``, ``PoseStamped``, ``PoseWithCovarianceStamped``, ``TwistWithCovarianceStamped``,
``Vector3Stamped`` and every ``pdr_msgs`` message) are a ``std_msgs/Header`` followed by
primitives and fixed arrays. For a given ``frame_id`` length their CDR (little-endian,
XCDR1 as ROS 2 uses) has the same byte layout in every message, so a whole topic is
decoded with one NumPy structured view and encoded with one structured array, with no
per-message Python work beyond splitting the buffer. The result is byte-identical to
``rosbags``' serializer (tested).

A type with a string after its header (``nav_msgs/Odometry``'s ``child_frame_id``) or a
``tf2_msgs/TFMessage`` of one transform has a fixed layout too once its strings are known:
:func:`encode_rows` and :func:`encode` take such a batch when each string field (a str
array) holds one value, as the poses a navigator broadcasts do. Other types with strings
or sequences (``nav_msgs/Path``) go through ``rosbags``: see :func:`decode_generic` and
:mod:`pdr_core.io.bag`.

Public: :func:`fixed_layout`, :func:`decode`, :func:`decode_rows`, :func:`encode`,
:func:`encode_rows`, :func:`decode_generic`, :func:`encode_generic`.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from rosbags.interfaces import Nodetype

from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import APPENDED_FIELDS, typestore

_BASE_DTYPES = {
    "bool": "?", "byte": "u1", "char": "u1", "octet": "u1", "int8": "i1", "uint8": "u1",
    "int16": "<i2", "uint16": "<u2", "int32": "<i4", "uint32": "<u4", "int64": "<i8",
    "uint64": "<u8", "float32": "<f4", "float64": "<f8",
}
_HEADER_FIELD = ("header", (Nodetype.NAME, "std_msgs/msg/Header"))
_CDR_LE = b"\x00\x01\x00\x00"
_NS = 1_000_000_000


@dataclass(frozen=True)
class Leaf:
    """One flattened field after the header: ROS field path, dtype, element count."""

    path: str
    dtype: np.dtype
    count: int


def _is_float_struct(fields: list) -> bool:
    return bool(fields) and all(
        kind == Nodetype.BASE and detail[0] == "float64" for _, (kind, detail) in fields)


def _flatten(path: str, node: tuple, out: list[Leaf]) -> bool:
    kind, detail = node
    if kind == Nodetype.BASE:
        if detail[0] not in _BASE_DTYPES:
            return False
        out.append(Leaf(path, np.dtype(_BASE_DTYPES[detail[0]]), 1))
        return True
    if kind == Nodetype.ARRAY:
        (sub_kind, sub_detail), count = detail
        if sub_kind != Nodetype.BASE or sub_detail[0] not in _BASE_DTYPES:
            return False
        out.append(Leaf(path, np.dtype(_BASE_DTYPES[sub_detail[0]]), count))
        return True
    if kind == Nodetype.NAME:
        _, sub_fields = typestore().fielddefs[detail]
        if _is_float_struct(sub_fields):
            out.append(Leaf(path, np.dtype("<f8"), len(sub_fields)))
            return True
        return all(_flatten(f"{path}.{name}", sub, out) for name, sub in sub_fields)
    return False


@functools.cache
def fixed_layout(msgtype: str) -> tuple[Leaf, ...] | None:
    """The flattened fields after the header, or None if ``msgtype`` is not header-first
    with a fixed layout (then use :func:`decode_generic`)."""
    _, fields = typestore().fielddefs[msgtype]
    if not fields or fields[0] != _HEADER_FIELD:
        return None
    leaves: list[Leaf] = []
    if not all(_flatten(name, node, leaves) for name, node in fields[1:]):
        return None
    return tuple(leaves)


@functools.cache
def _record_dtype(msgtype: str, frame_len: int, older: bool = False) -> np.dtype:
    """Structured dtype of one message whose frame_id has ``frame_len`` bytes; ``older``:
    as written before the fields of pdr_core.io.msgtypes.APPENDED_FIELDS were appended.

    CDR alignment is relative to the end of the 4-byte encapsulation header; each
    primitive is aligned to its own size.
    """
    names = ["cdr", "sec", "nanosec", "strlen", "frame"]
    formats: list[Any] = [("u1", (4,)), "<i4", "<u4", "<u4", f"S{frame_len + 1}"]
    offsets = [0, 4, 8, 12, 16]
    pos = 12 + frame_len + 1
    appended = APPENDED_FIELDS.get(msgtype, ()) if older else ()
    for leaf in fixed_layout(msgtype):
        if leaf.path in appended:
            continue
        size = leaf.dtype.itemsize
        pos = -(-pos // size) * size
        names.append(leaf.path)
        formats.append(leaf.dtype if leaf.count == 1 else (leaf.dtype, (leaf.count,)))
        offsets.append(4 + pos)
        pos += size * leaf.count
    return np.dtype({"names": names, "formats": formats, "offsets": offsets,
                     "itemsize": 4 + pos})


def _require_fixed(msgtype: str) -> tuple[Leaf, ...]:
    leaves = fixed_layout(msgtype)
    if leaves is None:
        raise ValueError(f"{msgtype} has no fixed CDR layout; use decode_generic")
    return leaves


def decode(msgtype: str, raws: list[bytes]) -> MessageBatch:
    """Decode serialized CDR messages of a fixed-layout type into a MessageBatch.

    Raises ValueError if a message is truncated or not little-endian CDR.
    """
    lengths = np.fromiter((len(r) for r in raws), dtype=np.int64, count=len(raws))
    return _decode_buffer(msgtype, np.frombuffer(b"".join(raws), dtype=np.uint8), lengths)


def decode_rows(msgtype: str, blocks: list[np.ndarray]) -> MessageBatch:
    """:func:`decode` of messages given as the rows of (k, size) uint8 arrays, one size
    in each array (the chunks of a bag, pdr_core.io.mcap_bulk.chunk_rows; views into them
    will do), in order. The messages of an array that share one layout, the usual case,
    are read through one structured view and copied once, into the batch's arrays."""
    if fixed_layout(msgtype) is None:
        lengths = [np.full(len(rows), rows.shape[1], np.int64) for rows in blocks]
        return _decode_with_strings(msgtype,
                                    np.concatenate([rows.reshape(-1) for rows in blocks]
                                                   or [np.zeros(0, np.uint8)]),
                                    np.concatenate(lengths or [np.zeros(0, np.int64)]))
    parts, start = [], 0
    for rows in blocks:
        n, size = rows.shape
        lengths = np.full(n, size)
        for _, slen, idx in _groups(lengths, _frame_lengths(msgtype, rows[:, :16], lengths)):
            index = slice(start, start + n) if isinstance(idx, slice) else start + idx
            parts.append((index, _records(msgtype, rows[idx], slen)))
        start += n
    return _batch(msgtype, start, parts)


def _decode_buffer(msgtype: str, buf: np.ndarray, lengths: np.ndarray) -> MessageBatch:
    """Messages of ``lengths`` bytes back to back in ``buf``."""
    if fixed_layout(msgtype) is None:
        return _decode_with_strings(msgtype, buf, lengths)
    n = len(lengths)
    starts = np.concatenate(([0], np.cumsum(lengths)[:-1])) if n else np.zeros(0, np.int64)
    if n and lengths.min() < 16:    # first: a short last message ends before a header would
        raise ValueError(f"{msgtype}: message shorter than a CDR header")
    head = sliding_window_view(buf, 16)[starts] if n else np.zeros((0, 16), np.uint8)
    parts = []
    for length, slen, idx in _groups(lengths, _frame_lengths(msgtype, head, lengths)):
        rows = buf.reshape(n, length) if isinstance(idx, slice) else \
            sliding_window_view(buf, length)[starts[idx]]
        parts.append((idx, _records(msgtype, rows, slen)))
    return _batch(msgtype, n, parts)


def _frame_lengths(msgtype: str, head: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """The frame_id lengths (with the null; (n,) uint32) of messages of ``lengths`` bytes
    (n,) whose first 16 bytes are the rows of ``head`` (n, 16): encapsulation, stamp and
    frame_id's length. Raises ValueError for a message shorter than that, not
    little-endian CDR or with a frame_id longer than itself."""
    if len(lengths) and lengths.min() < 16:
        raise ValueError(f"{msgtype}: message shorter than a CDR header")
    if not np.all(head[:, :2] == np.frombuffer(_CDR_LE[:2], np.uint8)):
        raise ValueError(f"{msgtype}: not little-endian CDR")
    strlen = head[:, 12:16].copy().view("<u4").ravel()
    if (strlen.astype(np.int64) > lengths - 16).any():
        raise ValueError(f"{msgtype}: frame_id longer than its message")
    return strlen


def _records(msgtype: str, rows: np.ndarray, strlen: int) -> np.ndarray:
    """The messages in the rows of ``rows`` (k, size) uint8, whose frame_ids have
    ``strlen`` bytes with the null, as (k,) records of their layout (:func:`_record_dtype`;
    an older bag's, without the appended fields, when they are too short for today's): a
    view. Raises ValueError when they are too short for either."""
    size = rows.shape[1]
    dtype = _record_dtype(msgtype, strlen - 1)
    if size < dtype.itemsize and msgtype in APPENDED_FIELDS:
        dtype = _record_dtype(msgtype, strlen - 1, older=True)
    if size < dtype.itemsize:
        raise ValueError(f"{msgtype}: message of {size} bytes, layout needs {dtype.itemsize}")
    return rows[:, :dtype.itemsize].view(dtype)[:, 0]


def _batch(msgtype: str, n: int, parts: list[tuple[slice | np.ndarray, np.ndarray]]
           ) -> MessageBatch:
    """The batch of ``n`` messages from ``parts``: (which of them, a slice or indices;
    their records, :func:`_records`), each copied once into the batch's arrays."""
    leaves = _require_fixed(msgtype)
    frames = [_decoded_frames(records["frame"]) for _, records in parts]
    stamp_ns = np.empty(n, np.int64)
    frame_id = np.empty(n, np.result_type("<U1", *frames))     # as long as the longest
    fields = {leaf.path: np.zeros((n,) if leaf.count == 1 else (n, leaf.count), leaf.dtype)
              for leaf in leaves}
    for (index, records), frame in zip(parts, frames, strict=True):
        stamp_ns[index] = records["sec"].astype(np.int64) * _NS + records["nanosec"]
        frame_id[index] = frame
        for leaf in leaves:
            if leaf.path in records.dtype.names:
                fields[leaf.path][index] = records[leaf.path]
    return MessageBatch(msgtype, stamp_ns, frame_id, fields)


def _groups(lengths: np.ndarray, strlen: np.ndarray):
    """(length, frame length, indices) of the messages sharing a byte layout; in the usual
    case of a single layout one group, without sorting, whose indices are ``slice(None)``
    (all the messages: copied as slices, several times as fast as by an index array)."""
    if len(lengths) and (lengths == lengths[0]).all() and (strlen == strlen[0]).all():
        yield int(lengths[0]), int(strlen[0]), slice(None)
        return
    keys = np.stack([lengths, strlen], axis=1)
    for length, slen in np.unique(keys, axis=0):
        yield int(length), int(slen), np.flatnonzero((lengths == length) & (strlen == slen))


def _decoded_frames(raw: np.ndarray) -> np.ndarray:
    """frame_id strings (a str array) from their null-terminated bytes (one decode per
    distinct value)."""
    if (raw == raw[0]).all():
        return np.full(len(raw), raw[0].decode())
    frames, inverse = np.unique(raw, return_inverse=True)
    return np.array([f.decode() for f in frames])[inverse]


def _frame_groups(frame_id: np.ndarray):
    """(frame, indices) per distinct frame_id; no sorting when there is only one."""
    if len(frame_id) and (frame_id == frame_id[0]).all():
        yield str(frame_id[0]), np.arange(len(frame_id))
        return
    frames, inverse = np.unique(frame_id, return_inverse=True)
    for k, frame in enumerate(frames):
        yield str(frame), np.flatnonzero(inverse == k)


def encode_rows(batch: MessageBatch, frame: str, select: slice | np.ndarray = slice(None)
                ) -> np.ndarray:
    """The CDR of the selected messages of a fixed-layout batch, all in ``frame``, as one
    (n, message size) uint8 array: row i is message i, encapsulation header included.
    A type with strings after the header goes through :func:`_encode_with_strings`."""
    if fixed_layout(batch.msgtype) is None:
        return _encode_with_strings(batch, frame, select)
    leaves = _require_fixed(batch.msgtype)
    encoded = frame.encode()
    dtype = _record_dtype(batch.msgtype, len(encoded))
    sec, nanosec = np.divmod(batch.stamp_ns[select], _NS)
    rec = np.zeros(len(sec), dtype)
    rec["cdr"] = np.frombuffer(_CDR_LE, np.uint8)
    rec["sec"] = sec
    rec["nanosec"] = nanosec
    rec["strlen"] = len(encoded) + 1
    rec["frame"] = encoded
    for leaf in leaves:
        rec[leaf.path] = batch.fields[leaf.path][select]
    return rec.view(np.uint8).reshape(len(rec), dtype.itemsize)


@functools.cache
def _string_entries(msgtype: str) -> tuple[tuple[str, str, np.dtype | None, int], ...]:
    """(kind, path, dtype, count) of every field of ``msgtype`` in CDR order, the header's
    included: kind ``value`` (a primitive, a fixed array or a struct of float64, as
    :class:`Leaf`), ``string`` or ``count`` (a sequence's length; its element's fields
    follow, named through it). Raises ValueError for a sequence of primitives or a field
    with no fixed layout."""
    store = typestore()
    out: list[tuple[str, str, np.dtype | None, int]] = []

    def walk(name_of: str, prefix: str) -> None:
        for name, (kind, detail) in store.fielddefs[name_of][1]:
            path = f"{prefix}{name}"
            if kind == Nodetype.BASE and detail[0] == "string":
                out.append(("string", path, None, 0))
            elif kind == Nodetype.SEQUENCE and detail[0][0] == Nodetype.NAME:
                out.append(("count", path, np.dtype("<u4"), 1))
                walk(detail[0][1], f"{path}.")
            elif kind == Nodetype.NAME and not _is_float_struct(store.fielddefs[detail][1]):
                walk(detail, f"{path}.")
            else:
                leaves: list[Leaf] = []
                if not _flatten(path, (kind, detail), leaves):
                    raise ValueError(f"{msgtype}: {path} has no fixed CDR layout")
                out.extend(("value", leaf.path, leaf.dtype, leaf.count) for leaf in leaves)

    walk(msgtype, "")
    return tuple(out)


@functools.cache
def _string_record_dtype(msgtype: str, lengths: tuple[int, ...]) -> np.dtype:
    """Structured dtype of one ``msgtype`` message whose strings have ``lengths`` bytes
    (in CDR order) and whose sequences one element each; a string is its length
    (``<path>#length``, uint32) then its bytes with the terminating null."""
    names, formats, offsets = ["cdr"], [("u1", (4,))], [0]
    pos, strings = 0, iter(lengths)
    for kind, path, dtype, count in _string_entries(msgtype):
        if kind == "string":
            size = next(strings) + 1
            pos = -(-pos // 4) * 4
            names += [f"{path}#length", path]
            formats += ["<u4", f"S{size}"]
            offsets += [4 + pos, 8 + pos]
            pos += 4 + size
            continue
        pos = -(-pos // dtype.itemsize) * dtype.itemsize
        names.append(path)
        formats.append(dtype if count == 1 else (dtype, (count,)))
        offsets.append(4 + pos)
        pos += dtype.itemsize * count
    return np.dtype({"names": names, "formats": formats, "offsets": offsets,
                     "itemsize": 4 + pos})


def _encode_with_strings(batch: MessageBatch, frame: str, select: slice | np.ndarray
                         ) -> np.ndarray:
    """:func:`encode_rows` of a type with strings after its header (see the module's
    docstring): the header's frame is ``frame``, each other string the one value of its
    field, each sequence one element. Raises ValueError when a string differs between
    the messages."""
    entries = _string_entries(batch.msgtype)
    stamps = batch.stamp_ns[select]
    strings: dict[str, bytes] = {}
    for kind, path, _, _ in entries:
        if kind != "string":
            continue
        values = [frame] if path.endswith("header.frame_id") else \
            np.unique(batch.fields[path][select]).tolist()
        if len(values) > 1:
            raise ValueError(f"{batch.msgtype}: {path} differs between the messages "
                             f"({values[:3]}); encode each value's messages apart")
        strings[path] = str(values[0] if values else "").encode()
    dtype = _string_record_dtype(batch.msgtype, tuple(len(v) for v in strings.values()))
    sec, nanosec = np.divmod(stamps, _NS)
    rec = np.zeros(len(stamps), dtype)
    rec["cdr"] = np.frombuffer(_CDR_LE, np.uint8)
    for kind, path, _, _ in entries:
        if kind == "string":
            rec[f"{path}#length"] = len(strings[path]) + 1
            rec[path] = strings[path]
        elif kind == "count":
            rec[path] = 1
        elif path.endswith("header.stamp.sec"):
            rec[path] = sec
        elif path.endswith("header.stamp.nanosec"):
            rec[path] = nanosec
        else:
            rec[path] = batch.fields[path][select]
    return rec.view(np.uint8).reshape(len(rec), dtype.itemsize)


def _string_lengths(msgtype: str, raw: np.ndarray) -> tuple[int, ...]:
    """The byte lengths of one message's strings (CDR order, without the null), read
    along its layout. Raises ValueError for a sequence of other than one element or a
    message too short."""
    pos, lengths = 0, []
    payload = raw[4:]
    for kind, path, dtype, count in _string_entries(msgtype):
        size = 4 if kind in ("string", "count") else dtype.itemsize
        pos = -(-pos // size) * size
        if pos + 4 > len(payload) and kind != "value":
            raise ValueError(f"{msgtype}: message of {len(raw)} bytes ends in {path}")
        if kind == "value":
            pos += size * count
            continue
        value = int(payload[pos:pos + 4].view("<u4")[0])
        if kind == "count" and value != 1:
            raise ValueError(f"{msgtype}: {path} holds {value} elements; one is read here "
                             "(use decode_generic)")
        if kind == "string":
            lengths.append(value - 1)
            pos += value
        pos += 4
    return tuple(lengths)


def _layout_keys(msgtype: str, buf: np.ndarray, starts: np.ndarray, lengths: np.ndarray
                 ) -> list[tuple[int, ...]]:
    """Each message's string lengths (:func:`_string_lengths`): read on the first message
    of each size and checked on the others of that size at once (one layout in the usual
    case); a message that differs is read by itself."""
    keys: list[tuple[int, ...]] = [()] * len(lengths)
    for size in np.unique(lengths).tolist():
        idx = np.flatnonzero(lengths == size)
        key = _string_lengths(msgtype, buf[starts[idx[0]]:starts[idx[0]] + size])
        dtype = _string_record_dtype(msgtype, key)
        view = np.ascontiguousarray(buf[starts[idx, None] + np.arange(dtype.itemsize)]
                                    ).view(dtype).ravel()
        same = np.ones(len(idx), bool)
        for kind, path, _, _ in _string_entries(msgtype):
            if kind == "count":
                same &= view[path] == 1
        strings = [n for n in dtype.names if n.endswith("#length")]
        for name, length in zip(strings, key, strict=True):
            same &= view[name] == length + 1
        for i, ok in zip(idx.tolist(), same.tolist(), strict=True):
            keys[i] = key if ok else _string_lengths(msgtype, buf[starts[i]:starts[i] + size])
    return keys


def _decode_with_strings(msgtype: str, buf: np.ndarray, lengths: np.ndarray) -> MessageBatch:
    """:func:`decode` of a type with strings after its header (the module's docstring):
    messages grouped by the lengths of their strings, each group through one view. The
    header's frame is the batch's frame_id, each other string a str field."""
    n = len(lengths)
    starts = np.concatenate(([0], np.cumsum(lengths)[:-1])) if n else np.zeros(0, np.int64)
    keys = _layout_keys(msgtype, buf, starts, lengths)
    entries = _string_entries(msgtype)
    strings = [path for kind, path, _, _ in entries if kind == "string"]
    values = [(path, dtype, count) for kind, path, dtype, count in entries
              if kind == "value" and not path.endswith(("header.stamp.sec",
                                                        "header.stamp.nanosec"))]
    stamp_ns = np.zeros(n, np.int64)
    text = {path: np.empty(n, dtype=object) for path in strings}
    fields = {path: np.zeros((n,) if count == 1 else (n, count), dtype)
              for path, dtype, count in values}
    for key in dict.fromkeys(keys):
        idx = np.flatnonzero([k == key for k in keys])
        dtype = _string_record_dtype(msgtype, key)
        if int(lengths[idx].min()) < dtype.itemsize:
            raise ValueError(f"{msgtype}: message shorter than its layout")
        rows = buf[starts[idx, None] + np.arange(dtype.itemsize)]
        view = np.ascontiguousarray(rows).view(dtype).ravel()
        sec = next(p for p in dtype.names if p.endswith("header.stamp.sec"))
        stamp_ns[idx] = view[sec].astype(np.int64) * _NS + view[sec.replace(".sec", ".nanosec")]
        for path in strings:
            text[path][idx] = _decoded_frames(view[path])
        for path, _, _ in values:
            fields[path][idx] = view[path]
    frame = next(p for p in strings if p.endswith("header.frame_id"))
    fields |= {path: column.astype(str) for path, column in text.items() if path != frame}
    return MessageBatch(msgtype, stamp_ns, text[frame].astype(str), fields)


def encode(batch: MessageBatch) -> list[bytes]:
    """Serialize every message of a fixed-layout batch (or one of
    :func:`_encode_with_strings`' types) to CDR, in order."""
    n = len(batch)
    out: list[bytes] = [b""] * n
    for frame, idx in _frame_groups(batch.frame_id):
        select = slice(None) if len(idx) == n else idx
        rows = encode_rows(batch, frame, select)
        blob, size = rows.tobytes(), rows.shape[1]
        pieces = [blob[i:i + size] for i in range(0, len(blob), size)]
        if len(idx) == n:
            return pieces
        for i, piece in zip(idx.tolist(), pieces, strict=True):
            out[i] = piece
    return out


def decode_generic(msgtype: str, raw: bytes) -> Any:
    """Deserialize one CDR message of any known type to a rosbags message object."""
    return typestore().deserialize_cdr(raw, msgtype)


def encode_generic(msg: Any) -> bytes:
    """Serialize one rosbags message object to CDR."""
    return bytes(typestore().serialize_cdr(msg, msg.__msgtype__))
