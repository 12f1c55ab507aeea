"""The ZUPT EKF's equations as compiled kernels (numba), shared by the offline loop and
the block steps of :class:`pdr_ins_ekf.zupt_ekf.ZuptEkf` (the live node).

State arrays are changed in place: position p, velocity v (3,), attitude C (3, 3), biases
b (6,) [accelerometer, gyroscope], covariance P (n, n), and ``prev`` (3, 3), whose rows
are the previous bias-corrected specific force, rate and navigation-frame specific force
(the trapezoidal mechanization needs them). ``params`` holds, in order: accelerometer
and gyro noise densities, accelerometer and gyro bias noise densities, the Gauss–Markov
correlation time [s], the bias model code (:data:`BIAS_MODEL_CODES`), gravity [m/s²] and
the ZARU's gate on its normalised innovation squared (:data:`PARAM_ZARU_GATE`).
The first call compiles (seconds) and caches the machine code beside this module.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_core import kernel_cache, small_matrix
from pdr_core.small_matrix import product3, rodrigues

kernel_cache.forget_if_changed(__file__, small_matrix.__file__)

BIAS_MODEL_CODES = {"none": 0, "random_walk": 1, "gauss_markov": 2}
PARAM_ZARU_GATE = 7   # params[7]: the ZARU is applied where νᵀS⁻¹ν is below it


@njit(cache=True)
def start(C, b, prev, f, w):
    """Set ``prev`` from the first sample."""
    prev[0] = f - b[:3]
    prev[1] = w - b[3:]
    _matvec3(C, prev[0], prev[2])


@njit(cache=True)
def mechanize(p, v, C, b, prev, f, w, dt, gravity):
    """Trapezoidal strapdown step of the nominal state over dt (001_5b5dbf275b14cf0a.txt,
    Eqs. (1)–(5)); returns the navigation-frame specific force. Loops over the three
    axes: cheaper than NumPy's temporaries at this size."""
    f_c = np.empty(3)
    w_mid = np.empty(3)
    for i in range(3):
        f_c[i] = f[i] - b[i]
        w_c = w[i] - b[3 + i]
        w_mid[i] = (prev[1, i] + w_c) / 2
        prev[1, i] = w_c
    R = np.empty((3, 3))
    rodrigues(w_mid[0] * dt, w_mid[1] * dt, w_mid[2] * dt, R)
    for i in range(3):
        r0, r1, r2 = C[i, 0], C[i, 1], C[i, 2]
        for j in range(3):
            C[i, j] = r0 * R[0, j] + r1 * R[1, j] + r2 * R[2, j]
    a_now = np.empty(3)
    _matvec3(C, f_c, a_now)
    for i in range(3):
        accel = (prev[2, i] + a_now[i]) / 2 - (gravity if i == 2 else 0.0)
        v_new = v[i] + accel * dt
        p[i] += (v[i] + v_new) / 2 * dt
        v[i] = v_new
        prev[0, i] = f_c[i]
        prev[2, i] = a_now[i]
    return a_now


@njit(cache=True)
def apply_transition(M, C, a_now, dt, params):
    """F·M for the error-state transition F = I + A·dt over dt, M (n, k), as a new array
    (:func:`transition_in_place`)."""
    out = M.copy()
    transition_in_place(out, C, a_now, dt, params)
    return out


@njit(cache=True)
def transition_in_place(M, C, a_now, dt, params):
    """M ← F·M for the error-state transition F = I + A·dt over dt (module docstring of
    :mod:`pdr_ins_ekf.zupt_ekf`), M (n, k), without forming F: F is the identity plus
    four 3×3 blocks (δp/δv, δv/δθ = [fⁿ×], and with 15 states δv/δb_a = −Ĉ,
    δθ/δb_g = Ĉ) and, for Gauss–Markov biases, −dt/τ on the bias diagonal. Each block
    row reads only rows below it, so updating rows top-down, column by column, needs no
    copy; a 3×3 block times a 3-vector is cheaper written out than as a BLAS call."""
    n, k = M.shape
    a0, a1, a2 = a_now[0], a_now[1], a_now[2]
    decay = dt / params[4] if n == 15 and params[5] == 2 else 0.0
    for j in range(k):
        M[0, j] += dt * M[3, j]
        M[1, j] += dt * M[4, j]
        M[2, j] += dt * M[5, j]
        t0, t1, t2 = M[6, j], M[7, j], M[8, j]
        M[3, j] += dt * (a1 * t2 - a2 * t1)
        M[4, j] += dt * (a2 * t0 - a0 * t2)
        M[5, j] += dt * (a0 * t1 - a1 * t0)
        if n == 15:
            b0, b1, b2 = M[9, j], M[10, j], M[11, j]
            g0, g1, g2 = M[12, j], M[13, j], M[14, j]
            for i in range(3):
                M[3 + i, j] -= dt * (C[i, 0] * b0 + C[i, 1] * b1 + C[i, 2] * b2)
                M[6 + i, j] += dt * (C[i, 0] * g0 + C[i, 1] * g1 + C[i, 2] * g2)
            for i in range(9, 15):
                M[i, j] -= decay * M[i, j]


@njit(cache=True)
def transposed_transition_in_place(y, C, a_now, dt, params):
    """y ← Fᵀ·y for a vector y (n,), with the blocks of :func:`transition_in_place`
    transposed: δv gains dt·δp's, δθ gains dt·[fⁿ×]ᵀ·δv's, and with 15 states b_a gains
    −dt·Ĉᵀ·δv's and b_g dt·Ĉᵀ·δθ's; Gauss–Markov biases decay. Each block row reads
    only rows above it, so updating rows bottom-up needs no copy."""
    n = y.shape[0]
    a0, a1, a2 = a_now[0], a_now[1], a_now[2]
    u0, u1, u2 = y[3], y[4], y[5]
    if n == 15:
        decay = dt / params[4] if params[5] == 2 else 0.0
        for i in range(9, 15):
            y[i] -= decay * y[i]
        for j in range(3):
            y[9 + j] -= dt * (C[0, j] * u0 + C[1, j] * u1 + C[2, j] * u2)
            y[12 + j] += dt * (C[0, j] * y[6] + C[1, j] * y[7] + C[2, j] * y[8])
    y[6] += dt * (a2 * u1 - a1 * u2)
    y[7] += dt * (a0 * u2 - a2 * u0)
    y[8] += dt * (a1 * u0 - a0 * u1)
    for i in range(3):
        y[3 + i] += dt * y[i]


@njit(cache=True)
def inverse_transition_in_place(x, C, a_now, dt, params):
    """x ← F⁻¹·x for a vector x (n,): :func:`transition_in_place` undone by back
    substitution, bottom-up (biases, then attitude, velocity, position), since each of
    F's block rows reads only the rows below it. F is unipotent (A·dt nilpotent) except
    for the Gauss–Markov decay, which is divided out."""
    n = x.shape[0]
    if n == 15:
        decay = dt / params[4] if params[5] == 2 else 0.0
        for i in range(9, 15):
            x[i] /= 1.0 - decay
        b0, b1, b2 = x[9], x[10], x[11]
        g0, g1, g2 = x[12], x[13], x[14]
        for i in range(3):
            x[6 + i] -= dt * (C[i, 0] * g0 + C[i, 1] * g1 + C[i, 2] * g2)
            x[3 + i] += dt * (C[i, 0] * b0 + C[i, 1] * b1 + C[i, 2] * b2)
    a0, a1, a2 = a_now[0], a_now[1], a_now[2]
    t0, t1, t2 = x[6], x[7], x[8]
    x[3] -= dt * (a1 * t2 - a2 * t1)
    x[4] -= dt * (a2 * t0 - a0 * t2)
    x[5] -= dt * (a0 * t1 - a1 * t0)
    for i in range(3):
        x[i] -= dt * x[3 + i]


@njit(cache=True)
def process_noise(params, i, dt):
    """Qᵢᵢ, the variance :func:`propagate` adds to state i over dt: none on position, then
    per block of three the accelerometer, gyro, accelerometer-bias and gyro-bias noise
    densities (``params[0:4]``) squared, times dt."""
    return params[i // 3 - 1] ** 2 * dt if i >= 3 else 0.0


@njit(cache=True)
def symmetrize(P):
    """P ← (P + Pᵀ)/2 in place, keeping the covariance exactly symmetric."""
    n = P.shape[0]
    for i in range(n):
        for j in range(i + 1, n):
            mean = (P[i, j] + P[j, i]) / 2
            P[i, j] = mean
            P[j, i] = mean


@njit(cache=True)
def _transpose(P):
    """P ← Pᵀ in place (P square)."""
    n = P.shape[0]
    for i in range(n):
        for j in range(i + 1, n):
            P[i, j], P[j, i] = P[j, i], P[i, j]


@njit(cache=True)
def propagate(P, C, a_now, dt, params):
    """P ← F·P·Fᵀ + Q (symmetrised), Q = G·diag(σ²)·Gᵀ·dt, in place: F·(F·P)ᵀ, which is
    F·P·Fᵀ for a symmetric P. The noise is isotropic in the body frame, so its rotation
    by Ĉ leaves Q diagonal."""
    transition_in_place(P, C, a_now, dt, params)
    _transpose(P)
    transition_in_place(P, C, a_now, dt, params)
    for i in range(3, P.shape[0]):
        P[i, i] += process_noise(params, i, dt)
    symmetrize(P)


@njit(cache=True)
def predict(p, v, C, b, P, prev, f, w, dt, params):
    """Trapezoidal mechanization over dt, then the covariance (:func:`propagate`)."""
    a_now = mechanize(p, v, C, b, prev, f, w, dt, params[6])
    propagate(P, C, a_now, dt, params)


@njit(cache=True)
def _inverse3(S):
    """Inverse of a 3×3 matrix by its adjugate (S is a symmetric positive-definite
    innovation covariance here, well conditioned by the measurement noise)."""
    inv = np.empty((3, 3))
    inv[0, 0] = S[1, 1] * S[2, 2] - S[1, 2] * S[2, 1]
    inv[0, 1] = S[0, 2] * S[2, 1] - S[0, 1] * S[2, 2]
    inv[0, 2] = S[0, 1] * S[1, 2] - S[0, 2] * S[1, 1]
    inv[1, 0] = S[1, 2] * S[2, 0] - S[1, 0] * S[2, 2]
    inv[1, 1] = S[0, 0] * S[2, 2] - S[0, 2] * S[2, 0]
    inv[1, 2] = S[0, 2] * S[1, 0] - S[0, 0] * S[1, 2]
    inv[2, 0] = S[1, 0] * S[2, 1] - S[1, 1] * S[2, 0]
    inv[2, 1] = S[0, 1] * S[2, 0] - S[0, 0] * S[2, 1]
    inv[2, 2] = S[0, 0] * S[1, 1] - S[0, 1] * S[1, 0]
    det = S[0, 0] * inv[0, 0] + S[0, 1] * inv[1, 0] + S[0, 2] * inv[2, 0]
    return inv / det


@njit(cache=True)
def correct(dx, P, innovation, rows, sigma):
    """Kalman update of the error state dx and, in Joseph form, of P with a direct
    measurement of the three states from ``rows`` (noise σ per axis).

    H only selects states, so H·P, P·Hᵀ and H·P·Hᵀ are slices of P and the Joseph form
    (I − KH)·P·(I − KH)ᵀ + K·R·Kᵀ costs O(n²) instead of O(n³); written as loops, with
    no temporary arrays beyond Kᵀ and M: K = P·Hᵀ·S⁻¹ with S = H·P·Hᵀ + σ²I,
    M = P − K·H·P, P ← M − M·Hᵀ·Kᵀ + σ²·K·Kᵀ, then symmetrised. Returns Kᵀ (3, n) and
    S⁻¹·ν (3,) for the innovation ν, which the smoother's backward pass needs
    (:func:`pdr_ins_ekf.compiled_smoother.adjoint_before_update`)."""
    n = P.shape[0]
    S_inv = _inverse3(P[rows:rows + 3, rows:rows + 3] + np.eye(3) * sigma**2)
    K_T = np.zeros((3, n))  # Kᵀ = S⁻¹·H·P
    for a in range(3):
        for b in range(3):
            w = S_inv[a, b]
            for j in range(n):
                K_T[a, j] += w * P[rows + b, j]
    for i in range(n):
        dx[i] += K_T[0, i] * innovation[0] + K_T[1, i] * innovation[1] \
            + K_T[2, i] * innovation[2]
    M = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            M[i, j] = P[i, j] - (K_T[0, i] * P[rows, j] + K_T[1, i] * P[rows + 1, j]
                                 + K_T[2, i] * P[rows + 2, j])
    s2 = sigma**2
    for i in range(n):
        for j in range(n):
            P[i, j] = (M[i, j] - (M[i, rows] * K_T[0, j] + M[i, rows + 1] * K_T[1, j]
                                  + M[i, rows + 2] * K_T[2, j])
                       + s2 * (K_T[0, i] * K_T[0, j] + K_T[1, i] * K_T[1, j]
                               + K_T[2, i] * K_T[2, j]))
    symmetrize(P)
    weighted = np.empty(3)
    _matvec3(S_inv, innovation, weighted)
    return K_T, weighted


@njit(cache=True)
def orthonormalize(C):
    """The nearest rotation (the polar factor) of a nearly orthonormal C, in place, by
    Newton–Schulz steps C ← C·(3I − CᵀC)/2: each squares the deviation from
    orthonormality, so two take (I − [δθ×])·C, off by |δθ|², to machine precision, at a
    fraction of an SVD's cost."""
    G, CG = np.empty((3, 3)), np.empty((3, 3))
    for _ in range(2):
        for i in range(3):
            for j in range(3):
                G[i, j] = -(C[0, i] * C[0, j] + C[1, i] * C[1, j] + C[2, i] * C[2, j])
            G[i, i] += 3.0
        product3(C, G, CG)
        for i in range(3):
            for j in range(3):
                C[i, j] = CG[i, j] / 2.0


@njit(cache=True)
def compensate(p, v, C, b, dx):
    """Feed the error state back into the nominal state (001, Eq. (8)):
    p += δp, v += δv, C ← (I − [δθ×])·C (then re-orthonormalised), b += δb."""
    for i in range(3):
        p[i] += dx[i]
        v[i] += dx[3 + i]
    t0, t1, t2 = dx[6], dx[7], dx[8]
    correction = np.array([[1.0, t2, -t1], [-t2, 1.0, t0], [t1, -t0, 1.0]])
    corrected = np.empty((3, 3))
    product3(correction, C, corrected)
    C[:, :] = corrected
    orthonormalize(C)
    if dx.shape[0] == 15:
        for i in range(6):
            b[i] += dx[9 + i]


@njit(cache=True)
def _matvec3(C, x, out):
    """out ← C·x for a 3×3 C and a 3-vector x."""
    for i in range(3):
        out[i] = C[i, 0] * x[0] + C[i, 1] * x[1] + C[i, 2] * x[2]


@njit(cache=True)
def update(p, v, C, b, P, prev, z, rows, sigma):
    """Joseph-form update with H selecting the three error states from ``rows``, then
    the closed-loop compensation of 001_5b5dbf275b14cf0a.txt, Eq. (8)."""
    dx = np.zeros(P.shape[0])
    correct(dx, P, z, rows, sigma)
    feed_back(p, v, C, b, dx, prev)


@njit(cache=True)
def within_gate(P, innovation, rows, sigma, gate):
    """True when the normalised innovation squared νᵀ·S⁻¹·ν of a direct measurement of
    the three states from ``rows`` (S = H·P·Hᵀ + σ²I) is below ``gate``, a χ² bound with
    3 degrees of freedom (16.27 at 0.999; Bar-Shalom et al. 2001, section 5.4)."""
    S_inv = _inverse3(P[rows:rows + 3, rows:rows + 3] + np.eye(3) * sigma**2)
    nis = 0.0
    for a in range(3):
        for c in range(3):
            nis += innovation[a] * S_inv[a, c] * innovation[c]
    return nis < gate


@njit(cache=True)
def feed_back(p, v, C, b, dx, prev):
    """:func:`compensate`, then the navigation-frame specific force of ``prev`` rotated
    by the corrected attitude (the next trapezoidal step averages it)."""
    compensate(p, v, C, b, dx)
    _matvec3(C, prev[0], prev[2])


@njit(cache=True)
def filter_loop(t, accel, gyro, stance, zaru, C0, b0, P0, params, zupt_sigma, zaru_sigma):
    """All samples of a record from the aligned state (C0, b0, P0) at the origin at rest:
    :func:`filter_block` over stamps t [s]."""
    N = t.shape[0]
    p, v = np.zeros(3), np.zeros(3)
    C, b, P = C0.copy(), b0.copy(), P0.copy()
    prev = np.empty((3, 3))
    start(C, b, prev, accel[0], gyro[0])
    dt = np.zeros(N)
    for k in range(1, N):
        dt[k] = t[k] - t[k - 1]
    return filter_block(p, v, C, b, P, prev, accel, gyro, dt, stance, zaru, params,
                        zupt_sigma, zaru_sigma)


@njit(cache=True)
def filter_block(p, v, C, b, P, prev, accel, gyro, dt, stance, zaru, params, zupt_sigma,
                 zaru_sigma):
    """Consecutive samples from the state (p, v, C, b, P, prev), changed in place: each
    propagated over dt[k] [s], then ZUPT where ``stance`` (and ZARU there, where the
    angular rate passes :func:`within_gate`: a foot that turns is not at rest, however
    still its velocity). Returns position,
    velocity (N, 3), attitude (N, 3, 3), bias (N, 6), covariance diagonal (N, n) and
    position and velocity covariance (N, 3, 3) after each sample."""
    N = accel.shape[0]
    n = P.shape[0]
    pos, vel, bias = np.empty((N, 3)), np.empty((N, 3)), np.empty((N, 6))
    att, pcov, vcov = np.empty((N, 3, 3)), np.empty((N, 3, 3)), np.empty((N, 3, 3))
    var = np.empty((N, n))
    for k in range(N):
        predict(p, v, C, b, P, prev, accel[k], gyro[k], dt[k], params)
        if stance[k]:
            update(p, v, C, b, P, prev, -v, 3, zupt_sigma)
            if zaru and within_gate(P, gyro[k] - b[3:], 12, zaru_sigma,
                                    params[PARAM_ZARU_GATE]):
                update(p, v, C, b, P, prev, gyro[k] - b[3:], 12, zaru_sigma)
        pos[k], vel[k], att[k], bias[k] = p, v, C, b
        for i in range(n):
            var[k, i] = P[i, i]
        pcov[k] = P[0:3, 0:3]
        vcov[k] = P[3:6, 3:6]
    return pos, vel, att, bias, var, pcov, vcov
