"""What a change of the barometric height was (pdr_pocket.height_filter's docstring,
"Changes of the barometric height and the rides"), as plain functions of the epochs the
filter keeps: where it passed 10 % and 90 % of its height (:func:`passages`), the vertical
force's double integral over the still span around it, a lift's pulses
(:func:`force_height`), its kind: stairs, a lift, an escalator or an offset
(:func:`change_kind`), and the variance of its height from the levels before and after
(:func:`change_height_variance`).
"""
from __future__ import annotations

import numpy as np

from pdr_core.sensors.barometry import PRESSURE_NOISE_RATE_HZ, HeightChangeKind
from pdr_pocket.config import BarometerConfig
from pdr_pocket.height_records import Epochs, HeightCoefficients, epoch_count

# a change of the barometric height this close to a stairs step's climb was walked
STAIRS_MARGIN_S = 1.0
# the change's start and end: where the barometric height passes these shares of it
START_SHARE, END_SHARE = 0.1, 0.9


def change_kind(config: BarometerConfig, stairs: list[tuple[float, float]], height: float,
                start_s: float, end_s: float, z: np.ndarray, accel: float
                ) -> HeightChangeKind | None:
    """What a change of ``height`` [m] between ``start_s`` and ``end_s`` [s] was,
    with ``z`` its epochs' barometric heights from 10 % to 90 % and ``accel`` the
    vertical force's double integral over it (pdr_pocket.height_filter's docstring, 1-4);
    ``stairs``: the stairs steps' climbs (start, end) [s]; None: too small
    to be anything."""
    c = config
    if any(t1 >= start_s - STAIRS_MARGIN_S and t0 <= end_s + STAIRS_MARGIN_S
           for t0, t1 in stairs):
        return HeightChangeKind.STAIRS
    big = abs(height) >= c.ride_min_height_m
    if big and np.isfinite(accel) and \
            1.0 / c.lift_height_ratio_max <= accel / height <= c.lift_height_ratio_max:
        return HeightChangeKind.LIFT
    if big and c.escalators and end_s - start_s >= c.escalator_min_s:
        one_second = epoch_count(1.0, c.epoch_s)
        speed = np.abs(z[one_second:] - z[:-one_second]) / (one_second * c.epoch_s)
        if len(speed) and np.nanmax(speed) <= c.escalator_max_speed_mps:
            return HeightChangeKind.ESCALATOR
    if abs(height) < c.motion_speed_mps * c.motion_window_s:
        return None
    return HeightChangeKind.OFFSET


def force_height(config: BarometerConfig, epochs: Epochs, lo: int, hi: int, start: int,
                 end: int) -> float:
    """The vertical force's double integral [m] over the still span around the
    change's epochs [lo, hi) that holds its 10-90 % epochs [start, end], with zero
    velocity at both ends; NaN when the person was not still enough or the speed does
    not peak beyond lift_min_speed_mps in the integral's direction."""
    c = config
    still = epochs.array("still", lo, hi).astype(bool)
    index = np.flatnonzero(still)
    if not len(index):
        return np.nan
    first, last = lo + index[0], lo + index[-1] + 1
    span = still[index[0]:index[-1] + 1]
    if first > start or last <= end or span.mean() < c.lift_min_still_fraction:
        return np.nan
    force = epochs.array("force", first, last)
    if not np.isfinite(force).all():
        return np.nan
    dt = c.epoch_s
    velocity = np.concatenate([[0.0], np.cumsum((force - force.mean()) * dt)])
    velocity -= velocity[-1] * np.arange(len(velocity)) / len(force)
    height = float(np.sum(velocity[:-1] + velocity[1:]) * dt / 2.0)
    if not np.max(velocity * np.sign(height)) >= c.lift_min_speed_mps:
        return np.nan
    return height


def change_height_variance(coefficients: HeightCoefficients, epochs: Epochs,
                           before: np.ndarray, after: np.ndarray) -> float:
    """The variance of a change's height from its levels' means [m²]."""
    c = coefficients
    n = epochs.columns["n"][-len(after):]
    per_epoch = c.reading_var_m2 / max(1.0 / PRESSURE_NOISE_RATE_HZ, float(np.mean(n))) \
        + c.correlated_var_m2
    return per_epoch * (1.0 / np.isfinite(before).sum() + 1.0 / np.isfinite(after).sum())


def passages(z: np.ndarray, before: float, after: float) -> tuple[int, int]:
    """The indices of ``z`` (a change's epochs) where it is last below 10 % of the way
    from ``before`` to ``after`` before first reaching 90 %, plus one, and where it first
    reaches 90 %."""
    share = (z - before) / (after - before) if after != before else np.zeros_like(z)
    reached = np.flatnonzero(share >= END_SHARE)
    end = int(reached[0]) if len(reached) else len(z) - 1
    below = np.flatnonzero(share[:end + 1] < START_SHARE)
    start = int(below[-1]) + 1 if len(below) else 0
    return min(start, end), end
