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
   formed, and no Pₙ|ₙ is needed between loop closures either: the smoothed deviation
   runs backward through the model, δx̂ₙ|ₑ = Fₙ₊₁⁻¹·(δx̂ₙ₊₁|ₑ − Qₙ₊₁·λ̃ₙ₊₁)
   (:func:`smooth_states`), O(n) per sample instead of a Cholesky factor and n×n
   products, and the store holds no covariance per sample.
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

from pdr_core import kernel_cache, small_matrix
from pdr_core.small_matrix import cholesky, product3, rodrigues
from pdr_ins_ekf import compiled_filter
from pdr_ins_ekf.compiled_filter import (
    PARAM_ZARU_GATE,
    apply_transition,
    correct,
    feed_back,
    inverse_transition_in_place,
    mechanize,
    process_noise,
    propagate,
    start,
    transition_in_place,
    transposed_transition_in_place,
    within_gate,
)

kernel_cache.forget_if_changed(__file__, compiled_filter.__file__, small_matrix.__file__)

# the segment store (new_segment_store), by sample: nominal position, velocity, attitude;
# predicted and filtered deviation; their covariances; Fₙ's inputs, the update count and
# the row of the stored filtered deviation; per update, Kᵀ and S⁻¹·ν; then the layout
POS, VEL, ATT, DX_PRED, DX_FILT, COV_PRED, COV_FILT, STEP, GAIN, WEIGHTED, LAYOUT = range(11)
# seg[STEP] columns: Fₙ's navigation-frame specific force (3), dt, updates, row
STEP_UPDATES, STEP_ROW = 4, 5
# seg[LAYOUT]: rows of DX_FILT / COV_FILT in use, whether every sample has one (1) or
# only the anchors (0), and whether the covariance is smoothed too (see new_segment_store)
LAYOUT_ROWS, LAYOUT_DENSE, LAYOUT_COVARIANCE = range(3)
# rule: [γs, τs, Σ diag(P_v) of the previous sample, c] (c: time since the crossing [s])
RULE_GAMMA, RULE_TAU, RULE_PREVIOUS, RULE_CLOCK = range(4)


@njit(cache=True)
def new_segment_store(capacity, n, covariance, dense, updates):
    """Arrays for ``capacity`` samples of a segment (indexed by :data:`POS` …
    :data:`LAYOUT`): nominal p, v (cap, 3), C (cap, 3, 3); per sample what the
    transition Fₙ is rebuilt from in the backward pass (the navigation-frame specific
    force and dt), how many measurement updates it had and the row of its stored
    filtered deviation (cap, 6); per update (ZUPT, and ZARU when ``updates`` is 2) the
    gain Kᵀ (cap, updates, 3, n) and S⁻¹·ν (cap, updates, 3).

    The filtered deviations and covariances: with ``covariance`` (Eq. (9) as written)
    every sample's, with the predicted ones where a measurement changed them (see
    :func:`predicted_covariance`); ``dense`` without it, every sample's deviation and
    the first 9 rows of its covariance (the adjoint form with a P that is not the
    filter's own, :func:`smooth_states_dense`); otherwise only the anchors': the samples
    where the forward pass closed the loop (:func:`anchor`), all the recursion of
    :func:`smooth_states` needs. Unused arrays are (1, …) placeholders."""
    per_sample = covariance or dense
    rows = capacity if per_sample else 4
    return (np.empty((capacity, 3)), np.empty((capacity, 3)), np.empty((capacity, 3, 3)),
            np.empty((capacity if covariance else 1, n)), np.empty((rows, n)),
            np.empty((capacity if covariance else 1, n, n)),
            np.empty((rows, 9 if dense and not covariance else n, n)),
            np.empty((capacity, 6)), np.empty((capacity, updates, 3, n)),
            np.empty((capacity, updates, 3)),
            np.array([0, 1 if per_sample else 0, 1 if covariance else 0], np.int64))


@njit(cache=True)
def grown(seg, needed):
    """``seg`` with room for ``needed`` samples (contents kept; the anchors of the sparse
    layout grow on their own, in :func:`anchor`)."""
    capacity = seg[POS].shape[0]
    if needed <= capacity:
        return seg
    n = seg[DX_FILT].shape[1]
    covariance = seg[LAYOUT][LAYOUT_COVARIANCE] == 1
    dense = seg[LAYOUT][LAYOUT_DENSE] == 1
    bigger = new_segment_store(max(needed, 2 * capacity), n, covariance, dense,
                               seg[GAIN].shape[1])
    bigger[POS][:capacity] = seg[POS]
    bigger[VEL][:capacity] = seg[VEL]
    bigger[ATT][:capacity] = seg[ATT]
    bigger[STEP][:capacity] = seg[STEP]
    bigger[GAIN][:capacity] = seg[GAIN]
    bigger[WEIGHTED][:capacity] = seg[WEIGHTED]
    if covariance:
        bigger[DX_PRED][:capacity] = seg[DX_PRED]
        bigger[COV_PRED][:capacity] = seg[COV_PRED]
    if not dense:
        return (bigger[POS], bigger[VEL], bigger[ATT], bigger[DX_PRED], seg[DX_FILT],
                bigger[COV_PRED], seg[COV_FILT], bigger[STEP], bigger[GAIN],
                bigger[WEIGHTED], seg[LAYOUT])
    bigger[DX_FILT][:capacity] = seg[DX_FILT]
    bigger[COV_FILT][:capacity] = seg[COV_FILT]
    bigger[LAYOUT][:] = seg[LAYOUT]
    return bigger


@njit(cache=True)
def anchor(seg, j, dx, P):
    """Store sample j's filtered deviation and covariance as an anchor of the sparse
    layout (a no-op in the dense one, which stores every sample's), where the forward
    pass closes the loop (:func:`close_segment`). Returns ``seg``, with more anchor rows
    if it needed them."""
    layout = seg[LAYOUT]
    if layout[LAYOUT_DENSE]:
        return seg
    row = layout[LAYOUT_ROWS]
    if row == seg[DX_FILT].shape[0]:
        dx_rows = np.empty((2 * row, dx.shape[0]))
        cov_rows = np.empty((2 * row, dx.shape[0], dx.shape[0]))
        dx_rows[:row] = seg[DX_FILT]
        cov_rows[:row] = seg[COV_FILT]
        seg = (seg[POS], seg[VEL], seg[ATT], seg[DX_PRED], dx_rows, seg[COV_PRED], cov_rows,
               seg[STEP], seg[GAIN], seg[WEIGHTED], layout)
    seg[DX_FILT][row] = dx
    seg[COV_FILT][row] = P
    seg[STEP][j, STEP_ROW] = row
    layout[LAYOUT_ROWS] = row + 1
    return seg


@njit(cache=True)
def open_loop_step(seg, j, p, v, C, b, dx, P, prev, f, w, dt, stance, zaru, params,
                   zupt_sigma, zaru_sigma, zero_heading_position, rule):
    """Pass 1 for one sample, stored at segment position j; returns True when the
    segmentation rule ends the segment at this sample."""
    covariance = seg[LAYOUT][LAYOUT_COVARIANCE] == 1
    a_now = mechanize(p, v, C, b, prev, f, w, dt, params[6])
    transition_in_place(dx.reshape(-1, 1), C, a_now, dt, params)
    propagate(P, C, a_now, dt, params)
    if zero_heading_position:
        P[0:3, 8] = 0.0
        P[8, 0:3] = 0.0
    step = seg[STEP][j]
    step[0:3] = a_now
    step[3] = dt
    step[STEP_UPDATES] = 0.0
    step[STEP_ROW] = -1.0
    if covariance:
        seg[DX_PRED][j] = dx
    if stance and covariance:
        seg[COV_PRED][j] = P
    if stance:
        seg[GAIN][j, 0], seg[WEIGHTED][j, 0] = correct(dx, P, -v - dx[3:6], 3, zupt_sigma)
        step[STEP_UPDATES] = 1.0
        if zaru and within_gate(P, w - b[3:] - dx[12:15], 12, zaru_sigma,
                                params[PARAM_ZARU_GATE]):
            seg[GAIN][j, 1], seg[WEIGHTED][j, 1] = correct(
                dx, P, w - b[3:] - dx[12:15], 12, zaru_sigma)
            step[STEP_UPDATES] = 2.0
    if seg[LAYOUT][LAYOUT_DENSE]:
        seg[COV_FILT][j] = P[0:seg[COV_FILT].shape[1]]
        seg[DX_FILT][j] = dx
        step[STEP_ROW] = j
    seg[POS][j] = p
    seg[VEL][j] = v
    seg[ATT][j] = C
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
    return seg[COV_PRED][j] if seg[STEP][j, STEP_UPDATES] else seg[COV_FILT][j]


@njit(cache=True)
def adjoint_before_update(seg, j, lam):
    """λ̃ from λ across sample j's measurement updates, last first, in place:
    λ ← Hᵀ·S⁻¹·ν + (I − K·H)ᵀ·λ = λ + Hᵀ·(S⁻¹·ν − Kᵀ·λ), H selecting the rows of
    the velocity (ZUPT) or the gyro bias (ZARU)."""
    n = lam.shape[0]
    for u in range(int(seg[STEP][j, STEP_UPDATES]) - 1, -1, -1):
        rows = 3 if u == 0 else 12
        K_T = seg[GAIN][j, u]
        k0 = k1 = k2 = 0.0
        for i in range(n):
            k0 += K_T[0, i] * lam[i]
            k1 += K_T[1, i] * lam[i]
            k2 += K_T[2, i] * lam[i]
        lam[rows] += seg[WEIGHTED][j, u, 0] - k0
        lam[rows + 1] += seg[WEIGHTED][j, u, 1] - k1
        lam[rows + 2] += seg[WEIGHTED][j, u, 2] - k2


@njit(cache=True)
def spd_solve(S, B):
    """X = S⁻¹·B for a symmetric positive-definite S (n, n) and B (n, k): Cholesky
    S = L·Lᵀ, then L·Y = B and Lᵀ·X = Y, in loops that run along B's rows. An S that is
    not positive definite (zeroing the heading–position cross-covariance can make it
    indefinite, 001 section IV) is solved by LU (LAPACK) instead."""
    n, k = B.shape
    L = np.empty((n, n))
    if not cholesky(S, L):
        return np.linalg.solve(S, B)
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
def smooth_segment(seg, m, params, pos, vel, att, vel_var):
    """Passes 2 and 3 over the segment's m samples: smoothed, compensated position,
    velocity, attitude (m, …) and, in a store that smooths the covariance too (Eq. (9)
    as written, through
    :func:`rts_step`), the smoothed velocity variances (m, 3); without it the states
    alone in the adjoint form (module docstring) and NaN variances. Empties the store's
    anchors."""
    if seg[LAYOUT][LAYOUT_COVARIANCE]:
        _smooth_with_covariance(seg, m, params, pos, vel, att, vel_var)
    else:
        vel_var[:] = np.nan
        if seg[LAYOUT][LAYOUT_DENSE]:
            smooth_states_dense(seg, m, params, pos, vel, att)
        else:
            smooth_states(seg, m, params, pos, vel, att)
    seg[LAYOUT][LAYOUT_ROWS] = 0


@njit(cache=True)
def _compensate_sample(seg, j, dxs, pos, vel, att):
    """Pass 3 at sample j: the nominal state corrected by the smoothed deviation, the
    attitude by the rotation exp(−[δθ×]), exact to first order like (I − [δθ×]) and
    orthonormal without a re-orthonormalisation."""
    for i in range(3):
        pos[j, i] = seg[POS][j, i] + dxs[i]
        vel[j, i] = seg[VEL][j, i] + dxs[3 + i]
    rotation = np.empty((3, 3))
    rodrigues(-dxs[6], -dxs[7], -dxs[8], rotation)
    product3(rotation, seg[ATT][j], att[j])


@njit(cache=True)
def _smooth_with_covariance(seg, m, params, pos, vel, att, vel_var):
    """Eq. (9) as written (:func:`rts_step`), states and covariance."""
    dxs = seg[DX_FILT][m - 1].copy()
    Ps = seg[COV_FILT][m - 1].copy()
    for j in range(m - 1, -1, -1):
        if j < m - 1:
            C_next, a_next, dt_next = seg[ATT][j + 1], seg[STEP][j + 1, 0:3], seg[STEP][j + 1, 3]
            FP = apply_transition(seg[COV_FILT][j], C_next, a_next, dt_next, params)
            rts_step(seg[DX_FILT][j], seg[COV_FILT][j], seg[DX_PRED][j + 1],
                     predicted_covariance(seg, j + 1), FP, dxs, Ps)
        _compensate_sample(seg, j, dxs, pos, vel, att)
        for i in range(3):
            vel_var[j, i] = Ps[3 + i, 3 + i]


@njit(cache=True)
def adjoint_smoothed(dx_f, P_f, lam, dxs, rows):
    """δx̂ₙ|ₑ = δx̂ₙ|ₙ + Pₙ|ₙ·λₙ, its first ``rows`` states, into dxs."""
    for i in range(rows):
        acc = dx_f[i]
        for q in range(lam.shape[0]):
            acc += P_f[i, q] * lam[q]
        dxs[i] = acc


@njit(cache=True)
def smooth_states_dense(seg, m, params, pos, vel, att):
    """The states alone, δx̂ₙ|ₑ = δx̂ₙ|ₙ + Pₙ|ₙ·λₙ at every sample: for a covariance that
    is not the filter's own propagation (zero_heading_position), where the recursion of
    :func:`smooth_states` does not hold."""
    n = seg[DX_FILT].shape[1]
    dxs = seg[DX_FILT][m - 1].copy()
    lam = np.zeros(n)  # λ at the segment's last sample: smoothed = filtered there
    for j in range(m - 1, -1, -1):
        if j < m - 1:
            C_next, a_next, dt_next = seg[ATT][j + 1], seg[STEP][j + 1, 0:3], seg[STEP][j + 1, 3]
            adjoint_before_update(seg, j + 1, lam)
            transposed_transition_in_place(lam, C_next, a_next, dt_next, params)
            # position, velocity, attitude: all the output needs
            adjoint_smoothed(seg[DX_FILT][j], seg[COV_FILT][j], lam, dxs, 9)
        _compensate_sample(seg, j, dxs, pos, vel, att)


@njit(cache=True)
def smooth_states(seg, m, params, pos, vel, att):
    """The states alone, backward through the model, storing no covariance per sample.

    With Pₙ₊₁|ₙ = Fₙ₊₁·Pₙ|ₙ·Fₙ₊₁ᵀ + Qₙ₊₁, the adjoint form gives
    Fₙ₊₁·δx̂ₙ|ₑ = δx̂ₙ₊₁|ₙ + (Pₙ₊₁|ₙ − Qₙ₊₁)·λ̃ₙ₊₁ = δx̂ₙ₊₁|ₑ − Qₙ₊₁·λ̃ₙ₊₁ (Qₙ₊₁·λ̃ₙ₊₁ is
    the smoothed process noise), so δx̂ₙ|ₑ = Fₙ₊₁⁻¹·(δx̂ₙ₊₁|ₑ − Qₙ₊₁·λ̃ₙ₊₁): O(n) per
    sample with the diagonal Q and the block-triangular F. Where the forward pass closed
    the loop (the anchors: δx̂ was fed back and restarted from 0), δx̂ₙ|ₑ is taken as
    δx̂ₙ|ₙ + Pₙ|ₙ·λₙ from the stored ones, which also bounds the rounding carried
    backward to one segment."""
    n = seg[DX_FILT].shape[1]
    dxs = seg[DX_FILT][int(seg[STEP][m - 1, STEP_ROW])].copy()
    lam = np.zeros(n)  # λ at the segment's last sample: smoothed = filtered there
    _compensate_sample(seg, m - 1, dxs, pos, vel, att)
    for j in range(m - 2, -1, -1):
        C_next, a_next, dt_next = seg[ATT][j + 1], seg[STEP][j + 1, 0:3], seg[STEP][j + 1, 3]
        adjoint_before_update(seg, j + 1, lam)
        row = int(seg[STEP][j, STEP_ROW])
        if row < 0:
            for i in range(3, n):
                dxs[i] -= process_noise(params, i, dt_next) * lam[i]
            inverse_transition_in_place(dxs, C_next, a_next, dt_next, params)
        transposed_transition_in_place(lam, C_next, a_next, dt_next, params)
        if row >= 0:
            adjoint_smoothed(seg[DX_FILT][row], seg[COV_FILT][row], lam, dxs, n)
        _compensate_sample(seg, j, dxs, pos, vel, att)


@njit(cache=True)
def close_segment(seg, j, p, v, C, b, dx, P, prev, rule):
    """Pass 3 at the segment's last sample j: keep its filtered deviation as an anchor
    (:func:`anchor`), feed the deviation back, restart it from zero and rearm the
    segmentation rule. Returns ``seg`` (see :func:`anchor`); the segment can be smoothed
    after this, from the store."""
    seg = anchor(seg, j, dx, P)
    feed_back(p, v, C, b, dx, prev)
    dx[:] = 0.0
    rule[RULE_CLOCK] = 0.0
    return seg


@njit(cache=True)
def forward_run(seg, first, k, t, accel, gyro, stance, zaru, params, zupt_sigma, zaru_sigma,
                zero_heading_position, rule, p, v, C, b, dx, P, prev):
    """Pass 1 from sample k on (segment position k − first), until the segmentation rule
    cuts, the store is full or the input ends; returns the last sample done and whether
    the rule cut there. A loop of its own because ``seg`` is re-bound (grown, anchored)
    only outside it: a store that may be re-bound inside the loop costs numba a
    reference count of each of its arrays at every sample (a third of the forward
    pass)."""
    capacity = seg[POS].shape[0]
    N = t.shape[0]
    while True:
        cut = open_loop_step(seg, k - first, p, v, C, b, dx, P, prev, accel[k], gyro[k],
                             t[k] - t[k - 1] if k else 0.0, stance[k], zaru, params,
                             zupt_sigma, zaru_sigma, zero_heading_position, rule)
        if cut or k == N - 1 or k - first + 1 == capacity:
            return k, cut
        k += 1


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
    seg = new_segment_store(N if full else min(N, 1024), n, covariance,
                            zero_heading_position, 2 if zaru else 1)
    rule = np.array([gamma_s, tau_s, 0.0, 0.0])
    first = k = 0
    while k < N:
        k, cut = forward_run(seg, first, k, t, accel, gyro, stance, zaru, params, zupt_sigma,
                             zaru_sigma, zero_heading_position, rule, p, v, C, b, dx, P,
                             prev)
        j = k - first
        if not (cut or k == N - 1):
            seg = grown(seg, j + 2)
        else:
            seg = close_segment(seg, j, p, v, C, b, dx, P, prev, rule)
            if not full or k == N - 1:
                smooth_segment(seg, j + 1, params, pos[first:k + 1], vel[first:k + 1],
                               att[first:k + 1], vel_var[first:k + 1])
                ends[segments] = k
                segments += 1
                first = k + 1
        k += 1
    return pos, vel, att, vel_var, ends[:segments]
