"""The position filter of the pocket navigator (Muñoz Díaz 2016, chapter 6).

The thesis' state is the 3D position [x, y, z] (Eq. (6.1)), propagated once per step by
Eq. (5.1): x += s·cos ψ, y += s·sin ψ, z += v. Here it is augmented with the heading ψ
(the augmented form of Section 5.2) and the heading drift ε, the heading error rate the
orientation filter leaves (chapter 5's "drift"), so that the covariance grows as a
heading error that persists and grows from step to step makes it grow, not as
independent per-step noise:

    state X = [x, y, z, ψ, ε] (ENU; m, rad, rad/s), covariance P (5 × 5)
    per step j:  ψ ← the orientation filter's heading of the step (its mean; ε's mean 0)
                 P_ψψ += q_ψ = max(ΔP_yaw, 0)
                 X ← X + [s cos ψ, s sin ψ, v, 0, 0]
                 P ← F P Fᵀ + G diag(σ_s², σ_v², σ_ψ,step²) Gᵀ,
                 F = I + [[0,0,0,−s sin ψ,0],[0,0,0,s cos ψ,0],0,[0,0,0,0,Δt],0],
                 G = [[cos ψ, 0, −s sin ψ],[sin ψ, 0, s cos ψ],[0, 1, 0],0,0]

with ΔP_yaw the growth of the orientation filter's yaw variance since the previous step
(its gyroscope and bias uncertainty integrated), Δt the step's duration, σ_ε the prior
of the drift (``heading_drift_sigma_deg_per_s``: the orientation filter's own z-bias σ
is about ten times too small on a walking thigh, see docs/pocket.md), σ_s a stride's
scatter about its line, σ_v a step's climb's error (a stairs step's, or a level step's
grade times its stride, never 0) and σ_ψ,step the hip sway left in one step's mean
heading (an error of that step alone). The propagation is linear in the inputs given ψ,
so an extended filter with the exact Jacobian is what the unscented one of the thesis
computes here to second order. With a barometer, z is the height filter's
(:meth:`PositionFilter.hold_height`).

**What is published** (``pdr/pocket/odometry``, for a fusion node; issue 55) is the
covariance P̃ (6 × 6) of the same estimate's error with what P leaves out, the way the
foot's odometry carries its scaled covariance while its strides keep the filter's:

- the offset b [m] of the person's stride line from the one configured, the same in
  every level stride (Section 4.2.3), a state of P̃ (F[x,b] = cos ψ, F[y,b] = sin ψ for
  a stride of the level line), prior σ_b (``stride_offset_sigma_m``, or
  ``calibrated_stride_offset_sigma_m`` for a calibrated line);
- a fall of P_yaw (the orientation filter's field or rest updates outweighed its
  growth) as a heading update on ψ alone (:func:`_learn_heading`), which the position
  does not take;
- a flight's first step's climb, which the classifier's level prior may have put in the
  step before it, in z's variance (``missed_climb_var``).

P alone stays the filter's: its gains, the corrections' gates (Eqs. (6.2)-(6.3)),
``pdr/pocket/pose`` and ``pdr/pocket/step``, which the drift loop's association reads
(Eq. (5.4) adds both visits' absolute covariances, where b and the start's heading,
errors both visits share, would count twice). P̃ follows every update with the gain K
the filter computed from P, padded with 0 for b: the Joseph form holds for any gain, so
P̃ is the covariance of the error of the estimate the filter makes (Bar-Shalom et al.
2001, Section 5.2.3; a suboptimal filter's covariance analysis, Gelb 1974, chapter 7).

Updates (Eq. (6.3) and a heading fix), Kalman with a χ² gate:
:meth:`PositionFilter.correct_position` (3 dof) and :meth:`PositionFilter.correct_heading`
(1 dof, applied when the orientation filter accepted a yaw correction, so the position's
correlation with the heading is kept honest).
"""
from __future__ import annotations

import numpy as np

from pdr_core.maths.angles import wrap_angle
from pdr_core.maths.chi2 import chi2_quantile
from pdr_pocket.config import PositionConfig

X, Y, Z, PSI, EPS, B = range(6)
N_POSITION_STATE = 5        # P's states; P̃ adds b (module docstring)
N_PUBLISHED_STATE = 6


class PositionFilter:
    def __init__(self, config: PositionConfig | None = None, start=(0.0, 0.0, 0.0),
                 stride_offset_sigma_m: float = 0.0) -> None:
        """``stride_offset_sigma_m``: σ_b of P̃ [m] (module docstring)."""
        self.config = config or PositionConfig()
        self.x = np.zeros(N_POSITION_STATE)
        self.x[:3] = start
        self.p = np.zeros((N_POSITION_STATE, N_POSITION_STATE))
        self.p[:3, :3] = np.eye(3) * self.config.initial_position_sigma_m**2
        self.p[EPS, EPS] = np.radians(self.config.heading_drift_sigma_deg_per_s) ** 2
        self.published = np.zeros((N_PUBLISHED_STATE, N_PUBLISHED_STATE))
        self.published[:N_POSITION_STATE, :N_POSITION_STATE] = self.p
        self.published[B, B] = stride_offset_sigma_m**2
        self.yaw_variance: float | None = None
        self.step_heading_var = np.radians(self.config.heading_sigma_per_step_deg) ** 2

    def step(self, length_m: float, vertical_m: float, heading_rad: float,
             yaw_variance: float, length_var: float, vertical_var: float,
             duration_s: float, on_line: bool = False, missed_climb_var: float = 0.0
             ) -> None:
        """One step (Eq. (5.1)) with its input variances [m², rad²] and duration [s];
        for P̃ alone: ``on_line``, its stride is the level line's, which errs by the
        person's offset b, and ``missed_climb_var`` [m²] (module docstring)."""
        if self.yaw_variance is None:
            self.p[PSI, PSI] = self.published[PSI, PSI] = yaw_variance
        elif yaw_variance > self.yaw_variance:
            self.p[PSI, PSI] += yaw_variance - self.yaw_variance
            self.published[PSI, PSI] += yaw_variance - self.yaw_variance
        elif yaw_variance < self.yaw_variance:
            _learn_heading(self.published, yaw_variance / self.yaw_variance)
        self.yaw_variance = yaw_variance
        self.x[PSI] = heading_rad
        c, s = np.cos(heading_rad), np.sin(heading_rad)
        f = np.eye(N_PUBLISHED_STATE)
        f[X, PSI], f[Y, PSI] = -length_m * s, length_m * c
        f[PSI, EPS] = duration_s
        if on_line:
            f[X, B], f[Y, B] = c, s
        g = np.zeros((N_PUBLISHED_STATE, 3))
        g[X, 0], g[Y, 0], g[Z, 1] = c, s, 1.0
        g[X, 2], g[Y, 2] = -length_m * s, length_m * c
        self.x[:3] += (length_m * c, length_m * s, vertical_m)
        q = np.diag([length_var, vertical_var, self.step_heading_var])
        n = N_POSITION_STATE
        self.p = _symmetric(f[:n, :n] @ self.p @ f[:n, :n].T + g[:n] @ q @ g[:n].T)
        self.published = _symmetric(f @ self.published @ f.T + g @ q @ g.T)
        self.published[Z, Z] += missed_climb_var

    def hold_height(self, variance: float) -> None:
        """z is the height filter's fused height (pdr_pocket.height_filter): its variance
        [m²] is that filter's, uncorrelated with the horizontal and the heading."""
        for p in (self.p, self.published):
            p[Z, :] = 0.0
            p[:, Z] = 0.0
            p[Z, Z] = variance

    @property
    def position(self) -> np.ndarray:
        return self.x[:3].copy()

    @property
    def covariance(self) -> np.ndarray:
        """The filter's position covariance [m²] (3, 3): P's."""
        return self.p[:3, :3].copy()

    @property
    def published_covariance(self) -> np.ndarray:
        """The position covariance [m²] (3, 3) for a fusion node: P̃'s."""
        return self.published[:3, :3].copy()

    def gate_position(self, position, covariance) -> tuple[str | None, float]:
        """Why a position fix [m] with its covariance (3, 3) [m²] would be refused (None:
        it passes), and its NIS, against the covariance as it is now. An axis that both the
        filter and the fix know exactly (the height of a level walk) must agree and is left
        out of the update."""
        z = np.asarray(position, float)
        r = np.asarray(covariance, float).reshape(3, 3)
        if not (np.isfinite(z).all() and np.isfinite(r).all()):
            return "position fix: not finite", np.nan
        if not np.allclose(r, r.T) or np.linalg.eigvalsh(r).min() < 0:
            return "position fix: covariance not symmetric positive semi-definite", np.nan
        innovation = z - self.x[:3]
        keep = self._informative(r)
        if np.any(np.abs(innovation[~keep]) > 1e-6):
            return ("position fix: differs on an axis both know exactly (the change "
                    f"{_xyz(innovation)} m)"), np.nan
        if not keep.any():
            return "position fix: both covariances zero", np.nan
        s = (self.p[:3, :3] + r)[np.ix_(keep, keep)]
        nis = float(innovation[keep] @ np.linalg.solve(s, innovation[keep]))
        limit = float(chi2_quantile(self.config.correction_gate_probability, int(keep.sum())))
        if nis > limit:
            return (f"position fix refused by the χ² gate: NIS {nis:.1f} > {limit:.1f} "
                    f"({int(keep.sum())} dof, the change {_xyz(innovation)} m)"), nis
        return None, nis

    def _informative(self, r: np.ndarray) -> np.ndarray:
        return np.diag(self.p[:3, :3] + r) > 1e-12

    def correct_position(self, position, covariance) -> tuple[bool, str]:
        """Eq. (6.3): the landmark's first-visit position and its covariance (3, 3) [m,
        m²], refused (state untouched) as :meth:`gate_position` says."""
        problem, _ = self.gate_position(position, covariance)
        if problem is not None:
            return False, problem
        return True, self.apply_position(position, covariance)

    def apply_position(self, position, covariance) -> str:
        """The Kalman update of a fix that :meth:`gate_position` passed, not gated again
        (PocketNavigator.apply_correction gates every part before it applies any)."""
        r = np.asarray(covariance, float).reshape(3, 3)
        keep = self._informative(r)
        h = np.zeros((int(keep.sum()), N_POSITION_STATE))
        h[:, :3] = np.eye(3)[keep]
        z = np.asarray(position, float)
        return self._update(h, (z - self.x[:3])[keep], r[np.ix_(keep, keep)], "position fix")

    def correct_heading(self, heading_rad: float, variance: float,
                        yaw_variance_after: float) -> str:
        """A heading fix [rad, rad²] the orientation filter accepted (no gate here);
        ``yaw_variance_after``: its yaw variance once it took the fix, from which the next
        step's growth counts."""
        h = np.zeros((1, N_POSITION_STATE))
        h[0, PSI] = 1.0
        innovation = wrap_angle(heading_rad - self.x[PSI])
        message = self._update(h, np.array([innovation]), np.array([[variance]]), "heading")
        self.yaw_variance = yaw_variance_after
        return message

    def limit_drift(self, variance: float) -> None:
        """A z-bias correction of this variance [rad²/s²] went to the orientation filter:
        the drift left is no more uncertain than that (its correlations scaled alike)."""
        for p in (self.p, self.published):
            if 0 < variance < p[EPS, EPS]:
                scale = np.sqrt(variance / p[EPS, EPS])
                p[EPS, :] *= scale
                p[:, EPS] *= scale

    def _update(self, h: np.ndarray, innovation: np.ndarray, r: np.ndarray, what: str) -> str:
        """The Kalman update (Joseph form) of X and P, and of P̃ with the same gain
        (module docstring)."""
        s = h @ self.p @ h.T + r
        nis = float(innovation @ np.linalg.solve(s, innovation))
        k = self.p @ h.T @ np.linalg.inv(s)
        self.x = self.x + k @ innovation
        self.p = _joseph(self.p, k, h, r)
        pad = N_PUBLISHED_STATE - N_POSITION_STATE
        self.published = _joseph(self.published, np.pad(k, ((0, pad), (0, 0))),
                                 np.pad(h, ((0, 0), (0, pad))), r)
        return f"{what} applied (NIS {nis:.2f})"


def _joseph(p: np.ndarray, k: np.ndarray, h: np.ndarray, r: np.ndarray) -> np.ndarray:
    """(I − K·H)·P·(I − K·H)ᵀ + K·R·Kᵀ: the covariance after an update with the gain K,
    whether or not K is the optimal one for P."""
    i_kh = np.eye(len(p)) - k @ h
    return _symmetric(i_kh @ p @ i_kh.T + k @ r @ k.T)


def _learn_heading(p: np.ndarray, kept: float) -> None:
    """The orientation filter's yaw variance fell to ``kept`` times itself since the
    previous step (its field or rest updates outweighed the growth): a heading measurement
    with the gain k = 1 − ``kept`` on ψ alone, whose innovation the heading already took
    (the step's ψ is the filter's) and the position did not (nothing feeds it back).
    Joseph form with that gain, (I − k·e_ψ·e_ψᵀ)·P·(…)ᵀ + k²·R with R = P_ψψ·kept/k:
    P_ψψ and ψ's covariances with the other states shrink by ``kept`` in place, the
    position's own variances not (its error stays what it is)."""
    p[PSI, :] *= kept
    p[:, PSI] *= kept
    p[PSI, PSI] /= kept


def _symmetric(p: np.ndarray) -> np.ndarray:
    return 0.5 * (p + p.T)


def _xyz(v: np.ndarray) -> str:
    """A vector [m] labelled by its axes: "(x +0.10, y −0.02, z +0.00)"."""
    return "(" + ", ".join(f"{axis} {value:+.2f}" for axis, value
                           in zip("xyz", v, strict=True)) + ")"
