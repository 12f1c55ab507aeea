"""The graph's defining loop (issue 18): bag_play → pocket_pdr ⇄ landmark_drift →
bag_record, as four processes, on a simulated walk whose corners are revisited."""
from __future__ import annotations

import json
import signal

import numpy as np
import pytest

from pdr_core.bag import BagReader
from wstest import log_text, wait_for_log

pytestmark = pytest.mark.ros


def test_landmark_drift_corrects_pocket_pdr_over_the_service(procs, tmp_path):
    walk = tmp_path / "walk"
    generated = procs.run("pdr-sim", "generate", "--placement", "pocket", "--scenario",
                          "block_two_laps", "--imu", "thesis_table_6_1", "--out", str(walk))
    assert generated.returncode == 0, generated.stderr
    offline = procs.run("pdr-pocket", "run", str(walk), "--out", str(tmp_path / "offline"),
                        "--drift", "online")
    assert offline.returncode == 0, offline.stderr
    report = json.loads((tmp_path / "offline" / "report.json").read_text())
    drift = report["drift"]
    assert drift["associations"] >= 1 and drift["corrections_accepted"] >= 1
    expected = report["steps"] + drift["landmarks"] + drift["associations"]
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={tmp_path / 'live'}", "-p",
                           "topics:=[pdr/pocket/pose, pdr/landmarks, pdr/drift]", "-p",
                           f"max_messages:={expected}", name="record")
    navigator = procs.start("pocket_pdr", "--ros-args", "-p", "imu_durability:=transient_local",
                            name="pocket_pdr")
    estimator = procs.start("landmark_drift", name="landmark_drift")
    wait_for_log(recorder, "recording /pdr/pocket/pose", "recording /pdr/landmarks",
                 "recording /pdr/drift")
    played = procs.run("bag_play", "--ros-args", "-p", f"bag:={walk}", "-p",
                       "topics:=[/imu/data, /imu/mag]", "-p", "rate:=0.0", "-p",
                       "wait_for_subscribers:=1", timeout=300)
    assert played.returncode == 0, played.stderr
    assert recorder.wait(timeout=180) == 0, log_text(recorder) + log_text(estimator)
    assert "correction accepted" in log_text(navigator), log_text(navigator)
    assert "correction accepted" in log_text(estimator), log_text(estimator)
    assert procs.stop(estimator, signal.SIGINT) == 0, log_text(estimator)
    assert procs.stop(navigator, signal.SIGINT) == 0, log_text(navigator)
    live = BagReader(tmp_path / "live")
    landmarks = live.read("/pdr/landmarks")
    assert len(landmarks) == drift["landmarks"]
    estimates = live.read("/pdr/drift")
    np.testing.assert_allclose(np.degrees(estimates["drift"]), drift["drift_deg_per_s"],
                               atol=1e-3)
    poses = live.read("/pdr/pocket/pose")["pose.pose.position"]
    offline_poses = BagReader(tmp_path / "offline").read("/pdr/pocket/pose")["pose.pose.position"]
    assert len(poses) == len(offline_poses)
    assert np.linalg.norm(poses[-1] - offline_poses[-1]) < 0.5
