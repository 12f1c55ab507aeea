"""Report metrics of docs/reports.md (the trajectory figures)."""
import itertools

import numpy as np
import pytest

from pdr_core.evaluation.metrics import aligned, error_report, walk_figures, within_step_rmse


def test_rotated_and_shifted_estimate_has_no_error():
    t = np.linspace(0, 10, 101)
    truth = np.column_stack([t, np.sin(t), 0.1 * t])
    angle = 0.7
    rot = np.array([[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0],
                    [0, 0, 1]])
    estimate = truth @ rot.T + [5.0, -3.0, 1.0]
    np.testing.assert_allclose(aligned(estimate, truth), truth - truth[0], atol=1e-12)
    report = error_report(t, estimate, truth)
    assert report["armse_3d_m"] == pytest.approx(0.0, abs=1e-12)
    assert report["duration_s"] == 10.0


def test_armse_follows_the_pyshoe_definition():
    t = np.arange(4.0)
    truth = np.column_stack([np.arange(4.0) * 1.0, np.zeros(4), np.zeros(4)])
    estimate = truth + [[0, 0, 0], [0, 0, 0.3], [0, 0, 0.3], [0, 0, 0.6]]
    report = error_report(t, estimate, truth)
    errors = np.array([0, 0.3, 0.3, 0.6])
    assert report["armse_3d_m"] == pytest.approx((errors / np.sqrt(3)).mean())
    assert report["armse_2d_m"] == pytest.approx(0.0)
    assert report["final_error_m"] == pytest.approx(0.6)
    assert report["final_error_pct"] == pytest.approx(20.0)
    assert report["mean_error_3d_m"] == pytest.approx(0.3)


def test_without_truth_the_loop_gap_is_reported():
    estimate = np.array([[0, 0, 0], [3, 0, 0], [3, 4, 0], [0.1, 0, 0]], float)
    report = error_report(np.arange(4.0), estimate, None)
    assert report == {"duration_s": 3.0, "distance_m": pytest.approx(3 + 4 + np.hypot(2.9, 4)),
                      "loop_gap_m": pytest.approx(0.1)}


def test_the_walks_figures_count_from_its_start():
    """Issue 29: one definition for pdr-pocket run and pdr-drift run, from the first IMU
    sample and the origin, not from the first step: a walk that stands 10 s at the
    origin, then steps 1 m east at 11 s and 1 m north at 12 s."""
    t = np.array([0.0, 11.0, 12.0])
    position = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0]], float)
    figures = walk_figures(t, position)
    assert figures == {"duration_s": 12.0, "distance_m": pytest.approx(2.0),
                       "loop_gap_m": pytest.approx(np.sqrt(2))}
    assert error_report(t, position, None) == figures
    assert error_report(t, position, position)["duration_s"] == 12.0


def test_within_step_error_ignores_each_steps_heading():
    """Steps whose heading error drifts from step to step, but are otherwise exact, have
    no within-step error; an offset in the middle of one step is counted."""
    t = np.linspace(0, 4, 401)
    truth = np.column_stack([t, 0.1 * np.sin(np.pi * t), 0.05 * np.abs(np.sin(np.pi * t))])
    cuts = np.arange(0, 401, 100)
    estimate = truth.copy()
    for k, (a, b) in enumerate(itertools.pairwise(cuts)):
        angle = 0.05 * (k + 1)
        d = truth[a:b + 1] - truth[a]
        c, s = np.cos(angle), np.sin(angle)
        estimate[a:b + 1] = estimate[a] + np.column_stack(
            [c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1], d[:, 2]])
    assert within_step_rmse(estimate, truth, cuts) == pytest.approx(0.0, abs=1e-12)
    estimate[150, 2] += 0.02
    assert within_step_rmse(estimate, truth, cuts) == pytest.approx(0.02 / np.sqrt(404))
    with pytest.raises(ValueError, match="two cuts"):
        within_step_rmse(estimate, truth, cuts[:1])
