"""Is a navigator's covariance honest? The normalised estimation error squared (NEES)
against a truth: the ``consistency`` object of docs/reports.md.

ε = eᵀ·P⁻¹·e of an error e (k,) and its predicted covariance P (k, k) is χ²(k) if the
error is Gaussian with that covariance (Bar-Shalom et al., Estimation with Applications to
Tracking and Navigation, 2001, Section 5.4.2); its mean is k. The mean of n independent
ε, divided by k, then lies within χ²(n·k)/(n·k) at 2.5 % and 97.5 % with 95 %
probability: above the band the navigator is overconfident, below it pessimistic.

What is compared is what pdr_core.evaluation.metrics.error_report compares: the estimate
and the truth both start at 0, the estimate turned about the vertical onto the truth by
pdr_core.evaluation.metrics.alignment_yaw (the heading is unobservable), its covariance
turned with it.

- :func:`nees`: ε of each error against its covariance;
- :func:`checkpoints`: one sample a second, where the NEES are taken (consecutive samples
  of a filter are nearly the same draw; one a second is closer to the band's independence,
  yet still correlated over seconds, so the band is indicative);
- :func:`position_nees` and :func:`attitude_nees`: ε at the checkpoints, so aligned;
- :func:`attitude_consistency`: the attitude alone against an attitude truth (a phone's
  motion capture), the heading aligned at the start as pdr_core.evaluation.attitude_metrics does;
- :func:`nees_figures`: the mean NEES of some samples, per degree of freedom, the band;
- :func:`consistency_report`: position (3D and horizontal) and attitude together.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core.evaluation.attitude_metrics import heading_offset
from pdr_core.evaluation.metrics import aligned, alignment_yaw
from pdr_core.maths.chi2 import chi2_quantile
from pdr_core.maths.rotations import covariance_about_vertical

CHECKPOINT_INTERVAL_S = 1.0     # one NEES a second
BAND_PROBABILITY = 0.95         # the two-sided χ² band of the mean NEES
HORIZONTAL = slice(0, 2)        # x, y of an ENU position


def nees(error: np.ndarray, cov: np.ndarray) -> np.ndarray:
    """ε = eᵀ·P⁻¹·e (N,) of errors e (N, k) against covariances P (N, k, k); NaN where P is
    not positive definite (a variance of 0: no ε)."""
    out = np.full(len(error), np.nan)
    definite = np.linalg.eigvalsh(cov)[:, 0] > 0 if len(cov) else np.zeros(0, bool)
    e = error[definite]
    out[definite] = np.einsum("ni,ni->n", e, np.linalg.solve(cov[definite], e[..., None])[..., 0])
    return out


def checkpoints(t_s: np.ndarray, interval_s: float = CHECKPOINT_INTERVAL_S) -> np.ndarray:
    """The indices of the first sample of each ``interval_s`` after the first, ``t_s`` (N,)
    [s] increasing: one sample a second (the start, where both paths are 0, is left out)."""
    slot = np.floor((t_s - t_s[0]) / interval_s)
    return np.flatnonzero(np.diff(slot) > 0) + 1


def position_nees(position: np.ndarray, truth: np.ndarray, at: np.ndarray,
                  position_cov: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ε in 3D and horizontally (K,) each, at the samples ``at`` (K,) of the position (N, 3)
    ENU [m] against the truth (N, 3) [m] at the same stamps, whose covariances there are
    ``position_cov`` (K, 3, 3) [m²]. The error is pdr_core.evaluation.metrics.error_report's: both
    from their start, the estimate turned onto the truth by
    pdr_core.evaluation.metrics.alignment_yaw, its covariance turned with it."""
    error = (aligned(position, truth) - (truth - truth[0]))[at]
    cov = covariance_about_vertical(position_cov, alignment_yaw(position, truth))
    return nees(error, cov), nees(error[:, HORIZONTAL], cov[:, HORIZONTAL, HORIZONTAL])


def attitude_nees(attitude_xyzw: np.ndarray, cov: np.ndarray, truth_xyzw: np.ndarray,
                  yaw_rad: float) -> np.ndarray:
    """ε (K,) of the attitude error, the rotation vector in the truth's map frame of
    R̂'·Rᵀ [rad]: R̂' the estimated attitude (K, 4, x y z w; body to map) turned by
    ``yaw_rad`` about the vertical (the position's alignment,
    pdr_core.evaluation.metrics.alignment_yaw), R the truth's (K, 4); ``cov`` (K, 3, 3) [rad²] the
    estimate's covariance of rotations about the map's axes (``pose.covariance``'s),
    turned with it."""
    return nees(attitude_error(Rotation.from_quat(attitude_xyzw),
                               Rotation.from_quat(truth_xyzw), yaw_rad),
                covariance_about_vertical(cov, yaw_rad))


def attitude_error(attitude: Rotation, truth: Rotation, yaw_rad: float) -> np.ndarray:
    """The rotation vectors (K, 3) [rad] of R̂'·Rᵀ in the truth's map frame, R̂' the
    estimate (K rotations, body to map) turned by ``yaw_rad`` about the vertical, R the
    truth's."""
    return (Rotation.from_euler("z", yaw_rad) * attitude * truth.inv()).as_rotvec()


def attitude_consistency(t_s: np.ndarray, attitude: np.ndarray, cov: np.ndarray,
                         truth: np.ndarray) -> dict:
    """The ``consistency`` object of ``pdr-pocket attitude`` (docs/reports.md): at the
    :func:`checkpoints` of ``t_s`` (N,) [s], the NEES of the attitude C_b^n (N, 3, 3)
    against the truth's (N, 3, 3), its covariance ``cov`` (N, 3, 3) [rad²] of rotations
    about the navigation frame's axes: ``attitude`` (3 dof, the estimate turned about
    the vertical onto the truth by pdr_core.evaluation.attitude_metrics.heading_offset, the heading
    being relative to the start's as the heading error is) and ``tilt`` (2 dof, the
    horizontal components: the vertical's error, which no turn changes)."""
    at = checkpoints(t_s)
    yaw = -heading_offset(t_s, attitude, truth)
    error = attitude_error(Rotation.from_matrix(attitude[at]), Rotation.from_matrix(truth[at]),
                           yaw)
    turned = covariance_about_vertical(cov[at], yaw)
    return {"attitude": nees_figures(nees(error, turned), 3),
            "tilt": nees_figures(nees(error[:, HORIZONTAL], turned[:, HORIZONTAL, HORIZONTAL]),
                                 2)}


def nees_figures(values: np.ndarray, dof: int) -> dict:
    """The figures of the ε ``values`` (K,) of ``dof`` degrees of freedom, over those that
    are not NaN: ``samples`` n, ``nees`` their mean, ``nees_per_dof`` the mean / dof,
    ``band_per_dof`` its :data:`BAND_PROBABILITY` band for n independent samples,
    χ²(n·dof)/(n·dof) at (1 ∓ p)/2, and ``inside`` whether it is in it (all None when n
    is 0)."""
    values = values[~np.isnan(values)]
    if not len(values):
        return {"samples": 0, "nees": None, "nees_per_dof": None, "band_per_dof": None,
                "inside": None}
    n, mean = len(values), float(values.mean())
    tail = (1 - BAND_PROBABILITY) / 2
    low, high = (chi2_quantile(p, n * dof) / (n * dof) for p in (tail, 1 - tail))
    return {"samples": n, "nees": mean, "nees_per_dof": mean / dof,
            "band_per_dof": [float(low), float(high)],
            "inside": bool(low <= mean / dof <= high)}


def consistency_report(position: np.ndarray, truth: np.ndarray, at: np.ndarray,
                       position_cov: np.ndarray,
                       attitude: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
                       ) -> dict:
    """The ``consistency`` object of docs/reports.md: :func:`nees_figures` at the samples
    ``at`` (K,) (:func:`checkpoints` of the estimate's stamps) of :func:`position_nees` in
    3D (``position_3d``) and horizontally (``position_2d``), the position (N, 3) [m] and
    the truth (N, 3) [m] whole, ``position_cov`` (K, 3, 3) [m²] at ``at``; and of
    :func:`attitude_nees` for ``attitude`` (the estimate (K, 4) x y z w, its covariance
    (K, 3, 3) [rad²] and the truth's (K, 4), at ``at``; None: no ``attitude`` part)."""
    nees_3d, nees_2d = position_nees(position, truth, at, position_cov)
    parts = {"position_3d": nees_figures(nees_3d, 3), "position_2d": nees_figures(nees_2d, 2)}
    if attitude is not None:
        parts["attitude"] = nees_figures(
            attitude_nees(*attitude, alignment_yaw(position, truth)), 3)
    return parts


def has_attitude(truth_xyzw: np.ndarray) -> bool:
    """Whether a truth's orientations (N, 4) are an attitude: a truth of positions only is
    the identity at every sample (pdr_core.io.csv_import.pose_batch)."""
    return bool(np.any(np.abs(truth_xyzw[:, :3]) > 0))
