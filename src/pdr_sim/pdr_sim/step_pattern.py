"""Foot step patterns during the swing, with analytic first and second derivatives.

Every pattern gives four channels as functions of τ, the time since the start of the
swing (0 ≤ τ ≤ t_u): along-track displacement s [m], height z [m], and the pitch and roll
offsets Δθ, Δφ [rad] from the stance attitude. Each channel is a :class:`Channel` of
value, first and second time derivative, shape (N,).

Patterns are written over the swing phase w ∈ [0, 1]:

- :func:`basic_swing`: Zampella et al. 2011, Eqs. (1)–(2):
  s = SL/2·(1 − cos(πw)), z = SH/2·(1 − cos(2πw)), Δθ = θ_max·sin(2πw), Δφ = 0.
- :class:`FittedPattern`: Eqs. (3)–(4), two (half) raised cosines per channel
  (:class:`RaisedCosines`), as fitted by :mod:`pdr_sim.step_fit`.

Timing. With w = τ/t_u (``timing="linear"``) the patterns are exactly the paper's, whose
acceleration and turn rate jump at the stance/swing boundaries (s̈(0) = SL·π²/(2t_u²),
θ̇(0) = 2πθ_max/t_u): such a trajectory is not twice differentiable, and no sampled-rate
integrator converges on it faster than first order. The default ``timing="smooth"`` runs
the same curves on the quintic phase w = 10x³ − 15x⁴ + 6x⁵ (x = τ/t_u), whose first and
second derivatives vanish at both ends: positions, velocities, accelerations, attitude
and turn rates are then continuous through every boundary, with the same step length,
height, maximal pitch and durations.

Frames: s runs along the direction of travel, z up; with the FLU body frame a positive
Δθ turns the toes down (Zampella et al. 2011 use NWU, the same handedness).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

TIMINGS = ("smooth", "linear")


@dataclass(frozen=True)
class Channel:
    """Value and first and second derivatives of one pattern channel, each (N,)."""

    f: np.ndarray
    d1: np.ndarray
    d2: np.ndarray

    def __add__(self, other: Channel) -> Channel:
        return Channel(self.f + other.f, self.d1 + other.d1, self.d2 + other.d2)

    def scaled(self, k) -> Channel:
        return Channel(self.f * k, self.d1 * k, self.d2 * k)

    def in_time(self, phase: Channel) -> Channel:
        """This channel, given over the swing phase w, as a function of time through
        w(τ): chain rule f_τ = f_w·ẇ, f_ττ = f_ww·ẇ² + f_w·ẅ."""
        return Channel(self.f, self.d1 * phase.d1, self.d2 * phase.d1**2 + self.d1 * phase.d2)


@dataclass(frozen=True)
class Swing:
    """The four channels of a swing, as functions of time."""

    s: Channel
    z: Channel
    pitch: Channel
    roll: Channel


def swing_phase(tau: np.ndarray, swing_s, timing: str = "smooth") -> Channel:
    """w(τ) ∈ [0, 1] and its time derivatives (see the module docstring)."""
    x = tau / swing_s
    if timing == "linear":
        return Channel(x, np.ones_like(x) / swing_s, np.zeros_like(x))
    if timing != "smooth":
        raise ValueError(f"timing must be one of {TIMINGS}, got {timing!r}")
    w = x**3 * (10 - 15 * x + 6 * x**2)
    w_x = 30 * x**2 * (1 - x) ** 2
    w_xx = 60 * x * (1 - x) * (1 - 2 * x)
    return Channel(w, w_x / swing_s, w_xx / swing_s**2)


def _one_minus_cos(amplitude, omega, w) -> Channel:
    """A·(1 − cos(ω·w)) with derivatives in w."""
    phase = omega * w
    return Channel(amplitude * (1 - np.cos(phase)), amplitude * omega * np.sin(phase),
                   amplitude * omega**2 * np.cos(phase))


def basic_swing(phase: Channel, length_m, height_m, pitch_max_rad) -> Swing:
    """Zampella et al. 2011, Eqs. (1)–(2); parameters scalars or (N,) per sample."""
    w = phase.f
    zero = np.zeros_like(w)
    two_pi = 2 * np.pi
    pitch_w = Channel(pitch_max_rad * np.sin(two_pi * w),
                      pitch_max_rad * two_pi * np.cos(two_pi * w),
                      -pitch_max_rad * two_pi**2 * np.sin(two_pi * w))
    return Swing(s=_one_minus_cos(np.asarray(length_m) / 2, np.pi, w).in_time(phase),
                 z=_one_minus_cos(np.asarray(height_m) / 2, two_pi, w).in_time(phase),
                 pitch=pitch_w.in_time(phase), roll=Channel(zero, zero, zero))


@dataclass(frozen=True)
class RaisedCosines:
    """f(t) = A0·(1 − cos(k·π·f0·(t − t0))) + A1·(1 − cos(k·π·f1·(t − t1))), t [s].

    k = 2 for Eq. (3) (height, roll, pitch), k = 1 for Eq. (4) (along-track, "half"
    raised cosines), Zampella et al. 2011.
    """

    a0: float
    a1: float
    f0: float
    f1: float
    t0: float
    t1: float
    half: bool = False

    def __call__(self, t: np.ndarray) -> Channel:
        """Value and derivatives in t."""
        k = np.pi if self.half else 2 * np.pi
        t = np.asarray(t, float)
        return (_one_minus_cos(self.a0, k * self.f0, t - self.t0)
                + _one_minus_cos(self.a1, k * self.f1, t - self.t1))

    def as_list(self) -> list[float]:
        return [self.a0, self.a1, self.f0, self.f1, self.t0, self.t1]


@dataclass(frozen=True)
class FittedPattern:
    """Fitted raised-cosine channels over a swing of ``swing_s`` seconds.

    Used for a step of another duration and length through the swing phase (time scaled
    to t_u) and with the along-track channel scaled to the step length. A fit does not
    end exactly at rest, so each channel is closed: f − f(0)·(1 − c) − (f(T) − target)·c
    with c = (1 − cos(πw))/2, which starts and ends the step exactly at (0, 0, 0, 0) and
    (SL, 0, 0, 0) and keeps the pattern twice differentiable in w.
    """

    swing_s: float
    s: RaisedCosines
    z: RaisedCosines
    pitch: RaisedCosines
    roll: RaisedCosines

    def swing(self, phase: Channel, length_m) -> Swing:
        w = phase.f
        closure = _one_minus_cos(0.5, np.pi, w)
        one_minus = Channel(1 - closure.f, -closure.d1, -closure.d2)

        def channel(model: RaisedCosines, target) -> Channel:
            raw = model(self.swing_s * w)
            in_w = Channel(raw.f, raw.d1 * self.swing_s, raw.d2 * self.swing_s**2)
            start, stop = float(model(0.0).f), float(model(self.swing_s).f)
            return in_w + one_minus.scaled(-start) + closure.scaled(-(stop - target))

        span = float(self.s(self.swing_s).f - self.s(0.0).f)
        return Swing(s=channel(self.s, span).scaled(np.asarray(length_m) / span).in_time(phase),
                     z=channel(self.z, 0.0).in_time(phase),
                     pitch=channel(self.pitch, 0.0).in_time(phase),
                     roll=channel(self.roll, 0.0).in_time(phase))
