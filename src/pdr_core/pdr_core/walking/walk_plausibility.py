"""Whether a navigator's input looks like a walk, checked before its figures are trusted:
the checks both navigators (``pdr-ekf run``, ``pdr-pocket run``) share, each a warning on
the first line of the run's output, and with ``--strict`` a refusal (exit 2).

- :data:`WALK_SPECIFIC_FORCE_RANGE`: the median |f| [m/s²] of a walk, a run or a rest,
  and :func:`specific_force_problem`: what is wrong with one outside it, or with a
  gravity-removed accelerometer in any unit. The import's unit check
  (pdr_core.sensors.imu_checks.SPECIFIC_FORCE_RANGE, 0.5-5 g) only catches data a unit away; this
  one is the navigator's: a gravity-removed accelerometer read in g (a phone's "linear
  acceleration" file) has a median of 2-4 g at walking pace, which its slow part tells
  from a run's (pdr_core.sensors.imu_checks.gravity_removed).
- :data:`THIGH_SWING_MAX_RATIO` and :func:`swing_problem`: a thigh's pitch swing many
  times the one the walking lines give (pdr_pocket.placement's swing ratio ρ).
- :func:`implausible_input`: the problems found as warnings, or with ``strict`` an
  :class:`~pdr_core.errors.InputError` naming the file.
- :data:`EXIT_REFUSED`: the exit status of a run that read its input but refused to
  navigate it (``pdr-pocket run`` on a phone that is not in a pocket), its report
  written: a batch tool tells it from a crash (1) and from bad input (2).
"""
from __future__ import annotations

import numpy as np

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.sensors.imu_checks import (
    SLOW_PART_WINDOW_S,
    PlausibleRange,
    gravity_removed,
    median_specific_force_mps2,
    slow_part_median_norm,
)

# The median |f| of a walk is about 1 g (the legs' accelerations come and go about it):
# 1.00-1.31 g on the shared foot walks, 1.00-1.18 g on the shared thigh walks and jog; a
# foot-mounted IMU in a run reaches 2.16 g (a pyshoe trial). Below 0.5 g gravity is
# missing (a gravity-removed accelerometer); above 2.5 g no walk nor run gives it.
WALK_SPECIFIC_FORCE_MIN_MPS2 = 0.5 * STANDARD_GRAVITY_MPS2
WALK_SPECIFIC_FORCE_MAX_MPS2 = 2.5 * STANDARD_GRAVITY_MPS2
WALK_SPECIFIC_FORCE_RANGE = PlausibleRange(
    "median |f|", "m/s²", WALK_SPECIFIC_FORCE_MIN_MPS2, WALK_SPECIFIC_FORCE_MAX_MPS2,
    STANDARD_GRAVITY_MPS2, "0.5-2.5 g: a walk's is 0.9-1.3 g, a foot's in a run 2.2 g")
# A thigh's level swing is 0.82-1.17 of the walking lines' one on the shared thigh walks
# (windows of 8 cycles, 5-95 %), and the lines' swing at a walking cadence is 30-40°: a
# swing of twice that (60-80° every cycle) is no walk's, the pitch is not the thigh's
# (a tilt from a specific force without gravity, axes wrong)
THIGH_SWING_MAX_RATIO = 2.0
EXIT_REFUSED = 3


def specific_force_problem(t_s, accel_mps2) -> str | None:
    """What is wrong with specific forces (N, 3) [m/s²] at the stamps ``t_s`` [s] (N,)
    (None: nothing, or no finite sample), over the finite samples:

    - they look gravity-removed (pdr_core.sensors.imu_checks.gravity_removed: their 1 s mean is
      far below their median norm, in whatever unit they were read), whatever their
      median: a phone's "linear acceleration" read in g is about 2-4 g at walking pace,
      read in m/s² about 0.2 g;
    - else a median |f| outside :data:`WALK_SPECIFIC_FORCE_RANGE`: another unit."""
    t_s, accel_mps2 = np.asarray(t_s, float), np.asarray(accel_mps2, float)
    finite = np.isfinite(accel_mps2).all(axis=1) & np.isfinite(t_s)
    if not finite.any():
        return None
    t_s, accel_mps2 = t_s[finite], accel_mps2[finite]
    f = median_specific_force_mps2(accel_mps2)
    told = f"{WALK_SPECIFIC_FORCE_RANGE.statistic} {f:.1f} m/s² ({f / STANDARD_GRAVITY_MPS2:.2f} g)"
    if gravity_removed(t_s, accel_mps2):
        slow = slow_part_median_norm(t_s, accel_mps2)
        return (f"{told}, its {SLOW_PART_WINDOW_S:g} s mean {slow / f:.2f} times that (with "
                "gravity about 1): gravity is missing, the accelerometer is gravity-removed "
                "(a phone's linear or user acceleration; read in g it looks like several g): "
                "import the raw accelerometer, or add its gravity file (pdr-sim import-phone); "
                "the steps and distance are not to be trusted")
    if WALK_SPECIFIC_FORCE_RANGE.contains(f):
        return None
    return (f"{told} is no walk's ({WALK_SPECIFIC_FORCE_RANGE.expected}): the accelerometer "
            "is in another unit (g read as m/s², or m/s² read as g?) or not a specific "
            "force; the steps and distance are not to be trusted")


def swing_problem(swing_ratio: float | None) -> str | None:
    """What is wrong with a pitch swing ``swing_ratio`` times a thigh's (the placement's
    ρ, None: never judged) above :data:`THIGH_SWING_MAX_RATIO` (None: nothing)."""
    if swing_ratio is None or swing_ratio <= THIGH_SWING_MAX_RATIO:
        return None
    return (f"the pitch swings {swing_ratio:.1f} times a thigh's at its cadence (a walk's is "
            f"at most {THIGH_SWING_MAX_RATIO:g}): the pitch is not a thigh's (the accelerometer "
            "without gravity, or in another unit?); the strides are not to be trusted")


def implausible_input(source: object, problems: list[str | None], strict: bool) -> list[str]:
    """The ``problems`` found (None: none), as warnings; with ``strict`` the first raises
    :class:`~pdr_core.errors.InputError` naming ``source``."""
    found = [p for p in problems if p is not None]
    if strict and found:
        raise InputError(source, f"{found[0]} (refused: --strict)")
    return found
