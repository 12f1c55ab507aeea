"""bag_play -> zupt_ekf -> bag_record as three processes gives the offline trajectory
(issue 4, acceptance 4 and "live equals offline to 1e-9 m")."""
from __future__ import annotations

import signal

import numpy as np
import pytest

from pdr_core.bag import BagReader
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
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={tmp_path / 'live'}", "-p",
                           "topics:=[pdr/foot/pose, pdr/foot/stance, pdr/foot/smoothed_path]",
                           "-p", f"max_messages:={2 * expected + len(ref_smoothed)}",
                           name="record")
    node = procs.start("zupt_ekf", "--ros-args", "-p", f"config:={CONFIG}", "-p",
                       "imu_durability:=transient_local", "-p", "smoothed_path:=true",
                       name="zupt_ekf")
    wait_for_log(recorder, "recording /pdr/foot/pose", "recording /pdr/foot/stance",
                 "recording /pdr/foot/smoothed_path")
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
    live_smoothed = [path for _, path in
                     BagReader(tmp_path / "live").read_messages("/pdr/foot/smoothed_path")]
    assert len(live_smoothed) == len(ref_smoothed) > 30
    np.testing.assert_allclose(
        [[p.pose.position.x, p.pose.position.y, p.pose.position.z]
         for path in live_smoothed for p in path.poses],
        [[p.pose.position.x, p.pose.position.y, p.pose.position.z]
         for path in ref_smoothed for p in path.poses], rtol=0, atol=1e-9)
