"""The bags ``pdr-sim``, ``pdr-ekf run`` and ``pdr-pocket run`` write carry ``/tf`` and
``/tf_static`` (REP-105), so a viewer places them in ``map`` with no setting changed, and
the navigators' ``nav_msgs/Odometry`` is their pose with its covariance (issue 42)."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdr_core.io.bag import BagReader
from pdr_core.vocabulary import Activity
from wstest import ROOT, cli


def transforms(reader: BagReader, topic: str = "/tf"):
    """(stamps [ns], parent, child, positions, quaternions) of a bag's TF messages of one
    transform each."""
    items = [msg.transforms for _, msg in reader.read_messages(topic)]
    assert all(len(t) == 1 for t in items)
    ts = [t[0] for t in items]
    return (np.array([t.header.stamp.sec * 10**9 + t.header.stamp.nanosec for t in ts]),
            {t.header.frame_id for t in ts}, {t.child_frame_id for t in ts},
            np.array([[t.transform.translation.x, t.transform.translation.y,
                       t.transform.translation.z] for t in ts]),
            np.array([[t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
                       t.transform.rotation.w] for t in ts]))


def assert_tf_equals(reader: BagReader, child: str, stamp_ns: np.ndarray, position: np.ndarray,
                     orientation: np.ndarray) -> None:
    """/tf holds ``map → child`` at exactly these stamps, positions and orientations, and
    /tf_static the identity ``base_link → imu_link``."""
    stamps, parent, children, tf_position, quaternion = transforms(reader)
    assert parent == {"map"} and children == {child}
    np.testing.assert_array_equal(stamps, stamp_ns)
    np.testing.assert_array_equal(tf_position, position)
    np.testing.assert_array_equal(quaternion, orientation)
    assert_static_identity(reader)


def assert_static_identity(reader: BagReader) -> None:
    stamps, parent, child, position, quaternion = transforms(reader, "/tf_static")
    assert len(stamps) == 1 and parent == {"base_link"} and child == {"imu_link"}
    np.testing.assert_array_equal(position, [[0, 0, 0]])
    np.testing.assert_array_equal(quaternion, [[0, 0, 0, 1]])


@pytest.mark.parametrize("bag", ["foot_walk", "pocket_walk", "vicon_walk"])
def test_a_recording_puts_its_true_pose_on_tf(bag):
    """pdr-sim generate and import-csv (the sample bags are theirs, test_sample_bags.py)."""
    reader = BagReader(ROOT / "bags" / bag)
    truth = reader.read("/ground_truth/pose")
    assert_tf_equals(reader, "ground_truth", truth.stamp_ns, truth["pose.position"],
                     truth["pose.orientation"])


def test_the_foot_bag_has_its_pose_on_tf_and_as_odometry(tmp_path):
    result = cli("pdr-ekf", "run", str(ROOT / "bags" / "foot_walk"), "--out", str(tmp_path / "out"))
    assert result.returncode == 0, result.stderr
    reader = BagReader(tmp_path / "out")
    pose, velocity = reader.read("/pdr/foot/pose"), reader.read("/pdr/foot/velocity")
    assert_tf_equals(reader, "base_link", pose.stamp_ns, pose["pose.pose.position"],
                     pose["pose.pose.orientation"])
    odometry = [msg for _, msg in reader.read_messages("/pdr/foot/odometry")]
    assert len(odometry) == len(pose)
    assert {m.header.frame_id for m in odometry} == {"map"}
    assert {m.child_frame_id for m in odometry} == {"base_link"}
    np.testing.assert_array_equal([m.pose.covariance for m in odometry],
                                  pose["pose.covariance"])
    # the twist in the body: Cᵀ·v, its covariance Cᵀ·P·C (REP-105: in child_frame_id)
    c = Rotation.from_quat(pose["pose.pose.orientation"]).as_matrix()
    v_map = velocity["twist.twist.linear"]
    v_body = np.array([[m.twist.twist.linear.x, m.twist.twist.linear.y, m.twist.twist.linear.z]
                       for m in odometry])
    np.testing.assert_allclose(np.einsum("nij,nj->ni", c, v_body), v_map, atol=1e-12)
    p_map = velocity["twist.covariance"].reshape(-1, 6, 6)[:, :3, :3]
    p_body = np.array([m.twist.covariance for m in odometry]).reshape(-1, 6, 6)[:, :3, :3]
    np.testing.assert_allclose(np.einsum("nij,njk,nlk->nil", c, p_body, c), p_map, atol=1e-15)


def test_the_pocket_bag_has_each_step_on_tf_and_as_odometry(tmp_path):
    result = cli("pdr-pocket", "run", str(ROOT / "bags" / "pocket_walk"), "--out",
                 str(tmp_path / "out"))
    assert result.returncode == 0, result.stderr
    reader = BagReader(tmp_path / "out")
    pose = reader.read("/pdr/pocket/pose")
    assert len(pose) == 122
    assert_tf_equals(reader, "base_link", pose.stamp_ns, pose["pose.pose.position"],
                     pose["pose.pose.orientation"])
    odometry = [msg for _, msg in reader.read_messages("/pdr/pocket/odometry")]
    cov = np.array([m.pose.covariance for m in odometry]).reshape(-1, 6, 6)
    # the position's covariance for a fusion node (issue 55, pdr_pocket.position), not the
    # filter's that pdr/pocket/pose carries for the drift loop
    assert np.linalg.eigvalsh(cov[:, :3, :3])[:, 0].min() > 0
    assert not np.allclose(cov[:, :3, :3], pose["pose.covariance"].reshape(-1, 6, 6)[:, :3, :3])
    # the attitude's covariance, which pdr/pocket/pose leaves out, is in the odometry
    attitude = reader.read("/pdr/pocket/attitude")
    at = np.searchsorted(attitude.stamp_ns, pose.stamp_ns)
    np.testing.assert_array_equal(cov[:, 3:, 3:].reshape(-1, 9),
                                  attitude["orientation_covariance"][at])
    # the twist: each step's velocity in the body (issue 55), the rates unknown
    twist = np.array([m.twist.covariance for m in odometry]).reshape(-1, 6, 6)
    assert (np.diagonal(twist[:, 3:, 3:], axis1=1, axis2=2) == 1e6).all()
    assert np.linalg.eigvalsh(twist[:, :3, :3])[:, 0].min() > 0
    steps = reader.read("/pdr/pocket/step")
    level = steps["activity"] == Activity.WALKING
    speed = np.linalg.norm([[m.twist.twist.linear.x, m.twist.twist.linear.y,
                             m.twist.twist.linear.z] for m in odometry], axis=1)
    np.testing.assert_allclose(speed[level], (steps["length"] / steps["duration"])[level],
                               rtol=1e-9)
