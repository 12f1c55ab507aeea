"""The placement from the pitch swing, and the stride model it chooses
(pdr_pocket.placement): a thigh's swing is the front pocket's pitch line, a smaller one
the back pocket's cadence line, and nothing is decided before a window of level cycles;
footfalls the pitch does not swing with are no pocket's; the walk's placement is named
the same live and offline (simulated walks and a shared recording)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core.walking.gait import (
    PLACEMENT_MIN_CADENCE_HZ,
    PLACEMENT_WINDOW_STEPS,
    THIGH_SWING_MIN_RATIO,
)
from pdr_pocket.config import StepLengthConfig
from pdr_pocket.placement import (
    BACK_POCKET,
    FRONT_POCKET,
    NOT_IN_POCKET,
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


def test_the_walk_is_named_as_soon_as_the_live_node_names_it():
    """Issue 54, point 7: the final report's placement is the live node's (the verdict
    both give): one judged cycle names it; fewer level cycles than a window say so in
    words for a finished walk, without "so far"."""
    short = PlacementClassifier(CONFIG)
    found = [short.add(x) for x in cycles(0.5, 1.0, PLACEMENT_WINDOW_STEPS)]
    assert found[-1].placement == BACK_POCKET == short.verdict().placement
    assert short.summary()["placement"] == BACK_POCKET
    assert short.summary()["why"] == found[-1].why
    tug = PlacementClassifier(CONFIG)
    for x in cycles(0.5, 1.0, PLACEMENT_WINDOW_STEPS - 1):
        tug.add(x)
    why = tug.summary()["why"]
    assert tug.summary()["placement"] == UNKNOWN
    assert why == (f"{PLACEMENT_WINDOW_STEPS - 1} level gait cycles, fewer than the "
                   f"{PLACEMENT_WINDOW_STEPS} the placement is judged over")


def test_footfalls_the_pitch_does_not_swing_with_are_no_pocket():
    """More than 3 footfalls heard per gait cycle of the pitch, of at least 16 heard: not in
    a pocket, whatever the swing said; 2 per cycle (a thigh's), or too few heard to judge
    by, keep the swing's placement; without a separate count (no gyroscope) never."""
    classifier = PlacementClassifier(CONFIG)
    for x in cycles(1.0, 1.0, 10):
        classifier.add(x)
    assert classifier.verdict(10, 20).placement == FRONT_POCKET
    assert classifier.verdict(10, None).placement == FRONT_POCKET
    assert classifier.verdict(5, 15).placement == FRONT_POCKET       # too few heard
    hand = classifier.verdict(10, 31)
    assert (hand.placement, hand.model) == (NOT_IN_POCKET, "none")
    assert hand.why.startswith("the accelerometer heard 31 footfalls but the pitch swung "
                               "through 10 gait cycles")
    assert "the pitch swing is 100 % of a thigh's" in hand.why
    summary = classifier.summary(10, 31)
    assert summary["placement"] == NOT_IN_POCKET
    assert (summary["gait_cycles"], summary["footfalls_heard"]) == (10, 31)
    assert PlacementClassifier(CONFIG).verdict(0, 588).placement == NOT_IN_POCKET


def test_a_calibrated_line_moves_the_thigh_swing():
    """The person's own b_H (calibrate-step) is the line the swing is judged against."""
    mine = StepLengthConfig(b_h_m=0.30, calibrated=True)
    assert thigh_swing_deg(mine, 0.9) - thigh_swing_deg(CONFIG, 0.9) == pytest.approx(
        0.12 / CONFIG.a_h_m_per_deg)
    assert np.isfinite(thigh_swing_deg(mine, 0.9))


def live_and_offline(t_s: np.ndarray, accel: np.ndarray, gyro: np.ndarray,
                     chunk: int = 37) -> tuple:
    """The navigator of the live node (pdr_pocket.streaming, ``chunk`` samples a message
    batch) and of ``pdr-pocket run`` (the whole record at once) on the same samples."""
    from pdr_pocket.config import PocketConfig
    from pdr_pocket.navigator import PocketNavigator
    from pdr_pocket.samples import Samples
    from pdr_pocket.streaming import StreamingPocket

    live = StreamingPocket(PocketConfig())
    stamps = np.round(t_s * 1e9).astype(np.int64)
    for i in range(0, len(stamps), chunk):
        live.push_imus(stamps[i:i + chunk], accel[i:i + chunk], gyro[i:i + chunk])
    live.flush()
    offline = PocketNavigator(PocketConfig())
    offline.process(Samples((stamps - stamps[0]) * 1e-9, accel, gyro))
    return live.navigator, offline


@pytest.mark.parametrize(("carried", "placement"), [("front_pocket", FRONT_POCKET),
                                                    ("hand", NOT_IN_POCKET)])
def test_the_live_node_and_the_run_name_the_same_placement(carried, placement):
    """The simulated H1 walk (its first 120 s) in a front pocket and in the hand: the
    placement the live node says last (pdr_pocket.placement.walk_placement, as
    pocket_pdr logs it) is the final report's, reason and figures included."""
    from pdr_pocket.placement import placement_summary, walk_placement
    from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
    from pdr_sim.simulation import SimulationConfig, simulate

    _, data = load_pocket_scenario("h1_rectangle")
    data = {**data, "carried": carried}
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, "h1_rectangle"), data,
                                    "consumer_phone", {}, 100.0, 0, placement="pocket"))
    n = 12000
    live, offline = live_and_offline(sim.trajectory.t[:n], sim.imu["linear_acceleration"][:n],
                                     sim.imu["angular_velocity"][:n])
    said, reported = walk_placement(live), placement_summary(offline)
    assert (said.placement, said.why) == (reported["placement"], reported["why"])
    assert said.placement == placement and "so far" not in said.why
    assert placement_summary(live) == reported
