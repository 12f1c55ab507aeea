"""``pdr-eval --navigator auto``: the foot's or the pocket's navigator told from the data
(pdr_core.walking.navigator_choice; issue 54, acceptance 3), on every shared foot and pocket
recording and on the simulator's foot and thigh walks."""
from __future__ import annotations

import numpy as np
import pytest
from pdr_eval.auto_navigator import bag_navigator, refusal

from pdr_core.walking.navigator_choice import (
    FOOT_MIN_STANCES_HZ,
    FOOT_SWING_PEAK_RADPS,
    MIN_MOVING_S,
    choose_navigator,
)
from wstest import (
    ROOT,
    SHARED_RECORDINGS,
    cli,
    imported,
    needs_shared,
)


@pytest.mark.parametrize("name", [pytest.param(name, marks=needs_shared(csv))
                                  for name, (csv, _, _) in SHARED_RECORDINGS.items()])
def test_auto_picks_the_navigator_of_every_shared_recording(name):
    csv, args, navigator = SHARED_RECORDINGS[name]
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
