"""The orientation filter's per-sample loop, compiled with numba (Muñoz Díaz 2016, ch. 3).

An unscented Kalman filter on the thesis' state x = [φ, θ, ψ, b_x, b_y, b_z] (Eq. (3.1)).
The attitude part is carried as the direction cosine matrix C = C_b^n (ENU, FLU body) with
a 3-vector error δθ, a small rotation in the navigation frame (C_true = exp([δθ×])·C): the
sigma points are C_i = exp([δθ_i×])·C, so nothing ever divides by cos θ, and θ = ±90°
(a sitting thigh comes close) gives neither NaN nor a jump. φ, θ, ψ are read from C
(ZYX, :mod:`pdr_core.rotations`) and their covariance from the δθ block; near θ = ±90° only
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
     walking speed. (Its first model, the horizontal part of the sum in the navigation
     frame, turned with the yaw too: with the window's velocity change in it, the update
     moved the yaw, and took 0.08° of a landmark's 0.24° yaw correction back one sample
     after it.) The zero-acceleration periods it does not need are rare on a thigh: on
     the real ``thigh_revalew`` walk, |‖α‖ − g| ≤ 0.4 m/s² and ‖ω‖ ≤ 40 °/s over 0.1 s
     never hold while walking, so without it roll and pitch drift through a long walk
     without stops;
  7. ZARU ω − b = 0 (Eq. (3.22)), at zero angular rate (:func:`rest_zaru`): ω is the
     mean rate ω̄ of the window's older half (the white noise and the sway averaged, as
     VQF's rest bias estimate reads its low-passed rate; the newest half, where a thigh
     starting to move is still below the threshold, left out), R grows by the rate's
     variance over that half (a thigh settling into the stop sways), and a χ² gate on the
     innovation ω̄ − b − Cᵀ·ω_ie^n against P_bb + R (:func:`zaru_nis`) refuses a slow
     steady turn. (At the instantaneous ω behind max ‖ω‖ ≤ 3 °/s, a phone's 1 °/s
     turn-on bias kept the detector off, and with the AR(1) of a phone (220 °/h) the
     stops' edges, the thigh settling and starting at up to 3 °/s, taught the bias that
     rate: 89° of yaw after 22 min with ideal sensors.)
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

Kernel data, as NamedTuples: :class:`FilterParams` (set by the configuration),
:class:`FilterState` (changed by every sample), :class:`FilterInputs` and
:class:`FilterOutputs` (a record in, its estimates out), :class:`Sample` (one sample) and
:class:`Measurement` (one update, made by its builder). A compiled function that takes a
NamedTuple increments and decrements the reference count of every array in it on each
call, and numba does not always prune that: the small helpers called at every sample take
the arrays they use, not the whole state (taking it cost 15–20 % of the loop's time).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core import angles, kernel_cache, small_matrix
from pdr_core.angles import wrap_angle_jit
from pdr_core.small_matrix import cholesky, product3, rodrigues, rotation_increment
from pdr_pocket import compiled_gait_window
from pdr_pocket.compiled_gait_window import (
    GaitWindow,
    WindowParams,
    across,
    add_to_window,
    force_in_body,
    forget_window,
    holds_gravity,
    new_gait_window,
    restart_window,
    swing_marker,
)

kernel_cache.forget_if_changed(__file__, small_matrix.__file__, angles.__file__,
                               compiled_gait_window.__file__)

# the state's rows: the attitude error δθ (a small rotation in the navigation frame, ENU)
# and the gyro bias error δb (body frame)
N_STATE = 6
ATT, BIAS = 0, 3                        # first rows of the blocks δθ and δb
ATT_EAST, ATT_NORTH, ATT_UP = ATT, ATT + 1, ATT + 2   # δθ about east and north (the tilt)
                                                      # and about up (the yaw)
BIAS_Z = BIAS + 2                       # δb_z
ATT_ROWS, BIAS_ROWS = slice(ATT, ATT + 3), slice(BIAS, BIAS + 3)   # for NumPy code
# update kinds (columns of the "ran" output), then the external corrections (Eq. (6.2))
ABS_GRAVITY, DIFF_GRAVITY, ABS_MAG, DIFF_MAG, COMPASS, ZARU, MEAN_GRAVITY = range(7)
YAW_CORRECTION, BIAS_Z_CORRECTION = 7, 8
N_UPDATES = 7
# detectors (columns of the "detected" output)
ZERO_ACC, ZERO_RATE, MAG_STEADY, SATURATED = range(4)
N_DETECTORS = 4
RING = 2048                             # trailing-window capacity [samples]


class FilterParams(NamedTuple):
    """Everything the loop needs, SI units (built by pdr_pocket.config)."""

    gyro_noise_var: float           # σ_ν² [rad²/s²] per sample... times δt² gives Q
    bias_tau_s: float               # τ of the AR(1) bias [s] (inf: random constant)
    bias_sigma: float               # σ_bias [rad/s]
    bias_mean_decays: bool          # Eq. (3.8) literally (see pdr_pocket.config)
    earth_rate_n: np.ndarray        # ω_ie^n (3,) [rad/s], zeros when off
    gravity: float                  # [m/s²]
    use: np.ndarray                 # (N_UPDATES,) bool: which updates run
    gravity_angle_var: float        # [rad²] of φ̄, θ̄ at θ = 0
    diff_gravity_var: float         # [m²/s⁴] per axis
    mag_var: float                  # [T²] per axis (absolute and differential)
    compass_var: float              # [rad²]
    zaru_var: float                 # [rad²/s²] per axis
    window: WindowParams            # the mean gravity update's windows
    mean_gravity_velocity_var: float    # [m²/s²] of the velocity change over a window
    cycle_velocity_var: float       # ... and over whole gait cycles
    field_azimuth: float            # γ = π/2 − declination [rad]
    zero_acc_window_s: float
    zero_acc_threshold: float       # [m/s²]
    zero_acc_max_rate: float        # [rad/s] and the thigh turning no faster than this
    zero_rate_window_s: float
    zero_rate_threshold: float      # [rad/s] of ‖ω − ω̄‖ over the window
    zaru_gate_nis: float            # the ZARU is refused beyond this NIS (3 dof)
    mag_window_s: float
    mag_norm_threshold: float       # [T]
    mag_direction_threshold: float  # [rad]
    max_gap_s: float
    gyro_scale_var: float           # σ_s² of the rate's scale and cross-axis errors
    mag_reference_max_var: float    # tilt variance up to which a field reference is taken


class FilterState(NamedTuple):
    """The filter's memory, mutated in place by :func:`filter_loop` (so a live node can
    feed it one sample at a time and get the offline result)."""

    attitude: np.ndarray            # (3, 3) C_b^n
    bias: np.ndarray                # (3,) [rad/s]
    covariance: np.ndarray          # (N_STATE, N_STATE) of [δθ, δb]
    scalars: np.ndarray             # (N_SCALARS,) indexed by T_PREV ... GAPS
    gait: GaitWindow                # the mean gravity update's window
    previous_gyro: np.ndarray       # (3,)
    previous_accel: np.ndarray      # (3,)
    previous_mag: np.ndarray        # (3,); NaN when the last sample had none
    mag_reference: np.ndarray       # (3,) μ̄_r, navigation frame
    ring_t: np.ndarray              # (RING,) trailing windows: stamps
    ring_acc: np.ndarray            # (RING,) |‖α‖ − g|
    ring_rate: np.ndarray           # (RING,) ‖ω‖
    ring_mag: np.ndarray            # (RING, 3) C·μ (NaN: no reading)
    ring_gyro: np.ndarray           # (RING, 3) ω
    rest_rate: np.ndarray           # (2, 3) ω̄, the mean rate over the zero-rate window's
                                    # older half, and the variance of ω over it per axis


# FilterState.scalars
T_PREV = 0              # the last sample's stamp [s]
STARTED = 1             # 1: a sample has been seen
RING_COUNT = 2          # samples in the trailing windows' ring
RING_HEAD = 3           # where the next sample goes in it
MAG_WAS_STEADY = 4      # 1: the field was steady (and anchored) at the last sample
GAPS = 5                # gaps longer than max_gap_s seen
N_SCALARS = 6


def initial_state(attitude: np.ndarray, covariance: np.ndarray) -> FilterState:
    """A state at the attitude C_b^n (3, 3) with the covariance (N_STATE, N_STATE), zero
    biases and empty windows."""
    return FilterState(
        attitude=np.ascontiguousarray(attitude, dtype=float), bias=np.zeros(3),
        covariance=np.ascontiguousarray(covariance, dtype=float),
        scalars=np.zeros(N_SCALARS), gait=new_gait_window(), previous_gyro=np.zeros(3),
        previous_accel=np.zeros(3), previous_mag=np.full(3, np.nan),
        mag_reference=np.zeros(3), ring_t=np.zeros(RING), ring_acc=np.zeros(RING),
        ring_rate=np.zeros(RING), ring_mag=np.full((RING, 3), np.nan),
        ring_gyro=np.zeros((RING, 3)), rest_rate=np.zeros((2, 3)))


class FilterInputs(NamedTuple):
    """The samples a filter loop runs over (this module's and pdr_pocket.compiled_attitude's):
    N of each, body frame, SI units."""

    t: np.ndarray                   # (N,) stamps [s]
    gyro: np.ndarray                # (N, 3) ω [rad/s]
    accel: np.ndarray               # (N, 3) α, the specific force [m/s²]
    mag: np.ndarray                 # (N, 3) μ [T]; rows of NaN: no reading
    saturated: np.ndarray           # (N,) bool: the gyroscope saturated


class FilterOutputs(NamedTuple):
    """What a filter loop fills, per sample; the columns of ``detected`` and ``ran`` are the
    filter's own (here ZERO_ACC ... SATURATED and ABS_GRAVITY ... MEAN_GRAVITY)."""

    attitude: np.ndarray            # (N, 3, 3) C_b^n
    bias: np.ndarray                # (N, 3) b [rad/s]
    covariance: np.ndarray          # (N, M, M) of [δθ, δb] (M = 6 here)
    detected: np.ndarray            # (N, D) bool: the detectors
    ran: np.ndarray                 # (N, U) bool: the updates that ran


class Sample(NamedTuple):
    """One sample, as the prediction and the updates read it (body frame)."""

    dt: float                       # δt since the sample before [s]
    gyro: np.ndarray                # (3,) ω^k [rad/s]
    previous_gyro: np.ndarray       # (3,) ω^{k−1} [rad/s], at the start of the interval
    accel: np.ndarray               # (3,) α^k [m/s²]
    mag: np.ndarray                 # (3,) μ^k [T]; NaN: no reading
    saturated: bool                 # the gyroscope saturated: updates leave the biases alone


class Detected(NamedTuple):
    """The detectors at one sample (Muñoz Díaz 2016, Section 3.2)."""

    zero_acc: bool                  # zero acceleration: the gravity updates may run
    zero_rate: bool                 # zero angular rate: the ZARU may run (at ω̄)
    mag_steady: bool                # a quasi-constant field: the magnetic updates may run
    mag_anchored: bool              # ... and its reference μ̄_r taken with the tilt known:
                                    # the absolute magnetic update may run


class Measurement(NamedTuple):
    """One update's measurement, made by its builder (:func:`absolute_gravity` ...
    :func:`external_correction`) and applied by :func:`update`."""

    kind: int                       # ABS_GRAVITY ... BIAS_Z_CORRECTION: selects h(x)
    z: np.ndarray                   # (m,) the measurement
    r: np.ndarray                   # (m, m) its noise covariance R
    vectors: np.ndarray             # (2, 3) the vectors h(x) reads (see each builder)


class Workspace(NamedTuple):
    """Scratch arrays reused by every predict and update (no allocation per sample)."""

    deviations: np.ndarray          # (2n, n) sigma-point deviations
    attitudes: np.ndarray           # (2n, 3, 3)
    biases: np.ndarray              # (2n, 3)
    propagated: np.ndarray          # (2n, n)
    root: np.ndarray                # (n, n)
    m1: np.ndarray                  # (3, 3) scratch
    m2: np.ndarray
    m3: np.ndarray


@njit(cache=True)
def workspace():
    n2 = 2 * N_STATE
    return Workspace(np.empty((n2, N_STATE)), np.empty((n2, 3, 3)), np.empty((n2, 3)),
                     np.empty((n2, N_STATE)), np.empty((N_STATE, N_STATE)), np.empty((3, 3)),
                     np.empty((3, 3)), np.empty((3, 3)))


# --- rotations -------------------------------------------------------------------------
@njit(cache=True)
def rotation_log(r, out):
    """The rotation vector of a rotation matrix (the inverse of
    :func:`pdr_core.small_matrix.rodrigues`)."""
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
def _mul_bt(a, b, out):
    """out = a·bᵀ for 3 × 3 matrices."""
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[j, 0] + a[i, 1] * b[j, 1] + a[i, 2] * b[j, 2]


@njit(cache=True)
def _inverse_spd(a, out):
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
    :func:`pdr_core.small_matrix.rotation_increment`."""
    gyro, prev, dt = sample.gyro, sample.previous_gyro, sample.dt
    n2 = 2 * N_STATE
    _sigma_points(state, work)
    sat, sbias = work.attitudes, work.biases
    c_decay = 1.0 if not np.isfinite(params.bias_tau_s) else np.exp(-dt / params.bias_tau_s)
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
        _mul_bt(moved, mean_att, rel)
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
    _inverse_spd(s, s_inv)
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


# --- the measurements, one builder per update ------------------------------------------
@njit(cache=True)
def _diagonal(m_dim, variance):
    """R = variance·I (m_dim, m_dim)."""
    return np.eye(m_dim) * variance


@njit(cache=True)
def absolute_gravity(params, sample):
    """Roll and pitch from the specific force at rest, z = [φ̄, θ̄] (Muñoz Díaz 2016,
    Eqs. (3.12)–(3.14)) against h(x) = [φ, θ] of C; the roll's variance grows as
    1/cos²θ."""
    a = sample.accel
    z = np.empty(2)
    z[0] = np.arctan2(a[1], a[2])
    z[1] = np.arctan2(-a[0], np.sqrt(a[1] ** 2 + a[2] ** 2))
    cos_t = max(np.cos(z[1]), 1e-6)
    r = np.zeros((2, 2))
    r[0, 0] = params.gravity_angle_var / (cos_t * cos_t)
    r[1, 1] = params.gravity_angle_var
    return Measurement(ABS_GRAVITY, z, r, np.zeros((2, 3)))


@njit(cache=True)
def differential_gravity(params, sample, previous_accel):
    """z = α^k against h(x) = A(ω − b)ᵀ·α^{k−1} (Muñoz Díaz 2016, Eqs. (3.15)–(3.16));
    vectors[0] = α^{k−1} (body frame)."""
    vectors = np.zeros((2, 3))
    vectors[0] = previous_accel
    return Measurement(DIFF_GRAVITY, sample.accel.copy(), _diagonal(3, params.diff_gravity_var),
                       vectors)


@njit(cache=True)
def absolute_magnetic(params, sample, reference):
    """z = μ^k against h(x) = Cᵀ·μ̄_r, μ̄_r the field in the navigation frame taken at the
    start of the quasi-constant period (Muñoz Díaz 2016, Eq. (3.17)); vectors[0] = μ̄_r."""
    vectors = np.zeros((2, 3))
    vectors[0] = reference
    return Measurement(ABS_MAG, sample.mag.copy(), _diagonal(3, params.mag_var), vectors)


@njit(cache=True)
def differential_magnetic(params, sample, previous_mag):
    """z = μ^k against h(x) = A(ω − b)ᵀ·μ^{k−1} (Muñoz Díaz 2016, Eqs. (3.18)–(3.19));
    vectors[0] = μ^{k−1} (body frame)."""
    vectors = np.zeros((2, 3))
    vectors[0] = previous_mag
    return Measurement(DIFF_MAG, sample.mag.copy(), _diagonal(3, params.mag_var), vectors)


@njit(cache=True)
def compass(params, sample, attitude):
    """z = ψ̄ from the field tilt-compensated with the roll and pitch of ``attitude``
    (Muñoz Díaz 2016, Eqs. (3.20)–(3.21), in ENU: see :func:`compass_yaw`) against
    h(x) = ψ of C."""
    z = np.empty(1)
    z[0] = compass_yaw(attitude, sample.mag, params.field_azimuth)
    return Measurement(COMPASS, z, _diagonal(1, params.compass_var), np.zeros((2, 3)))


@njit(cache=True)
def mean_gravity(params, attitude, force_sum, window_s, cycles):
    """Beyond the thesis (the module docstring derives it): over a window of ``window_s``
    seconds, the up row of C across the summed force turned to the body frame,
    Cᵀ·Σ C·α·δt: z = [0, 0] against h(x) = [C[2, :]·b₁, C[2, :]·b₂], vectors = [b₁, b₂]
    two unit vectors across the sum, R = σ_Δv²/(g·W)² I, σ_Δv that of a window of whole
    gait cycles when ``cycles``."""
    total = params.gravity * window_s
    velocity_var = params.cycle_velocity_var if cycles else params.mean_gravity_velocity_var
    r = np.zeros((2, 2))
    r[0, 0] = r[1, 1] = velocity_var / (total * total)
    vectors = np.empty((2, 3))
    vectors[0], vectors[1] = across(force_in_body(attitude, force_sum))
    return Measurement(MEAN_GRAVITY, np.zeros(2), r, vectors)


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
    _inverse_spd(s, s_inv)
    return nu @ (s_inv @ nu)


@njit(cache=True)
def zaru(params):
    """z = [0, 0, 0] against h(x) = ω − b − Cᵀ·ω_ie^n (Muñoz Díaz 2016, Eq. (3.22))."""
    return Measurement(ZARU, np.zeros(3), _diagonal(3, params.zaru_var), np.zeros((2, 3)))


@njit(cache=True)
def external_correction(kind, value, variance):
    """An external correction (Muñoz Díaz 2016, Eq. (6.2)): the yaw ψ_L [rad] against
    h(x) = ψ of C (``kind`` YAW_CORRECTION), or the z gyro bias [rad/s] against b_z
    (BIAS_Z_CORRECTION), with its variance."""
    z = np.empty(1)
    z[0] = value
    r = np.empty((1, 1))
    r[0, 0] = variance
    return Measurement(kind, z, r, np.zeros((2, 3)))


# --- detectors ---------------------------------------------------------------------------
@njit(cache=True)
def _push_ring(state, params, t, sample):
    """Add the sample to the trailing windows: |‖α‖ − g|, ‖ω‖ and C·μ (NaN: no reading);
    returns its row."""
    s = state.scalars
    head = int(s[RING_HEAD])
    a, w, mu, c = sample.accel, sample.gyro, sample.mag, state.attitude
    state.ring_t[head] = t
    state.ring_acc[head] = abs(np.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2) - params.gravity)
    state.ring_rate[head] = np.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2)
    state.ring_gyro[head, 0], state.ring_gyro[head, 1], state.ring_gyro[head, 2] = \
        w[0], w[1], w[2]
    nav = state.ring_mag[head]
    if np.isfinite(mu[0]):
        for m in range(3):
            nav[m] = c[m, 0] * mu[0] + c[m, 1] * mu[1] + c[m, 2] * mu[2]
    else:
        nav[:] = np.nan
    s[RING_HEAD] = (head + 1) % RING
    s[RING_COUNT] = min(RING, s[RING_COUNT] + 1)
    return head


@njit(cache=True)
def _window_count(ring_t, scalars, t, window_s):
    """How many of the ring's newest samples lie within the last ``window_s`` seconds before
    ``t`` (−1 while the ring does not yet reach back that far)."""
    count, head = int(scalars[RING_COUNT]), int(scalars[RING_HEAD])
    for j in range(count):
        if t - ring_t[(head - 1 - j) % RING] > window_s + 1e-9:
            return j
    return -1


@njit(cache=True)
def _window_max(ring_t, values, scalars, t, window_s):
    """Max of ``values`` (a ring of the state) over the samples of the last ``window_s``
    seconds (−1 when the window is not yet full)."""
    n, head = _window_count(ring_t, scalars, t, window_s), int(scalars[RING_HEAD])
    if n < 0:
        return -1.0
    best = -np.inf
    for j in range(n):
        best = max(best, values[(head - 1 - j) % RING])
    return best


@njit(cache=True)
def _at_rest(ring_t, ring_gyro, scalars, t, window_s, threshold, out):
    """Whether every ω of the last ``window_s`` seconds lies within ``threshold`` of their
    mean (False while the window is not yet full); then into ``out`` (2, 3) ω̄, the mean of
    the window's older half (a stop's last samples, the thigh starting to move below the
    threshold, are not in it), and the variance of ω over it per axis."""
    n, head = _window_count(ring_t, scalars, t, window_s), int(scalars[RING_HEAD])
    if n <= 0:
        return False
    m0 = m1 = m2 = 0.0
    for j in range(n):
        i = (head - 1 - j) % RING
        m0 += ring_gyro[i, 0]
        m1 += ring_gyro[i, 1]
        m2 += ring_gyro[i, 2]
    m0, m1, m2 = m0 / n, m1 / n, m2 / n
    limit = threshold * threshold
    o0 = o1 = o2 = 0.0
    older = 0
    for j in range(n):
        i = (head - 1 - j) % RING
        if (ring_gyro[i, 0] - m0) ** 2 + (ring_gyro[i, 1] - m1) ** 2 + \
                (ring_gyro[i, 2] - m2) ** 2 > limit:
            return False
        if t - ring_t[i] >= 0.5 * window_s:
            o0 += ring_gyro[i, 0]
            o1 += ring_gyro[i, 1]
            o2 += ring_gyro[i, 2]
            older += 1
    if older == 0:
        return False
    out[0, 0], out[0, 1], out[0, 2] = o0 / older, o1 / older, o2 / older
    out[1, :] = 0.0
    for j in range(n - older, n):
        i = (head - 1 - j) % RING
        for m in range(3):
            out[1, m] += (ring_gyro[i, m] - out[0, m]) ** 2 / older
    return True


@njit(cache=True)
def _mag_steady(ring_t, ring_mag, scalars, t, params):
    """Norm spread and angle to the mean direction of C·μ over the trailing window."""
    n, head = _window_count(ring_t, scalars, t, params.mag_window_s), int(scalars[RING_HEAD])
    if n < 2:
        return False
    total = np.zeros(3)
    lo, hi = np.inf, -np.inf
    for j in range(n):
        v = ring_mag[(head - 1 - j) % RING]
        if not np.isfinite(v[0]):
            return False
        norm = np.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
        lo, hi = min(lo, norm), max(hi, norm)
        total += v / max(norm, 1e-12)
    if hi - lo > params.mag_norm_threshold:
        return False
    mean = total / max(np.sqrt(total[0] ** 2 + total[1] ** 2 + total[2] ** 2), 1e-12)
    min_cos = np.cos(params.mag_direction_threshold)
    for j in range(n):
        i = (head - 1 - j) % RING
        v = ring_mag[i]
        if v[0] * mean[0] + v[1] * mean[1] + v[2] * mean[2] < min_cos * np.sqrt(
                v[0] ** 2 + v[1] ** 2 + v[2] ** 2):
            return False
    return True


@njit(cache=True)
def detect(state, params, t, sample):
    """Push the sample into the trailing windows and read the detectors there; take the
    field reference μ̄_r at the start of a steady period."""
    s, ring_t, ring_rate = state.scalars, state.ring_t, state.ring_rate
    newest = _push_ring(state, params, t, sample)
    zero_acc = 0.0 <= _window_max(ring_t, state.ring_acc, s, t, params.zero_acc_window_s) \
        <= params.zero_acc_threshold and _window_max(
            ring_t, ring_rate, s, t, params.zero_acc_window_s) <= params.zero_acc_max_rate
    zero_rate = _at_rest(ring_t, state.ring_gyro, s, t, params.zero_rate_window_s,
                         params.zero_rate_threshold, state.rest_rate)
    steady = np.isfinite(sample.mag[0]) and _mag_steady(ring_t, state.ring_mag, s, t, params)
    # the absolute field update holds the attitude to the field's direction taken at
    # the start of the steady period: taken while the tilt is uncertain (after a gap)
    # it would hold an error as if it were known
    p = state.covariance
    anchored = steady and (s[MAG_WAS_STEADY] == 1.0 or max(
        p[ATT_EAST, ATT_EAST], p[ATT_NORTH, ATT_NORTH]) <= params.mag_reference_max_var)
    if anchored and s[MAG_WAS_STEADY] == 0.0:
        state.mag_reference[:] = state.ring_mag[newest]
    s[MAG_WAS_STEADY] = 1.0 if anchored else 0.0
    return Detected(zero_acc, zero_rate, steady, anchored)


# --- the loop ----------------------------------------------------------------------------
@njit(cache=True)
def _elapsed(scalars, gait, max_gap_s, t):
    """δt from the last sample to ``t`` [s] (0 at the first sample ever). After a gap the
    attitude across it is a guess (predict widens P), and a mean gravity window that
    straddles it would average two attitudes: the window starts anew."""
    s = scalars
    if s[STARTED] == 0.0:
        dt = 0.0
        s[STARTED] = 1.0
    else:
        dt = t - s[T_PREV]
        if dt > max_gap_s:
            s[GAPS] += 1.0
            forget_window(gait)
    s[T_PREV] = t
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
def compass_yaw(attitude, mu, field_azimuth):
    """ψ̄ from the field μ (body) tilt-compensated with the roll and pitch of ``attitude``:
    γ − atan2(μ_h,y, μ_h,x) (the module docstring derives it)."""
    e = np.empty(3)
    euler_of(attitude, e)
    cr, sr, cp, sp = np.cos(e[0]), np.sin(e[0]), np.cos(e[1]), np.sin(e[1])
    # μ_h = Ry(θ)·Rx(φ)·μ: the body field turned to the horizontal plane
    y1 = cr * mu[1] - sr * mu[2]
    z1 = sr * mu[1] + cr * mu[2]
    x2 = cp * mu[0] + sp * z1
    return wrap_angle_jit(field_azimuth - np.arctan2(y1, x2))


@njit(cache=True)
def correct(state, params, kind, value, variance):
    """An external correction (Muñoz Díaz 2016, Eq. (6.2)): the yaw ψ_L [rad] or the z
    gyro bias [rad/s] with its variance, as an unscented update; returns the NIS."""
    zero = np.zeros(3)
    return update(state, params, external_correction(kind, value, variance),
                  Sample(0.0, zero, state.previous_gyro, zero, zero, False), workspace())
