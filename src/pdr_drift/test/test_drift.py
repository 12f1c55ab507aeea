"""The drift estimator (Muñoz Díaz 2016, chapter 5): corners, stairs, association,
deviation and drift, against constructed walks and the simulator's truth; and its live
adapter against garbage (steps and poses with NaN, ±Inf, huge values, covariances that
are not positive semi-definite, activities that don't exist, stamps from the past):
nothing raises, every message is paired, waiting or counted, no correction is not finite,
and garbage mixed into a walk whose corners are revisited changes none of its
corrections."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from drift_walks import LEVEL, SIDES, walk
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pdr_core.vocabulary import LandmarkType
from pdr_drift.corners import BufferCornerDetector, StepSample, TurnCornerDetector
from pdr_drift.drift import DriftEstimate, deviation, drift_of, offline_drift
from pdr_drift.estimator import DriftEstimator
from pdr_drift.landmarks import Association, Landmark, LandmarkDatabase
from pdr_drift.streaming import StreamingDrift

CONFIG = Path(__file__).resolve().parents[1] / "config" / "landmark_drift.yaml"
BASE = 1_700_000_000_000_000_000


# Two laps of a block, its corners revisited, the heading drifting.
BLOCK = walk([(0, 45, LEVEL), *SIDES, (90, 45, LEVEL), *SIDES], drift_radps=np.radians(0.05))


def corners_of(detector, steps):
    return [c for c in (detector.push(s) for s in steps) if c is not None]


@pytest.mark.parametrize("detector", [BufferCornerDetector(), TurnCornerDetector()])
def test_both_detectors_find_left_and_right_right_angles(detector):
    steps = walk([(0, 20, LEVEL), (90, 20, LEVEL), (-90, 20, LEVEL), (-90, 20, LEVEL)])
    found = corners_of(detector, steps)
    assert [round(np.degrees(c.turn) / 90) for c in found] == [1, -1, -1]


def test_turn_detector_finds_wide_and_half_turns_the_buffer_one_does_not():
    steps = walk([(0, 15, LEVEL)])
    heading = 0.0
    for _ in range(10):                         # a 90° turn of 10 steps (a wide corner)
        heading += np.radians(9.0)
        steps.append(StepSample(steps[-1].t + 1.1, heading, LEVEL, steps[-1].position,
                                steps[-1].covariance, 0))
    for _ in range(8):
        steps.append(StepSample(steps[-1].t + 1.1, heading, LEVEL, steps[-1].position,
                                steps[-1].covariance, 0))
    for _ in range(2):                          # a 180° turn in two steps
        heading += np.pi / 2
        steps.append(StepSample(steps[-1].t + 1.1, heading, LEVEL, steps[-1].position,
                                steps[-1].covariance, 0))
    for _ in range(8):
        steps.append(StepSample(steps[-1].t + 1.1, heading, LEVEL, steps[-1].position,
                                steps[-1].covariance, 0))
    turns = [round(abs(np.degrees(c.turn))) for c in corners_of(TurnCornerDetector(), steps)]
    assert len(turns) == 2 and abs(turns[0] - 90) < 5 and abs(turns[1] - 180) < 5
    # the buffer detector sees right angles only: the half turn reads as one more 90°
    buffered = [round(abs(np.degrees(c.turn))) for c in corners_of(BufferCornerDetector(), steps)]
    assert buffered == [90, 90]


def test_hip_sway_makes_no_corner():
    """Step headings keep a few degrees of sway; a straight walk has no corner."""
    steps = walk([(0, 200, LEVEL)], sway_deg=3.0)
    assert corners_of(TurnCornerDetector(), steps) == []
    assert corners_of(BufferCornerDetector(), steps) == []


def landmark(id_, t, yaw_before, yaw_after, position=(0.0, 0.0, 0.0), var=1.0,
             kind=LandmarkType.CORNER, floor=0):
    return Landmark(id_, kind, t, np.asarray(position, float), np.eye(3) * var,
                    np.radians(yaw_before), np.radians(yaw_after), floor, floor)


@pytest.mark.parametrize(("revisit", "expected_deg"), [
    ((0.0, 90.0), 0.0),          # the same way
    ((270.0, 180.0), 0.0),       # the opposite way (Fig. 5.6)
    ((3.0, 93.0), -3.0),         # the same way, drifted by +3°
    ((273.0, 183.0), -3.0),      # the opposite way, drifted by +3°
    ((93.0, 183.0), -3.0),       # partial overlap (Fig. 5.4)
])
def test_deviation_is_direction_agnostic(revisit, expected_deg):
    first = landmark(0, 0.0, 0.0, 90.0)
    again = landmark(1, 300.0, *revisit)
    delta, _ = deviation(Association(first, again, 0.0))
    assert np.degrees(delta) == pytest.approx(expected_deg, abs=1e-9)


def test_stairs_deviation_up_then_down():
    first = landmark(0, 0.0, 40.0, 40.0, kind=LandmarkType.STAIRS)
    down = landmark(1, 400.0, 222.0, 222.0, kind=LandmarkType.STAIRS)
    estimate = drift_of(Association(first, down, 0.0))
    assert np.degrees(estimate.deviation) == pytest.approx(-2.0)
    assert np.degrees(estimate.drift) == pytest.approx(2.0 / 400.0)
    assert estimate.drift_variance == pytest.approx(2 * np.radians(4.0) ** 2 / 400.0**2)


def test_association_gate_type_floor_revisit_time_and_clearing():
    db = LandmarkDatabase()
    assert db.kappa == pytest.approx(4.48, abs=0.05)     # √χ²(99.7 %, 6) = 4.45
    db.associate(landmark(0, 0.0, 0.0, 90.0))
    db.associate(landmark(1, 10.0, 0.0, 90.0, position=(50.0, 0.0, 0.0)))
    assert db.associate(landmark(2, 60.0, 0.0, 90.0)) is None          # under 2 min
    assert db.associate(landmark(3, 200.0, 0.0, 90.0, kind=LandmarkType.STAIRS)) is None
    assert db.associate(landmark(4, 200.0, 0.0, 90.0, floor=1)) is None
    far = landmark(5, 200.0, 0.0, 90.0, position=(10.0, 0.0, 0.0), var=1.0)
    assert db.associate(far) is None                                   # Δ = 7.1 > κ
    found = db.associate(landmark(6, 300.0, 0.0, 90.0, position=(1.0, 1.0, 0.0)))
    assert found is not None and found.first.id == 0                    # the nearest
    assert db.stored == []                                              # cleared


def test_offline_drift_rejects_outliers_and_weights_by_elapsed_time():
    def est(drift, elapsed):
        return DriftEstimate(0, 1, 0.0, elapsed, np.radians(drift), 1e-8, 1e-3)

    estimates = [est(0.05, 300), est(0.052, 600), est(0.049, 300), est(0.9, 300),
                 est(-0.3, 200)]
    epsilon, kept = offline_drift(estimates, np.radians(0.5))
    assert len(kept) == 3
    assert np.degrees(epsilon) == pytest.approx((0.05 * 300 + 0.052 * 600 + 0.049 * 300)
                                                / 1200)


@settings(max_examples=40, deadline=None)
@given(st.floats(-0.05, 0.05), st.integers(0, 1000))
def test_estimator_recovers_a_constant_drift_on_a_revisited_block(drift_deg_per_s, seed):
    """Two laps of a block: the corners of the second lap revisit the first's, and the
    drift comes back within its own 3σ."""
    steps = walk([(0, 45, LEVEL), *SIDES, (90, 45, LEVEL), *SIDES],
                 drift_radps=np.radians(drift_deg_per_s), seed=seed)
    estimator = DriftEstimator()
    drifts = [d for s in steps for d in estimator.push(s).drifts]
    assert drifts
    for d in drifts:
        assert abs(d.drift - np.radians(drift_deg_per_s)) <= 3 * np.sqrt(d.drift_variance)


def test_streaming_pairs_steps_and_poses_and_drops_bad_messages():
    """Issue 18, acceptance 6: NaN, a covariance that is not positive semi-definite and
    stamps from the past are dropped and counted; the pairing goes on."""
    live = StreamingDrift()
    good = np.eye(3) * 0.1
    assert live.push_pose(2_000, (1.0, 0.0, 0.0), good) is None          # waits for its step
    assert live.push_step(2_000, 0.1, LEVEL) is not None                 # paired
    assert live.push_step(3_000, np.nan, LEVEL) is None
    assert live.push_pose(3_000, (np.nan, 0.0, 0.0), good) is None
    assert live.push_pose(4_000, (1.0, 0.0, 0.0), -good) is None         # negative
    assert live.push_pose(4_000, (1.0, 0.0, 0.0), np.zeros((3, 3))) is None   # zero: usable
    assert live.push_step(4_000, 0.2, 9) is None                          # no such activity
    assert live.push_step(1_000, 0.2, LEVEL) is None                      # from the past
    assert live.counts == {"bad_step": 2, "bad_pose": 2, "old_stamp": 1, "unpaired": 0,
                           "before_restart": 0}
    assert live.push_step(4_000, 0.2, LEVEL) is not None


value = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(-1e3, 1e3),
                  st.sampled_from([0.0, 9.81, -9.81, 1e300, -1e300]))
vector = st.tuples(value, value, value)
FUZZ = settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
def push_pair(live, stamp_ns, heading, activity, position, covariance, pose_first):
    """A step and its pose (same stamp), in either order; the result of the pair."""
    if pose_first:
        first = live.push_pose(stamp_ns, position, covariance)
        return first if first is not None else live.push_step(stamp_ns, heading, activity)
    first = live.push_step(stamp_ns, heading, activity)
    return first if first is not None else live.push_pose(stamp_ns, position, covariance)


def rule(live, is_step, stamp_ns, heading, activity, position, covariance) -> str | None:
    """The documented rule (pdr_drift.streaming): the count's key of a message dropped, or
    None when it is paired or waits for its partner."""
    if is_step and not (np.isfinite(heading) and 0 <= activity <= 4):
        return "bad_step"
    if not is_step:
        c = np.asarray(covariance, float).reshape(3, 3)
        if not (np.isfinite(position).all() and np.isfinite(c).all() and np.allclose(c, c.T)
                and np.linalg.eigvalsh(c).min() >= -1e-9):
            return "bad_pose"
    if live.last_stamp_ns is not None and stamp_ns <= live.last_stamp_ns:
        return "old_stamp"
    return None


@FUZZ
@given(st.lists(st.tuples(st.booleans(), st.integers(-2_000_000_000, 2_000_000_000), value,
                          st.integers(-3, 8), vector, st.lists(value, min_size=9, max_size=9)),
                max_size=60))
def test_landmark_drift_adapter_survives_garbage(events):
    live = StreamingDrift()
    stamp = BASE
    for is_step, offset, heading, activity, position, covariance in events:
        stamp += offset                     # mostly forward, sometimes back, often repeated
        before = dict(live.counts)
        with np.errstate(all="ignore"):
            expected = rule(live, is_step, stamp, heading, activity, position, covariance)
            result = (live.push_step(stamp, heading, activity) if is_step
                      else live.push_pose(stamp, position, covariance))
        counted = {k: n - before[k] for k, n in live.counts.items() if n != before[k]}
        assert counted == ({} if expected is None else {expected: 1}), "paired, waiting or counted"
        if expected is None:
            assert result is not None or stamp in (live.steps if is_step else live.poses)
        for correction in [] if result is None else result.corrections:
            assert np.isfinite([correction.yaw_rad, correction.gyro_bias_z_radps]).all()


def run_block(garbage_every: int = 0) -> tuple[list, StreamingDrift]:
    """BLOCK through StreamingDrift; with ``garbage_every`` > 0, before every such step a
    NaN step, a pose with a negative covariance and a step from the past."""
    live, results = StreamingDrift(), []
    for k, s in enumerate(BLOCK):
        stamp = BASE + round(s.t * 1e9)
        if garbage_every and k % garbage_every == 1:
            live.push_step(stamp, np.nan, LEVEL)
            live.push_pose(stamp, s.position, -np.eye(3))
            live.push_step(stamp - 10**10, s.heading, LEVEL)
        results.append(push_pair(live, stamp, s.heading, s.activity, s.position, s.covariance,
                                 k % 2 == 0))
    return results, live


def test_garbage_in_a_walk_changes_no_correction():
    clean, _ = run_block()
    corrections = [c for r in clean for c in r.corrections]
    assert len(corrections) >= 1 and all(np.isfinite(c.yaw_rad) for c in corrections)
    mixed, live = run_block(garbage_every=3)
    assert [[c.yaw_rad for c in r.corrections] for r in mixed] == \
        [[c.yaw_rad for c in r.corrections] for r in clean]
    assert [len(r.landmarks) for r in mixed] == [len(r.landmarks) for r in clean]
    garbage = sum(1 for k in range(len(BLOCK)) if k % 3 == 1)
    assert live.counts == {"bad_step": garbage, "bad_pose": garbage, "old_stamp": garbage,
                           "unpaired": 0, "before_restart": 0}
