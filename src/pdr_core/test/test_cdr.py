"""The vectorised CDR codec against rosbags' reference serializer."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core.io import cdr
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import typestore

FIXED_TYPES = [
    "sensor_msgs/msg/Imu", "sensor_msgs/msg/MagneticField", "geometry_msgs/msg/PoseStamped",
    "geometry_msgs/msg/PoseWithCovarianceStamped", "geometry_msgs/msg/TwistWithCovarianceStamped",
    "geometry_msgs/msg/Vector3Stamped", "pdr_msgs/msg/Stance", "pdr_msgs/msg/Step",
    "pdr_msgs/msg/Landmark", "pdr_msgs/msg/DriftEstimate",
]


def random_batch(msgtype: str, n: int, rng: np.random.Generator, frames: list[str]) -> MessageBatch:
    fields = {}
    for leaf in cdr.fixed_layout(msgtype):
        shape = (n,) if leaf.count == 1 else (n, leaf.count)
        if leaf.dtype.kind == "f":
            values = rng.normal(size=shape) * 10.0 ** rng.integers(-6, 6, size=shape)
        elif leaf.dtype.kind == "b":
            values = rng.integers(0, 2, size=shape).astype(bool)
        else:
            info = np.iinfo(leaf.dtype)
            values = rng.integers(info.min, info.max, size=shape, dtype=leaf.dtype, endpoint=True)
        fields[leaf.path] = values.astype(leaf.dtype)
    stamps = rng.integers(-(2**31) * 10**9, (2**31 - 1) * 10**9, size=n)
    return MessageBatch(msgtype, stamps, rng.choice(frames, size=n), fields)


def reference_bytes(batch: MessageBatch, i: int) -> bytes:
    """One message built field by field with rosbags objects and serialized by rosbags."""
    store = typestore()
    types = store.types

    def build(msgtype: str, prefix: str):
        _, fields = store.fielddefs[msgtype]
        kwargs = {}
        for name, (kind, detail) in fields:
            path = f"{prefix}{name}"
            if name == "header" and not prefix:
                sec, nanosec = divmod(int(batch.stamp_ns[i]), 10**9)
                kwargs[name] = types["std_msgs/msg/Header"](
                    stamp=types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec),
                    frame_id=str(batch.frame_id[i]))
            elif path in batch.fields and kind == 2:
                sub_names = [f for f, _ in store.fielddefs[detail][1]]
                kwargs[name] = types[detail](**dict(zip(sub_names, batch.fields[path][i].tolist(),
                                                        strict=True)))
            elif path in batch.fields:
                value = batch.fields[path][i]
                kwargs[name] = value.copy() if kind == 3 else value.item()
            else:
                kwargs[name] = build(detail, f"{path}.")
        return types[msgtype](**kwargs)

    return bytes(store.serialize_cdr(build(batch.msgtype, ""), batch.msgtype))


@pytest.mark.parametrize("msgtype", FIXED_TYPES)
def test_encode_matches_rosbags_byte_for_byte(msgtype):
    rng = np.random.default_rng(1)
    batch = random_batch(msgtype, 20, rng, ["", "imu_link", "map", "a_much_longer_frame_name"])
    encoded = cdr.encode(batch)
    for i in range(len(batch)):
        assert encoded[i] == reference_bytes(batch, i)


@pytest.mark.parametrize("msgtype", FIXED_TYPES)
def test_decode_inverts_encode(msgtype):
    rng = np.random.default_rng(2)
    batch = random_batch(msgtype, 50, rng, ["x", "imu_link", "frame_7"])
    back = cdr.decode(msgtype, cdr.encode(batch))
    np.testing.assert_array_equal(back.stamp_ns, batch.stamp_ns)
    np.testing.assert_array_equal(back.frame_id, batch.frame_id)
    for name, values in batch.fields.items():
        np.testing.assert_array_equal(back[name], values)


@settings(max_examples=40, deadline=None)
@given(frames=st.lists(st.text(alphabet="abcdefghij_/0123456789", max_size=23), min_size=1,
                       max_size=4),
       n=st.integers(1, 30), seed=st.integers(0, 2**32 - 1))
def test_roundtrip_any_frame_lengths(frames, n, seed):
    rng = np.random.default_rng(seed)
    batch = random_batch("sensor_msgs/msg/Imu", n, rng, frames)
    back = cdr.decode(batch.msgtype, cdr.encode(batch))
    np.testing.assert_array_equal(back.frame_id, batch.frame_id)
    np.testing.assert_array_equal(back["linear_acceleration"], batch["linear_acceleration"])
    np.testing.assert_array_equal(back.stamp_ns, batch.stamp_ns)


def test_decode_reads_rosbags_messages_with_trailing_padding():
    """DDS pads payloads to 4 bytes; the decoder must accept longer messages."""
    rng = np.random.default_rng(3)
    batch = random_batch("pdr_msgs/msg/Stance", 5, rng, ["imu_link"])
    raws = [r + b"\0" * (-len(r) % 4) for r in cdr.encode(batch)]
    back = cdr.decode(batch.msgtype, raws)
    np.testing.assert_array_equal(back["statistic"], batch["statistic"])


def test_layout_names_and_shapes_of_imu():
    leaves = {leaf.path: leaf.count for leaf in cdr.fixed_layout("sensor_msgs/msg/Imu")}
    assert leaves == {"orientation": 4, "orientation_covariance": 9, "angular_velocity": 3,
                      "angular_velocity_covariance": 9, "linear_acceleration": 3,
                      "linear_acceleration_covariance": 9}
    assert cdr.fixed_layout("nav_msgs/msg/Path") is None


def test_truncated_message_is_refused():
    batch = random_batch("sensor_msgs/msg/Imu", 2, np.random.default_rng(4), ["imu_link"])
    raws = cdr.encode(batch)
    with pytest.raises(ValueError, match="bytes"):
        cdr.decode(batch.msgtype, [raws[0], raws[1][:-8]])


def test_a_step_of_an_older_bag_reads_its_appended_fields_as_zero():
    """pdr_msgs/Step gained ``ride`` and ``ride_height`` (issue 41,
    pdr_core.io.msgtypes.APPENDED_FIELDS): a message written before, without them, reads
    them as 0 and the rest as written; one cut shorter still is refused."""
    batch = random_batch("pdr_msgs/msg/Step", 4, np.random.default_rng(5), ["map"])
    older = cdr._record_dtype(batch.msgtype, len("map"), older=True).itemsize
    raws = [r[:older] for r in cdr.encode(batch)]
    back = cdr.decode(batch.msgtype, raws)
    np.testing.assert_array_equal(back["ride"], 0)
    np.testing.assert_array_equal(back["ride_height"], 0.0)
    np.testing.assert_array_equal(back["heading"], batch["heading"])
    np.testing.assert_array_equal(back["activity"], batch["activity"])
    with pytest.raises(ValueError, match="bytes"):
        cdr.decode(batch.msgtype, [r[:older - 8] for r in raws])


def test_frame_id_longer_than_the_message_is_refused():
    batch = random_batch("sensor_msgs/msg/Imu", 1, np.random.default_rng(6), ["imu_link"])
    raw = cdr.encode(batch)[0]
    garbage = raw[:12] + (len(raw)).to_bytes(4, "little") + raw[16:]
    with pytest.raises(ValueError, match="frame_id longer than its message"):
        cdr.decode(batch.msgtype, [garbage])


def test_big_endian_is_refused():
    batch = random_batch("sensor_msgs/msg/Imu", 1, np.random.default_rng(5), ["imu_link"])
    raw = cdr.encode(batch)[0]
    with pytest.raises(ValueError, match="little-endian"):
        cdr.decode(batch.msgtype, [b"\x00\x00" + raw[2:]])


@given(path_frame=st.text(alphabet="abcdefghij_/0123456789", max_size=23),
       pose_frames=st.lists(st.text(alphabet="abcdefghij_/0123456789", max_size=23),
                            min_size=1, max_size=2),
       n=st.integers(0, 6), seed=st.integers(0, 2**32 - 1))
@settings(max_examples=80, deadline=None)
def test_encode_path_matches_rosbags_byte_for_byte(path_frame, pose_frames, n, seed):
    """Both paddings of the first pose (frame lengths of either parity), one or several
    pose frames (the generic fallback) and the empty path."""
    from pdr_core.io.nav_path import encode_path, path_message
    rng = np.random.default_rng(seed)
    poses = random_batch("geometry_msgs/msg/PoseStamped", n, rng, pose_frames)
    stamp = int(rng.integers(0, (2**31 - 1) * 10**9))
    assert encode_path(poses, stamp, path_frame) == cdr.encode_generic(
        path_message(poses, stamp, path_frame))


@pytest.mark.parametrize(("frame", "child"), [("map", "base_link"), ("", "x"),
                                              ("alice_map", "alice/base_link_7")])
def test_odometry_and_tf_encode_as_rosbags_does(frame, child):
    """Odometry (a string after the header) and a TFMessage of one transform, vectorised,
    byte for byte as rosbags serializes them, for frames of every alignment."""
    rng = np.random.default_rng(4)
    n = 7
    stamps = rng.integers(0, 2**31 * 10**9, n)
    odometry = MessageBatch("nav_msgs/msg/Odometry", stamps, frame, {
        "child_frame_id": np.full(n, child), "pose.pose.position": rng.normal(size=(n, 3)),
        "pose.pose.orientation": rng.normal(size=(n, 4)),
        "pose.covariance": rng.normal(size=(n, 36)), "twist.twist.linear": rng.normal(size=(n, 3)),
        "twist.twist.angular": rng.normal(size=(n, 3)),
        "twist.covariance": rng.normal(size=(n, 36))})
    tf = MessageBatch("tf2_msgs/msg/TFMessage", stamps, frame, {
        "transforms.child_frame_id": np.full(n, child),
        "transforms.transform.translation": rng.normal(size=(n, 3)),
        "transforms.transform.rotation": rng.normal(size=(n, 4))})
    types = typestore().types
    for i, (odo, tfm) in enumerate(zip(cdr.encode(odometry), cdr.encode(tf), strict=True)):
        sec, nanosec = divmod(int(stamps[i]), 10**9)
        header = types["std_msgs/msg/Header"](
            stamp=types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec), frame_id=frame)
        back = cdr.decode_generic("nav_msgs/msg/Odometry", odo)
        assert back.header == header and back.child_frame_id == child
        np.testing.assert_array_equal(back.pose.covariance, odometry["pose.covariance"][i])
        assert odo == cdr.encode_generic(back)
        transform = cdr.decode_generic("tf2_msgs/msg/TFMessage", tfm).transforms
        assert len(transform) == 1 and transform[0].header == header
        assert transform[0].child_frame_id == child
        assert transform[0].transform.rotation.w == tf["transforms.transform.rotation"][i, 3]
        assert tfm == cdr.encode_generic(cdr.decode_generic("tf2_msgs/msg/TFMessage", tfm))


def test_a_child_frame_that_differs_between_messages_is_refused():
    batch = MessageBatch("tf2_msgs/msg/TFMessage", np.arange(2), "map", {
        "transforms.child_frame_id": np.array(["a", "b"]),
        "transforms.transform.translation": np.zeros((2, 3)),
        "transforms.transform.rotation": np.zeros((2, 4))})
    with pytest.raises(ValueError, match="child_frame_id differs"):
        cdr.encode(batch)


def test_odometry_and_tf_decode_what_they_encode():
    """Frames of several lengths in one list: grouped, and read back as they were."""
    rng = np.random.default_rng(5)
    n = 6
    tf = MessageBatch("tf2_msgs/msg/TFMessage", rng.integers(0, 2**31 * 10**9, n), "map", {
        "transforms.child_frame_id": np.full(n, "base_link"),
        "transforms.transform.translation": rng.normal(size=(n, 3)),
        "transforms.transform.rotation": rng.normal(size=(n, 4))})
    other = MessageBatch(tf.msgtype, tf.stamp_ns, "odom", {
        **tf.fields, "transforms.child_frame_id": np.full(n, "alice/base_link")})
    raws = cdr.encode(tf) + cdr.encode(other)
    back = cdr.decode(tf.msgtype, raws)
    assert back.frame_id.tolist() == ["map"] * n + ["odom"] * n
    assert back["transforms.child_frame_id"].tolist() == ["base_link"] * n + \
        ["alice/base_link"] * n
    np.testing.assert_array_equal(back.stamp_ns, np.r_[tf.stamp_ns, tf.stamp_ns])
    np.testing.assert_array_equal(back["transforms.transform.rotation"][:n],
                                  tf["transforms.transform.rotation"])
    two = cdr.encode_generic(typestore().types["tf2_msgs/msg/TFMessage"](
        transforms=[cdr.decode_generic(tf.msgtype, raws[0]).transforms[0]] * 2))
    with pytest.raises(ValueError, match="holds 2 elements"):
        cdr.decode(tf.msgtype, [two])


def test_messages_of_one_size_with_other_strings_decode_apart():
    """Two TFMessages of the same byte size whose frames split the letters differently
    ("ab" → "cdef", "abcd" → "ef"): each read along its own layout."""
    tfs = [MessageBatch("tf2_msgs/msg/TFMessage", np.array([k]), frame, {
        "transforms.child_frame_id": np.array([child]),
        "transforms.transform.translation": np.full((1, 3), float(k)),
        "transforms.transform.rotation": np.array([[0.0, 0.0, 0.0, 1.0]])})
        for k, (frame, child) in enumerate([("ab", "cdef"), ("abcd", "ef"), ("ab", "cdef")])]
    raws = [cdr.encode(b)[0] for b in tfs]
    assert len({len(r) for r in raws}) == 1
    back = cdr.decode("tf2_msgs/msg/TFMessage", raws)
    assert back.frame_id.tolist() == ["ab", "abcd", "ab"]
    assert back["transforms.child_frame_id"].tolist() == ["cdef", "ef", "cdef"]
    np.testing.assert_array_equal(back["transforms.transform.translation"][:, 0], [0, 1, 2])
