"""bag_play -> zupt_ekf -> bag_record as three processes gives the offline trajectory
(issue 4, acceptance 4 and "live equals offline to 1e-9 m")."""
from __future__ import annotations

import signal
import time

import numpy as np
import pytest

from pdr_core.io.bag import BagReader
from pdr_ins_ekf.config import load_run_config
from wstest import ROOT, log_text, wait_for_log

pytestmark = pytest.mark.ros
CONFIG = ROOT / "src" / "pdr_ins_ekf" / "config" / "foot_ekf.yaml"


def test_live_node_equals_offline_run(procs, tmp_path):
    bag = ROOT / "bags" / "foot_walk"
    offline = procs.run("pdr-ekf", "run", str(bag), "--out", str(tmp_path / "offline"),
                        "--config", str(CONFIG), "--smoother", "segmented")
    assert offline.returncode == 0, offline.stderr
    lag = load_run_config(CONFIG).detector.context(100.0)[1]  # the live node's look-ahead
    expected = 6095 - lag
    ref = BagReader(tmp_path / "offline").read("/pdr/foot/pose")
    ref_smoothed = [path for stamp, path in
                    BagReader(tmp_path / "offline").read_messages("/pdr/foot/smoothed_path")
                    if stamp <= ref.stamp_ns[expected - 1]]  # the segments ended live
    strides = int(np.sum(BagReader(tmp_path / "offline").read("/pdr/foot/step").stamp_ns
                         <= ref.stamp_ns[expected - 1]))
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={tmp_path / 'live'}", "-p",
                           "topics:=[pdr/foot/pose, pdr/foot/stance, pdr/foot/smoothed_path, "
                           "pdr/foot/odometry, tf, tf_static, pdr/foot/step, "
                           "pdr/foot/step_pose]", "-p",
                           f"max_messages:={4 * expected + 1 + len(ref_smoothed) + 2 * strides}",
                           name="record")
    node = procs.start("zupt_ekf", "--ros-args", "-p", f"config:={CONFIG}", "-p",
                       "imu_durability:=transient_local", "-p", "smoothed_path:=true",
                       name="zupt_ekf")
    wait_for_log(recorder, "recording /pdr/foot/pose", "recording /pdr/foot/stance",
                 "recording /pdr/foot/smoothed_path", "recording /pdr/foot/odometry",
                 "recording /tf", "recording /tf_static", "recording /pdr/foot/step",
                 "recording /pdr/foot/step_pose")
    played = procs.run("bag_play", "--ros-args", "-p", f"bag:={bag}", "-p",
                       "topics:=[/imu/data]", "-p", "rate:=0.0", "-p", "wait_for_subscribers:=1")
    assert played.returncode == 0, played.stderr
    assert recorder.wait(timeout=120) == 0, log_text(recorder) + log_text(node)
    assert procs.stop(node, signal.SIGINT) == 0
    live = BagReader(tmp_path / "live").read("/pdr/foot/pose")
    assert len(live) == expected
    np.testing.assert_array_equal(live.stamp_ns, ref.stamp_ns[:expected])
    np.testing.assert_allclose(live["pose.pose.position"], ref["pose.pose.position"][:expected],
                               rtol=0, atol=1e-9)
    np.testing.assert_allclose(live["pose.covariance"], ref["pose.covariance"][:expected],
                               rtol=0, atol=1e-12)
    # the odometry and TF (issue 42) and the strides (issue 44): the offline bag's
    # messages, byte for byte
    for topic, count in (("/pdr/foot/odometry", expected), ("/tf", expected),
                         ("/tf_static", 1), ("/pdr/foot/step", strides),
                         ("/pdr/foot/step_pose", strides)):
        offline_raw = [m.data for m in BagReader(tmp_path / "offline").raw_messages([topic])]
        live_raw = [m.data for m in BagReader(tmp_path / "live").raw_messages([topic])]
        assert live_raw == offline_raw[:len(live_raw)] and len(live_raw) == count, topic
    assert strides >= 30
    live_smoothed = [path for _, path in
                     BagReader(tmp_path / "live").read_messages("/pdr/foot/smoothed_path")]
    assert len(live_smoothed) == len(ref_smoothed) > 30
    np.testing.assert_allclose(
        [[p.pose.position.x, p.pose.position.y, p.pose.position.z]
         for path in live_smoothed for p in path.poses],
        [[p.pose.position.x, p.pose.position.y, p.pose.position.z]
         for path in ref_smoothed for p in path.poses], rtol=0, atol=1e-9)


def test_with_an_odom_frame_it_publishes_map_to_odom(procs, ros, tmp_path):
    """``odom_frame:=odom`` (robot_localization's map instance): another node's
    odom → base_link comes on /tf (here a bag's: 0.5 m/s forward, 0.1 m/s left, turning
    0.2 rad/s, every second IMU sample), and zupt_ekf publishes map → odom, such that
    map → odom · odom → base_link is its pose at every stamp, to 1e-9 m, as
    ``pdr-ekf run`` gives it. A TF listener of this process hears them."""
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    from scipy.spatial.transform import Rotation

    from pdr_core.io.bag import write_batches
    from pdr_core.io.odometry import transform_batch
    from tf2_msgs.msg import TFMessage

    foot = ROOT / "bags" / "foot_walk"
    imu = BagReader(foot).read("/imu/data")
    t = (imu.stamp_ns[::2] - imu.stamp_ns[0]) * 1e-9
    odom_position = np.column_stack([0.5 * t, 0.1 * t, np.zeros_like(t)])
    odom_rotation = Rotation.from_euler("z", 0.2 * t[:, None])
    write_batches(tmp_path / "with_odometry", {"/imu/data": imu, "/tf": transform_batch(
        imu.stamp_ns[::2], "odom", "base_link", odom_position, odom_rotation.as_quat())})
    offline = procs.run("pdr-ekf", "run", str(foot), "--out", str(tmp_path / "offline"))
    assert offline.returncode == 0, offline.stderr
    pose = BagReader(tmp_path / "offline").read("/pdr/foot/pose")
    expected = len(pose) - load_run_config().detector.context(100.0)[1]
    heard: dict[int, tuple] = {}

    def listen(message) -> None:
        for tr in message.transforms:
            if (tr.header.frame_id, tr.child_frame_id) == ("map", "odom"):
                r, q = tr.transform.translation, tr.transform.rotation
                heard[tr.header.stamp.sec * 10**9 + tr.header.stamp.nanosec] = (
                    r.x, r.y, r.z, q.x, q.y, q.z, q.w)

    node, executor = ros
    node.create_subscription(TFMessage, "/tf", listen, QoSProfile(
        history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE))
    zupt = procs.start("zupt_ekf", "--ros-args", "-p", "imu_durability:=transient_local",
                       "-p", "odom_frame:=odom", name="zupt_ekf")
    wait_for_log(zupt, "/tf map -> odom from odom -> base_link")
    discovered = time.monotonic() + 10     # the listener matched to zupt_ekf's /tf first
    while node.count_publishers("/tf") < 1 and time.monotonic() < discovered:
        executor.spin_once(timeout_sec=0.1)
    executor.spin_once(timeout_sec=1.0)
    played = procs.run("bag_play", "--ros-args", "-p", f"bag:={tmp_path / 'with_odometry'}",
                       "-p", "rate:=0.0", "-p", "wait_for_subscribers:=1")
    assert played.returncode == 0, played.stderr
    deadline = time.monotonic() + 60
    while len(heard) < expected and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    assert procs.stop(zupt, signal.SIGINT) == 0, log_text(zupt)
    stamps = np.array(sorted(heard))
    np.testing.assert_array_equal(stamps, pose.stamp_ns[:expected])
    map_odom = np.array([heard[k] for k in stamps])
    r_mo, p_mo = Rotation.from_quat(map_odom[:, 3:]), map_odom[:, :3]
    t_pose = (stamps - imu.stamp_ns[0]) * 1e-9      # odom → base_link at the poses' stamps
    p_ob = np.column_stack([0.5 * t_pose, 0.1 * t_pose, np.zeros_like(t_pose)])
    r_ob = Rotation.from_euler("z", 0.2 * t_pose[:, None])
    np.testing.assert_allclose(p_mo + r_mo.apply(p_ob), pose["pose.pose.position"][:expected],
                               rtol=0, atol=1e-9)
    r_mb = Rotation.from_quat(pose["pose.pose.orientation"][:expected])
    assert ((r_mo * r_ob) * r_mb.inv()).magnitude().max() < 1e-9
