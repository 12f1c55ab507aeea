"""The path walked between two visits of a place, and how much heading errors open it
(for the multi-hypothesis association, pdr_drift.hypotheses).

A heading that drifts at ε [rad/s] from a visit at t_A on turns each later step j by
ε·(t_j − t_A); a heading error in proportion to the angle turned (a gyroscope's scale
factor, or a navigator that loses a little of each turn) by s·(ψ_j − ψ_A). So the second
visit of the same place is found off the first by

    e = ε · Σ_j (t_j − t_A) · R₉₀ Δp_j + s · Σ_j (ψ_j − ψ_A) · R₉₀ Δp_j = ε·v + s·w

(Eq. (5.1) to first order in the errors) over the steps Δp_j [m] (ENU, horizontal)
walked from A to B with headings ψ_j [rad, unwrapped], R₉₀ the quarter turn
counter-clockwise. A constant heading error (the start's, or any error the two visits
share) turns the whole loop and opens nothing: the navigator's absolute position
covariance, which Eq. (5.4) adds for both visits, counts it twice. :class:`WalkedPath`
keeps cumulative sums, so that v(A, B) and w(A, B) are O(1) for any pair:

    v = R₉₀ [(T_B − T_A) − t_A (P_B − P_A)],   P = Σ Δp_j,  T = Σ t_j Δp_j,
    w = R₉₀ [(H_B − H_A) − ψ_A (P_B − P_A)],   H = Σ ψ_j Δp_j.

A heading that wanders as a random walk of σ_w² [rad²/s] (what a navigator's heading does
between corners beyond a drift: the hip's sway left in its step headings, the filter's
updates) turns everything walked after each step's instant: e has the covariance
σ_w² R₉₀ M R₉₀ᵀ, M = Σ_j Δt_j (P_B − P_j)(P_B − P_j)ᵀ over the steps after A, which the
sums of Δt_j, Δt_j P_j and Δt_j P_j P_jᵀ give in O(1) as well.
"""
from __future__ import annotations

import numpy as np

from pdr_core.maths.angles import wrap_angle

QUARTER_TURN = np.array([[0.0, -1.0], [1.0, 0.0]])


class WalkedPath:
    """The steps' times [s], unwrapped headings [rad] and horizontal moves [m], as
    cumulative sums."""

    def __init__(self) -> None:
        self.t: list[float] = []
        self.heading: list[float] = []           # ψ_j, unwrapped
        self.moved: list[np.ndarray] = []        # P: Σ Δp_j up to each step (2,)
        self.timed: list[np.ndarray] = []        # T: Σ t_j Δp_j ...
        self.turned: list[np.ndarray] = []       # H: Σ ψ_j Δp_j ...
        self.elapsed: list[float] = []           # Σ Δt_j ...
        self.first: list[np.ndarray] = []        # Σ Δt_j P_j ...
        self.second: list[np.ndarray] = []       # Σ Δt_j P_j P_jᵀ ...

    def __len__(self) -> int:
        return len(self.t)

    def append(self, t_s: float, heading_rad: float, move_m) -> None:
        """A step at ``t_s`` [s] with heading ``heading_rad`` that moved by ``move_m``
        [m] (its x and y are used)."""
        move = np.asarray(move_m, float)[:2]
        heading = float(heading_rad) if not self.heading else \
            self.heading[-1] + float(wrap_angle(heading_rad - self.heading[-1]))
        zero = np.zeros(2)
        self.moved.append((self.moved[-1] if self.moved else zero) + move)
        self.timed.append((self.timed[-1] if self.timed else zero) + t_s * move)
        self.turned.append((self.turned[-1] if self.turned else zero) + heading * move)
        dt = t_s - self.t[-1] if self.t else 0.0
        p = self.moved[-1]
        self.elapsed.append((self.elapsed[-1] if self.elapsed else 0.0) + dt)
        self.first.append((self.first[-1] if self.first else zero) + dt * p)
        self.second.append((self.second[-1] if self.second else np.zeros((2, 2)))
                           + dt * np.outer(p, p))
        self.t.append(float(t_s))
        self.heading.append(heading)

    def spreads(self, t_a_s: float, t_b_s: float) -> tuple[np.ndarray, np.ndarray]:
        """v(A, B) [m per rad/s] and w(A, B) [m per unit scale], (2,) each, of the module
        docstring, between the steps at or just before ``t_a_s`` and ``t_b_s`` [s]."""
        a, b = self._indices(t_a_s, t_b_s)
        moved = self.moved[b] - self.moved[a]
        return (QUARTER_TURN @ (self.timed[b] - self.timed[a] - self.t[a] * moved),
                QUARTER_TURN @ (self.turned[b] - self.turned[a] - self.heading[a] * moved))

    def wander(self, t_a_s: float, t_b_s: float) -> np.ndarray:
        """R₉₀ M R₉₀ᵀ [m² s] (2, 2) of the module docstring: the covariance of the gap a
        heading random walk of 1 rad²/s opens between the two steps."""
        a, b = self._indices(t_a_s, t_b_s)
        end = self.moved[b]
        s0 = self.elapsed[b] - self.elapsed[a]
        s1 = self.first[b] - self.first[a]
        m = s0 * np.outer(end, end) - np.outer(end, s1) - np.outer(s1, end) \
            + self.second[b] - self.second[a]
        return QUARTER_TURN @ m @ QUARTER_TURN.T

    def _indices(self, t_a_s: float, t_b_s: float) -> tuple[int, int]:
        """The steps at or just before the two instants [s]."""
        a, b = (max(int(np.searchsorted(self.t, t, "right")) - 1, 0) for t in (t_a_s, t_b_s))
        return a, b
