"""Rauch–Tung–Striebel smoothing of the ZUPT-aided INS as compiled kernels (numba): the
3-pass algorithm of 001_5b5dbf275b14cf0a.txt, section III and Alg. 1.

1. Forward, open loop (:func:`open_loop_step`): the nominal state is mechanized without
   feedback and the deviation state is propagated, δx̂ₙ|ₙ₋₁ = Fₙ·δx̂ₙ₋₁|ₙ₋₁, and updated
   by the ZUPT (innovation −v̂ₙ − δv̂ₙ|ₙ₋₁) and, with 15 states, the ZARU.
   The segment ends τs seconds after Σ diag(P_v) has crossed γs from above at a ZUPT
   (section III-B). "At a ZUPT" is ours: on a foot, the yaw and tilt uncertainty times the
   foot's velocity makes Σ diag(P_v) peak mid-swing and fall again before the ZUPT, and
   the paper's rule alone would cut the step in two there.
2. Backward (:func:`smooth_segment`), Eq. (9) on the deviation states:
   Aₙ = Pₙ|ₙ·Fₙ₊₁ᵀ·Pₙ₊₁|ₙ⁻¹, δx̂ₙ|ₑ = δx̂ₙ|ₙ + Aₙ(δx̂ₙ₊₁|ₑ − δx̂ₙ₊₁|ₙ),
   Pₙ|ₑ = Pₙ|ₙ + Aₙ(Pₙ₊₁|ₑ − Pₙ₊₁|ₙ)Aₙᵀ (:func:`rts_step`). The smoothed covariance is
   optional. The smoothed states alone are computed in the equivalent adjoint form of
   the same smoother (Bierman's modified Bryson–Frazier recursion): with
   δx̂ₙ₊₁|ₑ − δx̂ₙ₊₁|ₙ = Pₙ₊₁|ₙ·λ̃ₙ₊₁, Eq. (9) becomes δx̂ₙ|ₑ = δx̂ₙ|ₙ + Pₙ|ₙ·λₙ with
   λₙ = Fₙ₊₁ᵀ·λ̃ₙ₊₁, and each measurement update turns λ into
   λ̃ = Hᵀ·S⁻¹·ν + (I − K·H)ᵀ·λ (:func:`adjoint_before_update`). No Pₙ₊₁|ₙ⁻¹ is
   formed: O(n²) per sample instead of a Cholesky factor and n×n products.
3. Compensation: each sample's nominal state is corrected by its smoothed deviation
   (p̂ += δp̂, v̂ += δv̂, Ĉ ← (I − [δθ̂×])Ĉ); the loop is closed at the segment's last
   sample, where the next segment starts with δx̂ = 0 and the filtered P.

Full-data-set smoothing (τs = ∞ for the smoothing lag) runs one backward pass over the
record; see :func:`smoother_loop` for why its forward pass still closes the loop.
``seg`` is the segment store: its arrays are indexed by the sample's position in the
current segment and grow (doubling) when a segment is longer than they are, so memory is
bounded by the longest segment, not by the record (except in the full mode).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_ins_ekf import compiled_filter, kernel_cache
from pdr_ins_ekf.compiled_filter import (
    _product3,
    _rodrigues,
    apply_transition,
    compensate,
    correct,
    mechanize,
    propagate,
    start,
    transition_in_place,
    transposed_transition,
)

kernel_cache.forget_if_changed(__file__, compiled_filter.__file__)

# the segment store (new_segment_store), by sample: nominal position, velocity, attitude;
# predicted and filtered deviation; their covariances; Fₙ's inputs and the update count;
# per update, Kᵀ and S⁻¹·ν
POS, VEL, ATT, DX_PRED, DX_FILT, COV_PRED, COV_FILT, STEP, GAIN, WEIGHTED = range(10)
# rule: [γs, τs, Σ diag(P_v) of the previous sample, c] (c: time since the crossing [s])
RULE_GAMMA, RULE_TAU, RULE_PREVIOUS, RULE_CLOCK = range(4)


@njit(cache=True)
def new_segment_store(capacity, n, covariance):
    """Arrays for ``capacity`` samples of a segment (indexed by :data:`POS` …
    :data:`WEIGHTED`): nominal p, v (cap, 3), C (cap, 3, 3), predicted and filtered
    deviations (cap, n), their covariances (with the smoothed ``covariance`` on, both
    (cap, n, n), the predicted one only where a measurement changed it, see
    :func:`predicted_covariance`; without it only the filtered one's first 9 rows, all
    the adjoint form uses: (cap, 9, n), and a (1, n, n) placeholder), per sample what
    the transition Fₙ is rebuilt from in the backward pass (the navigation-frame specific
    force and dt) and how many measurement updates it had (cap, 5), and per update
    (ZUPT, ZARU) the gain Kᵀ (cap, 2, 3, n) and S⁻¹·ν (cap, 2, 3)."""
    return (np.empty((capacity, 3)), np.empty((capacity, 3)), np.empty((capacity, 3, 3)),
            np.empty((capacity, n)), np.empty((capacity, n)),
            np.empty((capacity if covariance else 1, n, n)),
            np.empty((capacity, n if covariance else 9, n)), np.empty((capacity, 5)),
            np.empty((capacity, 2, 3, n)), np.empty((capacity, 2, 3)))


@njit(cache=True)
def grown(seg, needed):
    """``seg`` with room for ``needed`` samples (contents kept)."""
    capacity = seg[POS].shape[0]
    if needed <= capacity:
        return seg
    n = seg[DX_PRED].shape[1]
    covariance = seg[COV_FILT].shape[1] == n
    bigger = new_segment_store(max(needed, 2 * capacity), n, covariance)
    bigger[POS][:capacity] = seg[POS]
    bigger[VEL][:capacity] = seg[VEL]
    bigger[ATT][:capacity] = seg[ATT]
    bigger[DX_PRED][:capacity] = seg[DX_PRED]
    bigger[DX_FILT][:capacity] = seg[DX_FILT]
    if covariance:
        bigger[COV_PRED][:capacity] = seg[COV_PRED]
    bigger[COV_FILT][:capacity] = seg[COV_FILT]
    bigger[STEP][:capacity] = seg[STEP]
    bigger[GAIN][:capacity] = seg[GAIN]
    bigger[WEIGHTED][:capacity] = seg[WEIGHTED]
    return bigger


@njit(cache=True)
def open_loop_step(seg, j, p, v, C, b, dx, P, prev, f, w, dt, stance, zaru, params,
                   zupt_sigma, zaru_sigma, zero_heading_position, rule, covariance):
    """Pass 1 for one sample, stored at segment position j; returns True when the
    segmentation rule ends the segment at this sample."""
    a_now = mechanize(p, v, C, b, prev, f, w, dt, params[6])
    transition_in_place(dx.reshape(-1, 1), C, a_now, dt, params)
    propagate(P, C, a_now, dt, params)
    if zero_heading_position:
        P[0:3, 8] = 0.0
        P[8, 0:3] = 0.0
    seg[STEP][j, 0:3] = a_now
    seg[STEP][j, 3] = dt
    seg[STEP][j, 4] = 0.0
    seg[DX_PRED][j] = dx
    if stance and covariance:
        seg[COV_PRED][j] = P
    if stance:
        seg[GAIN][j, 0], seg[WEIGHTED][j, 0] = correct(dx, P, -v - dx[3:6], 3, zupt_sigma)
        seg[STEP][j, 4] = 1.0
        if zaru:
            seg[GAIN][j, 1], seg[WEIGHTED][j, 1] = correct(
                dx, P, w - b[3:] - dx[12:15], 12, zaru_sigma)
            seg[STEP][j, 4] = 2.0
    seg[COV_FILT][j] = P[0:seg[COV_FILT].shape[1]]
    seg[POS][j] = p
    seg[VEL][j] = v
    seg[ATT][j] = C
    seg[DX_FILT][j] = dx
    variance = P[3, 3] + P[4, 4] + P[5, 5]
    if rule[RULE_CLOCK] > 0:
        rule[RULE_CLOCK] += dt
    if stance and rule[RULE_PREVIOUS] > rule[RULE_GAMMA] >= variance and rule[RULE_CLOCK] == 0:
        rule[RULE_CLOCK] = dt
    rule[RULE_PREVIOUS] = variance
    return rule[RULE_CLOCK] > rule[RULE_TAU]


@njit(cache=True)
def predicted_covariance(seg, j):
    """Pₙ|ₙ₋₁ at segment position j: the filtered one where no measurement came."""
    return seg[COV_PRED][j] if seg[STEP][j, 4] else seg[COV_FILT][j]


@njit(cache=True)
def adjoint_before_update(seg, j, lam):
    """λ̃ from λ across sample j's measurement updates, last first, in place:
    λ ← Hᵀ·S⁻¹·ν + (I − K·H)ᵀ·λ = λ + Hᵀ·(S⁻¹·ν − Kᵀ·λ), H selecting the rows of
    the velocity (ZUPT) or the gyro bias (ZARU)."""
    n = lam.shape[0]
    for u in range(int(seg[STEP][j, 4]) - 1, -1, -1):
        rows = 3 if u == 0 else 12
        K_T = seg[GAIN][j, u]
        k = np.zeros(3)
        for a in range(3):
            for i in range(n):
                k[a] += K_T[a, i] * lam[i]
        for a in range(3):
            lam[rows + a] += seg[WEIGHTED][j, u, a] - k[a]


@njit(cache=True)
def spd_solve(S, B):
    """X = S⁻¹·B for a symmetric positive-definite S (n, n) and B (n, k): Cholesky
    S = L·Lᵀ, then L·Y = B and Lᵀ·X = Y, in loops that run along B's rows. An S that is
    not positive definite (zeroing the heading–position cross-covariance can make it
    indefinite, 001 section IV) is solved by LU (LAPACK) instead."""
    n, k = B.shape
    L = np.zeros((n, n))
    for j in range(n):
        d = S[j, j]
        for q in range(j):
            d -= L[j, q] * L[j, q]
        if not d > 0.0:
            return np.linalg.solve(S, B)
        d = np.sqrt(d)
        L[j, j] = d
        for i in range(j + 1, n):
            s = S[i, j]
            for q in range(j):
                s -= L[i, q] * L[j, q]
            L[i, j] = s / d
    X = B.copy()
    for i in range(n):
        for q in range(i):
            lq = L[i, q]
            for c in range(k):
                X[i, c] -= lq * X[q, c]
        for c in range(k):
            X[i, c] /= L[i, i]
    for i in range(n - 1, -1, -1):
        for q in range(i + 1, n):
            lq = L[q, i]
            for c in range(k):
                X[i, c] -= lq * X[q, c]
        for c in range(k):
            X[i, c] /= L[i, i]
    return X


@njit(cache=True)
def rts_step(dx_f, P_f, dx_p_next, P_p_next, FP, dxs, Ps):
    """Eq. (9) of 001 for one sample, in place on the next sample's smoothed dxs and Ps:
    Aₙ = Pₙ|ₙ·Fₙ₊₁ᵀ·Pₙ₊₁|ₙ⁻¹ = Xᵀ with X = Pₙ₊₁|ₙ⁻¹·(Fₙ₊₁·Pₙ|ₙ) (``FP``),
    δx̂ₙ|ₑ = δx̂ₙ|ₙ + Aₙ(δx̂ₙ₊₁|ₑ − δx̂ₙ₊₁|ₙ), Pₙ|ₑ = Pₙ|ₙ + Aₙ(Pₙ₊₁|ₑ − Pₙ₊₁|ₙ)Aₙᵀ."""
    n = P_f.shape[0]
    X = spd_solve(P_p_next, FP)
    diff = dxs - dx_p_next
    D = Ps - P_p_next
    T = np.zeros((n, n))  # Aₙ·D = Xᵀ·D
    for q in range(n):
        for i in range(n):
            x = X[q, i]
            for c in range(n):
                T[i, c] += x * D[q, c]
    for i in range(n):
        acc = dx_f[i]
        for q in range(n):
            acc += X[q, i] * diff[q]
        dxs[i] = acc
    for i in range(n):
        for c in range(n):
            Ps[i, c] = P_f[i, c]
        for q in range(n):
            t = T[i, q]
            for c in range(n):
                Ps[i, c] += t * X[q, c]


@njit(cache=True)
def smooth_segment(seg, m, params, pos, vel, att, vel_var, covariance):
    """Passes 2 and 3 over the segment's m samples: smoothed, compensated position,
    velocity, attitude (m, …) and, with ``covariance`` (Eq. (9) as written, through
    :func:`rts_step`), the smoothed velocity variances (m, 3); without it the states in
    the adjoint form (module docstring) and NaN variances. The attitude correction is
    applied as the rotation exp(−[δθ×]), exact to first order like (I − [δθ×]) and
    orthonormal without a re-orthonormalisation."""
    n = seg[DX_PRED].shape[1]
    dxs = seg[DX_FILT][m - 1].copy()
    Ps = seg[COV_FILT][m - 1].copy()
    lam = np.zeros(n)  # λ at the segment's last sample: smoothed = filtered there
    for j in range(m - 1, -1, -1):
        if j < m - 1:
            C_next, a_next, dt_next = seg[ATT][j + 1], seg[STEP][j + 1, 0:3], seg[STEP][j + 1, 3]
            if covariance:
                FP = apply_transition(seg[COV_FILT][j], C_next, a_next, dt_next, params)
                rts_step(seg[DX_FILT][j], seg[COV_FILT][j], seg[DX_PRED][j + 1],
                         predicted_covariance(seg, j + 1), FP, dxs, Ps)
            else:
                adjoint_before_update(seg, j + 1, lam)
                lam = transposed_transition(lam, C_next, a_next, dt_next, params)
                P_f = seg[COV_FILT][j]
                for i in range(9):  # position, velocity, attitude: all the output needs
                    acc = seg[DX_FILT][j, i]
                    for q in range(n):
                        acc += P_f[i, q] * lam[q]
                    dxs[i] = acc
        pos[j] = seg[POS][j] + dxs[0:3]
        vel[j] = seg[VEL][j] + dxs[3:6]
        _product3(_rodrigues(-dxs[6:9], 1.0), seg[ATT][j], att[j])
        for i in range(3):
            vel_var[j, i] = Ps[3 + i, 3 + i] if covariance else np.nan


@njit(cache=True)
def close_loop(p, v, C, b, dx, prev):
    """Pass 3 at the segment's last sample: feed the deviation back, restart from zero."""
    compensate(p, v, C, b, dx)
    prev[2] = C @ prev[0]
    dx[:] = 0.0


@njit(cache=True)
def smoother_loop(t, accel, gyro, stance, zaru, C0, b0, P0, params, zupt_sigma, zaru_sigma,
                  zero_heading_position, gamma_s, tau_s, full, covariance):
    """All samples: smoothed position, velocity (N, 3), attitude (N, 3, 3), velocity
    variances (N, 3; NaN without ``covariance``) and the index of each smoothed segment's
    last sample.

    ``full``: one backward pass over the whole record. The forward pass still closes the
    loop at every segment end, so the nominal state never drifts far from the truth and
    the linearisation stays as good as in the segmented mode; across a loop closure
    δx̂ₑ₊₁|ₑ = Fₑ₊₁·0 = 0 about the corrected state, and the same recursion carries on."""
    N = t.shape[0]
    n = P0.shape[0]
    p, v, dx = np.zeros(3), np.zeros(3), np.zeros(n)
    C, b, P = C0.copy(), b0.copy(), P0.copy()
    prev = np.empty((3, 3))
    start(C, b, prev, accel[0], gyro[0])
    pos, vel = np.empty((N, 3)), np.empty((N, 3))
    att, vel_var = np.empty((N, 3, 3)), np.empty((N, 3))
    ends = np.empty(N, np.int64)
    segments = 0
    seg = new_segment_store(N if full else min(N, 1024), n, covariance)
    rule = np.array([gamma_s, tau_s, 0.0, 0.0])
    first = 0
    for k in range(N):
        j = k - first
        seg = grown(seg, j + 1)
        cut = open_loop_step(seg, j, p, v, C, b, dx, P, prev, accel[k], gyro[k],
                             t[k] - t[k - 1] if k else 0.0, stance[k], zaru, params,
                             zupt_sigma, zaru_sigma, zero_heading_position, rule, covariance)
        if (cut and not full) or k == N - 1:
            smooth_segment(seg, j + 1, params, pos[first:k + 1], vel[first:k + 1],
                           att[first:k + 1], vel_var[first:k + 1], covariance)
            ends[segments] = k
            segments += 1
            first = k + 1
        if cut or k == N - 1:
            close_loop(p, v, C, b, dx, prev)
            rule[RULE_CLOCK] = 0.0
    return pos, vel, att, vel_var, ends[:segments]
