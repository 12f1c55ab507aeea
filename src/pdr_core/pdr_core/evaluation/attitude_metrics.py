"""Attitude errors against a truth, one definition for every tool that reports them
(``pdr-pocket attitude``, test/benchmarks/bench_attitude_peers.py).

Attitudes are C_b^n (N, 3, 3): the body (sensor) frame to a navigation frame whose z is up.
The estimate's and the truth's navigation frames may differ by a turn about the vertical
(a filter without an absolute heading, VQF's frame, a motion-capture room's), which the
heading error removes and the tilt error never sees.

- :func:`level_axis`: the body axis the truth holds most level over the record (the
  smallest mean |vertical component|): a phone in the hand held flat keeps x and y level,
  one held upright x and z; its heading is defined through every attitude the record
  shows, where a yaw angle is not (it jumps by 180° as the pitch passes 90°).
- :func:`heading_error`: the heading of that axis (the azimuth of its horizontal part),
  estimate minus truth, relative to its circular mean over the first ``reference_s``
  seconds, wrapped to (−π, π] [rad]: a filter with and one without an absolute heading
  are scored alike, by how far their heading moves from the truth's over the walk.
- :func:`heading_offset`: that mean itself, the turn between the two navigation frames;
- :func:`tilt_error`: the angle between the estimated and the true vertical [rad].
- :func:`error_summary`: RMS, mean, largest |error| and final value of a series, in degrees.
"""
from __future__ import annotations

import numpy as np

from pdr_core.maths.angles import wrap_angle

HEADING_REFERENCE_S = 2.0       # the heading error is relative to its mean over this start


def level_axis(truth: np.ndarray) -> int:
    """The body axis (0, 1, 2) with the smallest mean |vertical component| in the truth's
    attitudes (N, 3, 3)."""
    return int(np.argmin(np.abs(truth[:, 2, :]).mean(axis=0)))


def axis_heading(attitude: np.ndarray, axis: int) -> np.ndarray:
    """The azimuth [rad] of body axis ``axis`` in the navigation frame, (N,):
    atan2(north, east) of its horizontal part, counter-clockwise from east."""
    column = attitude[:, :, axis]
    return np.arctan2(column[:, 1], column[:, 0])


def heading_error(t_s: np.ndarray, estimate: np.ndarray, truth: np.ndarray,
                  reference_s: float = HEADING_REFERENCE_S, axis: int | None = None
                  ) -> np.ndarray:
    """The heading error (module docstring) [rad], (N,), of C_b^n ``estimate`` against
    ``truth`` (both (N, 3, 3) at the stamps ``t_s`` (N,) [s]), on the truth's
    :func:`level_axis` unless ``axis`` is given."""
    raw = _heading_difference(estimate, truth, level_axis(truth) if axis is None else axis)
    return wrap_angle(raw - _start_mean(t_s, raw, reference_s))


def heading_offset(t_s: np.ndarray, estimate: np.ndarray, truth: np.ndarray,
                   reference_s: float = HEADING_REFERENCE_S) -> float:
    """The turn about the vertical [rad] from the truth's navigation frame to the
    estimate's: the circular mean over the first ``reference_s`` of the heading of the
    truth's :func:`level_axis`, estimate minus truth (what :func:`heading_error` removes)."""
    return _start_mean(t_s, _heading_difference(estimate, truth, level_axis(truth)),
                       reference_s)


def _heading_difference(estimate: np.ndarray, truth: np.ndarray, axis: int) -> np.ndarray:
    """The heading of body ``axis``, estimate minus truth [rad], wrapped, (N,)."""
    return wrap_angle(axis_heading(estimate, axis) - axis_heading(truth, axis))


def _start_mean(t_s: np.ndarray, angle: np.ndarray, reference_s: float) -> float:
    """The circular mean [rad] of ``angle`` (N,) over the first ``reference_s`` of ``t_s``."""
    start = t_s <= t_s[0] + reference_s
    return float(np.arctan2(np.sin(angle[start]).mean(), np.cos(angle[start]).mean()))


def tilt_error(estimate: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """The angle [rad] between the estimated and the true vertical, each seen in the body
    frame (the third rows of C_b^n), (N,)."""
    cosine = np.einsum("nj,nj->n", estimate[:, 2, :], truth[:, 2, :])
    return np.arccos(np.clip(cosine, -1.0, 1.0))


def error_summary(error_rad: np.ndarray) -> dict:
    """``rms_deg``, ``mean_deg``, ``max_abs_deg`` and ``final_deg`` of a series [rad]."""
    e = np.degrees(np.asarray(error_rad, float))
    return {"rms_deg": float(np.sqrt(np.mean(e**2))), "mean_deg": float(e.mean()),
            "max_abs_deg": float(np.abs(e).max()), "final_deg": float(e[-1])}
