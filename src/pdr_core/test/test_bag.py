"""Bag writing and reading: round trips, other readers, and damaged input."""
import heapq

import numpy as np
import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st
from mcap.reader import SeekingReader, make_reader
from rosbags.highlevel import AnyReader

from pdr_core.errors import InputError, InputWarning
from pdr_core.io import cdr, mcap_bulk
from pdr_core.io.bag import BagReader, BagWriter, merged_messages, readable_extent, write_batches
from pdr_core.io.batch import LazyBatch
from pdr_core.io.msgtypes import PATH, typestore
from pdr_core.io.nav_path import last_path, path_message, path_poses


def assert_same(a, b):
    np.testing.assert_array_equal(a.stamp_ns, b.stamp_ns)
    np.testing.assert_array_equal(a.frame_id, b.frame_id)
    assert a.fields.keys() == b.fields.keys()
    for name in a.fields:
        np.testing.assert_array_equal(a[name], b[name])


def test_roundtrip_two_topics_in_time_order(tmp_path, imu, pose):
    out = tmp_path / "bag"
    write_batches(out, {"/imu/data": imu, "/ground_truth/pose": pose})
    reader = BagReader(out)
    assert reader.topics == {"/imu/data": "sensor_msgs/msg/Imu",
                             "/ground_truth/pose": "geometry_msgs/msg/PoseStamped"}
    back = reader.read_batches(["/imu/data", "/ground_truth/pose"])
    assert_same(back["/imu/data"], imu)
    assert_same(back["/ground_truth/pose"], pose)
    times = [m.log_time_ns for m in reader.raw_messages()]
    assert times == sorted(times) and len(times) == 1000


def test_bag_opens_with_rosbags_and_mcap_and_has_valid_metadata(tmp_path, imu):
    out = tmp_path / "bag"
    write_batches(out, {"/imu/data": imu}, custom_data={"pdr.scenario": "x"})
    info = yaml.safe_load((out / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    assert info["storage_identifier"] == "mcap"
    assert info["message_count"] == 500
    assert info["custom_data"] == {"pdr.scenario": "x"}
    with AnyReader([out], default_typestore=typestore()) as reader:
        msgs = [reader.deserialize(raw, c.msgtype) for c, _, raw in reader.messages()]
    assert len(msgs) == 500
    np.testing.assert_array_equal(msgs[7].linear_acceleration.z, imu["linear_acceleration"][7, 2])
    with (out / "bag.mcap").open("rb") as stream:
        mcap_reader = make_reader(stream)
        summary = mcap_reader.get_summary()
        assert summary.statistics.message_count == 500
        schema = next(iter(summary.schemas.values()))
        assert schema.name == "sensor_msgs/msg/Imu" and schema.encoding == "ros2msg"


def test_path_roundtrip(tmp_path, pose):
    msg = path_message(pose, int(pose.stamp_ns[-1]), "map")
    out = tmp_path / "bag"
    write_batches(out, {}, {"/pdr/foot/path": (PATH, [(int(pose.stamp_ns[-1]), msg)])})
    [(t, back)] = BagReader(out).read_messages("/pdr/foot/path")
    assert t == pose.stamp_ns[-1]
    assert_same(path_poses(back), pose)


def test_last_path_is_the_latest_of_the_topic(tmp_path, pose):
    """pocket_pdr publishes its path again after a correction: the last one is read."""
    end = int(pose.stamp_ns[-1])
    first = path_message(pose.take(slice(0, 10)), end - 1, "map")
    last = path_message(pose, end, "map")
    write_batches(tmp_path / "bag", {}, {"/pdr/foot/path": (PATH, [(end - 1, first),
                                                                   (end, last)])})
    assert_same(last_path(BagReader(tmp_path / "bag"), "/pdr/foot/path"), pose)


def test_missing_bag(tmp_path):
    with pytest.raises(InputError, match="no such bag") as err:
        BagReader(tmp_path / "nope")
    assert str(tmp_path / "nope") in str(err.value)


def test_directory_without_metadata(tmp_path):
    with pytest.raises(InputError, match=r"no metadata\.yaml"):
        BagReader(tmp_path)


def test_corrupt_metadata(tmp_path, imu):
    write_batches(tmp_path / "bag", {"/imu/data": imu})
    (tmp_path / "bag" / "metadata.yaml").write_text("rosbag2_bagfile_information: [1, 2")
    with pytest.raises(InputError, match=r"corrupt metadata\.yaml"):
        BagReader(tmp_path / "bag")


def test_not_an_mcap_file(tmp_path, imu):
    write_batches(tmp_path / "bag", {"/imu/data": imu})
    (tmp_path / "bag" / "bag.mcap").write_bytes(b"SQLite format 3\0" + b"x" * 100)
    with pytest.raises(InputError, match="not an MCAP file"):
        BagReader(tmp_path / "bag")


def test_unknown_topic_names_the_topics_present(tmp_path, imu):
    write_batches(tmp_path / "bag", {"/imu/data": imu})
    with pytest.raises(InputError, match=r"no topic /imu/mag \(the bag has: /imu/data\)"):
        BagReader(tmp_path / "bag").read("/imu/mag")


def test_truncated_bag_is_recovered_with_a_warning_or_refused_when_strict(tmp_path, make_imu):
    """Issue 19: a bag cut short yields every message of its complete chunks and warns
    where it stopped; ``strict`` refuses it, naming the file and the offset."""
    big = make_imu(12000)
    write_batches(tmp_path / "bag", {"/imu/data": big})
    mcap = tmp_path / "bag" / "bag.mcap"
    data = mcap.read_bytes()
    mcap.write_bytes(data[: int(len(data) * 0.7)])
    with pytest.warns(InputWarning, match="messages: those are used, the rest is lost") as caught:
        reader = BagReader(tmp_path / "bag")
    assert str(mcap) in str(caught[0].message)
    got = list(reader.raw_messages(["/imu/data"]))
    # Damage costs at most the chunk it falls in (rosbags writes 1 MiB chunks).
    per_chunk = 2**20 // len(got[0].data) + 1
    assert 12000 * 0.7 - per_chunk <= len(got) < 12000 * 0.7
    stamps = [m.log_time_ns for m in got]
    np.testing.assert_array_equal(stamps, big.stamp_ns[: len(got)])
    np.testing.assert_array_equal(reader.read("/imu/data").stamp_ns, stamps)
    extent = readable_extent(mcap)
    with pytest.raises(InputError, match=rf"readable to byte {extent.good_bytes} of "
                                         rf"{len(data) * 7 // 10}") as err:
        BagReader(tmp_path / "bag", strict=True)
    assert str(mcap) in str(err.value) and "--strict" in str(err.value)
    assert extent.messages == len(got)


def test_a_directory_without_metadata_is_read_from_its_mcap_files(tmp_path, imu):
    write_batches(tmp_path / "bag", {"/imu/data": imu})
    (tmp_path / "bag" / "metadata.yaml").unlink()
    with pytest.warns(InputWarning, match="no metadata.yaml"):
        reader = BagReader(tmp_path / "bag")
    np.testing.assert_array_equal(reader.read("/imu/data").stamp_ns, imu.stamp_ns)
    with pytest.raises(InputError, match=r"no metadata\.yaml; refused"):
        BagReader(tmp_path / "bag", strict=True)


def test_failed_write_leaves_no_output(tmp_path, imu):
    out = tmp_path / "bag"
    with pytest.raises(RuntimeError), BagWriter(out) as writer:
        writer.add_topic("/imu/data", imu.msgtype)
        raise RuntimeError("interrupted")
    assert list(tmp_path.iterdir()) == []


def test_existing_output_is_refused(tmp_path, imu):
    write_batches(tmp_path / "bag", {"/imu/data": imu})
    with pytest.raises(InputError, match="exists already"):
        write_batches(tmp_path / "bag", {"/imu/data": imu})
    write_batches(tmp_path / "bag", {"/imu/data": imu.take(slice(0, 10))}, overwrite=True)
    assert len(BagReader(tmp_path / "bag").read("/imu/data")) == 10


@pytest.mark.parametrize("compress", [False, True])
def test_vectorised_write_is_byte_identical_to_message_by_message(tmp_path, make_imu,
                                                                  make_pose, compress):
    """pdr_core.io.mcap_bulk builds the MCAP records with NumPy; the bag must be the one
    rosbags writes message by message: several chunks, equal stamps across topics
    (merged stream by stream), an empty topic, and zstd chunks."""
    imu, pose = make_imu(9000), make_pose(4000, rate_hz=90.0)
    pose.stamp_ns[:2000] = imu.stamp_ns[:4000:2]  # ties with imu/data
    pose.stamp_ns[2000:] = np.sort(pose.stamp_ns[2000:]) + 10**10
    batches = {"/imu/data": imu, "/ground_truth/pose": pose,
               "/empty": imu.take(slice(0, 0))}
    write_batches(tmp_path / "bulk" / "bag", batches, compress=compress)
    with BagWriter(tmp_path / "slow" / "bag", compress=compress) as writer:
        for topic, batch in batches.items():
            writer.add_topic(topic, batch.msgtype)
        for m in merged_messages(batches):
            writer.write_raw(m.topic, m.msgtype, m.log_time_ns, m.data)
    bulk = (tmp_path / "bulk" / "bag" / "bag.mcap").read_bytes()
    assert bulk == (tmp_path / "slow" / "bag" / "bag.mcap").read_bytes()
    with (tmp_path / "bulk" / "bag" / "bag.mcap").open("rb") as stream:
        chunk_indexes = make_reader(stream).get_summary().chunk_indexes
    # several chunks (4 measured, compressed or not), zstd when compressed
    assert len(chunk_indexes) > 1, "several chunks"
    assert {c.compression for c in chunk_indexes} == {"zstd" if compress else ""}
    assert ((tmp_path / "bulk" / "bag" / "metadata.yaml").read_text()
            == (tmp_path / "slow" / "bag" / "metadata.yaml").read_text())
    assert_same(BagReader(tmp_path / "bulk" / "bag").read("/ground_truth/pose"), pose)


@pytest.mark.parametrize("compress", [False, True])
def test_indexed_read_equals_the_message_by_message_read(tmp_path, make_imu, compress):
    """read_batches gathers fixed-size messages through the MCAP indexes; it must give
    what reading message by message gives, across chunks, and fall back to that when a
    topic's messages differ in size (two frame ids)."""
    imu = make_imu(9000)
    mixed = make_imu(300)
    mixed.frame_id = np.where(np.arange(300) % 2, "imu_link", "a_longer_frame_id")
    write_batches(tmp_path / "bag", {"/imu/data": imu, "/mixed": mixed}, compress=compress)
    reader = BagReader(tmp_path / "bag")
    with (tmp_path / "bag" / "bag.mcap").open("rb") as stream:
        summary = SeekingReader(stream).get_summary()
        channel = next(c.id for c in summary.channels.values() if c.topic == "/imu/data")
        chunks = list(mcap_bulk.chunk_rows(stream, summary, [channel]))
        assert len(chunks) > 1  # several chunks: 4 measured, compressed or not
        assert {c for c, _, _ in chunks} == {channel}
        np.testing.assert_array_equal(np.concatenate([t for _, t, _ in chunks]), imu.stamp_ns)
        np.testing.assert_array_equal(np.concatenate([r for _, _, r in chunks]),
                                      cdr.encode_rows(imu, "imu_link"))
        mixed_channel = next(c.id for c in summary.channels.values() if c.topic == "/mixed")
        with pytest.raises(ValueError, match="different sizes"):
            list(mcap_bulk.chunk_rows(stream, summary, [mixed_channel]))
    assert_same(reader.read("/imu/data"), reader._scanned_batches(["/imu/data"])["/imu/data"])
    assert_same(reader.read("/imu/data"), imu)
    assert_same(reader.read("/mixed"), mixed)


@given(st.lists(st.lists(st.integers(0, 20), max_size=12), min_size=1, max_size=4),
       st.integers(1, 4), st.booleans())
def test_merged_order_is_the_order_of_heapq_merge(streams, copies, shared):
    """Ties between streams go stream by stream, ties within one stream keep it first;
    streams sharing one time base (with or without repeated stamps) take the fast path."""
    stamps = [np.sort(np.array(s, np.int64)) for s in streams]
    if shared:
        stamps = [stamps[0]] * copies
    merged = heapq.merge(*[[(t, i, k) for k, t in enumerate(s.tolist())]
                           for i, s in enumerate(stamps)], key=lambda m: m[0])
    expected = [(i, k) for _, i, k in merged]
    stream, index = mcap_bulk.merged_order(stamps)
    assert list(zip(stream.tolist(), index.tolist(), strict=True)) == expected


def test_lazy_batches_write_what_their_built_batches_write(tmp_path, make_pose):
    """A LazyBatch is encoded block by block, never whole; the bag is the one its
    MessageBatch gives, here three topics on one time base (the filter's outputs)."""
    pose = make_pose(9000)
    lazy = LazyBatch(pose.msgtype, pose.stamp_ns, pose.frame_id[0],
                     lambda index: {k: v[index] for k, v in pose.fields.items()})
    names = ("/a", "/b", "/c")
    write_batches(tmp_path / "lazy" / "bag", dict.fromkeys(names, lazy))
    write_batches(tmp_path / "whole" / "bag", dict.fromkeys(names, pose))
    assert ((tmp_path / "lazy" / "bag" / "bag.mcap").read_bytes()
            == (tmp_path / "whole" / "bag" / "bag.mcap").read_bytes())
    for name in names:
        assert_same(BagReader(tmp_path / "lazy" / "bag").read(name), pose)
