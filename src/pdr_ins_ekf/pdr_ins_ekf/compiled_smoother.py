"""Rauch–Tung–Striebel smoothing of the ZUPT-aided INS as compiled kernels (numba): the
3-pass algorithm of Simón Colomar et al. 2012, section III and Alg. 1.

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
The open-loop deviation δx̂ is the ``dx`` of the filter's
:class:`~pdr_ins_ekf.kernel_data.NavState`. The :class:`SegmentStore` holds the current
segment: its arrays are indexed by the sample's position in the segment and grow
(doubling) when a segment is longer than they are, so memory is bounded by the longest
segment, not by the record (except in the full mode). ENU navigation frame, FLU body
frame, SI units.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache, small_matrix
from pdr_core.maths.small_matrix import cholesky, product3, rodrigues
from pdr_ins_ekf import compiled_filter, kernel_data
from pdr_ins_ekf.compiled_filter import (
    apply_transition,
    correct,
    feed_back,
    inverse_transition_in_place,
    mechanize,
    new_state,
    process_noise,
    propagate,
    start,
    transition_in_place,
    transposed_transition_in_place,
    within_gate,
)
from pdr_ins_ekf.kernel_data import (
    ATTITUDE,
    AXES,
    GYRO,
    GYRO_BIAS,
    HEADING,
    NAV_STATES,
    POSITION,
    VELOCITY,
)

kernel_cache.forget_if_changed(__file__, compiled_filter.__file__, small_matrix.__file__,
                               kernel_data.__file__)

# the measurement updates of a sample, in the order they are made (SegmentStore.gain)
ZUPT, ZARU = 0, 1
# SegmentStore.rule: the segmentation rule's memory
RULE_PREVIOUS = 0   # Σ diag(P_v) of the previous sample [m²/s²]
RULE_CLOCK = 1      # time since Σ diag(P_v) crossed γs [s]; 0 before the crossing


class SmootherParams(NamedTuple):
    """The smoother's settings (:class:`pdr_ins_ekf.zupt_ekf.SmootherConfig`)."""

    gamma_s_m2ps2: float         # γs: the segment rule's threshold on Σ diag(P_v)
    tau_s: float                 # τs: a segment ends this long after the crossing [s]
    zero_heading_position: bool  # zero the heading–position cross-covariance
    full: bool                   # one backward pass over the whole record
    covariance: bool             # smooth the covariance too (Eq. (9) as written)


class SegmentStore(NamedTuple):
    """What the backward pass needs of the current segment (:func:`new_segment_store`),
    indexed by the sample's position j in the segment (cap samples; n error states)."""

    position: np.ndarray     # (cap, 3) nominal p̂ [m]
    velocity: np.ndarray     # (cap, 3) nominal v̂ [m/s]
    attitude: np.ndarray     # (cap, 3, 3) nominal Ĉ
    dx_pred: np.ndarray      # (cap, n) predicted deviation δx̂ₙ|ₙ₋₁ (covariance layout)
    dx_filt: np.ndarray      # (rows, n) filtered deviation δx̂ₙ|ₙ, at row ``row[j]``
    cov_pred: np.ndarray     # (cap, n, n) Pₙ|ₙ₋₁ where updated (covariance layout)
    cov_filt: np.ndarray     # (rows, n or 9, n) Pₙ|ₙ, at row ``row[j]``
    nav_force: np.ndarray    # (cap, 3) Fₙ's navigation-frame specific force [m/s²]
    dt: np.ndarray           # (cap,) Fₙ's interval [s]
    updates: np.ndarray      # (cap,) int: the sample's measurement updates (ZUPT, ZARU)
    row: np.ndarray          # (cap,) int: the row of its dx_filt, cov_filt; −1 none
    gain: np.ndarray         # (cap, updates, 3, n) Kᵀ per update
    weighted: np.ndarray     # (cap, updates, 3) S⁻¹·ν per update
    anchors: np.ndarray      # (1,) int: the rows of dx_filt, cov_filt in use
    rule: np.ndarray         # (2,) the segmentation rule's memory (RULE_PREVIOUS, …)
    dense: bool              # a filtered deviation for every sample (else the anchors)
    covariance: bool         # the covariance is smoothed too


@njit(cache=True)
def new_segment_store(capacity, n, covariance, dense, updates):
    """A :class:`SegmentStore` for ``capacity`` samples of a segment with n error
    states: nominal p, v, C; per sample what the transition Fₙ is rebuilt from in the
    backward pass (the navigation-frame specific force and dt), how many measurement
    updates it had and the row of its stored filtered deviation; per update (ZUPT, and
    ZARU when ``updates`` is 2) the gain Kᵀ and S⁻¹·ν.

    The filtered deviations and covariances: with ``covariance`` (Eq. (9) as written)
    every sample's, with the predicted ones where a measurement changed them (see
    :func:`predicted_covariance`); ``dense`` without it, every sample's deviation and
    the first 9 rows (δp, δv, δθ) of its covariance (the adjoint form with a P that is
    not the filter's own, :func:`smooth_states_dense`); otherwise only the anchors': the
    samples where the forward pass closed the loop (:func:`anchor`), all the recursion of
    :func:`smooth_states` needs. Unused arrays are (1, …) placeholders."""
    per_sample = covariance or dense
    rows = capacity if per_sample else 4
    return SegmentStore(
        np.empty((capacity, 3)), np.empty((capacity, 3)), np.empty((capacity, 3, 3)),
        np.empty((capacity if covariance else 1, n)), np.empty((rows, n)),
        np.empty((capacity if covariance else 1, n, n)),
        np.empty((rows, NAV_STATES if dense and not covariance else n, n)),
        np.empty((capacity, 3)), np.empty(capacity), np.empty(capacity, np.int64),
        np.empty(capacity, np.int64), np.empty((capacity, updates, 3, n)),
        np.empty((capacity, updates, 3)), np.zeros(1, np.int64), np.zeros(2),
        per_sample, covariance)


@njit(cache=True)
def grown(seg, needed):
    """``seg`` with room for ``needed`` samples (contents kept; the anchors of the sparse
    layout grow on their own, in :func:`anchor`)."""
    capacity = seg.position.shape[0]
    if needed <= capacity:
        return seg
    bigger = new_segment_store(max(needed, 2 * capacity), seg.dx_filt.shape[1],
                               seg.covariance, seg.dense, seg.gain.shape[1])
    bigger.position[:capacity] = seg.position
    bigger.velocity[:capacity] = seg.velocity
    bigger.attitude[:capacity] = seg.attitude
    bigger.nav_force[:capacity] = seg.nav_force
    bigger.dt[:capacity] = seg.dt
    bigger.updates[:capacity] = seg.updates
    bigger.row[:capacity] = seg.row
    bigger.gain[:capacity] = seg.gain
    bigger.weighted[:capacity] = seg.weighted
    if seg.covariance:
        bigger.dx_pred[:capacity] = seg.dx_pred
        bigger.cov_pred[:capacity] = seg.cov_pred
    if not seg.dense:
        return SegmentStore(bigger.position, bigger.velocity, bigger.attitude,
                            bigger.dx_pred, seg.dx_filt, bigger.cov_pred, seg.cov_filt,
                            bigger.nav_force, bigger.dt, bigger.updates, bigger.row,
                            bigger.gain, bigger.weighted, seg.anchors, seg.rule, seg.dense,
                            seg.covariance)
    bigger.dx_filt[:capacity] = seg.dx_filt
    bigger.cov_filt[:capacity] = seg.cov_filt
    return SegmentStore(bigger.position, bigger.velocity, bigger.attitude, bigger.dx_pred,
                        bigger.dx_filt, bigger.cov_pred, bigger.cov_filt, bigger.nav_force,
                        bigger.dt, bigger.updates, bigger.row, bigger.gain, bigger.weighted,
                        seg.anchors, seg.rule, seg.dense, seg.covariance)


@njit(cache=True)
def anchor(seg, j, dx, P):
    """Store sample j's filtered deviation and covariance as an anchor of the sparse
    layout (a no-op in the dense one, which stores every sample's), where the forward
    pass closes the loop (:func:`close_segment`). Returns ``seg``, with more anchor rows
    if it needed them."""
    if seg.dense:
        return seg
    row = seg.anchors[0]
    if row == seg.dx_filt.shape[0]:
        dx_rows = np.empty((2 * row, dx.shape[0]))
        cov_rows = np.empty((2 * row, dx.shape[0], dx.shape[0]))
        dx_rows[:row] = seg.dx_filt
        cov_rows[:row] = seg.cov_filt
        seg = SegmentStore(seg.position, seg.velocity, seg.attitude, seg.dx_pred, dx_rows,
                           seg.cov_pred, cov_rows, seg.nav_force, seg.dt, seg.updates,
                           seg.row, seg.gain, seg.weighted, seg.anchors, seg.rule,
                           seg.dense, seg.covariance)
    seg.dx_filt[row] = dx
    seg.cov_filt[row] = P
    seg.row[j] = row
    seg.anchors[0] = row + 1
    return seg


@njit(cache=True)
def open_loop_step(seg, j, state, samples, k, params, smoother):
    """Pass 1 for sample k of ``samples`` (:class:`~pdr_ins_ekf.kernel_data.Samples`),
    stored at segment position j, from ``state`` (changed in place; its ``dx`` is the
    open-loop deviation); returns True when the segmentation rule ends the segment at
    this sample."""
    P, dx, b, v = state.P, state.dx, state.b, state.v
    w, dt, stance = samples.gyro[k], samples.dt[k], samples.stance[k]
    a_now = mechanize(state, samples.accel[k], w, dt, params.gravity_mps2)
    transition_in_place(dx.reshape(-1, 1), state.C, a_now, dt, params)
    propagate(P, state.C, a_now, dt, params)
    if smoother.zero_heading_position:
        P[POSITION:POSITION + AXES, HEADING] = 0.0
        P[HEADING, POSITION:POSITION + AXES] = 0.0
    seg.nav_force[j] = a_now
    seg.dt[j] = dt
    seg.updates[j] = 0
    seg.row[j] = -1
    if seg.covariance:
        seg.dx_pred[j] = dx
    if stance and seg.covariance:
        seg.cov_pred[j] = P
    if stance:
        seg.gain[j, ZUPT], seg.weighted[j, ZUPT] = correct(
            dx, P, -v - dx[VELOCITY:VELOCITY + AXES], VELOCITY, params.zupt_sigma_mps)
        seg.updates[j] = 1
        if params.zaru and within_gate(P, w - b[GYRO] - dx[GYRO_BIAS:GYRO_BIAS + AXES],
                                       GYRO_BIAS, params.zaru_sigma_radps,
                                       params.zaru_gate_nis):
            seg.gain[j, ZARU], seg.weighted[j, ZARU] = correct(
                dx, P, w - b[GYRO] - dx[GYRO_BIAS:GYRO_BIAS + AXES], GYRO_BIAS,
                params.zaru_sigma_radps)
            seg.updates[j] = 2
    if seg.dense:
        seg.cov_filt[j] = P[0:seg.cov_filt.shape[1]]
        seg.dx_filt[j] = dx
        seg.row[j] = j
    seg.position[j] = state.p
    seg.velocity[j] = v
    seg.attitude[j] = state.C
    variance = (P[VELOCITY, VELOCITY] + P[VELOCITY + 1, VELOCITY + 1]
                + P[VELOCITY + 2, VELOCITY + 2])
    rule = seg.rule
    if rule[RULE_CLOCK] > 0:
        rule[RULE_CLOCK] += dt
    if (stance and rule[RULE_PREVIOUS] > smoother.gamma_s_m2ps2 >= variance
            and rule[RULE_CLOCK] == 0):
        rule[RULE_CLOCK] = dt
    rule[RULE_PREVIOUS] = variance
    return rule[RULE_CLOCK] > smoother.tau_s


@njit(cache=True)
def predicted_covariance(seg, j):
    """Pₙ|ₙ₋₁ at segment position j: the filtered one where no measurement came."""
    return seg.cov_pred[j] if seg.updates[j] else seg.cov_filt[j]


@njit(cache=True)
def adjoint_before_update(seg, j, lam):
    """λ̃ from λ across sample j's measurement updates, last first, in place:
    λ ← Hᵀ·S⁻¹·ν + (I − K·H)ᵀ·λ = λ + Hᵀ·(S⁻¹·ν − Kᵀ·λ), H selecting the rows of
    the velocity (ZUPT) or the gyro bias (ZARU)."""
    n = lam.shape[0]
    for u in range(seg.updates[j] - 1, -1, -1):
        rows = VELOCITY if u == ZUPT else GYRO_BIAS
        K_T = seg.gain[j, u]
        k0 = k1 = k2 = 0.0
        for i in range(n):
            k0 += K_T[0, i] * lam[i]
            k1 += K_T[1, i] * lam[i]
            k2 += K_T[2, i] * lam[i]
        lam[rows] += seg.weighted[j, u, 0] - k0
        lam[rows + 1] += seg.weighted[j, u, 1] - k1
        lam[rows + 2] += seg.weighted[j, u, 2] - k2


@njit(cache=True)
def spd_solve(S, B):
    """X = S⁻¹·B for a symmetric positive-definite S (n, n) and B (n, k): Cholesky
    S = L·Lᵀ, then L·Y = B and Lᵀ·X = Y, in loops that run along B's rows. An S that is
    not positive definite (zeroing the heading–position cross-covariance can make it
    indefinite, Simón Colomar et al. 2012, section IV) is solved by LU (LAPACK)
    instead."""
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
    """Simón Colomar et al. 2012, Eq. (9) for one sample, in place on the next sample's
    smoothed dxs and Ps: Aₙ = Pₙ|ₙ·Fₙ₊₁ᵀ·Pₙ₊₁|ₙ⁻¹ = Xᵀ with
    X = Pₙ₊₁|ₙ⁻¹·(Fₙ₊₁·Pₙ|ₙ) (``FP``), δx̂ₙ|ₑ = δx̂ₙ|ₙ + Aₙ(δx̂ₙ₊₁|ₑ − δx̂ₙ₊₁|ₙ),
    Pₙ|ₑ = Pₙ|ₙ + Aₙ(Pₙ₊₁|ₑ − Pₙ₊₁|ₙ)Aₙᵀ."""
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
    """Passes 2 and 3 over the segment's m samples: smoothed, compensated position [m],
    velocity [m/s] (m, 3), attitude C_b^n (m, 3, 3) and, in a store that smooths the
    covariance too (Eq. (9) as written, through :func:`rts_step`), the smoothed velocity
    variances [m²/s²] (m, 3); without it the states alone in the adjoint form (module
    docstring) and NaN variances. Empties the store's anchors."""
    if seg.covariance:
        _smooth_with_covariance(seg, m, params, pos, vel, att, vel_var)
    else:
        vel_var[:] = np.nan
        if seg.dense:
            smooth_states_dense(seg, m, params, pos, vel, att)
        else:
            smooth_states(seg, m, params, pos, vel, att)
    seg.anchors[0] = 0


@njit(cache=True)
def _compensate_sample(seg, j, dxs, pos, vel, att):
    """Pass 3 at sample j: the nominal state corrected by the smoothed deviation, the
    attitude by the rotation exp(−[δθ×]), exact to first order like (I − [δθ×]) and
    orthonormal without a re-orthonormalisation."""
    for i in range(3):
        pos[j, i] = seg.position[j, i] + dxs[POSITION + i]
        vel[j, i] = seg.velocity[j, i] + dxs[VELOCITY + i]
    rotation = np.empty((3, 3))
    rodrigues(-dxs[ATTITUDE], -dxs[ATTITUDE + 1], -dxs[ATTITUDE + 2], rotation)
    product3(rotation, seg.attitude[j], att[j])


@njit(cache=True)
def _smooth_with_covariance(seg, m, params, pos, vel, att, vel_var):
    """Eq. (9) as written (:func:`rts_step`), states and covariance."""
    dxs = seg.dx_filt[m - 1].copy()
    Ps = seg.cov_filt[m - 1].copy()
    for j in range(m - 1, -1, -1):
        if j < m - 1:
            FP = apply_transition(seg.cov_filt[j], seg.attitude[j + 1], seg.nav_force[j + 1],
                                  seg.dt[j + 1], params)
            rts_step(seg.dx_filt[j], seg.cov_filt[j], seg.dx_pred[j + 1],
                     predicted_covariance(seg, j + 1), FP, dxs, Ps)
        _compensate_sample(seg, j, dxs, pos, vel, att)
        for i in range(3):
            vel_var[j, i] = Ps[VELOCITY + i, VELOCITY + i]


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
    n = seg.dx_filt.shape[1]
    dxs = seg.dx_filt[m - 1].copy()
    lam = np.zeros(n)  # λ at the segment's last sample: smoothed = filtered there
    for j in range(m - 1, -1, -1):
        if j < m - 1:
            adjoint_before_update(seg, j + 1, lam)
            transposed_transition_in_place(lam, seg.attitude[j + 1], seg.nav_force[j + 1],
                                           seg.dt[j + 1], params)
            # δp, δv, δθ: all the output needs
            adjoint_smoothed(seg.dx_filt[j], seg.cov_filt[j], lam, dxs, NAV_STATES)
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
    n = seg.dx_filt.shape[1]
    dxs = seg.dx_filt[seg.row[m - 1]].copy()
    lam = np.zeros(n)  # λ at the segment's last sample: smoothed = filtered there
    _compensate_sample(seg, m - 1, dxs, pos, vel, att)
    for j in range(m - 2, -1, -1):
        C_next, a_next, dt_next = seg.attitude[j + 1], seg.nav_force[j + 1], seg.dt[j + 1]
        adjoint_before_update(seg, j + 1, lam)
        row = seg.row[j]
        if row < 0:
            for i in range(VELOCITY, n):
                dxs[i] -= process_noise(params, i, dt_next) * lam[i]
            inverse_transition_in_place(dxs, C_next, a_next, dt_next, params)
        transposed_transition_in_place(lam, C_next, a_next, dt_next, params)
        if row >= 0:
            adjoint_smoothed(seg.dx_filt[row], seg.cov_filt[row], lam, dxs, n)
        _compensate_sample(seg, j, dxs, pos, vel, att)


@njit(cache=True)
def close_segment(seg, j, state):
    """Pass 3 at the segment's last sample j: keep its filtered deviation as an anchor
    (:func:`anchor`), feed the deviation back (:func:`feed_back`, which restarts it from
    zero) and rearm the segmentation rule. Returns ``seg`` (see :func:`anchor`); the
    segment can be smoothed after this, from the store."""
    seg = anchor(seg, j, state.dx, state.P)
    feed_back(state)
    seg.rule[RULE_CLOCK] = 0.0
    return seg


@njit(cache=True)
def forward_run(seg, first, k, state, samples, params, smoother):
    """Pass 1 from sample k on (segment position k − first), until the segmentation rule
    cuts, the store is full or the input ends; returns the last sample done and whether
    the rule cut there. A loop of its own because ``seg`` is re-bound (grown, anchored)
    only outside it: a store that may be re-bound inside the loop costs numba a
    reference count of each of its arrays at every sample (a third of the forward
    pass)."""
    capacity = seg.position.shape[0]
    N = samples.dt.shape[0]
    while True:
        cut = open_loop_step(seg, k - first, state, samples, k, params, smoother)
        if cut or k == N - 1 or k - first + 1 == capacity:
            return k, cut
        k += 1


@njit(cache=True)
def smoother_loop(samples, C0, b0, P0, params, smoother):
    """All samples of a record (:class:`~pdr_ins_ekf.kernel_data.Samples`) from the
    aligned state (attitude C0 (3, 3), biases b0 (6,), covariance P0 (n, n)) at the
    origin at rest: smoothed position [m], velocity [m/s] (N, 3), attitude C_b^n
    (N, 3, 3), velocity variances [m²/s²] (N, 3; NaN without ``smoother.covariance``)
    and the index of each smoothed segment's last sample.

    ``smoother.full``: one backward pass over the whole record. The forward pass still
    closes the loop at every segment end, so the nominal state never drifts far from the
    truth and the linearisation stays as good as in the segmented mode; across a loop
    closure δx̂ₑ₊₁|ₑ = Fₑ₊₁·0 = 0 about the corrected state, and the same recursion
    carries on."""
    N = samples.dt.shape[0]
    n = P0.shape[0]
    state = new_state(C0, b0, P0)
    start(state, samples.accel[0], samples.gyro[0])
    pos, vel = np.empty((N, 3)), np.empty((N, 3))
    att, vel_var = np.empty((N, 3, 3)), np.empty((N, 3))
    ends = np.empty(N, np.int64)
    segments = 0
    seg = new_segment_store(N if smoother.full else min(N, 1024), n, smoother.covariance,
                            smoother.zero_heading_position, 2 if params.zaru else 1)
    first = k = 0
    while k < N:
        k, cut = forward_run(seg, first, k, state, samples, params, smoother)
        j = k - first
        if not (cut or k == N - 1):
            seg = grown(seg, j + 2)
        else:
            seg = close_segment(seg, j, state)
            if not smoother.full or k == N - 1:
                smooth_segment(seg, j + 1, params, pos[first:k + 1], vel[first:k + 1],
                               att[first:k + 1], vel_var[first:k + 1])
                ends[segments] = k
                segments += 1
                first = k + 1
        k += 1
    return pos, vel, att, vel_var, ends[:segments]
