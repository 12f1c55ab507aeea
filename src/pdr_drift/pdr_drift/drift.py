"""Heading drift from associated landmarks (Muñoz Díaz 2016, Sections 5.3 and 6.2).

- :func:`deviation`: δ between the first visit and the revisit. Stairs: δ = ψ₁ − ψ₂
  (Eq. (5.6)); corners: the mean over the revisit's two yaws (Eq. (5.5)). The revisit may
  go the same way or the opposite way, and for corners any combination of Fig. 5.4, so
  each revisit yaw is paired with the first visit's direction (yaw before or after, or
  its opposite) it lies nearest: δ is taken modulo 180°.
- :func:`drift_of`: the drift ε, the rate at which the estimated heading turns away from
  the truth, ε = −δ/Δt [rad/s] (Eq. (5.8) with Eq. (5.7)'s sign: ψ₂ = ψ₁ + ε·Δt), with the
  variances of δ and ε (below).

**The variance of δ** is the landmarks' own, not a constant. Section 5.3 gives each yaw a
σ of 4°: a thigh's heading, the hip's sway (about 20° peak to peak) averaged over a
buffer of 1 s. Here each yaw is already the mean of ``q_steps`` step headings (corners) or
of a flight's (stairs), and each step heading the mean over a gait cycle, so what is left
(:class:`YawNoise`) is, per landmark yaw, the spread of the step headings it averages over
their count, s²/n (floored at σ_step², one step's heading about the line walked, since a
spread of two or three headings can come out near 0), plus σ_line², how far the line
walked on one visit lies from another's (a corridor walked again half a metre to the side
over 30 m: 1°). With p yaw pairs (two for a corner, Eq. (5.5); one for stairs, Eq.
(5.6)) σ_δ² = (σ₁² + σ₂²)/p. A corner's two pairs measure the same δ: their disagreement
is the fit's residual, (δ_b − δ_a)²/4 the variance of their mean that it shows, and the
larger of the two is kept (Bar-Shalom et al. 2001, Section 5.4: a filter is consistent
only when the variance it is given covers the error actually made).
- :func:`offline_drift`: ε₀ of Eq. (6.5), the Δt-weighted mean of the associations'
  drifts, after rejecting those beyond the sensor's plausible drift and those far from
  the others (more than ``spread_factor`` median absolute deviations from the median).

Signs, ENU yaw: ε > 0 means the estimated heading turns counter-clockwise too fast; the
orientation filter's z gyro bias should then grow by ε, and its yaw change by δ.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdr_core.angles import wrap_axial
from pdr_core.vocabulary import LandmarkType
from pdr_drift.landmarks import Association, Landmark


@dataclass(frozen=True)
class YawNoise:
    """What the error of a landmark yaw is made of (module docstring): σ of one step's
    heading about the line walked [rad], the floor of the steps' own spread, and σ of
    that line between two visits [rad]."""

    step_sigma_rad: float = float(np.radians(1.0))
    line_sigma_rad: float = float(np.radians(1.0))

    def variance(self, landmark: Landmark) -> float:
        """The variance [rad²] of each of ``landmark``'s yaws: σ_line² + max(s²,
        σ_step²)/n."""
        spread = max(landmark.yaw_spread, self.step_sigma_rad ** 2)
        return self.line_sigma_rad ** 2 + spread / max(landmark.yaw_count, 1)


@dataclass(frozen=True)
class DriftEstimate:
    """pdr_msgs/DriftEstimate: ids, δ [rad], Δt [s], ε [rad/s] and its variance."""

    landmark_first: int
    landmark_revisit: int
    deviation: float
    elapsed: float
    drift: float
    drift_variance: float
    deviation_variance: float


def pair_deviations(association: Association) -> list[float]:
    """δ of each yaw pair [rad] (module docstring): one for stairs, two for a corner."""
    first, revisit = association.first, association.revisit
    if first.type != LandmarkType.CORNER:
        return [float(wrap_axial(first.yaw_before - revisit.yaw_before))]
    directions = np.array([first.yaw_before, first.yaw_after])
    deltas = []
    for yaw in (revisit.yaw_before, revisit.yaw_after):
        candidates = wrap_axial(directions - yaw)
        deltas.append(float(candidates[np.argmin(np.abs(candidates))]))
    return deltas


def deviation(association: Association) -> tuple[float, int]:
    """δ [rad] (module docstring) and how many yaw pairs it averages."""
    deltas = pair_deviations(association)
    return float(np.mean(deltas)), len(deltas)


def deviation_variance(association: Association, noise: YawNoise) -> float:
    """σ_δ² [rad²] (module docstring): the landmarks' yaw variances over the pairs, or the
    pairs' disagreement when larger."""
    deltas = pair_deviations(association)
    pairs = len(deltas)
    model = (noise.variance(association.first) + noise.variance(association.revisit)) / pairs
    fit = (deltas[0] - deltas[1]) ** 2 / 4 if pairs == 2 else 0.0
    return max(model, fit)


def drift_of(association: Association, since_s: float = -np.inf,
             noise: YawNoise = YawNoise()) -> DriftEstimate:
    """ε = −δ/Δt with the variances of δ and ε (module docstring); Δt from the first
    visit, or from ``since_s`` [s] when later (the last correction of a hypothesis whose
    landmarks were corrected with it, pdr_drift.hypotheses)."""
    delta, _ = deviation(association)
    elapsed = association.revisit.t - max(association.first.t, since_s)
    delta_var = deviation_variance(association, noise)
    return DriftEstimate(association.first.id, association.revisit.id, delta, elapsed,
                         -delta / elapsed, delta_var / elapsed**2, delta_var)


def offline_drift(estimates: list[DriftEstimate], max_drift_radps: float,
                  spread_factor: float = 3.0) -> tuple[float | None, list[DriftEstimate]]:
    """ε₀ (Eq. (6.5)) and the estimates kept; None when none is left."""
    kept = [e for e in estimates if abs(e.drift) <= max_drift_radps]
    if len(kept) >= 3:
        drifts = np.array([e.drift for e in kept])
        median = np.median(drifts)
        mad = max(float(np.median(np.abs(drifts - median))), 1e-12)
        kept = [e for e in kept if abs(e.drift - median) <= spread_factor * 1.4826 * mad]
    if not kept:
        return None, []
    weights = np.array([e.elapsed for e in kept])
    return float(np.sum(weights * [e.drift for e in kept]) / weights.sum()), kept

