"""pdr-drift run's report (issue 29): the walk's figures from its start, and a correction's
move only when a correction was applied."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import POSE_WITH_COVARIANCE_STAMPED, STEP
from pdr_drift.config import DriftConfig
from pdr_drift.offline import correct, report

START_NS = 1_700_000_000_000_000_000
STANDING_S, PERIOD_S, STRIDE_M = 10.0, 1.1, 1.3


def straight_walk(steps: int = 40) -> tuple[MessageBatch, MessageBatch]:
    """Steps east after standing 10 s at the origin: no corner, nothing to correct."""
    stamps = START_NS + np.round((STANDING_S + PERIOD_S * np.arange(1, steps + 1)) * 1e9
                                 ).astype(np.int64)
    fields = {"index": np.arange(steps, dtype=np.uint32), "length": np.full(steps, STRIDE_M),
              "vertical_displacement": np.zeros(steps), "heading": np.zeros(steps),
              "pitch_max": np.full(steps, 0.4), "pitch_min": np.full(steps, -0.1),
              "pitch_amplitude": np.full(steps, 0.5), "duration": np.full(steps, PERIOD_S),
              "activity": np.ones(steps, np.uint8), "ride": np.zeros(steps, np.uint8),
              "ride_height": np.zeros(steps)}
    position = np.c_[STRIDE_M * np.arange(1, steps + 1), np.zeros((steps, 2))]
    covariance = np.zeros((steps, 6, 6))
    covariance[:, :3, :3] = np.eye(3) * 0.01
    quat = np.tile([0.0, 0.0, 0.0, 1.0], (steps, 1))
    return (MessageBatch(STEP, stamps, "map", fields),
            MessageBatch(POSE_WITH_COVARIANCE_STAMPED, stamps, "map", {
                "pose.pose.position": position, "pose.pose.orientation": quat,
                "pose.covariance": covariance.reshape(steps, 36)}))


def test_nothing_corrected_moves_nothing_and_the_figures_count_from_the_start():
    steps, poses = straight_walk()
    out = report(correct(steps, poses, DriftConfig(), 3.5, START_NS))
    assert out["associations"] == 0 and out["offline_drift_deg_per_s"] is None
    assert out["correction_applied"] is False and out["correction_shift_m"] == 0.0
    assert out["loop_gap_before_m"] == pytest.approx(out["loop_gap_after_m"], abs=1e-9)
    assert out["loop_gap_after_m"] == out["loop_gap_m"]
    # from the first IMU sample and the origin, not from the first step
    assert out["duration_s"] == pytest.approx(STANDING_S + 40 * PERIOD_S)
    assert out["distance_m"] == pytest.approx(40 * STRIDE_M)
    assert out["loop_gap_m"] == pytest.approx(40 * STRIDE_M)
    assert out["longest_step_m"] == pytest.approx(STRIDE_M)


def test_without_the_walks_start_the_first_steps_start_is_taken():
    steps, poses = straight_walk()
    result = correct(steps, poses, DriftConfig(), 3.5)
    assert result.start_ns == steps.stamp_ns[0] - round(PERIOD_S * 1e9)
    assert report(result)["duration_s"] == pytest.approx(40 * PERIOD_S)
