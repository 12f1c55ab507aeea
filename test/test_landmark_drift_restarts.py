"""The pocket graph with the drift loop when a node dies (issues 18 and 32) and two
people share a domain (issue 29): bag_play → pocket_pdr ⇄ landmark_drift → bag_record
on the demo's walk, apart from test_landmark_drift.py so that the suite's two workers
share the graph runs (a module stays on one worker)."""
from __future__ import annotations

import json
import signal

import numpy as np
import pytest
from graph_runs import (
    NO_MAG,
    GraphRun,
    assert_equals_in_process,
    demo_walk,
    final_path,
    generate,
    in_process,
    in_process_loop,
)

from pdr_core.io.bag import BagReader, write_batches
from wstest import log_text, wait_for_log

pytestmark = pytest.mark.ros


walk = pytest.fixture(scope="module")(demo_walk)
online = pytest.fixture(scope="module")(in_process_loop)


def split_laps(walk, folder) -> None:
    """``walk``'s IMU and magnetometer data as two bags, ``folder``/lap1 up to 5 s before
    the second lap's first corner and ``folder``/lap2 from there."""
    reader = BagReader(walk)
    corners = reader.read("/ground_truth/landmarks")
    cut = int(np.sort(corners.stamp_ns[corners["type"] == 0])[3]) - 5_000_000_000
    batches = reader.read_batches(["/imu/data", "/imu/mag"])
    for name, keep in (("lap1", lambda s: s < cut), ("lap2", lambda s: s >= cut)):
        write_batches(folder / name,
                      {t: b.take(np.flatnonzero(keep(b.stamp_ns))) for t, b in batches.items()})


def test_pocket_pdr_killed_and_restarted_mid_walk(procs, tmp_path, walk):
    """Issue 18, acceptance 5: pocket_pdr is killed at the end of the first lap and
    started again for the second; landmark_drift keeps running, and the correction of the
    second lap's revisit reaches the new pocket_pdr, which answers it. The new pocket_pdr
    counts its position from where it started, so the revisit's position fix is 35 m off
    in its frame and its χ² gate refuses it."""
    split_laps(walk, tmp_path)
    estimator = procs.start("landmark_drift", name="landmark_drift")
    first = procs.start("pocket_pdr", "--ros-args", "-p", "imu_durability:=transient_local",
                        "-p", f"config:={NO_MAG}", name="pocket_pdr_1")
    wait_for_log(estimator, "configuration")
    wait_for_log(first, "configuration")
    play = ["--ros-args", "-p", "topics:=[/imu/data, /imu/mag]", "-p", "rate:=0.0", "-p",
            "wait_for_subscribers:=1"]
    lap1 = procs.run("pdr-pocket", "run", str(tmp_path / "lap1"), "--config", NO_MAG,
                     "--out", str(tmp_path / "lap1_run"), "--drift", "online")
    assert lap1.returncode == 0, lap1.stderr
    landmarks = json.loads((tmp_path / "lap1_run" / "report.json").read_text())["drift"][
        "landmarks"]
    assert landmarks >= 3
    assert procs.run("bag_play", *play, "-p", f"bag:={tmp_path / 'lap1'}").returncode == 0
    # landmark_drift has the first lap's landmarks before pocket_pdr goes
    wait_for_log(estimator, *(f"new landmark {i}:" for i in range(landmarks)))
    first.send_signal(signal.SIGKILL)
    first.wait(timeout=30)
    # lap 2 plays as fast as acknowledged: a window that holds the whole lap, so that a
    # slow machine's late answer meets the χ² gate, not the window's end
    second = procs.start("pocket_pdr", "--ros-args", "-p", "imu_durability:=transient_local",
                         "-p", f"config:={NO_MAG}", "-p", "correction_window_s:=600.0",
                         name="pocket_pdr_2")
    wait_for_log(second, "configuration")
    assert procs.run("bag_play", *play, "-p", f"bag:={tmp_path / 'lap2'}",
                     timeout=300).returncode == 0
    wait_for_log(estimator, "revisit of landmark", timeout=120)
    wait_for_log(second, "correction refused", timeout=60)      # pocket_pdr took the call
    wait_for_log(estimator, "correction refused", timeout=30)   # ... landmark_drift the answer
    assert estimator.poll() is None
    # docs/pocket.md: the new pocket_pdr answers, and refuses the position fix: its frame
    # starts where it was started, 35 m from where the old one had that spot
    answer = log_text(estimator).split("revisit of landmark")[1]
    assert "correction refused: nothing applied: position fix refused by the χ² gate" \
        in answer, answer
    assert procs.stop(second, signal.SIGINT) == 0, log_text(second)
    assert procs.stop(estimator, signal.SIGINT) == 0, log_text(estimator)


def test_landmark_drift_killed_and_restarted_keeps_its_landmarks(procs, tmp_path, walk, online):
    """Issue 32, acceptance 5: landmark_drift, with a ``state_file``, is killed (SIGKILL)
    at the end of the first lap and started again for the second; pocket_pdr keeps
    running. The restarted node restores the first lap's landmarks, recognises the steps
    pocket_pdr's transient-local history sends again, and associates and corrects the
    second lap's revisit with the drift the uninterrupted in-process loop finds."""
    drift = online[1]["drift"]
    assert drift["associations"] == 1
    split_laps(walk, tmp_path)
    state = ["--ros-args", "-p", f"state_file:={tmp_path / 'drift.state'}"]
    first = procs.start("landmark_drift", *state, name="landmark_drift_1")
    # the restarted landmark_drift reads lap 1's steps again while pocket_pdr runs lap 2
    # as fast as it is played: its correction came 59.7 s of data behind the navigator
    # (a 60 s window) in one run; a window of the whole lap takes that race out
    navigator = procs.start("pocket_pdr", "--ros-args", "-p", "imu_durability:=transient_local",
                            "-p", f"config:={NO_MAG}", "-p", "correction_window_s:=300.0",
                            name="pocket_pdr")
    wait_for_log(first, "configuration")
    wait_for_log(navigator, "configuration")
    play = ["--ros-args", "-p", "topics:=[/imu/data, /imu/mag]", "-p", "wait_for_subscribers:=1"]
    assert procs.run("bag_play", *play, "-p", f"bag:={tmp_path / 'lap1'}", "-p",
                     "rate:=0.0").returncode == 0
    wait_for_log(first, *(f"new landmark {i}:" for i in range(3)))
    first.send_signal(signal.SIGKILL)
    first.wait(timeout=30)
    second = procs.start("landmark_drift", *state, name="landmark_drift_2")
    wait_for_log(second, "restored from")
    assert procs.run("bag_play", *play, "-p", f"bag:={tmp_path / 'lap2'}", "-p",
                     "rate:=0.0", timeout=300).returncode == 0
    wait_for_log(second, "revisit of landmark", timeout=120)
    wait_for_log(second, "correction accepted", timeout=60)
    text = log_text(second)
    assert "steps and poses from before the restart: known, dropped" in text, text
    revisit = text.split("revisit of landmark")[1]
    found = float(revisit.split("drift ")[1].split(" deg/s")[0])
    assert found == pytest.approx(drift["drift_deg_per_s"][0], abs=5e-5)
    assert procs.stop(second, signal.SIGINT) == 0, text
    assert procs.stop(navigator, signal.SIGINT) == 0, log_text(navigator)


@pytest.mark.slow("two whole graphs (eight processes) play two walks at once in one "
                  "domain, and bob's walk is simulated and navigated in process first")
def test_two_people_in_one_domain_keep_their_own_frames(procs, tmp_path, walk, online):
    """Issue 29, acceptance 2: two namespaced pocket graphs (/alice and /bob, each a
    bag_play, a pocket_pdr, a landmark_drift and a recorder) in one ROS domain, each with
    its own map frame. Each person's poses, landmarks and drift estimates carry their own
    frame, and there is no cross-talk: each gets exactly what the in-process loop gives
    for their own walk (bob's a different one), and each landmark_drift drops nothing
    as another's."""
    people = {"alice": walk, "bob": generate(tmp_path, seed=2)}
    offline = {"alice": online[0], "bob": tmp_path / "bob_offline"}
    expected = {"alice": online[1], "bob": in_process(people["bob"], offline["bob"])}
    recorders, nodes = {}, []
    for name in people:
        report, drift = expected[name], expected[name]["drift"]
        messages = (2 * report["steps"] + drift["landmarks"] + drift["associations"]
                    + drift["corrections_accepted"])
        ros = ["--ros-args", "-r", f"__ns:=/{name}"]
        frame = ["-p", f"map_frame:={name}_map"]
        recorders[name] = procs.start(
            "bag_record", *ros, "-p", f"out:={tmp_path / name / 'live'}", "-p",
            "topics:=[pdr/pocket/pose, pdr/pocket/path, pdr/landmarks, pdr/drift]", "-p",
            f"max_messages:={messages}", name=f"record_{name}")
        nodes.append(procs.start("pocket_pdr", *ros, *frame, "-p",
                                 "imu_durability:=transient_local", "-p", f"config:={NO_MAG}",
                                 name=f"pocket_pdr_{name}"))
        nodes.append(procs.start("landmark_drift", *ros, *frame, name=f"landmark_drift_{name}"))
        wait_for_log(nodes[-2], f"subscribes /{name}/imu/data")
        wait_for_log(nodes[-1], f"calls /{name}/pdr/pocket/apply_correction")
    for name, recorder in recorders.items():
        wait_for_log(recorder, f"recording /{name}/pdr/pocket/pose",
                     f"recording /{name}/pdr/pocket/path",
                     f"recording /{name}/pdr/landmarks", f"recording /{name}/pdr/drift")
    players = [procs.start("bag_play", "--ros-args", "-r", f"__ns:=/{name}", "-p",
                           f"bag:={bag}", "-p", "topics:=[/imu/data, /imu/mag]", "-p",
                           "rate:=0.0", "-p", "wait_for_subscribers:=1",
                           name=f"play_{name}")
               for name, bag in people.items()]
    for player in players:
        assert player.wait(timeout=300) == 0, log_text(player)
    for recorder in recorders.values():
        assert recorder.wait(timeout=180) == 0, log_text(recorder)
    for node in nodes:
        assert "dropped so far: stamped in frame" not in log_text(node), log_text(node)
        assert procs.stop(node, signal.SIGINT) == 0, log_text(node)
    finals = []
    for i, name in enumerate(people):
        run = GraphRun(BagReader(tmp_path / name / "live"), log_text(nodes[2 * i]),
                       log_text(nodes[2 * i + 1]))
        for topic in ("/pdr/pocket/pose", "/pdr/landmarks", "/pdr/drift"):
            assert set(run.live.read(topic).frame_id.tolist()) == {f"{name}_map"}
        assert len(run.live.read("/pdr/drift")) == expected[name]["drift"]["associations"]
        assert_equals_in_process(run, offline[name], expected[name], atol=1e-8)
        finals.append(final_path(run.live)[-1])
    assert np.linalg.norm(finals[0] - finals[1]) > 0.1      # two walks, told apart
