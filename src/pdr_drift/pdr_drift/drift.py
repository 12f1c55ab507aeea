"""Heading drift from associated landmarks (Muñoz Díaz 2016, Sections 5.3 and 6.2).

- :func:`deviation`: δ between the first visit and the revisit. Stairs: δ = ψ₁ − ψ₂
  (Eq. (5.6)); corners: the mean over the revisit's two yaws (Eq. (5.5)). The revisit may
  go the same way or the opposite way, and for corners any combination of Fig. 5.4, so
  each revisit yaw is paired with the first visit's direction (yaw before or after, or
  its opposite) it lies nearest: δ is taken modulo 180°.
- :func:`drift_of`: the drift ε, the rate at which the estimated heading turns away from
  the truth, ε = −δ/Δt [rad/s] (Eq. (5.8) with Eq. (5.7)'s sign: ψ₂ = ψ₁ + ε·Δt). Its
  variance comes from a σ on each yaw, 4° in Section 5.3 (a thigh's heading, the hip's sway
  averaged; ``landmark_yaw_sigma_deg`` of pdr_drift.config).
- :func:`offline_drift`: ε₀ of Eq. (6.5), the Δt-weighted mean of the associations'
  drifts, after rejecting those beyond the sensor's plausible drift and those far from
  the others (more than ``spread_factor`` median absolute deviations from the median).

Signs, ENU yaw: ε > 0 means the estimated heading turns counter-clockwise too fast; the
orientation filter's z gyro bias should then grow by ε, and its yaw change by δ.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdr_core.maths.angles import wrap_axial
from pdr_core.vocabulary import LandmarkType
from pdr_drift.landmarks import Association

YAW_SIGMA_RAD = np.radians(4.0)      # each landmark yaw (Section 5.3), the default


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


def deviation(association: Association) -> tuple[float, int]:
    """δ [rad] (module docstring) and how many yaw pairs it averages."""
    first, revisit = association.first, association.revisit
    if first.type != LandmarkType.CORNER:
        return float(wrap_axial(first.yaw_before - revisit.yaw_before)), 1
    directions = np.array([first.yaw_before, first.yaw_after])
    deltas = []
    for yaw in (revisit.yaw_before, revisit.yaw_after):
        candidates = wrap_axial(directions - yaw)
        deltas.append(candidates[np.argmin(np.abs(candidates))])
    return float(np.mean(deltas)), 2


def drift_of(association: Association, since_s: float = -np.inf,
             yaw_sigma_rad: float = YAW_SIGMA_RAD) -> DriftEstimate:
    """ε = −δ/Δt with its variance (module docstring), each landmark yaw with σ
    ``yaw_sigma_rad``; Δt from the first visit, or from ``since_s`` [s] when later (the last
    correction of a hypothesis whose landmarks were corrected with it,
    pdr_drift.hypotheses)."""
    delta, pairs = deviation(association)
    elapsed = association.revisit.t - max(association.first.t, since_s)
    delta_var = 2 * yaw_sigma_rad**2 / pairs
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

