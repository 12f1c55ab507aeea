"""``pdr-eval --navigator auto``: the foot's or the pocket's navigator told from the data
(pdr_core.navigator_choice; issue 54, acceptance 3), on every shared foot and pocket
recording and on the simulator's foot and thigh walks."""
from __future__ import annotations

import numpy as np
import pytest
from pdr_eval.auto_navigator import bag_navigator, refusal

from pdr_core.navigator_choice import (
    FOOT_MIN_STANCES_HZ,
    FOOT_SWING_PEAK_RADPS,
    MIN_MOVING_S,
    choose_navigator,
)
from wstest import (
    OXFORD,
    OXFORD_ARGS,
    PYSHOE,
    PYSHOE_ARGS,
    PYSHOE_CLIMB,
    ROOT,
    THIGH,
    XIO,
    XIO_ARGS,
    cli,
    imported,
    needs_shared,
)

THIGH_ARGS = ["--time-col", "time", "--acc-cols", "accel_x,accel_y,accel_z",
              "--gyro-cols", "gyro_x,gyro_y,gyro_z", "--mag-cols", "mag_x,mag_y,mag_z",
              "--mag-unit", "ut"]
BACK_POCKET = OXFORD.parent / "opt_Samsung_Dario_Hard_BackPocket_1" / "accelerometer.csv"
BACK_POCKET_ARGS = ["--no-header", "--time-col", "0", "--time-unit", "ns",
                    "--acc-cols", "2,3,4"]
THIGHS = ("norm_thigh_1", "fast_thigh_1", "jog_thigh_1", "tug_thigh_1", "s_up_thigh_1",
          "s_down_thigh_1", "s_both_thigh_1")
FOOT = {p.stem: (p, PYSHOE_ARGS) for p in [*PYSHOE, PYSHOE_CLIMB]} | {"xio": (XIO, XIO_ARGS)}
POCKET = {name: (THIGH / name / "imu.csv", THIGH_ARGS) for name in THIGHS} | {
    "oxford_front": (OXFORD, OXFORD_ARGS), "oxford_back": (BACK_POCKET, BACK_POCKET_ARGS)}
SHARED = {**{k: (v, "foot") for k, v in FOOT.items()},
          **{k: (v, "pocket") for k, v in POCKET.items()}}


@pytest.mark.parametrize("name", [pytest.param(name, marks=needs_shared(csv))
                                  for name, ((csv, _), _) in SHARED.items()])
def test_auto_picks_the_navigator_of_every_shared_recording(name):
    (csv, args), navigator = SHARED[name]
    choice = bag_navigator(imported(csv, args))
    assert choice.navigator == navigator, choice.figures()
    assert choice.moving_s >= MIN_MOVING_S


@pytest.fixture(scope="module")
def running_foot(tmp_path_factory):
    """The simulator's running foot (no still stance: its swing tells it)."""
    out = tmp_path_factory.mktemp("sim") / "running"
    result = cli("pdr-sim", "generate", "--placement", "foot", "--scenario", "running",
                 "--out", out)
    assert result.returncode == 0, result.stderr
    return out


def test_auto_picks_the_simulators_foot_and_thigh(running_foot):
    """bags/foot_walk (a walking foot: still stances), the running foot (its swing) and
    bags/pocket_walk (a thigh: neither)."""
    walk, run, thigh = (bag_navigator(b) for b in (ROOT / "bags" / "foot_walk",
                                                    running_foot, ROOT / "bags" / "pocket_walk"))
    assert walk.navigator == "foot" and walk.stances_hz >= FOOT_MIN_STANCES_HZ
    assert run.navigator == "foot" and run.stances_hz < FOOT_MIN_STANCES_HZ
    assert run.swing_peak_radps >= FOOT_SWING_PEAK_RADPS
    assert thigh.navigator == "pocket" and thigh.stances_hz < FOOT_MIN_STANCES_HZ
    assert thigh.swing_peak_radps < FOOT_SWING_PEAK_RADPS


def test_too_little_motion_is_refused_naming_the_option():
    t = np.arange(0, 20, 0.01)
    rng = np.random.default_rng(0)
    accel = np.array([0.0, 0.0, 9.81]) + 0.02 * rng.standard_normal((len(t), 3))
    choice = choose_navigator(t, accel, 0.01 * rng.standard_normal((len(t), 3)))
    assert choice.navigator is None and choice.moving_s < MIN_MOVING_S
    assert "--navigator foot" in refusal(choice) and "--navigator pocket" in refusal(choice)


def test_without_a_gyroscope_only_the_pocket_navigator_can_run():
    t = np.arange(0, 20, 0.01)
    accel = np.array([0.0, 0.0, 9.81]) + np.outer(np.sin(2 * np.pi * t), [3.0, 0, 0])
    choice = choose_navigator(t, accel, None)
    assert choice.navigator == "pocket" and "no gyroscope" in choice.why
    assert choice.stances_hz is None
