"""Trajectory error metrics: the ``report.json`` fields of docs/reports.md.

The estimate and the truth, both (N, 3) ENU [m] at the same stamps, are compared after
removing the start offset and rotating the estimate about the vertical so that its
horizontal displacement matches the truth's at the first sample where the estimate is
0.8 m from its start (heading is unobservable from the IMU alone).

- ``mean_error_3d_m``: mean Euclidean error;
- ``armse_3d_m`` / ``armse_2d_m``: the pyshoe papers' metric: per sample the RMS over the
  axes (Euclidean error / √3, or the horizontal error / √2), then the mean over samples;
- ``final_error_m`` and ``final_error_pct`` (of the true path length ``distance_m``);
- ``within_step_rmse_m`` (``pdr-ekf run``): :func:`within_step_rmse`.

:func:`walk_figures`: a walk's ``duration_s``, ``distance_m`` and ``loop_gap_m``, one
definition for every CLI that reports them (``pdr-ekf``, ``pdr-pocket run``, ``pdr-drift
run``), measured from the walk's start: the first IMU sample and the position the
navigator starts from.

:func:`truth_at` and :func:`truth_orientation_at` sample a ground-truth PoseStamped batch at
the estimate's stamps.
"""
from __future__ import annotations

import itertools

import numpy as np

from pdr_core.io.batch import MessageBatch
from pdr_core.maths.rotations import about_vertical

ALIGN_DISTANCE_M = 0.8


def alignment_yaw(estimate: np.ndarray, truth: np.ndarray,
                  distance_m: float = ALIGN_DISTANCE_M) -> float:
    """The angle [rad] about the vertical (counter-clockwise positive) that turns the
    estimate's horizontal displacement from its start onto the truth's at the first sample
    where the estimate is ``distance_m`` from its start (0: it never is); both (N, 3)."""
    est = estimate - estimate[0]
    ref = truth - truth[0]
    far = np.flatnonzero(np.linalg.norm(est[:, :2], axis=1) >= distance_m)
    if not len(far):
        return 0.0
    k = far[0]
    return float(np.arctan2(ref[k, 1], ref[k, 0]) - np.arctan2(est[k, 1], est[k, 0]))


def aligned(estimate: np.ndarray, truth: np.ndarray, distance_m: float = ALIGN_DISTANCE_M
            ) -> np.ndarray:
    """The estimate with the start offset removed and turned about the vertical onto the
    truth (start offset removed too) by :func:`alignment_yaw`, (N, 3)."""
    return about_vertical(estimate - estimate[0], alignment_yaw(estimate, truth, distance_m))


def path_length(position: np.ndarray) -> float:
    """Length [m] of a sampled path."""
    return float(np.linalg.norm(np.diff(position, axis=0), axis=1).sum())


def walk_figures(t_s: np.ndarray, position: np.ndarray) -> dict:
    """A walk's figures, whichever tool reports them. ``t_s`` (N,) [s] and ``position``
    (N, 3) ENU [m] begin at the walk's start: the first IMU sample and the position the
    navigator starts from (its origin); then one row per estimate (every sample of the
    foot navigator, each step's confirmation of a pocket navigator).

    - ``duration_s``: from the start to the last row [s];
    - ``distance_m``: the length of the path from the start through every position [m]
      (3D, so stairs count);
    - ``loop_gap_m``: the straight (3D) distance from the start to the last position [m].
    """
    return {"duration_s": float(t_s[-1] - t_s[0]), "distance_m": path_length(position),
            "loop_gap_m": float(np.linalg.norm(position[-1] - position[0]))}


def error_report(t_s: np.ndarray, estimate: np.ndarray, truth: np.ndarray | None) -> dict:
    """The trajectory figures of docs/reports.md, ``t_s`` and ``estimate`` from the walk's start
    as :func:`walk_figures` takes them. Without truth: :func:`walk_figures`. With truth:
    its ``duration_s``; ``distance_m`` is then the true path's length, and the errors
    (module docstring) replace the loop gap."""
    figures = walk_figures(t_s, estimate)
    if truth is None:
        return figures
    report = {"duration_s": figures["duration_s"]}
    est = aligned(estimate, truth)
    ref = truth - truth[0]
    error = est - ref
    norm3 = np.linalg.norm(error, axis=1)
    norm2 = np.linalg.norm(error[:, :2], axis=1)
    distance = path_length(truth)
    report |= {"distance_m": distance,
               "final_error_m": float(norm3[-1]),
               "final_error_pct": float(100 * norm3[-1] / distance) if distance else 0.0,
               "mean_error_3d_m": float(norm3.mean()),
               "armse_3d_m": float((norm3 / np.sqrt(3)).mean()),
               "armse_2d_m": float((norm2 / np.sqrt(2)).mean())}
    return report


def within_step_rmse(estimate: np.ndarray, truth: np.ndarray, cuts: np.ndarray) -> float:
    """RMS [m] of the error within steps, each step's heading error removed: between
    consecutive sample indices of ``cuts`` (e.g. the last stance sample before each
    swing), both paths are taken from the step's first sample and the truth is rotated
    about the vertical so that its displacement over the step points where the
    estimate's does. What remains is the error a step adds beyond heading, which is
    unobservable from the IMU alone and dominates any longer-range metric (issue 5: it
    shows what smoothing changes within the steps)."""
    errors = []
    for a, b in itertools.pairwise(cuts):
        est = estimate[a:b + 1] - estimate[a]
        ref = truth[a:b + 1] - truth[a]
        turned = about_vertical(ref, np.arctan2(est[-1, 1], est[-1, 0])
                                - np.arctan2(ref[-1, 1], ref[-1, 0]))
        errors.append(np.sum((est - turned) ** 2, axis=1))
    if not errors:
        raise ValueError("need at least two cuts")
    return float(np.sqrt(np.mean(np.concatenate(errors))))


def truth_at(truth: MessageBatch, stamp_ns: np.ndarray) -> np.ndarray:
    """Ground-truth positions (N, 3) [m] of a PoseStamped batch at ``stamp_ns``, linearly
    interpolated."""
    t = (truth.stamp_ns - stamp_ns[0]) * 1e-9
    q = (stamp_ns - stamp_ns[0]) * 1e-9
    return np.column_stack([np.interp(q, t, truth["pose.position"][:, i]) for i in range(3)])


def truth_orientation_at(truth: MessageBatch, stamp_ns: np.ndarray) -> np.ndarray:
    """Ground-truth orientations (N, 4) (x, y, z, w) of a PoseStamped batch at
    ``stamp_ns``, by spherical interpolation (held at the ends)."""
    from scipy.spatial.transform import Rotation, Slerp

    t = (truth.stamp_ns - truth.stamp_ns[0]) * 1e-9
    q = np.clip((stamp_ns - truth.stamp_ns[0]) * 1e-9, t[0], t[-1])
    return Slerp(t, Rotation.from_quat(truth["pose.orientation"]))(q).as_quat()
