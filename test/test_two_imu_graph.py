"""Issue 57, acceptance 3: ``zupt_ekf``, ``pocket_pdr`` and ``stride_calibrator`` as
separate processes on a two-IMU bag (``pdr-sim generate --placement pocket --with-foot``:
the phone on /imu/data, the foot of the same leg on /foot/imu/data, one clock), played by
``bag_play``: the fit the calibrator saves equals ``pdr-pocket calibrate-step --foot`` on
``pdr-ekf run``'s and ``pdr-pocket run``'s outputs of the same bag, and ``pocket_pdr``
takes the fitted lines while the walk goes on: from 30 pairs, then each 20 more, not at
each pair."""
from __future__ import annotations

import signal
import time

import numpy as np
import pytest
import yaml

from pdr_core import topics
from pdr_core.io.bag import BagReader
from pdr_pocket.saved_lines import read_fit
from wstest import cli, log_text, wait_for_log

pytestmark = pytest.mark.ros
FOOT_IMU = topics.FOOT_NAMESPACE + topics.IMU_DATA
WALK = {"name": "two IMUs, 100 s", "seed": 57,
        "person": {"b_h_m": 0.36, "stride_scatter_m": 0.035, "centre_scatter": False},
        "segments": [{"type": "standing", "duration_s": 5},
                     {"type": "walk", "distance_m": 50, "speed_kmh": 3.2},
                     {"type": "turn", "angle_deg": 90, "steps": 2},
                     {"type": "walk", "distance_m": 60, "speed_kmh": 5.0},
                     {"type": "standing", "duration_s": 5}]}


@pytest.fixture(scope="module")
def offline(tmp_path_factory):
    """The bag, and the offline chain on it: the foot INS on /foot, the pocket, the fit."""
    folder = tmp_path_factory.mktemp("two_imu")
    scenario = folder / "walk.yaml"
    scenario.write_text(yaml.safe_dump(WALK))
    for prog, *args in (
            ("pdr-sim", "generate", "--placement", "pocket", "--scenario", scenario,
             "--with-foot", "--out", folder / "walk"),
            ("pdr-ekf", "run", folder / "walk", "--out", folder / "foot", "--imu-topic",
             FOOT_IMU, "--truth-topic", topics.FOOT_NAMESPACE + topics.GROUND_TRUTH_POSE,
             "--stance-truth-topic", topics.FOOT_NAMESPACE + topics.GROUND_TRUTH_STANCE),
            ("pdr-pocket", "run", folder / "walk", "--out", folder / "pocket"),
            ("pdr-pocket", "calibrate-step", "--foot", folder / "foot", "--pocket",
             folder / "pocket", "--out", folder / "fit.yaml")):
        done = cli(prog, *args)
        assert done.returncode == 0, done.stderr
    return folder


def decided(fit) -> int:
    """The pocket steps a saved fit has decided: paired to a line or refused."""
    return sum(line.fit.pairs for line in fit.lines.values() if line.fit is not None) + \
        sum(fit.refused.values())


def test_the_live_fit_of_three_processes_equals_the_offline_one(procs, tmp_path, offline):
    saved = tmp_path / "live_fit.yaml"
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={tmp_path / 'live'}", "-p",
                           f"topics:=[{topics.POCKET_STRIDE_LINES}]", name="record")
    navigator = procs.start("pocket_pdr", "--ros-args", "-p", "imu_durability:=transient_local",
                            name="pocket_pdr")
    foot = procs.start("zupt_ekf", "--ros-args", "-p", "imu_durability:=transient_local", "-p",
                       "publish_tf:=false", "-r", f"imu/data:={FOOT_IMU}", name="zupt_ekf")
    calibrator = procs.start("stride_calibrator", "--ros-args", "-p", f"save_to:={saved}",
                             name="stride_calibrator")
    wait_for_log(recorder, f"recording {topics.POCKET_STRIDE_LINES}")
    wait_for_log(calibrator, "stride_calibrator: configuration")
    played = procs.run("bag_play", "--ros-args", "-p", f"bag:={offline / 'walk'}", "-p",
                       f"topics:=[{topics.IMU_DATA}, {topics.IMU_MAG}, {FOOT_IMU}]", "-p",
                       "rate:=0.0", "-p", "wait_for_subscribers:=1", timeout=120)
    assert played.returncode == 0, played.stderr
    # every step is in once the calibrator's saved fit has the offline pairs
    want = read_fit(offline / "fit.yaml")
    deadline = time.monotonic() + 20
    while not (saved.exists() and decided(read_fit(saved)) == decided(want)):
        assert time.monotonic() < deadline, log_text(calibrator)
        time.sleep(0.2)
    for proc in (recorder, calibrator, foot, navigator):
        assert procs.stop(proc, signal.SIGINT) == 0, log_text(proc)
    live = read_fit(saved)
    assert live.refused == want.refused
    for name, line in want.lines.items():
        got = live.lines[name]
        assert (got.slope, got.offset) == pytest.approx((line.slope, line.offset), rel=1e-9)
        assert (got.fit is None) == (line.fit is None)
        if line.fit is not None:
            assert got.fit.pairs == line.fit.pairs
            np.testing.assert_allclose(got.fit.covariance, line.fit.covariance, rtol=1e-9)
    # the lines went to pocket_pdr while the walk went on, and it said so
    lines = BagReader(tmp_path / "live").read_messages(topics.POCKET_STRIDE_LINES)
    assert len(lines) and lines[-1][1].level_pairs == want.lines["level"].fit.pairs
    assert "pocket_pdr took step_length" in log_text(calibrator)
    # docs/nodes.md: handed over from min_pairs (30) pairs, then each every_pairs (20) more,
    # not at each pair
    takes = log_text(navigator).count("took the person's lines from a parameter update")
    assert 1 <= takes <= 1 + (want.lines["level"].fit.pairs - 30) // 20, log_text(navigator)
