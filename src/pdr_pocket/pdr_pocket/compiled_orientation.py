"""The orientation filter's per-sample loop, compiled with numba (Muñoz Díaz 2016, ch. 3).

An unscented Kalman filter on the thesis' state x = [φ, θ, ψ, b_x, b_y, b_z] (Eq. (3.1)).
The attitude part is carried as the direction cosine matrix C = C_b^n (ENU, FLU body) with
a 3-vector error δθ, a small rotation in the navigation frame (C_true = exp([δθ×])·C): the
sigma points are C_i = exp([δθ_i×])·C, so nothing ever divides by cos θ, and θ = ±90°
(a sitting thigh comes close) gives neither NaN nor a jump. φ, θ, ψ are read from C
(ZYX, :mod:`pdr_core.maths.rotations`) and their covariance from the δθ block; near θ = ±90° only
the split of the attitude between roll and yaw is ill-defined, as it is for any Euler
angles. P is the 6 × 6 covariance of [δθ, δb], rows named by :data:`ATT_EAST` ...
:data:`BIAS_Z`.

Per sample k, with δt from the stamps (:func:`filter_loop`):
- prediction, each sigma point: C_i ← C_i·A(ω − b_i − C_iᵀ·ω_ie^n) with Rodrigues' A
  (Eqs. (3.3)–(3.5)) and the Earth rate of Eqs. (3.23)–(3.24) (zero when no latitude is
  set), the rotation vector by the trapezoidal rule with the coning term; b_i kept (a
  random constant, see pdr_pocket.config; b_i ← c·b_i, c = e^{−δt/τ} as Eq. (3.8) when
  ``bias_mean_decays``); Q = diag(σ_ν²δt² I, σ_n² I) with σ_n² = σ_bias²(1 − c²)
  (Eq. (3.9));
- detectors on trailing windows (causal, so the live node gives the offline result):
  zero acceleration (max |‖α‖ − g| ≤ threshold, and max ‖ω‖ ≤ a rate limit: a thigh
  turning at its hip puts ω × (ω × r) and ω̇ × r into the accelerometer at the lever arm
  r, which the norm alone does not see), zero angular rate (every ω of the window within
  a threshold of the window's mean rate ω̄: rest, whatever the gyroscope's bias, as VQF's
  rest detector (Laidig and Seel 2023) reads the rate's deviation from its low-pass),
  magnetic disturbance (‖C·μ‖ spread and angle to the window's mean direction, both
  ≤ thresholds);
- updates, each switched on or off, applied in turn where its detector holds, each a
  :class:`Measurement` made by its builder:
  1. absolute gravity [φ̄, θ̄] (Eqs. (3.12)–(3.14)), at zero acceleration
     (:func:`absolute_gravity`);
  2. differential gravity, α^k against A(ω − b)ᵀ·α^{k−1} (Eqs. (3.15)–(3.16)), at zero
     acceleration (:func:`differential_gravity`);
  3. absolute magnetic field, μ^k against Cᵀ·μ̄_r with μ̄_r = C·μ at the start of the
     quasi-constant period (Eq. (3.17)), in a steady field (:func:`absolute_magnetic`);
  4. differential magnetic field, μ^k against A(ω − b)ᵀ·μ^{k−1} (Eqs. (3.18)–(3.19)), in
     a steady field (:func:`differential_magnetic`);
  5. absolute compass ψ̄ (Eqs. (3.20)–(3.21)), in a steady field (:func:`compass`);
  6. beyond the thesis, mean gravity, at the end of each window (:func:`mean_gravity`):
     over a window of W seconds the specific force turned to the navigation frame sums
     to g·W·e_up plus the window's change of velocity, which is bounded while walking, so
     the summed direction, turned to the body frame, is the vertical there: the up axis
     of the attitude (the row C[2, :], which no yaw moves) across it, [0, 0] expected,
     measures the tilt with σ ≈ σ_Δv/(g·W) (0.6° for W = 10 s and σ_Δv = 1 m/s) at any
     walking speed, where the zero-acceleration periods the gravity updates need are rare
     on a thigh;
  7. ZARU ω − b = 0 (Eq. (3.22)), at zero angular rate (:func:`rest_zaru`): ω is the
     mean rate ω̄ of the window's older half (the white noise and the sway averaged, as
     VQF's rest bias estimate reads its low-passed rate; the newest half, where a thigh
     starting to move is still below the threshold, left out), R grows by the rate's
     variance over that half (a thigh settling into the stop sways), and a χ² gate on the
     innovation ω̄ − b − Cᵀ·ω_ie^n against P_bb + R (:func:`zaru_nis`) refuses a slow
     steady turn.
- external corrections between samples (Eq. (6.2), :func:`correct`): the yaw ψ_L or the
  z gyro bias, as the same unscented update (:func:`external_correction`).

A(ω)ᵀ maps a vector fixed in the navigation frame from the previous body frame to the
current one (C_k = C_{k−1}·A, so v_b^k = Aᵀ·v_b^{k−1}); the thesis writes A for it.
The compass is derived in ENU with ψ counter-clockwise from east: a field of azimuth
γ = 90° − d (d the declination, east positive) reads ψ̄ = γ − atan2(μ_h,y, μ_h,x) from
the tilt-compensated horizontal field μ_h. The compass and the external yaw correction
move the attitude only about the vertical (their gain on the tilt is zeroed): the compass
error follows the tilt error, and a compass applied at every sample as if its errors were
white otherwise turns yaw residuals into roll. Updates at samples whose gyroscope
saturated leave the biases alone (their bias gain is zeroed).

What each departure from the thesis was measured to do, on simulated and real walks:
docs/pocket.md, "The thesis' filter". The measurement builders are
pdr_pocket.compiled_orientation_measurements, the detectors' trailing windows
pdr_pocket.compiled_orientation_detectors, the 3 × 3 helpers pdr_core.maths.small_matrix.

Kernel data, as NamedTuples: :class:`FilterParams` (set by the configuration),
:class:`FilterState` (changed by every sample), :class:`FilterInputs` and
:class:`FilterOutputs` (a record in, its estimates out), :class:`Sample` (one sample) and
:class:`Measurement` (one update, made by its builder). A compiled function that takes a
NamedTuple increments and decrements the reference count of every array in it on each
call, and numba does not always prune that: the small helpers called at every sample take
the arrays they use, not the whole state (taking it cost 15–20 % of the loop's time).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_core.maths import angles, kernel_cache, lowpass, small_matrix
from pdr_core.maths.angles import wrap_angle_jit
from pdr_core.maths.lowpass import lowpass_decay
from pdr_core.maths.small_matrix import (
    cholesky,
    euler_of,
    inverse_spd,
    mul_bt,
    product3,
    rodrigues,
    rotation_increment,
    rotation_log,
)
from pdr_pocket import (
    compiled_gait_window,
    compiled_orientation_data,
    compiled_orientation_detectors,
    compiled_orientation_measurements,
)
from pdr_pocket.compiled_gait_window import (
    add_to_window,
    forget_window,
    holds_gravity,
    restart_window,
    swing_marker,
)
from pdr_pocket.compiled_orientation_data import (
    ATT,
    ATT_EAST,
    ATT_NORTH,
    ATT_UP,
    BIAS,
    MAG_STEADY,
    N_STATE,
    SATURATED,
    ZERO_ACC,
    ZERO_RATE,
    Sample,
    workspace,
)
from pdr_pocket.compiled_orientation_detectors import (
    detect,
)
from pdr_pocket.compiled_orientation_measurements import (
    ABS_GRAVITY,
    ABS_MAG,
    COMPASS,
    DIFF_GRAVITY,
    DIFF_MAG,
    MEAN_GRAVITY,
    YAW_CORRECTION,
    ZARU,
    absolute_gravity,
    absolute_magnetic,
    compass,
    differential_gravity,
    differential_magnetic,
    external_correction,
    mean_gravity,
    zaru,
)

kernel_cache.forget_if_changed(__file__, small_matrix.__file__, angles.__file__, lowpass.__file__,
                               compiled_gait_window.__file__,
                               compiled_orientation_data.__file__,
                               compiled_orientation_detectors.__file__,
                               compiled_orientation_measurements.__file__)


                                    # the absolute magnetic update may run


# --- sigma points ----------------------------------------------------------------------
@njit(cache=True)
def _sqrt_cov(p, out):
    """A square root L (L·Lᵀ = N·P) of the scaled covariance; an eigen-decomposition with
    non-negative eigenvalues when Cholesky fails (P driven indefinite by rounding)."""
    scaled = N_STATE * 0.5 * (p + p.T)
    if not cholesky(scaled, out):
        w, v = np.linalg.eigh(scaled)
        for j in range(N_STATE):
            out[:, j] = v[:, j] * np.sqrt(max(w[j], 0.0))


@njit(cache=True)
def _sigma_points(state, work):
    """The 2n sigma points (weights 1/2n, λ = 0) into the workspace: deviations (2n, 6)
    and, per point, the attitude (2n, 3, 3) and bias (2n, 3)."""
    root, rot = work.root, work.m1
    sigma_att, sigma_bias, deviations = work.attitudes, work.biases, work.deviations
    _sqrt_cov(state.covariance, root)
    for j in range(N_STATE):
        for sign in range(2):
            i = 2 * j + sign
            s = 1.0 if sign == 0 else -1.0
            for m in range(N_STATE):
                deviations[i, m] = s * root[m, j]
            rodrigues(deviations[i, ATT_EAST], deviations[i, ATT_NORTH], deviations[i, ATT_UP],
                      rot)
            product3(rot, state.attitude, sigma_att[i])
            for m in range(3):
                sigma_bias[i, m] = state.bias[m] + deviations[i, BIAS + m]


# --- prediction ------------------------------------------------------------------------
@njit(cache=True)
def predict(state, params, sample, work):
    """Propagate mean and covariance over δt with the (bias-corrected) rate: see
    :func:`pdr_core.maths.small_matrix.rotation_increment`."""
    gyro, prev, dt = sample.gyro, sample.previous_gyro, sample.dt
    n2 = 2 * N_STATE
    _sigma_points(state, work)
    sat, sbias = work.attitudes, work.biases
    c_decay = lowpass_decay(dt, params.bias_tau_s)
    c_mean = c_decay if params.bias_mean_decays else 1.0
    inc = np.empty((3, 3))
    rotation_increment(state.attitude, gyro, prev, state.bias, params.earth_rate_n, dt, inc)
    mean_att = np.empty((3, 3))
    product3(state.attitude, inc, mean_att)
    mean_bias = c_mean * state.bias
    prop = work.propagated
    err = np.empty(3)
    moved, rel = work.m2, work.m3
    for i in range(n2):
        rotation_increment(sat[i], gyro, prev, sbias[i], params.earth_rate_n, dt, inc)
        product3(sat[i], inc, moved)
        mul_bt(moved, mean_att, rel)
        rotation_log(rel, err)
        for m in range(3):
            prop[i, ATT + m] = err[m]
            prop[i, BIAS + m] = c_mean * sbias[i, m] - mean_bias[m]
    centre = np.zeros(N_STATE)
    for i in range(n2):
        centre += prop[i] / n2
    # the mean is the propagated centre, not re-centred on the sigma points' average:
    # that average holds the second-order (commutator) term of the rotation composition,
    # which on ±σ points does not cancel and walked the yaw of an ideal gyroscope by
    # 2° in two minutes
    state.attitude[:, :] = mean_att
    for m in range(3):
        state.bias[m] = mean_bias[m]
    p = np.zeros((N_STATE, N_STATE))
    for i in range(n2):
        for a in range(N_STATE):
            da = (prop[i, a] - centre[a]) / n2
            for b in range(N_STATE):
                p[a, b] += da * (prop[i, b] - centre[b])
    q_att = params.gyro_noise_var * dt * dt
    q_bias = params.bias_sigma ** 2 * (1.0 - c_decay * c_decay)
    gap = dt > params.max_gap_s
    for m in range(3):
        turned = 0.5 * (gyro[m] + prev[m]) * dt
        p[ATT + m, ATT + m] += q_att + params.gyro_scale_var * turned * turned
        if gap:
            # over a gap the trapezoid guesses the rate between its two ends: its error
            # is of the order of half their difference times the gap
            unknown = 0.5 * (gyro[m] - prev[m]) * dt
            p[ATT + m, ATT + m] += unknown * unknown
        p[BIAS + m, BIAS + m] += q_bias
    state.covariance[:, :] = 0.5 * (p + p.T)


# --- the unscented update ----------------------------------------------------------------
@njit(cache=True)
def _measure(measurement, sample, earth_n, attitude, bias, sigma_att, sigma_bias, out):
    """h(x) for the measurement's kind at the mean (``attitude``, ``bias``: ``out[0]``) and
    at each sigma point (``out[1 + i]``), out (2n + 1, m); the builders' docstrings give
    each model."""
    kind, vectors = measurement.kind, measurement.vectors
    e, inc = np.empty(3), np.empty((3, 3))
    for i in range(out.shape[0]):
        att = attitude if i == 0 else sigma_att[i - 1]
        b = bias if i == 0 else sigma_bias[i - 1]
        h = out[i]
        if kind == ABS_GRAVITY:                   # [φ, θ] of C
            euler_of(att, e)
            h[0], h[1] = e[0], e[1]
        elif kind in (DIFF_GRAVITY, DIFF_MAG):    # A(ω − b)ᵀ·v^{k−1}
            before = vectors[0]
            rotation_increment(att, sample.gyro, sample.previous_gyro, b, earth_n, sample.dt, inc)
            for m in range(3):
                h[m] = inc[0, m] * before[0] + inc[1, m] * before[1] + inc[2, m] * before[2]
        elif kind == ABS_MAG:                     # Cᵀ·μ̄_r
            ref = vectors[0]
            for m in range(3):
                h[m] = att[0, m] * ref[0] + att[1, m] * ref[1] + att[2, m] * ref[2]
        elif kind in (COMPASS, YAW_CORRECTION):   # ψ of C
            h[0] = np.arctan2(att[1, 0], att[0, 0])
        elif kind == MEAN_GRAVITY:                # C[2, :]·b₁, C[2, :]·b₂
            b1, b2 = vectors[0], vectors[1]
            h[0] = att[2, 0] * b1[0] + att[2, 1] * b1[1] + att[2, 2] * b1[2]
            h[1] = att[2, 0] * b2[0] + att[2, 1] * b2[1] + att[2, 2] * b2[2]
        elif kind == ZARU:                        # ω − b − Cᵀ·ω_ie^n
            w = sample.gyro
            for m in range(3):
                h[m] = w[m] - b[m] - (att[0, m] * earth_n[0] + att[1, m] * earth_n[1]
                                      + att[2, m] * earth_n[2])
        else:                                     # BIAS_Z_CORRECTION: b_z
            h[0] = b[2]


@njit(cache=True)
def _angular(kind, m):
    """Whether measurement component m of ``kind`` is an angle (wrapped)."""
    return kind in (ABS_GRAVITY, COMPASS, YAW_CORRECTION)


@njit(cache=True)
def update(state, params, measurement, sample, work):
    """One unscented update with ``measurement`` (z (m,), R (m, m)) at ``sample``; returns
    the normalised innovation squared ν^T·S^{-1}·ν. A saturated sample zeroes the bias
    gain; the compass and the yaw correction zero the tilt gain."""
    kind, z, r = measurement.kind, measurement.z, measurement.r
    m_dim = z.shape[0]
    n2 = 2 * N_STATE
    _sigma_points(state, work)
    dev, sat, sbias = work.deviations, work.attitudes, work.biases
    predicted = np.empty((n2 + 1, m_dim))
    _measure(measurement, sample, params.earth_rate_n, state.attitude, state.bias, sat, sbias,
             predicted)
    h_mean = predicted[0]
    hs = np.empty((n2, m_dim))
    for i in range(n2):
        for m in range(m_dim):
            d = predicted[1 + i, m] - h_mean[m]
            hs[i, m] = wrap_angle_jit(d) if _angular(kind, m) else d
    dbar = np.zeros(m_dim)
    for i in range(n2):
        dbar += hs[i] / n2
    s = r.copy()
    pxz = np.zeros((N_STATE, m_dim))
    for i in range(n2):
        for a in range(m_dim):
            da = (hs[i, a] - dbar[a]) / n2
            for b in range(m_dim):
                s[a, b] += da * (hs[i, b] - dbar[b])
            for b in range(N_STATE):
                pxz[b, a] += dev[i, b] * da
    innovation = np.empty(m_dim)
    for m in range(m_dim):
        v = z[m] - (h_mean[m] + dbar[m])
        innovation[m] = wrap_angle_jit(v) if _angular(kind, m) else v
    s_inv = np.empty((m_dim, m_dim))
    inverse_spd(s, s_inv)
    gain = np.zeros((N_STATE, m_dim))
    heading_only = kind in (COMPASS, YAW_CORRECTION)
    for a in range(N_STATE):
        if (sample.saturated and a >= BIAS) or (heading_only and a in (ATT_EAST, ATT_NORTH)):
            continue
        for b in range(m_dim):
            for c in range(m_dim):
                gain[a, b] += pxz[a, c] * s_inv[c, b]
    dx = np.zeros(N_STATE)
    for a in range(N_STATE):
        for b in range(m_dim):
            dx[a] += gain[a, b] * innovation[b]
    rot, corrected = work.m1, work.m2
    rodrigues(dx[ATT_EAST], dx[ATT_NORTH], dx[ATT_UP], rot)
    product3(rot, state.attitude, corrected)
    state.attitude[:, :] = corrected
    for m in range(3):
        state.bias[m] += dx[BIAS + m]
    # P − K·Pxzᵀ − Pxz·Kᵀ + K·S·Kᵀ: valid for any gain (the bias rows zeroed make it
    # sub-optimal); with the optimal gain it is P − K·S·Kᵀ
    ks = np.zeros((N_STATE, m_dim))
    for a in range(N_STATE):
        for b in range(m_dim):
            for c in range(m_dim):
                ks[a, b] += gain[a, c] * s[c, b]
    p = state.covariance
    for a in range(N_STATE):
        for b in range(a, N_STATE):
            v = p[a, b]
            for c in range(m_dim):
                v += -gain[a, c] * pxz[b, c] - pxz[a, c] * gain[b, c] + ks[a, c] * gain[b, c]
            p[a, b] = v
            p[b, a] = v
    nis = 0.0
    for a in range(m_dim):
        for b in range(m_dim):
            nis += innovation[a] * s_inv[a, b] * innovation[b]
    return nis


@njit(cache=True)
def rest_zaru(state, params):
    """The ZARU at rest (:func:`zaru`) with the variance of ω over the window's older half
    (:class:`FilterState` ``rest_rate[1]``) added to R per axis: the white noise, and the
    sway of a thigh settling, that its mean ω̄ is read through."""
    measurement = zaru(params)
    for m in range(3):
        measurement.r[m, m] += state.rest_rate[1, m]
    return measurement


@njit(cache=True)
def zaru_nis(state, params, r):
    """The ZARU's normalised innovation squared before it is applied: ν = ω̄ − b − Cᵀ·ω_ie^n
    (the window's mean rate, :class:`FilterState` ``rest_rate[0]``) against S = P_bb + R
    (h(x) is linear in b; the Earth rate's dependence on the attitude is left out)."""
    c, e, w, b = state.attitude, params.earth_rate_n, state.rest_rate[0], state.bias
    nu = np.empty(3)
    for m in range(3):
        nu[m] = w[m] - b[m] - (c[0, m] * e[0] + c[1, m] * e[1] + c[2, m] * e[2])
    s = r.copy()
    for row in range(3):
        for col in range(3):
            s[row, col] += state.covariance[BIAS + row, BIAS + col]
    s_inv = np.empty((3, 3))
    inverse_spd(s, s_inv)
    return nu @ (s_inv @ nu)


# --- detectors (their trailing windows: pdr_pocket.compiled_orientation_detectors) ---


# --- the loop ----------------------------------------------------------------------------
@njit(cache=True)
def _elapsed(scalars, gait, max_gap_s, t):
    """δt from the last sample to ``t`` [s] (0 at the first sample ever). After a gap the
    attitude across it is a guess (predict widens P), and a mean gravity window that
    straddles it would average two attitudes: the window starts anew."""
    s = scalars[0]
    if not s.started:
        dt = 0.0
        s.started = True
    else:
        dt = t - s.t_prev
        if dt > max_gap_s:
            s.gaps += 1
            forget_window(gait)
    s.t_prev = t
    return dt


@njit(cache=True)
def filter_loop(state, params, inputs, out):
    """Run the filter over ``inputs`` (:class:`FilterInputs`, N samples) and fill ``out``
    (:class:`FilterOutputs`): per sample the prediction, the detectors, and the updates
    of the module docstring in its order, each where its detector holds and its flag in
    ``params.use`` is set. The first sample ever only initialises the clock."""
    s, use, work = state.scalars, params.use, workspace()
    for k in range(inputs.t.shape[0]):
        t = inputs.t[k]
        dt = _elapsed(s, state.gait, params.max_gap_s, t)
        sample = Sample(dt, inputs.gyro[k], state.previous_gyro, inputs.accel[k],
                        inputs.mag[k], inputs.saturated[k])
        if dt > 0.0:
            predict(state, params, sample, work)
        found = detect(state, params, t, sample)
        detected, ran = out.detected[k], out.ran[k]
        detected[ZERO_ACC], detected[ZERO_RATE] = found.zero_acc, found.zero_rate
        detected[MAG_STEADY], detected[SATURATED] = found.mag_steady, sample.saturated
        ran[:] = False
        if dt > 0.0:
            if use[ABS_GRAVITY] and found.zero_acc:
                update(state, params, absolute_gravity(params, sample), sample, work)
                ran[ABS_GRAVITY] = True
            if use[DIFF_GRAVITY] and found.zero_acc:
                update(state, params, differential_gravity(params, sample, state.previous_accel),
                       sample, work)
                ran[DIFF_GRAVITY] = True
            if use[ABS_MAG] and found.mag_anchored:
                update(state, params, absolute_magnetic(params, sample, state.mag_reference),
                       sample, work)
                ran[ABS_MAG] = True
            if use[DIFF_MAG] and found.mag_steady and np.isfinite(state.previous_mag[0]):
                update(state, params, differential_magnetic(params, sample, state.previous_mag),
                       sample, work)
                ran[DIFF_MAG] = True
            if use[COMPASS] and found.mag_steady:
                update(state, params, compass(params, sample, state.attitude), sample, work)
                ran[COMPASS] = True
            gait = state.gait
            end = add_to_window(gait, params.window, state.attitude, sample.accel, dt,
                                swing_marker(gait, params.window, sample.gyro, dt))
            if use[MEAN_GRAVITY] and end.closes and holds_gravity(gait, params.window,
                                                                  state.attitude):
                update(state, params, mean_gravity(params, state.attitude, gait.force_sum,
                                                   gait.scalars[0].time_s, end.cycles),
                       sample, work)
                ran[MEAN_GRAVITY] = True
            restart_window(gait, end)
            if use[ZARU] and found.zero_rate:
                rest = rest_zaru(state, params)
                if zaru_nis(state, params, rest.r) <= params.zaru_gate_nis:
                    update(state, params, rest, Sample(
                        dt, state.rest_rate[0], state.previous_gyro, sample.accel,
                        sample.mag, sample.saturated), work)
                    ran[ZARU] = True
        state.previous_gyro[:] = sample.gyro
        state.previous_accel[:] = sample.accel
        state.previous_mag[:] = sample.mag
        out.attitude[k] = state.attitude
        out.bias[k] = state.bias
        out.covariance[k] = state.covariance


@njit(cache=True)
def correct(state, params, kind, value, variance):
    """An external correction (Muñoz Díaz 2016, Eq. (6.2)): the yaw ψ_L [rad] or the z
    gyro bias [rad/s] with its variance, as an unscented update; returns the NIS."""
    zero = np.zeros(3)
    return update(state, params, external_correction(kind, value, variance),
                  Sample(0.0, zero, state.previous_gyro, zero, zero, False), workspace())
