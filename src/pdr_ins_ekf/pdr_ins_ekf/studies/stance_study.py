"""Why a stance detector misses or invents stance on a recording with a position truth
(issue 45: the pyshoe VICON trial that climbs, docs/foot_ins.md "The foot on real stairs").

- :func:`zero_velocity_truth`: the foot at rest where the truth's speed is below a
  threshold, as pyshoe labels its VICON trials: the positions smoothed over
  :data:`SMOOTHING_S` and differentiated against time;
- :func:`stance_runs`: the runs of a boolean mask, as (first, stop) sample indices;
- :func:`false_stances`: the detected runs during which the truth never rests, with the
  detector's statistic there, the adaptive floor and the peak over the span, and their
  ratio (the valley's depth, pdr_ins_ekf.zero_velocity.AdaptiveShoeDetector);
- :func:`missed_stances`: the true rests the detector takes no sample of.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import maximum_filter1d, minimum_filter1d, uniform_filter1d

from pdr_ins_ekf.zero_velocity import AdaptiveShoeDetector, samples_of

SMOOTHING_S = 0.025          # the truth's positions averaged over this before the speed
REST_SPEED_MPS = 0.05        # at rest below this speed of the truth (marker noise: ~0.01)


def zero_velocity_truth(t_s: np.ndarray, position: np.ndarray,
                        threshold_mps: float = REST_SPEED_MPS) -> tuple[np.ndarray, np.ndarray]:
    """(at rest (N,), speed (N,) [m/s]) of the positions (N, 3) [m] at times t (N,) [s]."""
    rate = 1.0 / float(np.median(np.diff(t_s)))
    smooth = uniform_filter1d(position, samples_of(SMOOTHING_S, rate), axis=0, mode="nearest")
    speed = np.linalg.norm(np.gradient(smooth, t_s, axis=0), axis=1)
    return speed < threshold_mps, speed


def stance_runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """The runs of True in ``mask`` as (first, stop) indices, stop exclusive."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(int), [0]))))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True))


@dataclass(frozen=True)
class FalseStance:
    """A detected run on a moving foot: when [s], how long [samples], the truth's least
    speed there [m/s], the detector's least statistic, the span's floor and peak, their
    ratio (the valley's depth), and the largest angular rate [rad/s]."""

    t_s: float
    samples: int
    least_speed_mps: float
    statistic: float
    floor: float
    peak: float
    depth: float
    rate_radps: float


def false_stances(t_s: np.ndarray, detected: np.ndarray, at_rest: np.ndarray,
                  speed: np.ndarray, statistic: np.ndarray, gyro: np.ndarray,
                  detector: AdaptiveShoeDetector) -> list[FalseStance]:
    """The detected runs during which the truth is never at rest (module docstring)."""
    rate = 1.0 / float(np.median(np.diff(t_s)))
    span = samples_of(detector.span_s, rate)
    floor = minimum_filter1d(statistic, span, mode="nearest")
    peak = maximum_filter1d(statistic, span, mode="nearest")
    out = []
    for first, stop in stance_runs(detected):
        if at_rest[first:stop].any():
            continue
        k = first + int(np.argmin(statistic[first:stop]))
        out.append(FalseStance(float(t_s[first]), stop - first,
                               float(speed[first:stop].min()), float(statistic[k]),
                               float(floor[k]), float(peak[k]), float(peak[k] / floor[k]),
                               float(np.linalg.norm(gyro[first:stop], axis=1).max())))
    return out


def missed_stances(t_s: np.ndarray, detected: np.ndarray, at_rest: np.ndarray,
                   min_s: float = 0.1) -> list[tuple[float, float]]:
    """The true rests of at least ``min_s`` [s] with no detected sample: (start [s],
    duration [s]) each."""
    return [(float(t_s[a]), float(t_s[b - 1] - t_s[a])) for a, b in stance_runs(at_rest)
            if t_s[b - 1] - t_s[a] >= min_s and not detected[a:b].any()]
