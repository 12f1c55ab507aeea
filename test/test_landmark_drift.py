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


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    """Two laps of a block, a phone in the pocket, Table 6.1's z gyro bias."""
    from wstest import Processes
    folder = tmp_path_factory.mktemp("block")
    generated = Processes(0, folder).run(
        "pdr-sim", "generate", "--placement", "pocket", "--scenario", "block_two_laps",
        "--imu", "thesis_table_6_1", "--out", str(folder / "walk"))
    assert generated.returncode == 0, generated.stderr
    return folder / "walk"


def test_landmark_drift_corrects_pocket_pdr_over_the_service(procs, tmp_path, walk):
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


def test_pdr_drift_run_corrects_an_output_bag_offline(procs, tmp_path, walk):
    """Section 6.2 on a navigator's output: the same drift as the live estimator, a path
    without jumps, and one clear line for a bag without steps."""
    navigated = procs.run("pdr-pocket", "run", str(walk), "--out", str(tmp_path / "nav"))
    assert navigated.returncode == 0, navigated.stderr
    result = procs.run("pdr-drift", "run", str(tmp_path / "nav"), "--out",
                       str(tmp_path / "drift"), "--plot")
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "drift" / "report.json").read_text())
    online = procs.run("pdr-pocket", "run", str(walk), "--out", str(tmp_path / "online"),
                       "--drift", "online")
    assert online.returncode == 0, online.stderr
    live = json.loads((tmp_path / "online" / "report.json").read_text())["drift"]
    assert report["associations"] >= 1 and report["landmarks"] == live["landmarks"]
    # messages are stamped at each step's confirmation, the in-process steps at its pitch
    # maximum: the elapsed times differ by a fraction of a step
    assert report["drift_deg_per_s"][0] == pytest.approx(live["drift_deg_per_s"][0], rel=1e-3)
    assert report["offline_drift_deg_per_s"] is not None
    assert report["largest_move_m"] < 2.0                  # one stride at most: no jump
    out = BagReader(tmp_path / "drift")
    [(_, path)] = out.read_messages("/pdr/pocket/corrected_path")
    assert len(path.poses) == report["steps"]
    assert len(out.read("/pdr/landmarks")) == report["landmarks"]
    assert (tmp_path / "drift" / "drift.png").stat().st_size > 20_000
    refused = procs.run("pdr-drift", "run", str(walk), "--out", str(tmp_path / "x"))
    assert refused.returncode == 2
    assert "/pdr/pocket/step" in refused.stderr and str(walk) in refused.stderr
