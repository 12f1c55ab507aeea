"""The placement from the pitch swing, and the stride model it chooses
(pdr_pocket.placement): a thigh's swing is the front pocket's pitch line, a smaller one
the back pocket's cadence line, and nothing is decided before a window of level cycles."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core.gait import (
    PLACEMENT_MIN_CADENCE_HZ,
    PLACEMENT_WINDOW_STEPS,
    THIGH_SWING_MIN_RATIO,
)
from pdr_pocket.config import StepLengthConfig
from pdr_pocket.placement import (
    BACK_POCKET,
    FRONT_POCKET,
    UNKNOWN,
    PlacementClassifier,
    stride_choice,
    thigh_swing_deg,
)
from pdr_pocket.step_length import StrideInputs

CONFIG = StepLengthConfig()


def cycles(ratio: float, duration_s: float, n: int) -> list[StrideInputs]:
    swing = ratio * thigh_swing_deg(CONFIG, 1.0 / duration_s)
    return [StrideInputs(swing, duration_s, 10.0)] * n


def test_the_pitch_and_cadence_lines_agree_on_the_thigh_swing():
    """At Δθ_thigh(f) the pitch line (Eq. (4.2)) and the cadence line (Eq. (4.3)) give the
    same stride."""
    f = 0.9
    swing = thigh_swing_deg(CONFIG, f)
    assert CONFIG.a_h_m_per_deg * swing + CONFIG.b_h_m == pytest.approx(
        CONFIG.c_h_m_per_hz * f + CONFIG.d_h_m)


@settings(max_examples=40, deadline=None)
@given(ratio=st.floats(0.2, 1.6), duration_s=st.floats(0.6, 1.0 / PLACEMENT_MIN_CADENCE_HZ))
def test_the_swing_ratio_names_the_placement_and_its_model(ratio, duration_s):
    classifier = PlacementClassifier(CONFIG)
    found = [classifier.add(x) for x in cycles(ratio, duration_s, PLACEMENT_WINDOW_STEPS)]
    assert {p.placement for p in found[:-1]} == {UNKNOWN}
    assert {p.model for p in found[:-1]} == {"pitch"}
    assert found[-1].swing_ratio == pytest.approx(ratio)
    if abs(ratio - THIGH_SWING_MIN_RATIO) > 1e-9:
        thigh = ratio > THIGH_SWING_MIN_RATIO
        assert found[-1].placement == (FRONT_POCKET if thigh else BACK_POCKET)
        assert found[-1].model == ("pitch" if thigh else "frequency")


def test_a_slow_walk_keeps_the_placement_judged_last():
    """Under 90 steps/min a slow thigh swings as little as a back pocket: nothing is judged
    there, the placement stays (unknown before any judgement, and the pitch line)."""
    slow = 1.0 / (0.9 * PLACEMENT_MIN_CADENCE_HZ)
    classifier = PlacementClassifier(CONFIG)
    for x in cycles(0.5, slow, 2 * PLACEMENT_WINDOW_STEPS):
        found = classifier.add(x)
    assert (found.placement, found.model) == (UNKNOWN, "pitch") and "too slow" in found.why
    for x in cycles(0.5, 1.0, PLACEMENT_WINDOW_STEPS) + cycles(1.0, slow, PLACEMENT_WINDOW_STEPS):
        found = classifier.add(x)
    assert (found.placement, found.model) == (BACK_POCKET, "frequency")
    assert found.why.startswith("the pitch swing is ") and "too slow" in found.why


def test_a_configured_model_is_kept_and_the_placement_still_named():
    classifier = PlacementClassifier(StepLengthConfig(model="weinberg"))
    for x in cycles(0.5, 1.0, PLACEMENT_WINDOW_STEPS):
        found = classifier.add(x)
    assert (found.placement, found.model) == (BACK_POCKET, "weinberg")
    assert "as configured" in stride_choice(classifier.config)


def test_the_summary_names_the_placement_of_most_cycles_and_why():
    classifier = PlacementClassifier(CONFIG)
    for x in cycles(1.0, 1.0, 20) + cycles(0.5, 1.0, 10):
        classifier.add(x)
    summary = classifier.summary()
    assert summary["placement"] == FRONT_POCKET and summary["stride_model"] == "pitch"
    # the window's median turns once more than half of it is the back pocket's
    half = PLACEMENT_WINDOW_STEPS // 2
    assert summary["cycles"] == {UNKNOWN: PLACEMENT_WINDOW_STEPS - 1,
                                 FRONT_POCKET: 20 - PLACEMENT_WINDOW_STEPS + 1 + half,
                                 BACK_POCKET: 10 - half}
    assert "at least 75 %" in summary["why"]
    assert PlacementClassifier(CONFIG).summary()["placement"] == UNKNOWN
    short = PlacementClassifier(CONFIG)     # one judged cycle (a timed up-and-go) names none
    for x in cycles(0.5, 1.0, PLACEMENT_WINDOW_STEPS):
        short.add(x)
    assert short.summary()["placement"] == UNKNOWN


def test_a_calibrated_line_moves_the_thigh_swing():
    """The person's own b_H (calibrate-step) is the line the swing is judged against."""
    mine = StepLengthConfig(b_h_m=0.30, calibrated=True)
    assert thigh_swing_deg(mine, 0.9) - thigh_swing_deg(CONFIG, 0.9) == pytest.approx(
        0.12 / CONFIG.a_h_m_per_deg)
    assert np.isfinite(thigh_swing_deg(mine, 0.9))
