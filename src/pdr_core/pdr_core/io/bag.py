"""Reading and writing rosbag2 bags in MCAP storage, as NumPy batches or raw CDR.

A bag is a rosbag2 directory (``metadata.yaml`` + ``*.mcap``), as ``ros2 bag`` writes it;
a bare ``.mcap`` file is read too. Intact bags are read in log-time order by rosbags'
indexed reader. A file without its summary (a recording cut short, a copy interrupted, a
damaged tail) or a directory without ``metadata.yaml`` (a recorder killed before it wrote
one) is *recovered*: the ``mcap`` library's streaming reader yields every message up to
the last complete chunk and an :class:`InputWarning` says how many and where it stopped.
With ``strict=True`` (the CLIs' ``--strict``) such a bag is refused with an
:class:`InputError` naming the file and that offset. Writing uses
``rosbags`` (valid ``metadata.yaml``, ROS 2 message definitions in the MCAP schemas) into
a hidden temporary directory that is renamed into place only when the bag is complete,
so a failure never leaves half-written output.

A CSV log passed where a bag is read is refused with the ``pdr-sim import-csv`` command
that turns it into one (:func:`not_a_bag`).

Public: :class:`RawMessage`, :class:`BagReader`, :class:`BagWriter`,
:func:`merged_messages`, :func:`write_batches`, :func:`readable_extent`,
:func:`repair`, :func:`add_strict_option`, :func:`not_a_bag`.
"""
from __future__ import annotations

import functools
import heapq
import shlex
import shutil
import struct
import tempfile
import warnings
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from mcap.exceptions import McapError
from mcap.reader import NonSeekingReader, SeekingReader
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader
from rosbags.rosbag2 import Reader, StoragePlugin, Writer
from rosbags.rosbag2.enums import CompressionFormat, CompressionMode
from rosbags.rosbag2.errors import ReaderError

from pdr_core.errors import InputError, InputWarning
from pdr_core.io import cdr, mcap_bulk
from pdr_core.io.batch import LazyBatch, MessageBatch
from pdr_core.io.msgtypes import typestore

MCAP_MAGIC = b"\x89MCAP0\r\n"
_READ_ERRORS = (McapError, ReaderError, EOFError, ValueError, KeyError, OSError,
                AssertionError, struct.error)


@dataclass(frozen=True)
class RawMessage:
    """One serialized message: topic, ROS type, log time [ns] and CDR bytes."""

    topic: str
    msgtype: str
    log_time_ns: int
    data: bytes


def _bag_files(path: Path) -> tuple[list[Path], dict[str, str]]:
    """The MCAP files of a bag and its topics (name -> type) from metadata.yaml."""
    meta_path = path / "metadata.yaml"
    if not meta_path.is_file():
        raise InputError(path, "not a rosbag2 bag: no metadata.yaml")
    try:
        info = yaml.safe_load(meta_path.read_text())["rosbag2_bagfile_information"]
        storage = info["storage_identifier"]
        files = [path / name for name in info["relative_file_paths"]]
        topics = {t["topic_metadata"]["name"]: t["topic_metadata"]["type"]
                  for t in info["topics_with_message_count"]}
    except (yaml.YAMLError, KeyError, TypeError) as exc:
        raise InputError(meta_path, f"corrupt metadata.yaml ({exc!r})") from exc
    if storage != "mcap":
        raise InputError(path, f"storage '{storage}' is not supported; only mcap")
    for file in files:
        if not file.is_file():
            raise InputError(file, "listed in metadata.yaml but missing")
    return files, topics


def _summary_topics(file: Path) -> dict[str, str] | None:
    """The topics (name -> type) of ``file``'s summary; None when it has none (not
    closed cleanly)."""
    try:
        with file.open("rb") as stream:
            summary = SeekingReader(stream).get_summary()
    except _READ_ERRORS:
        return None
    if summary is None:
        return None
    return {ch.topic: summary.schemas[ch.schema_id].name for ch in summary.channels.values()}


@dataclass(frozen=True)
class Extent:
    """How much of a damaged MCAP file is readable: the byte where the last complete
    record ends, the file's size, the channels seen (topic -> type) and the messages."""

    good_bytes: int
    size: int
    topics: dict[str, str]
    messages: int

    def describe(self) -> str:
        return (f"cut short or unindexed: readable to byte {self.good_bytes} of {self.size}, "
                f"{self.messages} messages")


def readable_extent(file: Path) -> Extent:
    """Walk ``file``'s records (inside chunks too) to the first that cannot be read."""
    topics: dict[str, str] = {}
    schemas: dict[int, str] = {}
    messages = good = 0
    with file.open("rb") as stream:
        records = StreamReader(stream, validate_crcs=True).records
        try:
            for record in records:
                if isinstance(record, Schema):
                    schemas[record.id] = record.name
                elif isinstance(record, Channel):
                    topics[record.topic] = schemas.get(record.schema_id, "")
                elif isinstance(record, Message):
                    messages += 1
                good = stream.tell()
        except _READ_ERRORS:
            pass
    return Extent(good, file.stat().st_size, topics, messages)


# Text logs a user may pass where a bag is read: the refusal points to pdr-sim import-csv
TEXT_LOG_SUFFIXES = (".csv", ".txt", ".tsv")


def not_a_bag(file: Path) -> str:
    """Why ``file`` (without the MCAP magic bytes) is refused as a bag: for a CSV log (a
    .csv/.txt/.tsv name, or a first line of comma-separated text), the command that
    turns it into one, with its own columns where its header names them."""
    with file.open("rb") as stream:
        first = stream.readline(4096).decode("utf-8", errors="replace").strip()
    cells = [cell.strip() for cell in first.split(",")]
    if file.suffix.lower() not in TEXT_LOG_SUFFIXES and not (len(cells) > 1 and
                                                             first.isprintable()):
        return "not an MCAP file (bad magic bytes)"
    try:
        [float(cell) for cell in cells]
        columns = ["--no-header", "--time-col", "0", "--acc-cols", "1,2,3"]
    except ValueError:
        acc = [c for c in cells if "acc" in c.lower()]
        gyro = [c for c in cells if "gyr" in c.lower()]
        columns = ["--time-col", cells[0], "--acc-cols",
                   ",".join(acc if len(acc) == 3 else cells[1:4])]
        columns += ["--gyro-cols", ",".join(gyro)] if len(gyro) == 3 else []
    command = shlex.join(["pdr-sim", "import-csv", str(file), "--out", f"{file.stem}_bag",
                          *columns])
    return (f"a CSV log, not a bag (rosbag2 MCAP): import it first, e.g. `{command}` (units "
            "with --time-unit, --acc-unit, --gyro-unit; see pdr-sim import-csv --help)")


class BagReader:
    """Read-only view of a bag directory or a bare ``.mcap`` file.

    Raises :class:`InputError` (naming the path) for a missing or unreadable bag and for
    unknown topics. A bag cut short is recovered (module docstring), or refused with
    ``strict``.
    """

    def __init__(self, path: str | Path, *, strict: bool = False) -> None:
        self.path = Path(path)
        self.strict = strict
        if not self.path.exists():
            raise InputError(self.path, "no such bag")
        self.files, self.topics = self._files()
        for file in self.files:
            with file.open("rb") as stream:
                if stream.read(len(MCAP_MAGIC)) != MCAP_MAGIC:
                    raise InputError(file, not_a_bag(file))
        listed = bool(self.topics)          # from metadata.yaml
        self.damaged: dict[Path, Extent] = {}
        for file in self.files:
            indexed = _summary_topics(file)
            if indexed is not None:
                self.topics |= {} if listed else indexed
                continue
            extent = self.damaged[file] = readable_extent(file)
            if strict:
                raise InputError(file, f"{extent.describe()}; refused (--strict; "
                                       "`pdr-sim repair` rebuilds its index)")
            warnings.warn(InputWarning(file, f"{extent.describe()}: those are used, the rest "
                                             "is lost"), stacklevel=2)
            self.topics |= {} if listed else extent.topics

    def _files(self) -> tuple[list[Path], dict[str, str]]:
        """The MCAP files and the topics of metadata.yaml; a directory without it (a
        recorder killed before writing it) is recovered from its MCAP files."""
        if not self.path.is_dir():
            return [self.path], {}
        if (self.path / "metadata.yaml").is_file() or not list(self.path.glob("*.mcap")):
            return _bag_files(self.path)
        if self.strict:
            raise InputError(self.path, "no metadata.yaml; refused (--strict; `pdr-sim "
                                        "repair` rebuilds it)")
        warnings.warn(InputWarning(self.path, "no metadata.yaml: reading its MCAP files "
                                              "(`pdr-sim repair` rebuilds it)"), stacklevel=3)
        return sorted(self.path.glob("*.mcap")), {}

    @property
    def custom_texts(self) -> dict[str, str]:
        """``custom_data`` of metadata.yaml as stored (key -> text); {} when none."""
        meta_path = self.path / "metadata.yaml"
        if not meta_path.is_file():
            return {}
        info = yaml.safe_load(meta_path.read_text())["rosbag2_bagfile_information"]
        return info.get("custom_data") or {}

    def custom_data(self, key: str) -> Any:
        """The YAML document stored under ``custom_data[key]`` of metadata.yaml (e.g.
        ``pdr.simulation``: a simulated run's configuration and truth), parsed; None when
        the bag has none."""
        text = self.custom_texts.get(key)
        return None if text is None else yaml.safe_load(text)

    def require_topics(self, topics: Iterable[str]) -> None:
        """Raise InputError if any of ``topics`` is not in the bag."""
        missing = sorted(set(topics) - set(self.topics))
        if missing:
            have = ", ".join(sorted(self.topics)) or "none"
            raise InputError(self.path, f"no topic {', '.join(missing)} (the bag has: {have})")

    def raw_messages(self, topics: Iterable[str] | None = None) -> Iterator[RawMessage]:
        """Every message on ``topics`` (all if None) in log-time order.

        A damaged file yields all messages before the damage, then raises InputError.
        """
        wanted = list(self.topics) if topics is None else list(topics)
        self.require_topics(wanted)
        if self.path.is_dir() and not self.damaged and (self.path / "metadata.yaml").is_file():
            yielded = 0
            try:
                for message in self._indexed_messages(wanted):
                    yield message
                    yielded += 1
                return
            except _READ_ERRORS as exc:
                if yielded:
                    raise InputError(self.path, f"corrupt MCAP after {yielded} messages "
                                                f"({exc!r})") from exc
        streams = [self._file_messages(file, wanted) for file in self.files]
        yield from heapq.merge(*streams, key=lambda m: m.log_time_ns)

    def _indexed_messages(self, topics: list[str]) -> Iterator[RawMessage]:
        """Fast path for intact bags: rosbags' indexed reader (about 4x the ``mcap``
        library's rate); raises on any damage, and :meth:`raw_messages` falls back to the
        streaming reader when nothing was read yet."""
        with Reader(self.path) as reader:
            connections = [c for c in reader.connections if c.topic in topics]
            for connection, timestamp, data in reader.messages(connections=connections):
                yield RawMessage(connection.topic, connection.msgtype, timestamp, data)

    def _file_messages(self, file: Path, topics: list[str]) -> Iterator[RawMessage]:
        """``file``'s messages on ``topics``: of a file cut short, those before the damage
        (the reader warned); damage inside an intact file is an InputError."""
        count = good = 0
        with file.open("rb") as stream:
            try:
                if file in self.damaged:
                    reader: Any = NonSeekingReader(stream, validate_crcs=True)
                    messages = reader.iter_messages(topics=topics, log_time_order=False)
                else:
                    reader = SeekingReader(stream, validate_crcs=True)
                    messages = reader.iter_messages(topics=topics, log_time_order=True)
                for schema, channel, message in messages:
                    yield RawMessage(channel.topic, schema.name, message.log_time, message.data)
                    count += 1
                    good = stream.tell()
            except _READ_ERRORS as exc:
                if file in self.damaged:        # its readable part, as warned
                    return
                raise InputError(file, f"corrupt MCAP at byte {good} after {count} messages "
                                       f"({exc!r})") from exc

    def read(self, topic: str) -> MessageBatch:
        """All messages of a fixed-layout topic (Imu, PoseStamped, ...) as one batch."""
        return self.read_batches([topic])[topic]

    def read_batches(self, topics: Iterable[str]) -> dict[str, MessageBatch]:
        """Fixed-layout ``topics`` as batches: through the MCAP indexes with NumPy
        (:func:`pdr_core.io.mcap_bulk.chunk_rows`) when the bag is intact and every message of
        a topic has one size, else message by message in one pass over the files."""
        wanted = list(topics)
        self.require_topics(wanted)
        if self.path.is_dir() and not self.damaged:
            try:
                return self._indexed_batches(wanted)
            except _READ_ERRORS:
                pass
        return self._scanned_batches(wanted)

    def _indexed_batches(self, wanted: list[str]) -> dict[str, MessageBatch]:
        """``wanted`` through the MCAP indexes, each file's summary read and each chunk
        decompressed once for all of them, each topic decoded once from the rows of every
        chunk; raises a read error (and :meth:`read_batches` falls back) on anything
        unusual."""
        times: dict[str, list[np.ndarray]] = {t: [] for t in wanted}
        blocks: dict[str, list[np.ndarray]] = {t: [] for t in wanted}
        for file in self.files:
            with file.open("rb") as stream:
                summary = SeekingReader(stream).get_summary()
                if summary is None:
                    raise McapError("no summary section")
                topic_of = {channel.id: channel.topic for channel in summary.channels.values()
                            if channel.topic in times}
                for channel, t, rows in mcap_bulk.chunk_rows(stream, summary, list(topic_of)):
                    topic = topic_of[channel]
                    times[topic].append(t)
                    blocks[topic].append(rows)
        return {topic: self._in_time_order(topic, times[topic], blocks[topic])
                for topic in wanted}

    def _in_time_order(self, topic: str, times: list[np.ndarray], blocks: list[np.ndarray]
                       ) -> MessageBatch:
        """One topic's messages from the rows of several chunks, files and channels,
        decoded in log-time order (ties in file order)."""
        try:
            batch = cdr.decode_rows(self.topics[topic], blocks)
        except ValueError as exc:
            raise InputError(self.path, f"topic {topic}: {exc}") from exc
        if not blocks:
            return batch
        log_time = np.concatenate(times)
        if np.all(np.diff(log_time) >= 0):
            return batch
        return batch.take(np.argsort(log_time, kind="stable"))

    def _scanned_batches(self, wanted: list[str]) -> dict[str, MessageBatch]:
        raws: dict[str, list[bytes]] = {t: [] for t in wanted}
        for message in self.raw_messages(wanted):
            raws[message.topic].append(message.data)
        out = {}
        for topic in wanted:
            try:
                out[topic] = cdr.decode(self.topics[topic], raws[topic])
            except ValueError as exc:
                raise InputError(self.path, f"topic {topic}: {exc}") from exc
        return out

    def read_messages(self, topic: str) -> list[tuple[int, Any]]:
        """All messages of any topic as (log time [ns], rosbags message object)."""
        msgtype = self._msgtype(topic)
        return [(m.log_time_ns, cdr.decode_generic(msgtype, m.data))
                for m in self.raw_messages([topic])]

    def _msgtype(self, topic: str) -> str:
        self.require_topics([topic])
        return self.topics[topic]


class BagWriter:
    """Writes a rosbag2 bag with MCAP storage, atomically.

    Use as a context manager (or :meth:`open` / :meth:`close`). Messages go to a hidden
    directory beside ``path``; on a clean exit it is renamed to ``path``, on an exception
    it is deleted.
    ``custom_data`` (str -> str) lands in ``metadata.yaml``.
    """

    def __init__(self, path: str | Path, *, overwrite: bool = False,
                 custom_data: dict[str, str] | None = None, compress: bool = False) -> None:
        self.path = Path(path)
        self.compress = compress
        if self.path.exists() and not overwrite:
            raise InputError(self.path, "output exists already (remove it or pass --overwrite)")
        self.custom_data = custom_data or {}
        self._tmp: Path | None = None
        self._writer: Writer | None = None
        self._connections: dict[str, Any] = {}

    def open(self) -> BagWriter:
        """Start writing into the hidden temporary directory."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._tmp = Path(tempfile.mkdtemp(prefix=f".{self.path.name}.", dir=self.path.parent))
        self._writer = Writer(self._tmp / self.path.name, version=9,
                              storage_plugin=StoragePlugin.MCAP)
        for key, value in self.custom_data.items():
            self._writer.set_custom_data(key, value)
        if self.compress:
            self._writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
        self._writer.open()
        return self

    def close(self, *, commit: bool = True) -> None:
        """Finish the bag and move it to ``path`` (``commit``), or discard it."""
        assert self._tmp is not None and self._writer is not None, "BagWriter not open"
        try:
            if commit:
                self._writer.close()
                if self.path.exists():
                    shutil.rmtree(self.path)
                (self._tmp / self.path.name).rename(self.path)
        finally:
            shutil.rmtree(self._tmp, ignore_errors=True)
            self._tmp = self._writer = None

    def __enter__(self) -> BagWriter:
        return self.open()

    def __exit__(self, exc_type: Any, exc: Any, tb: Any) -> None:
        self.close(commit=exc_type is None)

    @property
    def staging(self) -> Path:
        """The bag directory being written; files put there move with it to ``path``."""
        assert self._tmp is not None, "BagWriter not open"
        return self._tmp / self.path.name

    def add_topic(self, topic: str, msgtype: str) -> None:
        """Declare ``topic`` of type ``msgtype`` (idempotent)."""
        if topic not in self._connections:
            assert self._writer is not None, "BagWriter not open"
            self._connections[topic] = self._writer.add_connection(
                topic, msgtype, typestore=typestore())

    def write_raw(self, topic: str, msgtype: str, log_time_ns: int, data: bytes) -> None:
        """Append one serialized message."""
        self.add_topic(topic, msgtype)
        self._writer.write(self._connections[topic], int(log_time_ns), data)

    def write_merged(self, batches: dict[str, MessageBatch | LazyBatch]) -> None:
        """Append fixed-layout ``batches`` (topic -> batch, logged at their stamps) merged
        in log-time order, as :func:`merged_messages` would. Batches with one frame_id and
        sorted stamps go through :mod:`pdr_core.io.mcap_bulk` (vectorised, the same bytes,
        encoded block by block); others message by message."""
        for topic, batch in batches.items():
            self.add_topic(topic, batch.msgtype)
        bulk = all(bool(np.all(b.frame_id == b.frame_id[:1]))
                   and bool(np.all(np.diff(b.stamp_ns) >= 0)) for b in batches.values())
        if not bulk:
            whole = {t: b.take(slice(None)) for t, b in batches.items()}
            for message in merged_messages(whole):
                self.write_raw(message.topic, message.msgtype, message.log_time_ns,
                               message.data)
            return
        full = {t: b for t, b in batches.items() if len(b)}
        encoders = [functools.partial(_encode_slice, b, str(b.frame_id[0]))
                    for b in full.values()]
        mcap_bulk.append(self._writer, [self._connections[t] for t in full],
                         [b.stamp_ns for b in full.values()], encoders,
                         [encode(slice(0, 1)).shape[1] for encode in encoders])


def _encode_slice(batch: MessageBatch | LazyBatch, frame: str, index: slice) -> np.ndarray:
    return cdr.encode_rows(batch.take(index), frame)


def merged_messages(batches: dict[str, MessageBatch],
                    generic: dict[str, tuple[str, list[tuple[int, Any]]]] | None = None
                    ) -> Iterator[RawMessage]:
    """Serialized messages of ``batches`` (topic -> fixed-layout batch, logged at their
    stamps) and ``generic`` (topic -> (msgtype, [(log time ns, rosbags message)])), merged
    in log-time order."""
    streams = [_batch_messages(topic, batch) for topic, batch in batches.items()]
    streams += [_generic_messages(topic, msgtype, items)
                for topic, (msgtype, items) in (generic or {}).items()]
    return heapq.merge(*streams, key=lambda m: m.log_time_ns)


def _batch_messages(topic: str, batch: MessageBatch) -> Iterator[RawMessage]:
    for t, data in zip(batch.stamp_ns.tolist(), cdr.encode(batch), strict=True):
        yield RawMessage(topic, batch.msgtype, t, data)


def _generic_messages(topic: str, msgtype: str, items: list[tuple[int, Any]]
                      ) -> Iterator[RawMessage]:
    for t, msg in items:
        yield RawMessage(topic, msgtype, t, cdr.encode_generic(msg))


def repair(source: str | Path, out: str | Path, *, overwrite: bool = False) -> dict[str, int]:
    """``ros2 bag reindex``'s equivalent: every readable message of ``source`` (a bag cut
    short, without its index or its metadata.yaml) written to a new bag ``out`` with its
    summary, index and metadata.yaml (``source`` is never touched); its custom_data is
    kept. An existing ``out`` is refused unless ``overwrite``. Returns the message count
    per topic."""
    reader = BagReader(source)
    counts = dict.fromkeys(reader.topics, 0)
    with BagWriter(out, overwrite=overwrite, custom_data=reader.custom_texts) as writer:
        for topic, msgtype in reader.topics.items():
            writer.add_topic(topic, msgtype)
        for message in reader.raw_messages():
            writer.write_raw(message.topic, message.msgtype, message.log_time_ns, message.data)
            counts[message.topic] += 1
    return counts


def add_strict_option(parser: Any) -> None:
    """``--strict`` of the CLIs that read a bag: refuse one cut short instead of using the
    part before the damage."""
    parser.add_argument("--strict", action="store_true",
                        help="refuse a bag cut short or without its index instead of using "
                             "its readable part (with a warning)")


def write_batches(path: str | Path, batches: dict[str, MessageBatch],
                  generic: dict[str, tuple[str, list[tuple[int, Any]]]] | None = None,
                  *, overwrite: bool = False, custom_data: dict[str, str] | None = None,
                  compress: bool = False) -> None:
    """Write a bag of :func:`merged_messages` (so that streaming readers replay the topics
    interleaved as recorded). ``compress`` zstd-compresses the MCAP chunks."""
    with BagWriter(path, overwrite=overwrite, custom_data=custom_data,
                   compress=compress) as writer:
        if not generic:
            writer.write_merged(batches)
            return
        for topic, batch in batches.items():
            writer.add_topic(topic, batch.msgtype)
        for topic, (msgtype, _) in generic.items():
            writer.add_topic(topic, msgtype)
        for message in merged_messages(batches, generic):
            writer.write_raw(message.topic, message.msgtype, message.log_time_ns, message.data)
