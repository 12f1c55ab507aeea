"""The multi-hypothesis association (pdr_drift.hypotheses) and the walked path's spreads
(pdr_drift.walked_path), on constructed walks. The simulated walks, where the nearest
association goes wrong and this one does not, are in pdr_pocket's test_drift_loop.py."""
from __future__ import annotations

import numpy as np
import pytest
from drift_walks import LEVEL, SIDES, walk
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_drift.config import DriftConfig
from pdr_drift.estimator import DriftEstimator
from pdr_drift.walked_path import QUARTER_TURN, WalkedPath

MULTI = DriftConfig(association="multi_hypothesis")


@settings(max_examples=50, deadline=None)
@given(st.lists(st.tuples(st.floats(0.5, 2.0), st.floats(-np.pi, np.pi), st.floats(0.0, 2.0)),
                min_size=3, max_size=40), st.data())
def test_spreads_are_the_sums_they_stand_for(steps, data):
    """v = Σ (t_j − t_A) R₉₀ Δp_j, w = Σ (ψ_j − ψ_A) R₉₀ Δp_j and the wander's
    Σ Δt_j R₉₀ (P_B − P_j)(P_B − P_j)ᵀ R₉₀ᵀ over the steps after A up to B (walked_path's
    docstring), for any pair of steps."""
    path, t = WalkedPath(), 0.0
    moves = []
    for dt, psi, length in steps:
        t += dt
        move = length * np.array([np.cos(psi), np.sin(psi), 0.0])
        path.append(t, psi, move)
        moves.append(move[:2])
    a = data.draw(st.integers(0, len(steps) - 1))
    b = data.draw(st.integers(a, len(steps) - 1))
    times, headings = np.array(path.t), np.array(path.heading)
    expected_v = sum(((times[j] - times[a]) * QUARTER_TURN @ moves[j]
                      for j in range(a + 1, b + 1)), np.zeros(2))
    expected_w = sum(((headings[j] - headings[a]) * QUARTER_TURN @ moves[j]
                      for j in range(a + 1, b + 1)), np.zeros(2))
    positions = np.cumsum(moves, axis=0)
    expected_m = sum(((times[j] - times[j - 1]) * QUARTER_TURN
                      @ np.outer(positions[b] - positions[j], positions[b] - positions[j])
                      @ QUARTER_TURN.T for j in range(a + 1, b + 1)), np.zeros((2, 2)))
    assert np.allclose(path.wander(times[a], times[b]), expected_m,
                       atol=1e-6 * (1 + np.abs(expected_m).max()))
    v, w = path.spreads(times[a], times[b])
    assert np.allclose(v, expected_v, atol=1e-6 * (1 + np.abs(expected_v).max()))
    assert np.allclose(w, expected_w, atol=1e-6 * (1 + np.abs(expected_w).max()))
    assert np.all(np.abs(np.diff(headings)) <= np.pi + 1e-12)      # unwrapped


def test_a_drift_opens_a_loop_by_epsilon_times_v():
    """A square loop walked with a heading drifting at ε from its start ends ε·v away from
    it, to first order in ε (walked_path's docstring), whatever the constant heading error
    it also has."""
    epsilon, offset = np.radians(0.05), np.radians(20.0)
    path, end = WalkedPath(), np.zeros(2)
    path.append(0.0, offset, np.zeros(3))
    for k in range(160):
        t = k + 1.0
        heading = (k // 40) * np.pi / 2 + offset + epsilon * t
        move = 0.7 * np.array([np.cos(heading), np.sin(heading)])
        path.append(t, heading, np.r_[move, 0.0])
        end += move
    v, _ = path.spreads(0.0, 160.0)
    assert np.linalg.norm(end) > 1.0
    assert np.linalg.norm(end - epsilon * v) < 0.1 * np.linalg.norm(end)


def test_block_walk_associates_every_revisit_of_the_first_lap():
    """Two laps of a block with a drifting heading (test_drift's BLOCK): the second lap's
    four corners are the first's, each committed, the database never cleared (the
    nearest association clears it at each revisit and finds fewer)."""
    steps = walk([(0, 45, LEVEL), *SIDES, (90, 45, LEVEL), *SIDES, (90, 45, LEVEL), *SIDES],
                 drift_radps=np.radians(0.03))
    multi = DriftEstimator(MULTI, feedback=False)
    found = [(d.landmark_first, d.landmark_revisit) for s in steps for d in multi.push(s).drifts]
    found += [(d.landmark_first, d.landmark_revisit) for d in multi.finish().drifts]
    assert found and all(first % 4 == revisit % 4 for first, revisit in found)
    nearest = DriftEstimator(feedback=False)
    assert len([d for s in steps for d in nearest.push(s).drifts]) < len(found)


@pytest.mark.parametrize("k", [1, 2, 4])
def test_never_more_than_k_hypotheses(k):
    estimator = DriftEstimator(DriftConfig(association="multi_hypothesis", hypotheses_k=k),
                               feedback=False)
    for step in walk([(0, 45, LEVEL), *SIDES, (90, 45, LEVEL), *SIDES],
                     drift_radps=np.radians(0.05)):
        estimator.push(step)
        assert 1 <= len(estimator.hypotheses.hypotheses) <= k


def test_nearest_is_the_default_and_other_names_are_refused():
    assert DriftConfig().association == "nearest" and DriftEstimator().hypotheses is None
    with pytest.raises(ValueError, match="association must be one of nearest, multi_hypothesis"):
        DriftConfig(association="mht")
    with pytest.raises(ValueError, match="hypotheses_k must be > 0"):
        DriftConfig(hypotheses_k=0)


def test_a_correction_commits_as_of_the_step_that_commits_it():
    """With feedback, a commit's correction is its hypothesis' frame at the committing
    step: a finite yaw, drift and position, and the hypothesis starts again from the
    navigator's output (its frame zero) at that step."""
    estimator = DriftEstimator(MULTI, feedback=True)
    steps = walk([(0, 45, LEVEL), *SIDES, (90, 45, LEVEL), *SIDES, (90, 45, LEVEL), *SIDES],
                 drift_radps=np.radians(0.03))
    for step in steps:
        result = estimator.push(step)
        for c in result.corrections:
            assert np.isfinite([c.yaw_rad, c.gyro_bias_z_radps, *c.position_m]).all()
            frame = estimator.hypotheses.hypotheses[0].frame
            assert frame.yaw_rad == 0.0 and frame.drift_radps == 0.0 and frame.t_ref_s == step.t
