"""The ZUPT EKF's equations as compiled kernels (numba), shared by the offline loop and
the block steps of :class:`pdr_ins_ekf.zupt_ekf.ZuptEkf` (the live node).

The kernels take the named data of :mod:`pdr_ins_ekf.kernel_data`: the state
(:class:`~pdr_ins_ekf.kernel_data.NavState`: p, v, C, b, P, prev, dx, nis, stance, Pb),
whose arrays they change in place; the settings
(:class:`~pdr_ins_ekf.kernel_data.FilterParams`); the samples of a record
(:class:`~pdr_ins_ekf.kernel_data.Samples`); and the rows of the error state by name
(:data:`~pdr_ins_ekf.kernel_data.VELOCITY`, …). ENU navigation frame, FLU body frame, SI
units. The first call compiles (seconds) and caches the machine code beside this module.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache, small_matrix
from pdr_core.maths.small_matrix import product3, rodrigues
from pdr_ins_ekf import kernel_data
from pdr_ins_ekf.kernel_data import (
    ACC,
    ACC_BIAS,
    ATTITUDE,
    AXES,
    GAUSS_MARKOV,
    GYRO,
    GYRO_BIAS,
    NAV_AND_BIAS_STATES,
    NIS_COUNT,
    NIS_SUM,
    POSITION,
    PREV_FORCE,
    PREV_NAV_FORCE,
    PREV_RATE,
    VELOCITY,
    NavState,
)

kernel_cache.forget_if_changed(__file__, small_matrix.__file__, kernel_data.__file__)


@njit(cache=True)
def new_state(C0, b0, P0):
    """A :class:`~pdr_ins_ekf.kernel_data.NavState` at the origin at rest, with copies of
    the attitude C0 (3, 3), biases b0 (6,) and covariance P0 (n, n), δx̂ = 0, no
    touchdown innovation yet and in stance (the filter starts in the stance it is aligned
    on), the biases' share of P0 its bias block (:func:`bias_share`); ``prev`` is set by
    :func:`start`."""
    Pb = np.zeros_like(P0)
    if P0.shape[0] == NAV_AND_BIAS_STATES:
        Pb[ACC_BIAS:, ACC_BIAS:] = P0[ACC_BIAS:, ACC_BIAS:]
    return NavState(np.zeros(3), np.zeros(3), C0.copy(), b0.copy(), P0.copy(),
                    np.empty((3, 3)), np.zeros(P0.shape[0]), np.zeros(2), np.ones(1, np.bool_),
                    Pb)


@njit(cache=True)
def start(state, f, w):
    """Set ``state.prev`` from the first sample: specific force f [m/s²] and rate w
    [rad/s] (3,), body frame."""
    prev = state.prev
    prev[PREV_FORCE] = f - state.b[ACC]
    prev[PREV_RATE] = w - state.b[GYRO]
    _matvec3(state.C, prev[PREV_FORCE], prev[PREV_NAV_FORCE])


@njit(cache=True)
def mechanize(state, f, w, dt, gravity):
    """Trapezoidal strapdown step of the nominal state (p, v, C, prev) over dt [s] from
    the specific force f [m/s²] and rate w [rad/s] (3,), body frame, gravity [m/s²] along
    the navigation frame's −z (Simón Colomar et al. 2012, Eqs. (1)–(5)); returns the
    navigation-frame specific force [m/s²]. Loops over the three axes: cheaper than
    NumPy's temporaries at this size."""
    p, v, C, prev = state.p, state.v, state.C, state.prev
    b_a, b_g = state.b[ACC], state.b[GYRO]
    f_c = np.empty(3)
    w_mid = np.empty(3)
    for i in range(3):
        f_c[i] = f[i] - b_a[i]
        w_c = w[i] - b_g[i]
        w_mid[i] = (prev[PREV_RATE, i] + w_c) / 2
        prev[PREV_RATE, i] = w_c
    R = np.empty((3, 3))
    rodrigues(w_mid[0] * dt, w_mid[1] * dt, w_mid[2] * dt, R)
    for i in range(3):
        r0, r1, r2 = C[i, 0], C[i, 1], C[i, 2]
        for j in range(3):
            C[i, j] = r0 * R[0, j] + r1 * R[1, j] + r2 * R[2, j]
    a_now = np.empty(3)
    _matvec3(C, f_c, a_now)
    for i in range(3):
        accel = (prev[PREV_NAV_FORCE, i] + a_now[i]) / 2 - (gravity if i == 2 else 0.0)
        v_new = v[i] + accel * dt
        p[i] += (v[i] + v_new) / 2 * dt
        v[i] = v_new
        prev[PREV_FORCE, i] = f_c[i]
        prev[PREV_NAV_FORCE, i] = a_now[i]
    return a_now


@njit(cache=True)
def apply_transition(M, C, a_now, dt, params):
    """F·M for the error-state transition F = I + A·dt over dt, M (n, k), as a new array
    (:func:`transition_in_place`)."""
    out = M.copy()
    transition_in_place(out, C, a_now, dt, params)
    return out


@njit(cache=True)
def bias_decay(params, n, dt):
    """dt/τ, the Gauss–Markov biases' decay over dt [s] in F's bias diagonal (1 − dt/τ);
    0 for random-walk biases and for the 9 states."""
    if n == NAV_AND_BIAS_STATES and params.bias_model == GAUSS_MARKOV:
        return dt / params.bias_tau_s
    return 0.0


@njit(cache=True)
def transition_in_place(M, C, a_now, dt, params):
    """M ← F·M for the error-state transition F = I + A·dt over dt [s] (module docstring
    of :mod:`pdr_ins_ekf.zupt_ekf`; Wang et al. 2020, Eq. (2)), M (n, k), without
    forming F: F is the identity plus four 3×3 blocks (δp/δv, δv/δθ = [fⁿ×] with the
    navigation-frame specific force fⁿ = ``a_now`` [m/s²], and with 15 states
    δv/δb_a = −Ĉ, δθ/δb_g = Ĉ) and, for Gauss–Markov biases, −dt/τ on the bias
    diagonal. Each block row reads only rows below it, so updating rows top-down, column
    by column, needs no copy; a 3×3 block times a 3-vector is cheaper written out than as
    a BLAS call."""
    n, k = M.shape
    a0, a1, a2 = a_now[0], a_now[1], a_now[2]
    decay = bias_decay(params, n, dt)
    for j in range(k):
        M[POSITION, j] += dt * M[VELOCITY, j]
        M[POSITION + 1, j] += dt * M[VELOCITY + 1, j]
        M[POSITION + 2, j] += dt * M[VELOCITY + 2, j]
        t0, t1, t2 = M[ATTITUDE, j], M[ATTITUDE + 1, j], M[ATTITUDE + 2, j]
        M[VELOCITY, j] += dt * (a1 * t2 - a2 * t1)
        M[VELOCITY + 1, j] += dt * (a2 * t0 - a0 * t2)
        M[VELOCITY + 2, j] += dt * (a0 * t1 - a1 * t0)
        if n == NAV_AND_BIAS_STATES:
            b0, b1, b2 = M[ACC_BIAS, j], M[ACC_BIAS + 1, j], M[ACC_BIAS + 2, j]
            g0, g1, g2 = M[GYRO_BIAS, j], M[GYRO_BIAS + 1, j], M[GYRO_BIAS + 2, j]
            for i in range(3):
                M[VELOCITY + i, j] -= dt * (C[i, 0] * b0 + C[i, 1] * b1 + C[i, 2] * b2)
                M[ATTITUDE + i, j] += dt * (C[i, 0] * g0 + C[i, 1] * g1 + C[i, 2] * g2)
            for i in range(ACC_BIAS, NAV_AND_BIAS_STATES):
                M[i, j] -= decay * M[i, j]


@njit(cache=True)
def transposed_transition_in_place(y, C, a_now, dt, params):
    """y ← Fᵀ·y for a vector y (n,), with the blocks of :func:`transition_in_place`
    transposed: δv gains dt·δp's, δθ gains dt·[fⁿ×]ᵀ·δv's, and with 15 states b_a gains
    −dt·Ĉᵀ·δv's and b_g dt·Ĉᵀ·δθ's; Gauss–Markov biases decay. Each block row reads
    only rows above it, so updating rows bottom-up needs no copy."""
    n = y.shape[0]
    a0, a1, a2 = a_now[0], a_now[1], a_now[2]
    u0, u1, u2 = y[VELOCITY], y[VELOCITY + 1], y[VELOCITY + 2]
    if n == NAV_AND_BIAS_STATES:
        decay = bias_decay(params, n, dt)
        for i in range(ACC_BIAS, NAV_AND_BIAS_STATES):
            y[i] -= decay * y[i]
        t0, t1, t2 = y[ATTITUDE], y[ATTITUDE + 1], y[ATTITUDE + 2]
        for j in range(3):
            y[ACC_BIAS + j] -= dt * (C[0, j] * u0 + C[1, j] * u1 + C[2, j] * u2)
            y[GYRO_BIAS + j] += dt * (C[0, j] * t0 + C[1, j] * t1 + C[2, j] * t2)
    y[ATTITUDE] += dt * (a2 * u1 - a1 * u2)
    y[ATTITUDE + 1] += dt * (a0 * u2 - a2 * u0)
    y[ATTITUDE + 2] += dt * (a1 * u0 - a0 * u1)
    for i in range(3):
        y[VELOCITY + i] += dt * y[POSITION + i]


@njit(cache=True)
def inverse_transition_in_place(x, C, a_now, dt, params):
    """x ← F⁻¹·x for a vector x (n,): :func:`transition_in_place` undone by back
    substitution, bottom-up (biases, then attitude, velocity, position), since each of
    F's block rows reads only the rows below it. F is unipotent (A·dt nilpotent) except
    for the Gauss–Markov decay, which is divided out."""
    n = x.shape[0]
    if n == NAV_AND_BIAS_STATES:
        decay = bias_decay(params, n, dt)
        for i in range(ACC_BIAS, NAV_AND_BIAS_STATES):
            x[i] /= 1.0 - decay
        b0, b1, b2 = x[ACC_BIAS], x[ACC_BIAS + 1], x[ACC_BIAS + 2]
        g0, g1, g2 = x[GYRO_BIAS], x[GYRO_BIAS + 1], x[GYRO_BIAS + 2]
        for i in range(3):
            x[ATTITUDE + i] -= dt * (C[i, 0] * g0 + C[i, 1] * g1 + C[i, 2] * g2)
            x[VELOCITY + i] += dt * (C[i, 0] * b0 + C[i, 1] * b1 + C[i, 2] * b2)
    a0, a1, a2 = a_now[0], a_now[1], a_now[2]
    t0, t1, t2 = x[ATTITUDE], x[ATTITUDE + 1], x[ATTITUDE + 2]
    x[VELOCITY] -= dt * (a1 * t2 - a2 * t1)
    x[VELOCITY + 1] -= dt * (a2 * t0 - a0 * t2)
    x[VELOCITY + 2] -= dt * (a0 * t1 - a1 * t0)
    for i in range(3):
        x[POSITION + i] -= dt * x[VELOCITY + i]


@njit(cache=True)
def process_noise(params, i, dt):
    """Qᵢᵢ, the variance :func:`propagate` adds to error-state row i over dt [s]: none on
    position, then per block the accelerometer, gyro, accelerometer-bias and gyro-bias
    noise densities squared, times dt."""
    if i >= GYRO_BIAS:
        density = params.gyro_bias_noise
    elif i >= ACC_BIAS:
        density = params.acc_bias_noise
    elif i >= ATTITUDE:
        density = params.gyro_noise
    elif i >= VELOCITY:
        density = params.acc_noise
    else:
        return 0.0
    return density ** 2 * dt


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
    for i in range(VELOCITY, P.shape[0]):
        P[i, i] += process_noise(params, i, dt)
    symmetrize(P)


@njit(cache=True)
def propagate_bias_share(Pb, C, a_now, dt, params):
    """Pb ← F·Pb·Fᵀ + Q_b (symmetrised) in place, the biases' share of P
    (:func:`bias_share`): F as :func:`propagate`'s, Q_b only the bias driving noise (the
    accelerometer- and gyro-bias densities squared times dt on the bias rows). Nothing
    with 9 states (no bias in the filter, Pb stays 0)."""
    n = Pb.shape[0]
    if n != NAV_AND_BIAS_STATES:
        return
    transition_in_place(Pb, C, a_now, dt, params)
    _transpose(Pb)
    transition_in_place(Pb, C, a_now, dt, params)
    for i in range(ACC_BIAS, n):
        Pb[i, i] += process_noise(params, i, dt)
    symmetrize(Pb)


@njit(cache=True)
def predict(state, f, w, dt, params):
    """Trapezoidal mechanization over dt [s] from f [m/s²] and w [rad/s] (3,), body
    frame (:func:`mechanize`), then the covariance (:func:`propagate`) and its biases'
    share (:func:`propagate_bias_share`)."""
    a_now = mechanize(state, f, w, dt, params.gravity_mps2)
    propagate(state.P, state.C, a_now, dt, params)
    propagate_bias_share(state.Pb, state.C, a_now, dt, params)


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
    measurement of the three error states from row ``rows`` (:data:`VELOCITY` for the
    ZUPT, :data:`GYRO_BIAS` for the ZARU; noise σ per axis, in their units).

    H only selects states, so H·P, P·Hᵀ and H·P·Hᵀ are slices of P and the Joseph form
    (I − KH)·P·(I − KH)ᵀ + K·R·Kᵀ costs O(n²) instead of O(n³); written as loops, with
    no temporary arrays beyond Kᵀ and M: K = P·Hᵀ·S⁻¹ with S = H·P·Hᵀ + σ²I,
    M = P − K·H·P, P ← M − M·Hᵀ·Kᵀ + σ²·K·Kᵀ, then symmetrised. Returns Kᵀ (3, n) and
    S⁻¹·ν (3,) for the innovation ν, which the smoother's backward pass needs
    (:func:`pdr_ins_ekf.compiled_smoother.adjoint_before_update`)."""
    n = P.shape[0]
    S_inv = _inverse3(P[rows:rows + AXES, rows:rows + AXES] + np.eye(3) * sigma**2)
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
def compensate(state):
    """Feed the error state δx̂ = ``state.dx`` back into the nominal state (Simón Colomar
    et al. 2012, Eq. (8)): p += δp, v += δv, C ← (I − [δθ×])·C (then
    re-orthonormalised), b += δb."""
    p, v, C, b, dx = state.p, state.v, state.C, state.b, state.dx
    for i in range(3):
        p[i] += dx[POSITION + i]
        v[i] += dx[VELOCITY + i]
    t0, t1, t2 = dx[ATTITUDE], dx[ATTITUDE + 1], dx[ATTITUDE + 2]
    correction = np.array([[1.0, t2, -t1], [-t2, 1.0, t0], [t1, -t0, 1.0]])
    corrected = np.empty((3, 3))
    product3(correction, C, corrected)
    C[:, :] = corrected
    orthonormalize(C)
    if dx.shape[0] == NAV_AND_BIAS_STATES:
        for i in range(6):
            b[i] += dx[ACC_BIAS + i]


@njit(cache=True)
def _matvec3(C, x, out):
    """out ← C·x for a 3×3 C and a 3-vector x."""
    for i in range(3):
        out[i] = C[i, 0] * x[0] + C[i, 1] * x[1] + C[i, 2] * x[2]


@njit(cache=True)
def bias_share(Pb, K_T, rows):
    """Pb ← (I − K·H)·Pb·(I − K·H)ᵀ in place (symmetrised), with the gain K = (Kᵀ)ᵀ,
    Kᵀ (3, n), that :func:`correct` used for P and H selecting the three states from
    ``rows``; no K·R·Kᵀ, the measurement noise being white.

    For given gains the Joseph form holds whatever they are, and P is linear in what
    drives it: P₀, the white noises (Q's first blocks, R) and the biases' (P₀'s bias
    block, their driving noise). Pb is the last part alone, the covariance the biases put
    into the error through the filter's own F and gains (the sensitivity analysis of a
    filter with given gains, Gelb, Applied Optimal Estimation, 1974, Section 7.1), and
    P − Pb the white noises' part. Pb's position and attitude are what piles up over the
    strides with one sign, which the touchdown innovations do not measure
    (:func:`covariance_scale`)."""
    n = Pb.shape[0]
    if n != NAV_AND_BIAS_STATES:
        return
    M = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            M[i, j] = Pb[i, j] - (K_T[0, i] * Pb[rows, j] + K_T[1, i] * Pb[rows + 1, j]
                                  + K_T[2, i] * Pb[rows + 2, j])
    for i in range(n):
        for j in range(n):
            Pb[i, j] = M[i, j] - (M[i, rows] * K_T[0, j] + M[i, rows + 1] * K_T[1, j]
                                  + M[i, rows + 2] * K_T[2, j])
    symmetrize(Pb)


@njit(cache=True)
def update(state, z, rows, sigma):
    """Joseph-form update (:func:`correct`) with H selecting the three error states from
    row ``rows``, measurement z (3,) and noise σ per axis, the biases' share of P with
    the same gain (:func:`bias_share`), then the closed-loop compensation of Simón
    Colomar et al. 2012, Eq. (8) (:func:`feed_back`)."""
    K_T, _ = correct(state.dx, state.P, z, rows, sigma)
    bias_share(state.Pb, K_T, rows)
    feed_back(state)


@njit(cache=True)
def within_gate(P, innovation, rows, sigma, gate):
    """True when the normalised innovation squared νᵀ·S⁻¹·ν of a direct measurement of
    the three states from ``rows`` (S = H·P·Hᵀ + σ²I) is below ``gate``, a χ² bound with
    3 degrees of freedom (16.27 at 0.999; Bar-Shalom et al. 2001, section 5.4)."""
    return normalised_innovation(P, innovation, rows, sigma) < gate


@njit(cache=True)
def normalised_innovation(P, innovation, rows, sigma):
    """νᵀ·S⁻¹·ν of a direct measurement of the three error states from ``rows``, S =
    H·P·Hᵀ + σ²I (Bar-Shalom et al. 2001, section 5.4)."""
    S_inv = _inverse3(P[rows:rows + AXES, rows:rows + AXES] + np.eye(3) * sigma**2)
    nis = 0.0
    for a in range(3):
        for c in range(3):
            nis += innovation[a] * S_inv[a, c] * innovation[c]
    return nis


@njit(cache=True)
def count_touchdown(state, stance):
    """Before a stance sample's ZUPT: if it is the first of its stance (a touchdown), add
    ν·P_v⁻¹·ν / 3 with ν = −v̂ to ``state.nis``; then note whether this sample is stance.
    The touchdown ZUPT tests the whole swing's prediction: ν is the velocity error the
    INS gathered since the last stance (and the foot's own velocity at touchdown, which
    the ZUPT will put into the estimate as well), P_v the covariance the filter predicted
    for it; the ZUPT's σ, which stands for the whole stance's micro-motion, is left out."""
    nis = state.nis
    if stance and not state.stance[0]:
        nis[NIS_SUM] += normalised_innovation(state.P, -state.v, VELOCITY, 0.0) / AXES
        nis[NIS_COUNT] += 1.0
    state.stance[0] = stance


@njit(cache=True)
def covariance_scale(state, params):
    """The factor λ the published covariance scales P's white noises' part by, λ·(P − Pb)
    + Pb (:func:`bias_share`): with ``innovation_scale``, the mean touchdown
    νᵀ·P_v⁻¹·ν / 3 so far (:func:`count_touchdown`; 1 before the first touchdown), else 1.

    Covariance matching (Mehra, "Approaches to adaptive filtering", IEEE TAC 17(5), 1972;
    Maybeck, Stochastic Models, Estimation and Control, vol. 2, 1982, ch. 10): if the
    true noises are λ times the configured ones, Q, R and P₀ all, the Kalman gain is the
    configured filter's and its true error covariance is λ·P, while the innovations'
    normalised squares have the mean λ per degree of freedom. So the gain (the estimate)
    stays the tuned filter's and the covariance published with it is λ·P, λ measured on
    the walk itself: a foot that is never quite still in stance, or an IMU whose errors
    are not the configured white noise, shows in the velocity the INS has gathered at
    touchdown (docs/foot_ins.md, "Covariance honesty"). A bias, nearly the same through
    many strides, does not: its share keeps the configured bias model."""
    if params.innovation_scale and state.nis[NIS_COUNT] > 0.0:
        return state.nis[NIS_SUM] / state.nis[NIS_COUNT]
    return 1.0


@njit(cache=True)
def feed_back(state):
    """:func:`compensate`, δx̂ ← 0, then the navigation-frame specific force of
    ``prev`` rotated by the corrected attitude (the next trapezoidal step averages it)."""
    compensate(state)
    state.dx[:] = 0.0
    _matvec3(state.C, state.prev[PREV_FORCE], state.prev[PREV_NAV_FORCE])


@njit(cache=True)
def filter_loop(samples, C0, b0, P0, params):
    """All samples of a record (:class:`~pdr_ins_ekf.kernel_data.Samples`) from the
    aligned state (attitude C0 (3, 3), biases b0 (6,), covariance P0 (n, n)) at the
    origin at rest: :func:`filter_block`."""
    state = new_state(C0, b0, P0)
    start(state, samples.accel[0], samples.gyro[0])
    return filter_block(state, samples, params)


@njit(cache=True)
def filter_block(state, samples, params):
    """Consecutive samples from ``state``, changed in place: each propagated over its
    ``dt`` [s], then ZUPT where ``stance`` (and ZARU there, where the angular rate
    passes :func:`within_gate`: a foot that turns is not at rest, however still its
    velocity). Returns position, velocity (N, 3), attitude (N, 3, 3), bias (N, 6),
    covariance diagonal (N, n), position and velocity covariance (N, 3, 3) after each
    sample, the factor (N,) the published covariances scale their white noises' part by
    (:func:`covariance_scale`), and the biases' share of the diagonal (N, n) and of the
    position and velocity blocks (N, 3, 3) (:func:`bias_share`)."""
    p, v, C, b, P, Pb = state.p, state.v, state.C, state.b, state.P, state.Pb
    N = samples.accel.shape[0]
    n = P.shape[0]
    pos, vel, bias = np.empty((N, 3)), np.empty((N, 3)), np.empty((N, 6))
    att, pcov, vcov = np.empty((N, 3, 3)), np.empty((N, 3, 3)), np.empty((N, 3, 3))
    var, scale = np.empty((N, n)), np.empty(N)
    bvar, bpcov, bvcov = np.empty((N, n)), np.empty((N, 3, 3)), np.empty((N, 3, 3))
    for k in range(N):
        w = samples.gyro[k]
        predict(state, samples.accel[k], w, samples.dt[k], params)
        count_touchdown(state, samples.stance[k])
        if samples.stance[k]:
            update(state, -v, VELOCITY, params.zupt_sigma_mps)
            if params.zaru and within_gate(P, w - b[GYRO], GYRO_BIAS,
                                           params.zaru_sigma_radps, params.zaru_gate_nis):
                update(state, w - b[GYRO], GYRO_BIAS, params.zaru_sigma_radps)
        pos[k], vel[k], att[k], bias[k] = p, v, C, b
        for i in range(n):
            var[k, i] = P[i, i]
            bvar[k, i] = Pb[i, i]
        pcov[k] = P[POSITION:POSITION + AXES, POSITION:POSITION + AXES]
        vcov[k] = P[VELOCITY:VELOCITY + AXES, VELOCITY:VELOCITY + AXES]
        bpcov[k] = Pb[POSITION:POSITION + AXES, POSITION:POSITION + AXES]
        bvcov[k] = Pb[VELOCITY:VELOCITY + AXES, VELOCITY:VELOCITY + AXES]
        scale[k] = covariance_scale(state, params)
    return pos, vel, att, bias, var, pcov, vcov, scale, bvar, bpcov, bvcov
