"""The phone's attitude filter, compiled with numba: an error-state Kalman filter that
holds its heading on real phones (``orientation.filter: ekf``, the default; the unscented
filter of Muñoz Díaz 2016, chapter 3, stays in pdr_pocket.compiled_orientation as
``filter: thesis``). Why it departs from the thesis: docs/pocket.md ("Heading on real
phones").

What it estimates (the nominal state, :class:`AttitudeState`) and the error it carries (the
rows of P, named by :data:`ATT_EAST` ... :data:`FIELD_DOWN`):

- C = C_b^n, the attitude (ENU navigation frame, body = sensor frame), with a small
  rotation δθ in the navigation frame as its error, C_true = exp([δθ×])·C, as the thesis'
  filter carries it: δθ_east and δθ_north are the tilt, δθ_up the heading;
- b, the gyro bias [rad/s] (body): a random constant whose variation follows the AR(1) of
  Muñoz Díaz 2016, Eqs. (3.8)–(3.9), as in the thesis' filter (pdr_pocket.config);
- o, the magnetometer's offset [T] (body): the hard-iron field that a phone's own
  calibration leaves, 4–6 µT on the OxIOD iPhones, which with the room's own field
  spreads the field's azimuth by 10–17° as the phone turns (docs/simulator.md);
- B_h, B_v, the local field's horizontal and downward magnitudes [T]. Its azimuth γ (ENU,
  counter-clockwise from east) is fixed: 90° − declination when the heading is taken from
  the field, else the azimuth the field had in the map frame at the first reading;
- b_a, the accelerometer's bias [m/s²] (body), a random walk: a phone's 10–40 mg turn-on
  bias tilts the gravity reference by up to 2°, and it is seen as the attitude turns.

One entry point per sensor, each taking what that sensor tells, at its own stamps:

- :func:`gyro_step`, the gyroscope: the prediction, C ← C·A(ω − b) (Eqs. (3.3)–(3.5) with
  the trapezoid and the coning term: pdr_core.maths.small_matrix.rotation_increment) and
  P ← F·P·Fᵀ + Q, F = I but δθ ← δθ − C·δb·δt; Q holds the white noise σ_ν²δt, the scale
  and cross-axis errors (σ_s times the angle turned, per body axis), the bias's AR(1)
  noise σ_bias²(1 − c²), and what the samples do not tell: over a gap the rate is
  unknown by half the larger of |ω| and its recent peak (a leaky peak of
  ``RATE_PEAK_TAU_S``), on a saturated sample by ``SATURATED_UNKNOWN`` of the angle. At
  rest (:func:`accel_step` decides), the rest update: z = ω against h = b + Cᵀ·ω_ie^n
  (the ZARU of Eq. (3.22)), R = σ_ν² + σ_sway²·2τ_rest/δt with the rest's own spread of
  the rate beyond σ_ν as its sway, behind a χ² gate against P_bb + σ_ν² + σ_sway² (a
  slow steady turn is no bias).
- :func:`accel_step`, the accelerometer, f = α − b_a: the rest detector (the rate and the
  specific force each within a threshold of its own low-pass, of time constant τ_rest,
  for ``rest_min_s``), the window of whole gait cycles, then the tilt from the best
  reference there is:

  - at rest the specific force itself, z across f in the body frame
    (:func:`rest_tilt_update`, σ ``rest_tilt_sigma_deg`` correlated over τ_rest);
  - walking, a window of whole gait cycles when one closed within ``cycle_timeout_s``
    (:func:`cycle_update`: the sum Σ C·f·δt from one swing marker to another is g·W·e_up
    plus the velocity change, the thigh's periodic accelerations cancelling exactly,
    pdr_pocket.compiled_gait_window);
  - else the specific force turned to the navigation frame, C·f = g·e_up + a, low-passed
    by two first-order stages of time constant τ (40 dB a decade above 1/(2πτ): a gait's
    1–3 Hz is gone, what is left is the walk's change of speed over τ). Its direction u
    measures the tilt: u ≈ e_up − δθ × e_up, so z = [u_east, u_north] against
    h = [−δθ_north, δθ_east] plus the low-pass's memory of δb and δb_a,
    R = σ_tilt²·4τ/δt per sample (the low-pass's output is correlated over 4τ: per unit
    time it carries one measurement of variance σ_tilt² per 4τ). Each correction of the
    attitude turns the low-pass's state with it, so that it keeps averaging C·f in the
    frame the attitude is now in.

  A window whose gyroscope saturated updates the tilt but not the gyro biases.
- :func:`mag_step`, the magnetometer. A field whose low-passed magnitude (offset
  removed, ``field_norm_time_constant_s``) is beyond the Earth's 18.7–77 µT
  (pdr_core.constants.EARTH_FIELD_RANGE_UT) is no Earth field: nothing is updated. Else
  the field update, z = μ against
  h = Cᵀ·m_n + o, m_n = (B_h cos γ, B_h sin γ, −B_v), H = [Cᵀ[m_n×], 0, I, Cᵀ·e_h, −Cᵀ·e_up].
  A disturbed field fails a χ² gate of the innovation against H·P·Hᵀ + σ_field²·I (3
  degrees of freedom): nothing is updated, and after ``field_reset_s`` of consecutive
  refusals the field's magnitudes are taken again from the reading (a new building, a
  new floor). What passes updates the heading, the offset and the field's magnitudes
  only: the gain's tilt and bias rows are zeroed (the accelerometer keeps the tilt, and
  a field steers no gyro bias), with R = σ_field²·2τ_field/δt (the disturbance is
  correlated over τ_field). A reading equal to the one before is the magnetometer's
  held output, not a new measurement, and is skipped.
- :func:`correct`: an external correction of the yaw ψ_L or the z gyro bias
  (Muñoz Díaz 2016, Eq. (6.2)), a Kalman update; the yaw's moves the heading only.

Every update is :func:`kalman_update`: K = P·Hᵀ·S⁻¹ with rows zeroed where the update must
not reach (the tilt and biases for the field, the tilt for a yaw, the biases on a sample
whose gyroscope saturated), and P ← P − K·H·P − P·Hᵀ·Kᵀ + K·S·Kᵀ, the Joseph form, valid
for any gain. The first reading of the field sets B_h, B_v (and the heading, when it is
taken from the field) with their covariance against the offset still unknown
(:func:`start_field`).

Speed: the entry points and the updates each runs are inlined (``inline='always'``);
called, each passed the state's and the parameters' tuples of arrays, which cost more than
the arithmetic (160,000 samples/s before, 290,000 after with a 100 Hz magnetometer, and
the module compiles in 30 s instead of 44). The shared pieces (:func:`kalman_update`,
:func:`innovation_covariance`, :func:`apply_correction`) stay calls: inlined at each of
their callers they doubled the compile time for a few percent.

Kernel data: :class:`AttitudeParams` (what the configuration sets, in SI units, built
once), :class:`AttitudeState` (what changes per sample; its scalars in a record,
:data:`SCALARS`), and the thesis filter's FilterInputs and FilterOutputs
(pdr_pocket.compiled_orientation): the same samples in, the same estimates out.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_core.maths import angles, kernel_cache, lowpass, small_matrix
from pdr_core.maths.angles import wrap_angle_jit
from pdr_core.maths.lowpass import lowpass_decay, lowpass_gain
from pdr_core.maths.small_matrix import product3, rotation_increment
from pdr_pocket import (
    compiled_attitude_data,
    compiled_attitude_field,
    compiled_attitude_kalman,
    compiled_gait_window,
)
from pdr_pocket.compiled_attitude_data import (
    ACCEL_BIAS,
    AT_REST,
    ATT_EAST,
    ATT_NORTH,
    ATT_UP,
    BIAS,
    BIAS_Z,
    CYCLE,
    FIELD,
    FIELD_DOWN,
    FIELD_HORIZONTAL,
    N_OUTPUT,
    N_STATE,
    NO_READING,
    OFFSET,
    REST,
    SATURATED,
    TILT,
    TILT_STAGES,
    YAW_CORRECTION,
    workspace,
)
from pdr_pocket.compiled_attitude_field import mag_step
from pdr_pocket.compiled_attitude_kalman import (
    apply_correction,
    clear_work,
    innovation_covariance,
    kalman_update,
    nis,
)
from pdr_pocket.compiled_gait_window import (
    across,
    add_to_window,
    force_in_body,
    forget_window,
    holds_gravity,
    restart_window,
    swing_marker,
    turned,
)

kernel_cache.forget_if_changed(__file__, small_matrix.__file__, angles.__file__,
                               lowpass.__file__, compiled_gait_window.__file__,
                               compiled_attitude_data.__file__, compiled_attitude_kalman.__file__,
                               compiled_attitude_field.__file__)

RATE_PEAK_TAU_S = 2.0           # the leaky peak of the rate forgets over about a gait cycle
SATURATED_MIN_RADPS = 2.0       # an axis this fast on a saturated sample may be clipped
SATURATED_UNKNOWN = 0.3         # ... and its angle is unknown by this fraction (1σ)


# --- the gyroscope -----------------------------------------------------------------------
@njit(cache=True, inline='always')
def _propagate_covariance(p, c, dt, decay, q_att, work):
    """P ← F·P·Fᵀ with F = I but δθ ← δθ − C·δt·δb and δb ← c·δb (the bias's decay, 1 as
    a random constant); then Q's attitude part ``q_att`` (3, 3) added. With G = −C·δt:
    P_θθ ← P_θθ + G·P_bθ + P_θb·Gᵀ + G·P_bb·Gᵀ, P_θx ← P_θx + G·P_bx for the other
    rows x, and the bias rows times c."""
    g, t = work.g, work.rows
    for i in range(3):
        for j in range(3):
            g[i, j] = -c[i, j] * dt
    # rows δθ: T = P_θ· + G·P_b· (3 × N), with the bias rows' decay
    for i in range(3):
        for col in range(N_STATE):
            v = p[i, col]
            for m in range(3):
                v += g[i, m] * p[BIAS + m, col]
            t[i, col] = v
    # P_θθ = T_θ + T_b·Gᵀ, P_θx = T_x; then the bias rows and columns decay
    for i in range(3):
        for j in range(3):
            p[i, j] = t[i, j] + t[i, BIAS] * g[j, 0] + t[i, BIAS + 1] * g[j, 1] + \
                t[i, BIAS + 2] * g[j, 2] + q_att[i, j]
        for col in range(3, N_STATE):
            p[i, col] = t[i, col]
            p[col, i] = t[i, col]
    if decay != 1.0:
        for i in range(BIAS, BIAS + 3):
            for col in range(N_STATE):
                p[i, col] *= decay
                p[col, i] *= decay
    for i in range(3):
        for j in range(i):
            v = 0.5 * (p[i, j] + p[j, i])
            p[i, j] = v
            p[j, i] = v


@njit(cache=True, inline='always')
def _attitude_noise(params, state, gyro, dt, gap, saturated, q, out):
    """Q's attitude part (3, 3), navigation frame: σ_ν²·δt·I plus C·diag(q)·Cᵀ with, per
    body axis, q = (σ_s·Δθ)², Δθ the angle turned; over a gap (ω_peak·δt/2)², the rate
    between the gap's ends unknown up to the fastest the axis turned lately (its ends' and
    the leaky peak's, :data:`RATE_PEAK_TAU_S`: a thigh swings back and forth within a gap
    of a quarter cycle, and the trapezoid's guess can be off by the whole swing); on a
    saturated sample (0.3·Δθ)² on every axis turning faster than the flat tops' floor:
    how far the rate went beyond the range is unknown (up to the range again, uniform:
    σ ≈ 0.3 of it)."""
    c, previous, peak = state.attitude, state.previous_gyro, state.rate_peak
    for m in range(3):
        turned = 0.5 * (gyro[m] + previous[m]) * dt
        q[m] = params.gyro_scale_var * turned * turned
        if gap:
            unknown = 0.5 * max(abs(gyro[m]), abs(previous[m]), peak[m]) * dt
            q[m] += unknown * unknown
        if saturated and abs(gyro[m]) > SATURATED_MIN_RADPS:
            q[m] += (SATURATED_UNKNOWN * turned) ** 2
    white = params.gyro_noise_density2 * dt
    for i in range(3):
        for j in range(3):
            out[i, j] = c[i, 0] * q[0] * c[j, 0] + c[i, 1] * q[1] * c[j, 1] + \
                c[i, 2] * q[2] * c[j, 2] + (white if i == j else 0.0)


@njit(cache=True, inline='always')
def predict(state, params, work, gyro, dt, gap, saturated):
    """The prediction over δt [s] (the module docstring)."""
    c_decay = lowpass_decay(dt, params.bias_tau_s)
    c_mean = c_decay if params.bias_mean_decays else 1.0
    inc, moved = work.m1, work.m2
    rotation_increment(state.attitude, gyro, state.previous_gyro, state.bias,
                       params.earth_rate_n, dt, inc)
    product3(state.attitude, inc, moved)
    state.attitude[:, :] = moved
    for m in range(3):
        state.bias[m] *= c_mean
    q_att = work.q_att
    _attitude_noise(params, state, gyro, dt, gap, saturated, work.q, q_att)
    p = state.covariance
    _propagate_covariance(p, state.attitude, dt, c_mean, q_att, work)
    q_bias = params.bias_sigma ** 2 * (1.0 - c_decay * c_decay)
    for m in range(3):
        p[BIAS + m, BIAS + m] += q_bias
        p[OFFSET + m, OFFSET + m] += params.offset_change_var_per_s * dt
    for m in range(3):
        p[ACCEL_BIAS + m, ACCEL_BIAS + m] += params.accel_bias_change_var_per_s * dt
    p[FIELD_HORIZONTAL, FIELD_HORIZONTAL] += params.field_change_var_per_s * dt
    p[FIELD_DOWN, FIELD_DOWN] += params.field_change_var_per_s * dt


@njit(cache=True, inline='always')
def rest_update(state, params, work, gyro, dt):
    """The rest update (the module docstring); True when applied."""
    c, e, p = state.attitude, params.earth_rate_n, state.covariance
    clear_work(work)
    for m in range(3):
        work.h[m, BIAS + m] = 1.0
        work.innovation[m] = gyro[m] - state.bias[m] - (
            c[0, m] * e[0] + c[1, m] * e[1] + c[2, m] * e[2])
    innovation_covariance(p, work, 3)
    sway = params.rest_sway_var
    for m in range(3):
        sway = max(sway, state.rest_spread[m] - params.gyro_noise_var)
    if nis(work, 3, params.gyro_noise_var + sway) > params.rest_gate_nis:
        return False
    if not kalman_update(p, work, 3, params.gyro_noise_var + sway * 2.0 * params.rest_tau_s / dt):
        return False
    apply_correction(state, work)
    return True


@njit(cache=True, inline='always')
def gyro_step(state, params, work, t, gyro, saturated):
    """The gyroscope's sample ω [rad/s] at ``t`` [s]: the prediction, the rest detector's
    rate, and at rest the rest update; True when the rest update ran. The first sample
    only starts the clock."""
    s = state.scalars[0]
    ran = False
    if s.gyro_started:
        dt = t - s.t_gyro
        if dt > 0.0:
            gap = dt > params.max_gap_s
            if gap:
                s.gaps += 1
                forget_window(state.gait)
            predict(state, params, work, gyro, dt, gap, saturated)
            leak = lowpass_decay(dt, RATE_PEAK_TAU_S)
            for m in range(3):
                state.rate_peak[m] = max(abs(gyro[m]), leak * state.rate_peak[m])
            s.marker = swing_marker(state.gait, params.window, gyro, dt)
            alpha = lowpass_gain(dt, params.rest_tau_s)
            deviation = 0.0
            for m in range(3):
                state.rest_gyro[m] += alpha * (gyro[m] - state.rest_gyro[m])
                d2 = (gyro[m] - state.rest_gyro[m]) ** 2
                state.rest_spread[m] += alpha * (d2 - state.rest_spread[m])
                deviation += d2
            s.gyro_deviation2 = deviation
            if params.use_rest and s.at_rest and not saturated:
                ran = rest_update(state, params, work, gyro, dt)
    else:
        state.rest_gyro[:] = gyro
        s.gyro_started = True
    s.t_gyro = t
    state.previous_gyro[:] = gyro
    return ran


# --- the accelerometer -------------------------------------------------------------------
@njit(cache=True, inline='always')
def _detect_rest(state, params, accel, dt):
    """The rest detector (the module docstring), updated with the specific force α."""
    s = state.scalars[0]
    alpha = lowpass_gain(dt, params.rest_tau_s)
    deviation = 0.0
    for m in range(3):
        state.rest_accel[m] += alpha * (accel[m] - state.rest_accel[m])
        deviation += (accel[m] - state.rest_accel[m]) ** 2
    if deviation < params.rest_accel_threshold2 and \
            s.gyro_deviation2 < params.rest_gyro_threshold2:
        s.rest_s += dt
    else:
        s.rest_s = 0.0
    s.at_rest = s.rest_s >= params.rest_min_s


@njit(cache=True, inline='always')
def _low_pass_tilt(state, force, alpha, dt):
    """Add C·f (f = α − b_a, the specific force less the accelerometer bias) to the tilt's
    low-pass, C to its low-pass of the attitude L(C), and C·δt to its memory: per stage
    k, D_k = A − L_k(A), A = ∫C dt, the attitude integrated and less its low-pass, kept as
    D_k ← (1 − α)·(D_k + C·δt) + α·D_{k−1} (D_0 = 0). The low-pass's attitude error is
    L(δθ(t′)) = δθ(t) + D_n·δb: a bias error δb turned the attitude by ∫C·δb dt since
    each sample it averages (δθ̇ = −C·δb); an accelerometer bias error δb_a adds
    L(C)·δb_a to the low-passed force."""
    c, lp, memory, lp_c = state.attitude, state.tilt_lowpass, state.tilt_memory, \
        state.tilt_attitude
    for m in range(3):
        nav = c[m, 0] * force[0] + c[m, 1] * force[1] + c[m, 2] * force[2]
        lp[0, m] += alpha * (nav - lp[0, m])
        for stage in range(1, TILT_STAGES):
            lp[stage, m] += alpha * (lp[stage - 1, m] - lp[stage, m])
    for stage in range(TILT_STAGES):
        for i in range(3):
            for j in range(3):
                before = 0.0 if stage == 0 else memory[stage - 1, i, j]
                memory[stage, i, j] = (1.0 - alpha) * (memory[stage, i, j] + c[i, j] * dt) + \
                    alpha * before
                source = c[i, j] if stage == 0 else lp_c[stage - 1, i, j]
                lp_c[stage, i, j] += alpha * (source - lp_c[stage, i, j])


@njit(cache=True, inline='always')
def tilt_update(state, params, work, force, dt, saturated, due):
    """Add the sample to the low-pass (:func:`_low_pass_tilt`), then, when ``due``, the
    tilt update from its direction u (the module docstring): z = [u_east, u_north] against
    h = [−(δθ + D·δb)_north, (δθ + D·δb)_east] + (L(C)·δb_a)_[east, north]/‖L‖; True when
    applied."""
    _low_pass_tilt(state, force, lowpass_gain(dt, params.tilt_tau_s), dt)
    out, memory = state.tilt_lowpass[TILT_STAGES - 1], state.tilt_memory[TILT_STAGES - 1]
    lp_c = state.tilt_attitude[TILT_STAGES - 1]
    norm = np.sqrt(out[0] ** 2 + out[1] ** 2 + out[2] ** 2)
    if not (due and params.use_tilt and norm > 0.5 * params.gravity and out[2] > 0.0):
        return False
    clear_work(work)
    work.h[0, ATT_NORTH] = -1.0
    work.h[1, ATT_EAST] = 1.0
    for m in range(3):
        work.h[0, BIAS + m] = -memory[1, m]
        work.h[1, BIAS + m] = memory[0, m]
        work.h[0, ACCEL_BIAS + m] = lp_c[0, m] / norm
        work.h[1, ACCEL_BIAS + m] = lp_c[1, m] / norm
    work.innovation[0] = out[0] / norm
    work.innovation[1] = out[1] / norm
    if saturated:
        for m in range(3):
            work.frozen[BIAS + m] = True
    innovation_covariance(state.covariance, work, 2)
    if not kalman_update(state.covariance, work, 2,
                         params.tilt_var * 2.0 * TILT_STAGES * params.tilt_tau_s / dt):
        return False
    apply_correction(state, work)
    return True


@njit(cache=True, inline='always')
def _tilt_measurement(work, c, force):
    """z = [u_east, u_north] of u = C·f/‖f‖ (f = α − b_a) against
    h = [−δθ_north, δθ_east] + (C·δb_a)_[east, north]/‖f‖ into ``work``; False for a
    specific force that points down."""
    clear_work(work)
    nav = np.empty(3)
    for m in range(3):
        nav[m] = c[m, 0] * force[0] + c[m, 1] * force[1] + c[m, 2] * force[2]
    norm = np.sqrt(nav[0] ** 2 + nav[1] ** 2 + nav[2] ** 2)
    work.h[0, ATT_NORTH] = -1.0
    work.h[1, ATT_EAST] = 1.0
    for m in range(3):
        work.h[0, ACCEL_BIAS + m] = c[0, m] / norm
        work.h[1, ACCEL_BIAS + m] = c[1, m] / norm
    work.innovation[0] = nav[0] / norm
    work.innovation[1] = nav[1] / norm
    return norm > 0.0 and nav[2] > 0.0


@njit(cache=True, inline='always')
def rest_tilt_update(state, params, work, force, dt):
    """At rest the specific force is gravity, to the accelerometer's noise and the sway:
    the tilt from its direction (:func:`_tilt_measurement`), R = σ_rest²·2τ_rest/δt per
    sample (the sway correlated over τ_rest); True when applied."""
    if not _tilt_measurement(work, state.attitude, force):
        return False
    innovation_covariance(state.covariance, work, 2)
    if not kalman_update(state.covariance, work, 2,
                         params.rest_tilt_var * 2.0 * params.rest_tau_s / dt):
        return False
    apply_correction(state, work)
    return True


@njit(cache=True, inline='always')
def marker_jitter_var(c, force, gravity, dt):
    """The variance [m²/s²] a window's velocity change takes from its ends: the window
    sums whole samples, so each end lies off the marker's phase by up to a sample δt [s]
    and adds a velocity error of about |a|·δt/2 (1σ), a = C·f − g·e_up the acceleration at
    the closing sample (the same phase of the gait cycle as the opening one):
    2·(|a|·δt/2)² in all (on simulated thighs the windows' directions scatter by 0.18°
    at 100 Hz and 0.33° at 50 Hz beyond their true velocity change)."""
    dyn = 0.0
    for m in range(3):
        nav = c[m, 0] * force[0] + c[m, 1] * force[1] + c[m, 2] * force[2]
        if m == 2:
            nav -= gravity
        dyn += nav * nav
    return dyn * dt * dt / 2.0


@njit(cache=True, inline='always')
def cycle_update(state, params, work, saturated, jitter_var):
    """The tilt from a window of whole gait cycles (pdr_pocket.compiled_gait_window): z =
    [0, 0] against h = [C[2, :]·b₁, C[2, :]·b₂], b₁, b₂ across the summed force in the body
    frame, with the window's mean attitude error δθ + (S/W)·δb: H_θ = [C[1, :]·b_i,
    −C[0, :]·b_i, 0] (the up row of exp([δθ×])·C is C[2, :] + (−δθ_north, δθ_east, 0)·C),
    H_b = H_θ·S/W, and the accelerometer bias's A·δb_a in the summed force (A = Σ C·δt):
    H_ba = (C·b_i)ᵀ·A/(g·W); R = (σ_Δv² + (v·Δψ)² + σ_jitter²)/(g·W)² per component, Δψ the
    turn over the window, σ_jitter² the markers' timing (:func:`marker_jitter_var`), behind
    a χ² gate (a window over which the walker sped up, stopped or set foot on a stair
    changed velocity by more than σ_Δv); True when applied."""
    gait, c = state.gait, state.attitude
    window_s = gait.scalars[0].time_s
    b = across(force_in_body(c, gait.force_sum))
    clear_work(work)
    for i in range(2):
        east = c[1, 0] * b[i][0] + c[1, 1] * b[i][1] + c[1, 2] * b[i][2]
        north = -(c[0, 0] * b[i][0] + c[0, 1] * b[i][1] + c[0, 2] * b[i][2])
        work.h[i, ATT_EAST], work.h[i, ATT_NORTH] = east, north
        nav = c @ b[i]
        for m in range(3):
            work.h[i, BIAS + m] = (east * gait.memory[0, m] + north * gait.memory[1, m]) / window_s
            work.h[i, ACCEL_BIAS + m] = (nav[0] * gait.attitude_sum[0, m] + nav[1] *
                                         gait.attitude_sum[1, m] + nav[2] *
                                         gait.attitude_sum[2, m]) / (params.gravity * window_s)
        work.innovation[i] = -(c[2, 0] * b[i][0] + c[2, 1] * b[i][1] + c[2, 2] * b[i][2])
    if saturated:
        for m in range(3):
            work.frozen[BIAS + m] = True
    innovation_covariance(state.covariance, work, 2)
    total = params.gravity * window_s
    turn = params.walking_speed * turned(gait, c)
    r_var = (params.cycle_velocity_var + turn * turn + jitter_var) / (total * total)
    if nis(work, 2, r_var) > params.cycle_gate_nis or \
            not kalman_update(state.covariance, work, 2, r_var):
        return False
    apply_correction(state, work)
    return True


@njit(cache=True, inline='always')
def _gait_tilt(state, params, work, t, force, dt, saturated):
    """Add the sample (f = α − b_a) to the window of gait cycles; when one closes, the
    cycle update (:func:`cycle_update`); True when it ran."""
    gait, s = state.gait, state.scalars[0]
    end = add_to_window(gait, params.window, state.attitude, force, dt, s.marker)
    s.window_saturated |= saturated
    ran = False
    if end.cycles and params.use_cycles and holds_gravity(gait, params.window, state.attitude) \
            and abs(turned(gait, state.attitude)) <= params.cycle_turn_max:
        ran = cycle_update(state, params, work, s.window_saturated,
                           marker_jitter_var(state.attitude, force, params.gravity, dt))
        if ran:
            s.t_cycle = t
    if end.closes or end.marker:
        s.window_saturated = saturated and not end.closes
    restart_window(gait, end)
    return ran


@njit(cache=True, inline='always')
def accel_step(state, params, work, t, accel, saturated):
    """The accelerometer's sample α [m/s²] at ``t`` [s]: the rest detector, the window of
    gait cycles, then the tilt from the best reference there is: at rest the specific
    force itself (:func:`rest_tilt_update`), while walking the windows of whole gait
    cycles when one closed within ``cycle_timeout_s`` (their periodic accelerations cancel
    exactly: :func:`cycle_update`), else the low-pass (:func:`tilt_update`); (tilt ran,
    cycle ran), the tilt at rest counting as a tilt. The first sample fills the
    low-passes."""
    s = state.scalars[0]
    ran = cycled = False
    force = work.force
    for m in range(3):
        force[m] = accel[m] - state.accel_bias[m]
    if s.accel_started:
        dt = t - s.t_accel
        if dt > 0.0:
            _detect_rest(state, params, accel, dt)
            cycled = _gait_tilt(state, params, work, t, force, dt, saturated)
            still = s.at_rest and params.use_tilt
            ran = tilt_update(state, params, work, force, dt, saturated,
                              not still and t - s.t_cycle > params.cycle_timeout_s)
            if still:
                ran = rest_tilt_update(state, params, work, force, dt)
    else:
        c = state.attitude
        for m in range(3):
            state.rest_accel[m] = accel[m]
            state.tilt_lowpass[:, m] = c[m, 0] * force[0] + c[m, 1] * force[1] + \
                c[m, 2] * force[2]
        for stage in range(TILT_STAGES):
            state.tilt_attitude[stage][:, :] = c
        s.accel_started = True
    s.t_accel = t
    return ran, cycled


# --- the loop and the external corrections -----------------------------------------------
@njit(cache=True)
def filter_loop(state, params, inputs, out):
    """Run the entry points over ``inputs`` (pdr_pocket.compiled_orientation.FilterInputs,
    N samples, each with all three sensors) and fill ``out`` (FilterOutputs: the
    covariance's first N_OUTPUT rows, the columns of "detected" and "ran" this module's
    DETECTOR_NAMES and UPDATE_NAMES)."""
    work = workspace()
    s = state.scalars[0]
    for k in range(inputs.t.shape[0]):
        t, saturated = inputs.t[k], inputs.saturated[k]
        ran, detected = out.ran[k], out.detected[k]
        ran[REST] = gyro_step(state, params, work, t, inputs.gyro[k], saturated)
        ran[TILT], ran[CYCLE] = accel_step(state, params, work, t, inputs.accel[k], saturated)
        judged, ran[FIELD] = mag_step(state, params, work, t, inputs.mag[k])
        detected[AT_REST], detected[SATURATED] = s.at_rest, saturated
        if judged != NO_READING:
            detected[judged] = True
        out.attitude[k] = state.attitude
        out.bias[k] = state.bias
        for i in range(N_OUTPUT):
            for j in range(N_OUTPUT):
                out.covariance[k, i, j] = state.covariance[i, j]


@njit(cache=True)
def correct(state, params, kind, value, variance):
    """An external correction (Muñoz Díaz 2016, Eq. (6.2)): the yaw ψ_L [rad]
    (``kind`` YAW_CORRECTION: the heading only moves) or the z gyro bias [rad/s]
    (BIAS_Z_CORRECTION), with its variance; returns its NIS (inf, nothing changed, when
    its S is singular)."""
    work = workspace()
    c = state.attitude
    if kind == YAW_CORRECTION:
        work.h[0, ATT_UP] = 1.0
        work.innovation[0] = wrap_angle_jit(value - np.arctan2(c[1, 0], c[0, 0]))
        work.frozen[ATT_EAST] = work.frozen[ATT_NORTH] = True
    else:
        work.h[0, BIAS_Z] = 1.0
        work.innovation[0] = value - state.bias[2]
    innovation_covariance(state.covariance, work, 1)
    result = nis(work, 1, variance)
    if kalman_update(state.covariance, work, 1, variance):
        apply_correction(state, work)
        return result
    return np.inf
