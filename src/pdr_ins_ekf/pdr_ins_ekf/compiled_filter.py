"""The ZUPT EKF's equations as compiled kernels (numba), shared by the offline loop and
the one-sample steps of :class:`pdr_ins_ekf.zupt_ekf.ZuptEkf` (the live node).

State arrays are changed in place: position p, velocity v (3,), attitude C (3, 3), biases
b (6,) [accelerometer, gyroscope], covariance P (n, n), and ``prev`` (3, 3), whose rows
are the previous bias-corrected specific force, rate and navigation-frame specific force
(the trapezoidal mechanization needs them). ``params`` holds, in order: accelerometer
and gyro noise densities, accelerometer and gyro bias noise densities, the Gauss–Markov
correlation time [s], the bias model code (:data:`BIAS_MODEL_CODES`) and gravity [m/s²].
The first call compiles (seconds) and caches the machine code beside this module.
"""
from __future__ import annotations

import numpy as np
from numba import njit

BIAS_MODEL_CODES = {"none": 0, "random_walk": 1, "gauss_markov": 2}


@njit(cache=True)
def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


@njit(cache=True)
def _rodrigues(w, dt):
    """exp([w×]·dt), 000_fbd401126d10f515.txt, Eq. (12)."""
    norm = np.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2)
    big = _skew(w)
    if norm > 0:
        s = np.sin(norm * dt) / norm
        c = (1 - np.cos(norm * dt)) / norm**2
    else:
        s = dt
        c = dt**2 / 2
    return np.eye(3) + s * big + c * (big @ big)


@njit(cache=True)
def start(C, b, prev, f, w):
    """Set ``prev`` from the first sample."""
    prev[0] = f - b[:3]
    prev[1] = w - b[3:]
    prev[2] = C @ prev[0]


@njit(cache=True)
def mechanize(p, v, C, b, prev, f, w, dt, gravity):
    """Trapezoidal strapdown step of the nominal state over dt (001_5b5dbf275b14cf0a.txt,
    Eqs. (1)–(5)); returns the navigation-frame specific force."""
    f_c = f - b[:3]
    w_c = w - b[3:]
    C[:, :] = C @ _rodrigues((prev[1] + w_c) / 2, dt)
    a_now = C @ f_c
    v_new = v + ((prev[2] + a_now) / 2 - np.array([0.0, 0.0, gravity])) * dt
    p += (v + v_new) / 2 * dt
    v[:] = v_new
    prev[0] = f_c
    prev[1] = w_c
    prev[2] = a_now
    return a_now


@njit(cache=True)
def apply_transition(M, C, a_now, dt, params):
    """F·M for the error-state transition F = I + A·dt over dt (module docstring of
    :mod:`pdr_ins_ekf.zupt_ekf`), M (n, k), without forming F: F is the identity plus
    four 3×3 blocks (δp/δv, δv/δθ = [fⁿ×], and with 15 states δv/δb_a = −Ĉ,
    δθ/δb_g = Ĉ) and, for Gauss–Markov biases, −dt/τ on the bias diagonal."""
    out = M.copy()
    out[0:3] += dt * M[3:6]
    out[3:6] += (_skew(a_now) * dt) @ M[6:9]
    if M.shape[0] == 15:
        out[3:6] -= (C * dt) @ M[9:12]
        out[6:9] += (C * dt) @ M[12:15]
        if params[5] == 2:
            out[9:15] -= (dt / params[4]) * M[9:15]
    return out


@njit(cache=True)
def propagate(P, C, a_now, dt, params):
    """P ← F·P·Fᵀ + Q (symmetrised), Q = G·diag(σ²)·Gᵀ·dt. The noise is isotropic in the
    body frame, so its rotation by Ĉ leaves Q diagonal."""
    acc_noise, gyro_noise, acc_bias_noise, gyro_bias_noise = params[0:4]
    n = P.shape[0]
    FP_T = np.ascontiguousarray(apply_transition(P, C, a_now, dt, params).T)
    P[:, :] = apply_transition(FP_T, C, a_now, dt, params)
    for i in range(3):
        P[3 + i, 3 + i] += acc_noise**2 * dt
        P[6 + i, 6 + i] += gyro_noise**2 * dt
    if n == 15:
        for i in range(3):
            P[9 + i, 9 + i] += acc_bias_noise**2 * dt
            P[12 + i, 12 + i] += gyro_bias_noise**2 * dt
    P[:, :] = (P + P.T) / 2


@njit(cache=True)
def predict(p, v, C, b, P, prev, f, w, dt, params):
    """Trapezoidal mechanization over dt, then the covariance (:func:`propagate`)."""
    a_now = mechanize(p, v, C, b, prev, f, w, dt, params[6])
    propagate(P, C, a_now, dt, params)


@njit(cache=True)
def correct(dx, P, innovation, rows, sigma):
    """Kalman update of the error state dx and, in Joseph form, of P with a direct
    measurement of the three states from ``rows`` (noise σ per axis).

    H only selects states, so H·P, P·Hᵀ and H·P·Hᵀ are slices of P and the Joseph form
    (I − KH)·P·(I − KH)ᵀ + K·R·Kᵀ costs O(n²) instead of O(n³)."""
    S = P[rows:rows + 3, rows:rows + 3] + np.eye(3) * sigma**2
    K_T = np.linalg.solve(S, np.ascontiguousarray(P[rows:rows + 3, :]))
    K = np.ascontiguousarray(K_T.T)
    dx += K @ innovation
    M = P - K @ np.ascontiguousarray(P[rows:rows + 3, :])
    P[:, :] = M - np.ascontiguousarray(M[:, rows:rows + 3]) @ K_T + sigma**2 * (K @ K_T)
    P[:, :] = (P + P.T) / 2


@njit(cache=True)
def orthonormalize(C):
    """The nearest rotation (the polar factor) of a nearly orthonormal C, in place, by
    Newton–Schulz steps C ← C·(3I − CᵀC)/2: each squares the deviation from
    orthonormality, so two take (I − [δθ×])·C, off by |δθ|², to machine precision, at a
    fraction of an SVD's cost."""
    for _ in range(2):
        C[:, :] = C @ (3.0 * np.eye(3) - C.T @ C) / 2.0


@njit(cache=True)
def compensate(p, v, C, b, dx):
    """Feed the error state back into the nominal state (001, Eq. (8))."""
    p += dx[0:3]
    v += dx[3:6]
    C[:, :] = (np.eye(3) - _skew(dx[6:9])) @ C
    orthonormalize(C)
    if dx.shape[0] == 15:
        b += dx[9:15]


@njit(cache=True)
def update(p, v, C, b, P, prev, z, rows, sigma):
    """Joseph-form update with H selecting the three error states from ``rows``, then
    the closed-loop compensation of 001_5b5dbf275b14cf0a.txt, Eq. (8)."""
    dx = np.zeros(P.shape[0])
    correct(dx, P, z, rows, sigma)
    compensate(p, v, C, b, dx)
    prev[2] = C @ prev[0]


@njit(cache=True)
def filter_loop(t, accel, gyro, stance, zaru, C0, b0, P0, params, zupt_sigma, zaru_sigma):
    """All samples: returns position, velocity (N, 3), attitude (N, 3, 3), bias (N, 6),
    covariance diagonal (N, n) and position and velocity covariance (N, 3, 3)."""
    N = t.shape[0]
    n = P0.shape[0]
    p, v = np.zeros(3), np.zeros(3)
    C, b, P = C0.copy(), b0.copy(), P0.copy()
    prev = np.empty((3, 3))
    start(C, b, prev, accel[0], gyro[0])
    pos, vel, bias = np.empty((N, 3)), np.empty((N, 3)), np.empty((N, 6))
    att, pcov, vcov = np.empty((N, 3, 3)), np.empty((N, 3, 3)), np.empty((N, 3, 3))
    var = np.empty((N, n))
    for k in range(N):
        predict(p, v, C, b, P, prev, accel[k], gyro[k], t[k] - t[k - 1] if k else 0.0,
                params)
        if stance[k]:
            update(p, v, C, b, P, prev, -v, 3, zupt_sigma)
            if zaru:
                update(p, v, C, b, P, prev, gyro[k] - b[3:], 12, zaru_sigma)
        pos[k], vel[k], att[k], bias[k] = p, v, C, b
        for i in range(n):
            var[k, i] = P[i, i]
        pcov[k] = P[0:3, 0:3]
        vcov[k] = P[3:6, 3:6]
    return pos, vel, att, bias, var, pcov, vcov
