"""Pieces of a foot's motion beyond the paper's step pattern, with analytic derivatives.

The gaits of :mod:`pdr_sim.foot_gaits` are sequences of *pieces*, each evaluated for all
its samples at once (no per-sample loop):

- ``ROLL``: the foot rotates about a fixed contact point c (heel, ball of the foot or
  toes): the sensor is at p = c + C·r, C = C_b^n(φ, θ, ψ) = Rz(ψ)·Ry(θ)·Rx(φ) and r the
  lever from the contact to the sensor in the body frame (FLU). Then
  v = Ċ·r and a = C̈·r, with Ċ and C̈ from the product rule over the three elementary
  rotations (:func:`rotation_with_derivatives`). A piece whose angles do not change is
  the foot at rest: v and a are exactly 0.
- ``SWING``: the sensor position itself follows a polynomial, between the state the foot
  leaves the ground with and the state it lands with.
- Both kinds give the Euler angles as polynomials of the normalised time x = τ/T:
  quintic Hermite polynomials through value, rate and second derivative at both ends
  (:func:`quintic`), plus, for a swing's height, the bump 64·h·x³(1 − x)³ (peak h at
  x = ½, value and first two derivatives 0 at both ends) for the foot clearance.

Derivatives in time are f_τ = f_x/T and f_ττ = f_xx/T². Adjacent pieces are joined by
matching position, velocity and acceleration (and angles, rates and angular
accelerations), so the whole trajectory is C² except at a landing, where the impact
(below) makes the acceleration jump, as a contact force does.

- :class:`Impacts`: the landing impact as an additive transient of position and Euler
  angles, d(τ) = V/ω·sin(ωτ)·(1 − τ/T)⁴ for 0 ≤ τ < T: it starts with the velocity V
  the contact absorbs (d(0) = 0, ḋ(0) = V) and ends exactly at rest with its first two
  derivatives (a heel pad and shoe sole that ring once or twice at ω/2π and are still
  after T, so that a stance truth |v| = 0 exists after it). Its acceleration peaks at
  about V·ω/2 in the first half-period.

Frames and units: navigation frame ENU [m], body frame FLU, angles [rad], time [s].
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdr_sim.step_pattern import Channel

ROLL, SWING = 0, 1
DEGREE = 6
BUMP = 64.0 * np.array([0.0, 0.0, 0.0, 1.0, -3.0, 3.0, -1.0])   # 64·x³(1 − x)³


def quintic(start: Channel, end: Channel, duration) -> np.ndarray:
    """Coefficients (..., 7) in x = τ/T (x⁰ … x⁶, the last 0) of the quintic Hermite
    polynomial with value, first and second time derivative ``start`` at x = 0 and
    ``end`` at x = 1 (each a :class:`Channel` of arrays of one shape)."""
    t = np.asarray(duration, float)
    p0, v0, a0 = start.f, start.d1 * t, start.d2 * t**2
    p1, v1, a1 = end.f, end.d1 * t, end.d2 * t**2
    dp = p1 - p0
    zero = np.zeros_like(dp)
    return np.stack([p0, v0, a0 / 2,
                     10 * dp - 6 * v0 - 4 * v1 - (3 * a0 - a1) / 2,
                     -15 * dp + 8 * v0 + 7 * v1 + (3 * a0 - 2 * a1) / 2,
                     6 * dp - 3 * (v0 + v1) - (a0 - a1) / 2, zero], axis=-1)


def polynomial(coefficients: np.ndarray, x: np.ndarray, duration: np.ndarray) -> Channel:
    """Value and time derivatives (n, k) of polynomials (n, k, 7) in x (n,) ∈ [0, 1] over
    pieces of ``duration`` (n,) [s]."""
    powers = x[:, None] ** np.arange(DEGREE + 1)
    j = np.arange(1, DEGREE + 1)
    f = np.einsum("nkj,nj->nk", coefficients, powers)
    d1 = np.einsum("nkj,nj->nk", coefficients[..., 1:] * j, powers[:, :-1])
    d2 = np.einsum("nkj,nj->nk", coefficients[..., 2:] * j[1:] * j[:-1], powers[:, :-2])
    return Channel(f, d1 / duration[:, None], d2 / duration[:, None] ** 2)


def _elementary(axis: int, angle: Channel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """R(α), dR/dt and d²R/dt² (n, 3, 3) of the rotation about body axis 0 (x), 1 (y) or
    2 (z) by α(t): Ṙ = R′·α̇, R̈ = R″·α̇² + R′·α̈ with R″ = −R over the rotated plane."""
    c, s = np.cos(angle.f), np.sin(angle.f)
    n = len(c)
    i, j = [(1, 2), (0, 2), (0, 1)][axis]
    sign = -1.0 if axis == 1 else 1.0          # Ry has +sin above the diagonal
    r, r1, r2 = np.zeros((3, n, 3, 3))
    r[:, axis, axis] = 1.0
    r[:, i, i] = r[:, j, j] = c
    r[:, i, j], r[:, j, i] = -sign * s, sign * s
    r1[:, i, i] = r1[:, j, j] = -s
    r1[:, i, j], r1[:, j, i] = -sign * c, sign * c
    r2[:, i, i] = r2[:, j, j] = -c
    r2[:, i, j], r2[:, j, i] = sign * s, -sign * s
    rate, acc = angle.d1[:, None, None], angle.d2[:, None, None]
    return r, r1 * rate, r2 * rate**2 + r1 * acc


def rotation_with_derivatives(euler: Channel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """C_b^n = Rz(ψ)·Ry(θ)·Rx(φ) and its first and second time derivatives (n, 3, 3), from
    Euler angles (n, 3) (roll, pitch, yaw) with their rates and second derivatives."""
    x, y, z = (_elementary(k, Channel(euler.f[:, k], euler.d1[:, k], euler.d2[:, k]))
               for k in range(3))
    mm = np.matmul
    c = mm(z[0], mm(y[0], x[0]))
    c1 = mm(z[1], mm(y[0], x[0])) + mm(z[0], mm(y[1], x[0])) + mm(z[0], mm(y[0], x[1]))
    c2 = (mm(z[2], mm(y[0], x[0])) + mm(z[0], mm(y[2], x[0])) + mm(z[0], mm(y[0], x[2]))
          + 2 * (mm(z[1], mm(y[1], x[0])) + mm(z[1], mm(y[0], x[1]))
                 + mm(z[0], mm(y[1], x[1]))))
    return c, c1, c2


@dataclass(frozen=True)
class Pieces:
    """The pieces of a walk, one row per phase (rows of other phases are unused).

    kind (P,): ROLL or SWING; euler (P, 3, 7): roll, pitch, yaw polynomials in x [rad];
    position (P, 3, 7): SWING, the sensor position polynomials in x (ENU [m]); ROLL, the
    contact point c in ``position[:, :, 0]``; lever (P, 3): ROLL, r from the contact to the
    sensor, body frame [m].
    """

    kind: np.ndarray
    euler: np.ndarray
    position: np.ndarray
    lever: np.ndarray

    @classmethod
    def empty(cls, rows: int) -> Pieces:
        return cls(np.full(rows, ROLL), np.zeros((rows, 3, DEGREE + 1)),
                   np.zeros((rows, 3, DEGREE + 1)), np.zeros((rows, 3)))


@dataclass(frozen=True)
class PieceState:
    """Sensor position, velocity, acceleration (n, 3) [m, m/s, m/s²] and Euler angles
    with their rates and second derivatives (n, 3) [rad, rad/s, rad/s²]."""

    position: Channel
    euler: Channel


def evaluate(pieces: Pieces, rows: np.ndarray, tau: np.ndarray,
             duration: np.ndarray) -> PieceState:
    """The pieces ``rows`` (n,) at ``tau`` (n,) [s] from their starts, of ``duration``
    (n,) [s]."""
    x = tau / duration
    euler = polynomial(pieces.euler[rows], x, duration)
    position = polynomial(pieces.position[rows], x, duration)
    rolling = pieces.kind[rows] == ROLL
    if rolling.any():
        c, c1, c2 = rotation_with_derivatives(Channel(euler.f[rolling], euler.d1[rolling],
                                                      euler.d2[rolling]))
        lever = pieces.lever[rows[rolling]]
        position.f[rolling] = position.f[rolling] + np.einsum("nij,nj->ni", c, lever)
        position.d1[rolling] = np.einsum("nij,nj->ni", c1, lever)
        position.d2[rolling] = np.einsum("nij,nj->ni", c2, lever)
    return PieceState(position, euler)


@dataclass(frozen=True)
class Impacts:
    """Landing transients, one row per landing, sorted by time: start [s], the velocity
    the contact absorbs (L, 3) ENU [m/s], the Euler-rate step (L, 3) [rad/s], ringing
    frequency [Hz] and duration [s]."""

    time: np.ndarray
    velocity: np.ndarray
    euler_rate: np.ndarray
    frequency_hz: np.ndarray
    duration_s: np.ndarray

    @classmethod
    def from_rows(cls, rows: list[tuple]) -> Impacts:
        if not rows:
            return cls(np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0),
                       np.zeros(0))
        cols = list(zip(*rows, strict=True))
        return cls(np.asarray(cols[0], float), np.asarray(cols[1], float),
                   np.asarray(cols[2], float), np.asarray(cols[3], float),
                   np.asarray(cols[4], float))

    def at(self, t: np.ndarray) -> tuple[np.ndarray, Channel, Channel]:
        """Samples within a transient (indices into ``t``), and its position and Euler
        angle offsets there (value, first and second derivatives, (n, 3))."""
        k = np.searchsorted(self.time, t, side="right") - 1
        inside = k >= 0
        inside[inside] = t[inside] - self.time[k[inside]] < self.duration_s[k[inside]]
        rows = np.flatnonzero(inside)
        k = k[rows]
        tau = t[rows] - self.time[k]
        omega = 2 * np.pi * self.frequency_hz[k]
        big_t = self.duration_s[k]
        u = tau / big_t
        env = Channel((1 - u) ** 3 * (1 + 3 * u), -12 * u * (1 - u) ** 2 / big_t,
                      -12 * (1 - u) * (1 - 3 * u) / big_t**2)
        s, c = np.sin(omega * tau), np.cos(omega * tau)
        shape = Channel(s * env.f / omega, c * env.f + s * env.d1 / omega,
                        -omega * s * env.f + 2 * c * env.d1 + s * env.d2 / omega)

        def scaled(amplitude: np.ndarray) -> Channel:
            return Channel(shape.f[:, None] * amplitude, shape.d1[:, None] * amplitude,
                           shape.d2[:, None] * amplitude)

        return rows, scaled(self.velocity[k]), scaled(self.euler_rate[k])
