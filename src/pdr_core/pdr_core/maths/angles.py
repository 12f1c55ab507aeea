"""Angles on the circle, defined once: the wrap, the axial wrap and the circular mean.

- :func:`wrap_angle`: an angle [rad] to (−π, π], equal to it modulo 2π, as
  (a + π) mod 2π − π with −π taken to π (the range of arctan2 and of a heading west in
  the messages). :func:`wrap_angle_jit` is the same function compiled, for the kernels:
  both give the same bits, in NumPy and in numba (whose sin and cos, and so
  arctan2(sin a, cos a), differ from NumPy's in the last bit).
- :func:`wrap_axial`: an axis direction [rad] (a direction and its opposite are one) to
  (−π/2, π/2], equal to it modulo π.
- :func:`circular_mean`: the direction of the mean unit vector of angles [rad].

The wrap rounds: a result is exact to about 4e-16 rad (one unit in the last place of π),
and a rounding can give π for an angle just below −π.
"""
from __future__ import annotations

import numpy as np
from numba import njit


def wrap_angle(angle):
    """``angle`` [rad] (scalar or array) to (−π, π], equal to it modulo 2π."""
    wrapped = (angle + np.pi) % (2.0 * np.pi) - np.pi
    return wrapped + 2.0 * np.pi * (wrapped == -np.pi)      # −π + 2π is π exactly


wrap_angle_jit = njit(cache=True)(wrap_angle)


def wrap_axial(angle):
    """An axis direction ``angle`` [rad] to (−π/2, π/2], equal to it modulo π: the wrap of
    the doubled angle, halved."""
    return wrap_angle(2.0 * np.asarray(angle, float)) / 2.0


def circular_mean(angles) -> float:
    """The circular mean [rad] of ``angles`` [rad]: atan2(Σ sin a, Σ cos a), the direction of
    their mean unit vector, in [−π, π]."""
    a = np.asarray(angles, float)
    return float(np.arctan2(np.sin(a).sum(), np.cos(a).sum()))
