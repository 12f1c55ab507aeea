"""pdr_core.evaluation.consistency: the NEES of an estimate against a truth, aligned as the error
metrics are (docs/reports.md, "Consistency: is the covariance honest?")."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdr_core.evaluation.consistency import (
    attitude_consistency,
    checkpoints,
    consistency_report,
    nees,
    nees_figures,
)
from pdr_core.maths.rotations import about_vertical

RATE_HZ = 10.0
SECONDS = 2000
HEADING_RAD = 0.7                   # the estimate's frame, turned from the truth's
POSITION_COV_M2 = np.array([[0.04, 0.01, 0.0], [0.01, 0.09, 0.0], [0.0, 0.0, 0.01]])
ATTITUDE_COV_RAD2 = np.diag([1e-4, 2e-4, 9e-4])


def walk(cov_scale: float, seed: int = 0) -> tuple:
    """A curving walk's truth and an estimate whose errors are drawn from the covariance
    (the one reported, ``cov_scale`` times it), expressed in a frame turned by
    -HEADING_RAD and shifted, as a navigator that starts with its own heading and origin.
    The errors are 0 over the first 3 m, so the alignment finds the turn exactly."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(SECONDS * RATE_HZ)) / RATE_HZ
    truth = np.column_stack([20 * np.sin(t / 60), 20 * (1 - np.cos(t / 60)), 0.01 * t])
    error = rng.multivariate_normal(np.zeros(3), POSITION_COV_M2, len(t))
    error[np.linalg.norm(truth - truth[0], axis=1) < 3] = 0
    estimate = about_vertical(truth + error, -HEADING_RAD) + [5.0, -2.0, 1.0]
    turn = Rotation.from_euler("z", -HEADING_RAD)
    cov = np.broadcast_to(turn.as_matrix() @ POSITION_COV_M2 @ turn.as_matrix().T * cov_scale,
                          (len(t), 3, 3))
    true_attitude = Rotation.random(len(t), random_state=seed)
    delta = Rotation.from_rotvec(rng.multivariate_normal(np.zeros(3), ATTITUDE_COV_RAD2, len(t)))
    attitude = turn * delta * true_attitude
    attitude_cov = np.broadcast_to(turn.as_matrix() @ ATTITUDE_COV_RAD2 @ turn.as_matrix().T
                                   * cov_scale, (len(t), 3, 3))
    return t, estimate, cov, truth, attitude.as_quat(), attitude_cov, true_attitude.as_quat()


def report(cov_scale: float) -> dict:
    t, estimate, cov, truth, attitude, attitude_cov, true_attitude = walk(cov_scale)
    at = checkpoints(t)
    return consistency_report(estimate, truth, at, cov[at],
                              (attitude[at], attitude_cov[at], true_attitude[at]))


def test_checkpoints_are_the_first_sample_of_each_second():
    t = np.arange(0.0, 3.2, 0.3)        # 0, 0.3, ..., 0.9, 1.2, ..., 3.0
    np.testing.assert_array_equal(checkpoints(t), [4, 7, 10])


def test_errors_drawn_from_the_covariance_are_inside_the_band():
    """Whatever the estimate's own heading and origin: ε/dof near 1, inside the band."""
    figures = report(1.0)
    for part in ("position_3d", "position_2d", "attitude"):
        assert figures[part]["samples"] == SECONDS - 1
        assert figures[part]["nees_per_dof"] == pytest.approx(1.0, abs=0.06), part
        assert figures[part]["inside"], part
    assert figures["position_3d"]["nees"] == pytest.approx(
        3 * figures["position_3d"]["nees_per_dof"])


def test_a_covariance_ten_times_too_small_is_outside():
    figures = report(0.1)
    for part in ("position_3d", "position_2d", "attitude"):
        high = figures[part]["band_per_dof"][1]
        assert figures[part]["nees_per_dof"] == pytest.approx(10.0, rel=0.06), part
        assert figures[part]["nees_per_dof"] > high and not figures[part]["inside"], part


def test_the_band_is_that_of_the_mean_of_n_chi_squared_samples():
    """χ²(n·k)/(n·k): for n = 1 and k = 3 the one-sample band of ε/3."""
    figures = nees_figures(np.array([3.0]), 3)
    assert figures["band_per_dof"] == pytest.approx([0.2158 / 3, 9.3484 / 3], rel=1e-4)
    assert figures["inside"]


def test_a_variance_of_zero_gives_no_nees():
    """The pocket on level ground: a vertical variance of 0 counts in no 3D ε."""
    cov = np.array([np.diag([1.0, 1.0, 0.0]), np.eye(3)])
    values = nees(np.ones((2, 3)), cov)
    assert np.isnan(values[0]) and values[1] == pytest.approx(3.0)
    assert nees_figures(values, 3)["samples"] == 1
    assert nees_figures(values[:1], 3) == {"samples": 0, "nees": None, "nees_per_dof": None,
                                           "band_per_dof": None, "inside": None}


def phone_attitudes(cov_scale: float, seed: int = 0) -> dict:
    """``pdr-pocket attitude``'s consistency of a phone that turns and sways: the estimate's
    errors drawn from the covariance (``cov_scale`` times it reported), in a navigation
    frame turned by -HEADING_RAD from the truth's (a filter with its own heading)."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(SECONDS * RATE_HZ)) / RATE_HZ
    truth = Rotation.from_euler("ZYX", np.column_stack(
        [t / 60, 0.2 * np.sin(t), 0.1 * np.cos(0.7 * t)]))
    turn = Rotation.from_euler("z", -HEADING_RAD)
    delta = Rotation.from_rotvec(rng.multivariate_normal(np.zeros(3), ATTITUDE_COV_RAD2, len(t)))
    cov = np.broadcast_to(turn.as_matrix() @ ATTITUDE_COV_RAD2 @ turn.as_matrix().T
                          * cov_scale, (len(t), 3, 3))
    return attitude_consistency(t, (turn * delta * truth).as_matrix(), cov, truth.as_matrix())


def test_attitude_alone_is_judged_with_the_heading_aligned_at_the_start():
    """The heading offset taken over the first seconds, the whole attitude (3 dof) and the
    tilt (2 dof) near 1 per dof when the errors are drawn from the covariance, 10 when it
    is ten times too small."""
    honest, small = phone_attitudes(1.0), phone_attitudes(0.1)
    for part in ("attitude", "tilt"):
        assert honest[part]["samples"] == SECONDS - 1
        assert honest[part]["nees_per_dof"] == pytest.approx(1.0, abs=0.08), part
        assert small[part]["nees_per_dof"] == pytest.approx(10.0, rel=0.08), part
        assert not small[part]["inside"], part
