"""Compiled (numba) kernels for the 3 × 3 rotations and small symmetric positive-definite
matrices of the navigators' per-sample loops, written out in loops: at these sizes a
BLAS or LAPACK call costs more than the arithmetic.

Used by pdr_ins_ekf.compiled_filter, pdr_ins_ekf.compiled_smoother,
pdr_pocket.compiled_orientation (and its measurements) and pdr_pocket.compiled_attitude.
numba's cache checks a kernel against its own file only, so each caller registers this file with
:func:`pdr_core.maths.kernel_cache.forget_if_changed`.
"""
from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def rodrigues(w0, w1, w2, out):
    """out = exp([w×]) for a rotation vector w [rad]: I + a·[w×] + b·[w×]² with
    a = sin σ / σ, b = (1 − cos σ) / σ², σ = |w| (Rodrigues' formula: Zampella et al. 2011,
    Eq. (12); Muñoz Díaz 2016, Eq. (3.4)); a and b by their series below 1e-8 rad."""
    s2 = w0 * w0 + w1 * w1 + w2 * w2
    s = np.sqrt(s2)
    if s < 1e-8:
        a, b = 1.0 - s2 / 6.0, 0.5 - s2 / 24.0
    else:
        a, b = np.sin(s) / s, (1.0 - np.cos(s)) / s2
    out[0, 0] = 1.0 - b * (w1 * w1 + w2 * w2)
    out[1, 1] = 1.0 - b * (w0 * w0 + w2 * w2)
    out[2, 2] = 1.0 - b * (w0 * w0 + w1 * w1)
    out[0, 1] = -a * w2 + b * w0 * w1
    out[1, 0] = a * w2 + b * w0 * w1
    out[0, 2] = a * w1 + b * w0 * w2
    out[2, 0] = -a * w1 + b * w0 * w2
    out[1, 2] = -a * w0 + b * w1 * w2
    out[2, 1] = a * w0 + b * w1 * w2


@njit(cache=True)
def rotation_increment(c, gyro, previous_gyro, bias, earth_n, dt, out):
    """out = A(ω − b − Cᵀ·ω_ie^n), the body frame's rotation over δt [s] of a strapdown
    attitude C = C_b^n (C_k = C_{k−1}·A): ω^{k−1}, ω^k [rad/s] the rates at the interval's
    ends, b the gyro bias, ω_ie^n the Earth rate in the navigation frame (zeros when off).
    The rotation vector by the trapezoidal rule with the coning term,
    (ω_{k−1} + ω_k)·δt/2 + ω_{k−1} × ω_k·δt²/12, through Rodrigues' A (Muñoz Díaz 2016,
    Eqs. (3.3)–(3.5), whose ω^k·δt is first order: at 100 Hz it turns a thigh's swing by
    0.5°)."""
    e0 = c[0, 0] * earth_n[0] + c[1, 0] * earth_n[1] + c[2, 0] * earth_n[2]
    e1 = c[0, 1] * earth_n[0] + c[1, 1] * earth_n[1] + c[2, 1] * earth_n[2]
    e2 = c[0, 2] * earth_n[0] + c[1, 2] * earth_n[1] + c[2, 2] * earth_n[2]
    a0, a1, a2 = previous_gyro[0] - bias[0] - e0, previous_gyro[1] - bias[1] - e1, \
        previous_gyro[2] - bias[2] - e2
    b0, b1, b2 = gyro[0] - bias[0] - e0, gyro[1] - bias[1] - e1, gyro[2] - bias[2] - e2
    k = dt * dt / 12.0
    rodrigues((a0 + b0) * dt / 2 + k * (a1 * b2 - a2 * b1),
              (a1 + b1) * dt / 2 + k * (a2 * b0 - a0 * b2),
              (a2 + b2) * dt / 2 + k * (a0 * b1 - a1 * b0), out)


@njit(cache=True)
def product3(a, b, out):
    """out = a·b for 3 × 3 matrices."""
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]


@njit(cache=True)
def cholesky(a, out):
    """Lower L with L·Lᵀ = a (n × n) into ``out``; False when a is not positive definite
    (a pivot not above zero, NaN included)."""
    n = a.shape[0]
    for j in range(n):
        d = a[j, j]
        for k in range(j):
            d -= out[j, k] * out[j, k]
        if not d > 0.0:
            return False
        d = np.sqrt(d)
        out[j, j] = d
        for i in range(j + 1, n):
            s = a[i, j]
            for k in range(j):
                s -= out[i, k] * out[j, k]
            out[i, j] = s / d
        for i in range(j):
            out[i, j] = 0.0
    return True


@njit(cache=True)
def rotation_log(r, out):
    """The rotation vector of a rotation matrix (the inverse of
    :func:`pdr_core.maths.small_matrix.rodrigues`)."""
    c = (r[0, 0] + r[1, 1] + r[2, 2] - 1.0) / 2.0
    c = min(1.0, max(-1.0, c))
    angle = np.arccos(c)
    v0, v1, v2 = r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]
    if angle < 1e-6:
        k = 0.5 + angle * angle / 12.0
    elif angle > np.pi - 1e-6:
        # near π: the axis from the diagonal
        k = 0.0
        d = np.array([r[0, 0], r[1, 1], r[2, 2]])
        i = int(np.argmax(d))
        axis = np.zeros(3)
        axis[i] = np.sqrt(max(0.0, (d[i] + 1.0) / 2.0))
        for j in range(3):
            if j != i:
                axis[j] = (r[i, j] + r[j, i]) / (4.0 * axis[i])
        out[0], out[1], out[2] = axis[0] * angle, axis[1] * angle, axis[2] * angle
        return
    else:
        k = angle / (2.0 * np.sin(angle))
    out[0], out[1], out[2] = k * v0, k * v1, k * v2


@njit(cache=True)
def euler_of(c, out):
    """Roll, pitch, yaw [rad] of C = Rz(ψ)·Ry(θ)·Rx(φ); finite at θ = ±90°."""
    out[0] = np.arctan2(c[2, 1], c[2, 2])
    out[1] = -np.arcsin(min(1.0, max(-1.0, c[2, 0])))
    out[2] = np.arctan2(c[1, 0], c[0, 0])


@njit(cache=True)
def mul_bt(a, b, out):
    """out = a·bᵀ for 3 × 3 matrices."""
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[j, 0] + a[i, 1] * b[j, 1] + a[i, 2] * b[j, 2]


@njit(cache=True)
def inverse_spd(a, out):
    """out = a⁻¹ for a small symmetric positive-definite matrix, by Cholesky."""
    n = a.shape[0]
    low = np.empty((n, n))
    if not cholesky(a, low):
        out[:, :] = np.linalg.pinv(a)
        return
    inv_low = np.zeros((n, n))
    for i in range(n):
        inv_low[i, i] = 1.0 / low[i, i]
        for j in range(i):
            s = 0.0
            for k in range(j, i):
                s -= low[i, k] * inv_low[k, j]
            inv_low[i, j] = s / low[i, i]
    for i in range(n):
        for j in range(n):
            s = 0.0
            for k in range(max(i, j), n):
                s += inv_low[k, i] * inv_low[k, j]
            out[i, j] = s
