"""The ZUPT EKF loop of :func:`pdr_ins_ekf.zupt_ekf.run`, compiled with numba.

Offline, all samples are filtered in one compiled call: the same equations, in the same
order, as :class:`pdr_ins_ekf.zupt_ekf.ZuptEkf` (trapezoidal mechanization, first-order
F and Q, Joseph-form ZUPT/ZARU updates, symmetrised covariance, orthonormalised attitude).
The Python class remains the reference and the live node's engine; a test holds the two
to 1e-9 m. The first call compiles (a few seconds) and caches the machine code beside
this module.
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
def _update(p, v, C, b, P, z, rows, sigma):
    """Joseph-form update with H selecting three ``rows`` of the error state; corrects
    p, v, C, b and P in place."""
    n = P.shape[0]
    H = np.zeros((3, n))
    for i in range(3):
        H[i, rows + i] = 1.0
    R = np.eye(3) * sigma**2
    S = H @ P @ H.T + R
    K = np.linalg.solve(S, H @ P).T
    dx = K @ z
    IKH = np.eye(n) - K @ H
    P[:, :] = IKH @ P @ IKH.T + K @ R @ K.T
    P[:, :] = (P + P.T) / 2
    p += dx[0:3]
    v += dx[3:6]
    C[:, :] = (np.eye(3) - _skew(dx[6:9])) @ C
    u, _, vt = np.linalg.svd(C)
    C[:, :] = u @ vt
    if n == 15:
        b += dx[9:15]


@njit(cache=True)
def filter_loop(t, accel, gyro, stance, zaru, C0, b0, P0, acc_noise, gyro_noise,
                acc_bias_noise, gyro_bias_noise, bias_tau_s, bias_model, zupt_sigma,
                zaru_sigma, gravity):
    """All samples: returns position, velocity (N, 3), attitude (N, 3, 3), bias (N, 6),
    covariance diagonal (N, n) and position and velocity covariance (N, 3, 3)."""
    N = t.shape[0]
    n = P0.shape[0]
    p = np.zeros(3)
    v = np.zeros(3)
    C = C0.copy()
    b = b0.copy()
    P = P0.copy()
    g = np.array([0.0, 0.0, gravity])
    pos = np.empty((N, 3))
    vel = np.empty((N, 3))
    att = np.empty((N, 3, 3))
    bias = np.empty((N, 6))
    var = np.empty((N, n))
    pcov = np.empty((N, 3, 3))
    vcov = np.empty((N, 3, 3))
    prev_f = accel[0] - b[:3]
    prev_w = gyro[0] - b[3:]
    prev_a = C @ prev_f
    for k in range(N):
        dt = t[k] - t[k - 1] if k else 0.0
        f_c = accel[k] - b[:3]
        w_c = gyro[k] - b[3:]
        a_prev = prev_a
        C = C @ _rodrigues((prev_w + w_c) / 2, dt)
        a_now = C @ f_c
        v_new = v + ((a_prev + a_now) / 2 - g) * dt
        p = p + (v + v_new) / 2 * dt
        v = v_new
        prev_f, prev_w, prev_a = f_c, w_c, a_now
        F = np.eye(n)
        F[0:3, 3:6] = np.eye(3) * dt
        F[3:6, 6:9] = _skew(a_now) * dt
        Q = np.zeros((n, n))
        q_acc = np.eye(3) * acc_noise**2 * dt
        q_gyro = np.eye(3) * gyro_noise**2 * dt
        if n == 15:
            F[3:6, 9:12] = -C * dt
            F[6:9, 12:15] = C * dt
            if bias_model == 2:
                F[9:15, 9:15] -= np.eye(6) * dt / bias_tau_s
            Q[9:12, 9:12] = np.eye(3) * acc_bias_noise**2 * dt
            Q[12:15, 12:15] = np.eye(3) * gyro_bias_noise**2 * dt
            q_acc = C @ q_acc @ C.T
            q_gyro = C @ q_gyro @ C.T
        Q[3:6, 3:6] = q_acc
        Q[6:9, 6:9] = q_gyro
        P = F @ P @ F.T + Q
        P = (P + P.T) / 2
        if stance[k]:
            _update(p, v, C, b, P, -v, 3, zupt_sigma)
            prev_a = C @ prev_f
            if zaru:
                _update(p, v, C, b, P, gyro[k] - b[3:], 12, zaru_sigma)
                prev_a = C @ prev_f
        pos[k] = p
        vel[k] = v
        att[k] = C
        bias[k] = b
        for i in range(n):
            var[k, i] = P[i, i]
        pcov[k] = P[0:3, 0:3]
        vcov[k] = P[3:6, 3:6]
    return pos, vel, att, bias, var, pcov, vcov
