"""NumPy twins of the phone's attitude filter (pdr_pocket.compiled_attitude).

The error-state Kalman filter, written again as plain NumPy from its equations (the
kernel's module docstring), one symbol per line, with full matrices where the kernel
unrolls its loops, and asserted equal to the compiled kernels (to 1e-11 of each value
and of its scale: :func:`assert_twins`) on hypothesis-drawn states: attitude, gyro bias,
magnetometer offset, field magnitudes, accelerometer bias, a correlated covariance, the
tilt's low-pass, its memory and its low-passed attitude, δt (with gaps) and the samples.

- :func:`predict`: C ← C·exp([ω̄δt×]) (ω̄ by the trapezoid with the coning term), b ← c·b,
  P ← F·P·Fᵀ + Q with F = I − C·δt from δb to δθ (and c on the bias rows), Q the white
  noise σ_ν²δt, C·diag((σ_s·Δθ)²)·Cᵀ (plus the gap's and the saturation's unknown turn),
  σ_bias²(1 − c²) for each bias, and the offset's and the field's random walks.
- the measurements, one function each, as (innovation ν, H, R, the rows frozen): the
  tilt from the low-pass with its memory D (:func:`tilt_measurement`), the tilt at rest,
  a window of whole gait cycles (:func:`cycle_measurement`), the rest update
  (:func:`rest_measurement`), the field (:func:`field_measurement`), the external yaw
  and z-bias corrections.
- :func:`update`: S = H·P·Hᵀ + R, K = P·Hᵀ·S⁻¹ with the frozen rows zeroed, P ← (I − K·H)·P·
  (I − K·H)ᵀ + K·R·Kᵀ (Joseph), δx = K·ν applied as C ← exp([δθ×])·C and the rest added.

The last test copies the kernel's covariance update with one sign changed and shows that
the twin then fails.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

from pdr_core.constants import earth_rate_enu
from pdr_pocket import compiled_attitude as k
from pdr_pocket import compiled_attitude_data, compiled_attitude_field, compiled_attitude_kalman
from pdr_pocket.compiled_attitude_data import (
    ACCEL_BIAS,
    ATT_EAST,
    ATT_NORTH,
    ATT_UP,
    BIAS,
    BIAS_Z,
    BIAS_Z_CORRECTION,
    FIELD_DOWN,
    FIELD_HORIZONTAL,
    N_STATE,
    OFFSET,
    TILT_STAGES,
    YAW_CORRECTION,
)
from pdr_pocket.orientation_config import OrientationConfig

RTOL = 1e-11
TWINS = settings(max_examples=40, deadline=None)
DEFAULTS = OrientationConfig().ekf_params()
TILT = [ATT_EAST, ATT_NORTH]
BIASES = [BIAS, BIAS + 1, BIAS + 2]
ACCEL_BIASES = [ACCEL_BIAS, ACCEL_BIAS + 1, ACCEL_BIAS + 2]


def skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def exp_rotation(v: np.ndarray) -> np.ndarray:
    return Rotation.from_rotvec(v).as_matrix()


class Case(NamedTuple):
    """A state, the filter's parameters and one sample."""

    attitude: np.ndarray
    bias: np.ndarray
    offset: np.ndarray
    field: np.ndarray           # B_h, B_v [T]
    accel_bias: np.ndarray      # b_a [m/s²]
    covariance: np.ndarray
    lowpass: np.ndarray         # (TILT_STAGES, 3)
    memory: np.ndarray          # (TILT_STAGES, 3, 3)
    lowpass_attitude: np.ndarray    # (TILT_STAGES, 3, 3)
    peak: np.ndarray            # the leaky peak of |ω| [rad/s]
    params: compiled_attitude_data.AttitudeParams
    dt: float
    gyro: np.ndarray
    previous_gyro: np.ndarray
    accel: np.ndarray
    mag: np.ndarray
    saturated: bool


# --- the prediction ----------------------------------------------------------------------
def rate_increment(c, gyro, previous, bias, earth_n, dt):
    """ω̄·δt: the trapezoid of ω − b − Cᵀ·ω_ie^n with the coning term."""
    a = previous - bias - c.T @ earth_n
    b = gyro - bias - c.T @ earth_n
    return (a + b) * dt / 2 + np.cross(a, b) * dt * dt / 12


def predict(case: Case):
    p, c, dt = case.params, case.attitude, case.dt
    decay = 1.0 if not np.isfinite(p.bias_tau_s) else np.exp(-dt / p.bias_tau_s)
    c_mean = decay if p.bias_mean_decays else 1.0
    moved = c @ exp_rotation(rate_increment(c, case.gyro, case.previous_gyro, case.bias,
                                            p.earth_rate_n, dt))
    bias = c_mean * case.bias
    f = np.eye(N_STATE)
    f[0:3, BIAS:BIAS + 3] = -moved * dt                 # δθ̇ = −C·δb
    f[BIAS:BIAS + 3, BIAS:BIAS + 3] *= c_mean
    turned = 0.5 * (case.gyro + case.previous_gyro) * dt
    q_body = p.gyro_scale_var * turned**2
    if dt > p.max_gap_s:
        peak = np.maximum(np.maximum(np.abs(case.gyro), np.abs(case.previous_gyro)), case.peak)
        q_body += (0.5 * peak * dt) ** 2
    if case.saturated:
        q_body += np.where(np.abs(case.gyro) > k.SATURATED_MIN_RADPS,
                           (k.SATURATED_UNKNOWN * turned) ** 2, 0.0)
    q = np.zeros((N_STATE, N_STATE))
    q[0:3, 0:3] = p.gyro_noise_density2 * dt * np.eye(3) + moved @ np.diag(q_body) @ moved.T
    q[BIAS:BIAS + 3, BIAS:BIAS + 3] = p.bias_sigma**2 * (1 - decay**2) * np.eye(3)
    q[OFFSET:OFFSET + 3, OFFSET:OFFSET + 3] = p.offset_change_var_per_s * dt * np.eye(3)
    q[FIELD_HORIZONTAL, FIELD_HORIZONTAL] = q[FIELD_DOWN, FIELD_DOWN] = \
        p.field_change_var_per_s * dt
    q[ACCEL_BIASES, ACCEL_BIASES] = p.accel_bias_change_var_per_s * dt
    return moved, bias, f @ case.covariance @ f.T + q


# --- the measurements: (ν, H, R, frozen rows) ---------------------------------------------
def lowpass_step(case: Case):
    """The low-pass, its memory and its low-passed attitude after the sample:
    L_k ← L_k + α·(L_{k−1} − L_k), L_0 input C·(α − b_a); the same for L(C), input C;
    D_k ← (1 − α)·(D_k + C·δt) + α·D_{k−1}, D_0 input 0."""
    alpha = 1 - np.exp(-case.dt / case.params.tilt_tau_s)
    low, memory = case.lowpass.copy(), case.memory.copy()
    low_c = case.lowpass_attitude.copy()
    before, before_memory = case.attitude @ (case.accel - case.accel_bias), np.zeros((3, 3))
    before_c = case.attitude
    for stage in range(TILT_STAGES):
        low[stage] = low[stage] + alpha * (before - low[stage])
        low_c[stage] = low_c[stage] + alpha * (before_c - low_c[stage])
        memory[stage] = (1 - alpha) * (memory[stage] + case.attitude * case.dt) + \
            alpha * before_memory
        before, before_memory, before_c = low[stage], memory[stage], low_c[stage]
    return low, memory, low_c


def tilt_measurement(case: Case):
    """u = L/‖L‖ ≈ e_up − (δθ + D·δb) × e_up + L(C)·δb_a/‖L‖: z = [u_E, u_N],
    h = [−(·)_N, (·)_E] + (L(C)·δb_a)_[E, N]/‖L‖."""
    low, memory, low_c = lowpass_step(case)
    norm = np.linalg.norm(low[-1])
    u = low[-1] / norm
    d = memory[-1]
    h = np.zeros((2, N_STATE))
    h[0, ATT_NORTH], h[0, BIASES], h[0, ACCEL_BIASES] = -1.0, -d[1], low_c[-1][0] / norm
    h[1, ATT_EAST], h[1, BIASES], h[1, ACCEL_BIASES] = 1.0, d[0], low_c[-1][1] / norm
    r = case.params.tilt_var * 2 * TILT_STAGES * case.params.tilt_tau_s / case.dt
    return u[:2], h, r * np.eye(2), BIASES if case.saturated else []


def rest_tilt_measurement(case: Case):
    """The specific force's own direction at rest, u = C·(α − b_a)/‖·‖, with
    (C·δb_a)_[E, N]/‖·‖; R = σ²·2τ_rest/δt."""
    u = case.attitude @ (case.accel - case.accel_bias)
    norm = np.linalg.norm(u)
    u = u / norm
    h = np.zeros((2, N_STATE))
    h[0, ATT_NORTH], h[1, ATT_EAST] = -1.0, 1.0
    h[0, ACCEL_BIASES], h[1, ACCEL_BIASES] = case.attitude[0] / norm, case.attitude[1] / norm
    r = case.params.rest_tilt_var * 2 * case.params.rest_tau_s / case.dt
    return u[:2], h, r * np.eye(2), []


def rest_measurement(case: Case, sway: float):
    """z = ω against h = b + Cᵀ·ω_ie^n, R = σ_ν² + sway·2τ_rest/δt."""
    p = case.params
    nu = case.gyro - case.bias - case.attitude.T @ p.earth_rate_n
    h = np.zeros((3, N_STATE))
    h[:, BIASES] = np.eye(3)
    r = p.gyro_noise_var + sway * 2 * p.rest_tau_s / case.dt
    return nu, h, r * np.eye(3), []


def field_measurement(case: Case, azimuth: float):
    """z = μ against h = Cᵀ·m_n + o, m_n = (B_h cos γ, B_h sin γ, −B_v); H = [Cᵀ[m_n×], 0,
    I, Cᵀ·e_h, −Cᵀ·e_up]; the tilt and the biases frozen."""
    c = case.attitude
    e_h = np.array([np.cos(azimuth), np.sin(azimuth), 0.0])
    m_n = case.field[0] * e_h + np.array([0.0, 0.0, -case.field[1]])
    nu = case.mag - (c.T @ m_n + case.offset)
    h = np.zeros((3, N_STATE))
    h[:, 0:3] = c.T @ skew(m_n)
    h[:, OFFSET:OFFSET + 3] = np.eye(3)
    h[:, FIELD_HORIZONTAL] = c.T @ e_h
    h[:, FIELD_DOWN] = -c.T @ np.array([0.0, 0.0, 1.0])
    r = case.params.field_var * 2 * case.params.field_tau_s / case.dt
    return nu, h, r * np.eye(3), TILT + BIASES


def cycle_measurement(case: Case, force_sum: np.ndarray, memory_sum: np.ndarray,
                      attitude_sum: np.ndarray, window_s: float, turn: float):
    """z = 0 against h = (up row of exp([δθ̄×])·C)·b_i, δθ̄ = δθ + (S/W)·δb, b₁, b₂ across
    Cᵀ·Σ C·f·δt, with the accelerometer bias's A·δb_a/(g·W) along C·b_i; R = (σ_Δv² +
    (v·Δψ)² + σ_jitter²)/(g·W)², σ_jitter² = 2·(|C·f − g·e_up|·δt/2)² at the closing
    sample (f = α − b_a)."""
    c, p = case.attitude, case.params
    acceleration = c @ (case.accel - case.accel_bias) - [0.0, 0.0, p.gravity]
    jitter = 2.0 * (acceleration @ acceleration) * (case.dt / 2.0) ** 2
    body = c.T @ force_sum
    d = body / np.linalg.norm(body)
    e = np.zeros(3)
    e[np.argmin(np.abs(d))] = 1.0
    b1 = np.cross(d, e)
    b1 /= np.linalg.norm(b1)
    b2 = np.cross(d, b1)
    h = np.zeros((2, N_STATE))
    nu = np.zeros(2)
    for i, b in enumerate((b1, b2)):
        h[i, ATT_EAST], h[i, ATT_NORTH] = c[1] @ b, -(c[0] @ b)
        h[i, BIASES] = (h[i, ATT_EAST] * memory_sum[0] + h[i, ATT_NORTH] * memory_sum[1]) / window_s
        h[i, ACCEL_BIASES] = (c @ b) @ attitude_sum / (p.gravity * window_s)
        nu[i] = -(c[2] @ b)
    r = (p.cycle_velocity_var + (p.walking_speed * turn) ** 2 + jitter) / \
        (p.gravity * window_s) ** 2
    return nu, h, r * np.eye(2), []


# --- the update ----------------------------------------------------------------------------
def update(covariance, nu, h, r, frozen):
    s = h @ covariance @ h.T + r
    gain = covariance @ h.T @ np.linalg.inv(s)
    gain[frozen] = 0.0
    i_kh = np.eye(N_STATE) - gain @ h
    p = i_kh @ covariance @ i_kh.T + gain @ r @ gain.T
    return gain @ nu, p, float(nu @ np.linalg.solve(s, nu))


def applied(case: Case, dx):
    """C ← exp([δθ×])·C and the other states added (the returned rotation turns the
    low-pass, its memory and its attitude)."""
    rot = exp_rotation(dx[0:3])
    return (rot @ case.attitude, case.bias + dx[BIAS:BIAS + 3],
            case.offset + dx[OFFSET:OFFSET + 3], case.field + dx[[FIELD_HORIZONTAL, FIELD_DOWN]],
            rot)


# --- drawing cases, running the kernels ---------------------------------------------------
def vectors(scale: float):
    return arrays(np.float64, 3, elements=st.floats(-scale, scale, allow_nan=False,
                                                    allow_infinity=False))


@st.composite
def cases(draw) -> Case:
    attitude = Rotation.from_rotvec(draw(vectors(1.2))).as_matrix()
    sigma = np.array([draw(st.floats(1e-3, 0.1)) for _ in range(3)] +
                     [draw(st.floats(1e-4, 1e-2)) for _ in range(3)] +
                     [draw(st.floats(1e-7, 1e-5)) for _ in range(3)] +
                     [draw(st.floats(1e-7, 5e-6)) for _ in range(2)] +
                     [draw(st.floats(1e-3, 0.5)) for _ in range(3)])
    root = np.linalg.cholesky(np.eye(N_STATE) * 0.7 + 0.3)     # correlation 0.3
    covariance = np.outer(sigma, sigma) * (root @ root.T)
    params = DEFAULTS._replace(
        bias_mean_decays=draw(st.booleans()),
        earth_rate_n=earth_rate_enu(48.0) if draw(st.booleans()) else np.zeros(3),
        gyro_scale_var=draw(st.floats(0.0, 1e-3)))
    dt = draw(st.sampled_from([0.002, 0.01, 0.3]))            # 500 Hz, 100 Hz, a gap
    accel = np.array([0.0, 0.0, 9.81]) @ attitude + draw(vectors(3.0))
    mag = np.array([0.0, 20e-6, -40e-6]) @ attitude + draw(vectors(5e-6))
    lowpass = np.tile(attitude @ accel, (TILT_STAGES, 1)) + draw(vectors(1.0))
    memory = np.stack([draw(st.floats(0.0, 2.0)) * attitude for _ in range(TILT_STAGES)])
    lowpass_attitude = np.stack([Rotation.from_rotvec(draw(vectors(0.2))).as_matrix() @ attitude
                                 for _ in range(TILT_STAGES)])
    assume(lowpass[-1, 2] > 0)
    return Case(attitude, draw(vectors(0.02)), draw(vectors(5e-6)),
                np.array([draw(st.floats(15e-6, 25e-6)), draw(st.floats(30e-6, 45e-6))]),
                draw(vectors(0.4)), covariance, lowpass, memory, lowpass_attitude,
                np.abs(draw(vectors(5.0))), params, dt,
                draw(vectors(3.0)), draw(vectors(3.0)), accel, mag, draw(st.booleans()))


def kernel_state(case: Case) -> compiled_attitude_data.AttitudeState:
    state = compiled_attitude_data.initial_state(case.attitude.copy(), case.covariance.copy())
    state.bias[:], state.offset[:], state.field[:] = case.bias, case.offset, case.field
    state.accel_bias[:] = case.accel_bias
    state.tilt_lowpass[:], state.tilt_memory[:] = case.lowpass, case.memory
    state.tilt_attitude[:] = case.lowpass_attitude
    state.rate_peak[:] = case.peak
    state.previous_gyro[:] = case.previous_gyro
    return state


def assert_twins(state, case: Case, c, b, p, nis_pair=None) -> None:
    """C, b and P equal to RTOL of their scale (1 for C, σ for b, √(P_aa·P_bb) for P)."""
    np.testing.assert_allclose(state.attitude, c, rtol=RTOL, atol=RTOL)
    sigma = np.sqrt(np.diag(case.covariance))
    np.testing.assert_allclose(state.bias / sigma[BIASES], b / sigma[BIASES], rtol=RTOL,
                               atol=RTOL * 10)
    scale = np.outer(sigma, sigma)
    np.testing.assert_allclose(state.covariance / scale, p / scale, rtol=RTOL, atol=RTOL * 10)
    if nis_pair is not None:
        np.testing.assert_allclose(*nis_pair, rtol=1e-9, atol=1e-9)


def check_update(state, case: Case, measurement, applied_kernel: bool) -> None:
    nu, h, r, frozen = measurement
    dx, p, _ = update(case.covariance, nu, h, r, frozen)
    c, b, _, _, _ = applied(case, dx)
    assert applied_kernel
    assert_twins(state, case, c, b, p)


# --- the twins against the kernels --------------------------------------------------------
@TWINS
@given(cases())
def test_predict_is_its_twin(case):
    state = kernel_state(case)
    k.predict(state, case.params, k.workspace(), case.gyro, case.dt, case.dt > 0.1,
              case.saturated)
    assert_twins(state, case, *predict(case))


@TWINS
@given(cases())
def test_the_tilt_update_from_the_low_pass_is_its_twin(case):
    state = kernel_state(case)
    ran = k.tilt_update(state, case.params, k.workspace(), case.accel - case.accel_bias,
                        case.dt, case.saturated, True)
    check_update(state, case, tilt_measurement(case), ran)
    low, memory, low_c = lowpass_step(case)
    rot = applied(case, update(case.covariance, *tilt_measurement(case))[0])[4]
    np.testing.assert_allclose(state.tilt_lowpass, low @ rot.T, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(state.tilt_memory, rot @ memory, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(state.tilt_attitude, rot @ low_c, rtol=1e-12, atol=1e-12)


@TWINS
@given(cases())
def test_the_tilt_at_rest_is_its_twin(case):
    state = kernel_state(case)
    ran = k.rest_tilt_update(state, case.params, k.workspace(), case.accel - case.accel_bias,
                             case.dt)
    check_update(state, case, rest_tilt_measurement(case), ran)


@TWINS
@given(cases(), st.floats(0.0, 1e-4))
def test_the_rest_update_is_its_twin(case, spread):
    """The sway: the largest of the floor and the rate's spread less its white noise."""
    state = kernel_state(case)
    state.rest_spread[:] = spread
    sway = max(case.params.rest_sway_var, spread - case.params.gyro_noise_var)
    measurement = rest_measurement(case, sway)
    _, _, nis = update(case.covariance, *measurement[:2],
                       (case.params.gyro_noise_var + sway) * np.eye(3), [])
    params = case.params._replace(rest_gate_nis=np.inf)
    ran = k.rest_update(state, params, k.workspace(), case.gyro, case.dt)
    check_update(state, case, measurement, ran)
    assume(nis > 1e-9)
    refused = kernel_state(case)
    refused.rest_spread[:] = spread
    gated = case.params._replace(rest_gate_nis=0.99 * nis)
    assert not k.rest_update(refused, gated, k.workspace(), case.gyro, case.dt)
    np.testing.assert_array_equal(refused.covariance, case.covariance)


@TWINS
@given(cases(), st.floats(-np.pi, np.pi))
def test_the_field_update_is_its_twin(case, azimuth):
    state = kernel_state(case)
    state.scalars[0]["field_azimuth"] = azimuth
    params = case.params._replace(field_gate_nis=np.inf)
    undisturbed, ran = compiled_attitude_field.field_update(state, params, k.workspace(),
                                                            case.mag, case.dt)
    assert undisturbed
    measurement = field_measurement(case, azimuth)
    check_update(state, case, measurement, ran)
    dx = update(case.covariance, *measurement)[0]
    np.testing.assert_allclose(state.offset, case.offset + dx[OFFSET:OFFSET + 3], rtol=0,
                               atol=1e-12 * 1e-5)
    assert dx[TILT + BIASES].tolist() == [0.0] * 5


@TWINS
@given(cases(), arrays(np.float64, (3, 3), elements=st.floats(0.0, 2.0)),
       st.floats(1.0, 3.0), vectors(0.3))
def test_the_cycle_update_is_its_twin(case, memory_sum, window_s, turn):
    """A window of ``window_s`` whose first attitude was turned by ``turn`` [rad] (its up
    component about the vertical: Δψ); refused beyond its χ² gate."""
    start = Rotation.from_rotvec(-turn).as_matrix() @ case.attitude
    relative = case.attitude @ start.T
    turned = np.arctan2(relative[1, 0] - relative[0, 1], relative[0, 0] + relative[1, 1])
    force_sum = case.attitude @ case.accel * window_s
    attitude_sum = case.attitude * window_s

    def window_state():
        state = kernel_state(case)
        state.gait.force_sum[:] = force_sum
        state.gait.memory[:] = memory_sum
        state.gait.attitude_sum[:] = attitude_sum
        state.gait.start[:] = start
        state.gait.scalars[0]["time_s"] = window_s
        return state

    measurement = cycle_measurement(case, force_sum, memory_sum, attitude_sum, window_s, turned)
    _, _, nis = update(case.covariance, *measurement[:3], [])
    jitter = k.marker_jitter_var(case.attitude, case.accel - case.accel_bias,
                                 case.params.gravity, case.dt)
    state = window_state()
    ran = k.cycle_update(state, case.params._replace(cycle_gate_nis=np.inf), k.workspace(),
                         False, jitter)
    check_update(state, case, measurement, ran)
    assume(nis > 1e-9)
    refused = window_state()
    gated = case.params._replace(cycle_gate_nis=0.99 * nis)
    assert not k.cycle_update(refused, gated, k.workspace(), False, jitter)
    np.testing.assert_array_equal(refused.covariance, case.covariance)


@TWINS
@given(cases(), st.floats(-1.0, 1.0), st.floats(1e-3, 1.0),
       st.sampled_from([YAW_CORRECTION, BIAS_Z_CORRECTION]))
def test_external_corrections_are_their_twins(case, value, sigma, kind):
    state = kernel_state(case)
    h = np.zeros((1, N_STATE))
    if kind == YAW_CORRECTION:
        yaw = np.arctan2(case.attitude[1, 0], case.attitude[0, 0])
        nu = np.array([np.angle(np.exp(1j * (value - yaw)))])
        h[0, ATT_UP], frozen = 1.0, TILT
    else:
        value, sigma = value * 1e-2, sigma * np.sqrt(case.covariance[BIAS_Z, BIAS_Z])
        nu = np.array([value - case.bias[2]])
        h[0, BIAS_Z], frozen = 1.0, []
    nis = k.correct(state, case.params, kind, value, sigma**2)
    dx, p, twin_nis = update(case.covariance, nu, h, sigma**2 * np.eye(1), frozen)
    c, b, _, _, _ = applied(case, dx)
    assert_twins(state, case, c, b, p, (nis, twin_nis))


# --- one perturbed kernel line fails its twin ----------------------------------------------
def walking_case() -> Case:
    """A phone mid-stride: tilted, turning, the covariance correlated."""
    attitude = Rotation.from_rotvec([0.3, -0.2, 1.1]).as_matrix()
    sigma = np.array([0.01, 0.01, 0.05, 2e-3, 2e-3, 3e-3, 3e-6, 3e-6, 3e-6, 2e-6, 2e-6,
                      0.2, 0.2, 0.2])
    covariance = np.outer(sigma, sigma) * (0.8 * np.eye(N_STATE) + 0.2)
    accel = np.array([0.0, 0.0, 9.81]) @ attitude + [0.4, -0.2, 0.3]
    return Case(attitude, np.array([1e-3, -2e-3, 5e-4]), np.array([1e-6, -2e-6, 3e-6]),
                np.array([20e-6, 40e-6]), np.array([0.1, -0.2, 0.05]), covariance,
                np.tile(attitude @ accel, (TILT_STAGES, 1)), np.zeros((TILT_STAGES, 3, 3)),
                np.tile(attitude, (TILT_STAGES, 1, 1)), np.zeros(3), DEFAULTS, 0.01,
                np.array([0.3, 1.8, -0.2]), np.array([0.25, 1.7, -0.1]), accel,
                np.array([0.0, 20e-6, -40e-6]) @ attitude, False)


def test_a_sign_slipped_in_the_joseph_update_fails_its_twin(perturb):
    """The covariance update's + K·S·Kᵀ turned to −: the tilt update's twin fails."""
    case = walking_case()
    slip = ("+ ks[a, c] * gain[b, c]", "- ks[a, c] * gain[b, c]")
    same = perturb(k.kalman_update, compiled_attitude_kalman, slip[0], slip[0])
    wrong = perturb(k.kalman_update, compiled_attitude_kalman, *slip)
    for kernel, fails in ((same, False), (wrong, True)):
        state = kernel_state(case)
        work = k.workspace()
        nu, h, r, frozen = rest_tilt_measurement(case)
        work.h[:2] = h
        work.innovation[:2] = nu
        k.innovation_covariance(state.covariance, work, 2)
        kernel(state.covariance, work, 2, r[0, 0])
        twin = update(case.covariance, nu, h, r, frozen)[1]
        scale = np.outer(np.sqrt(np.diag(case.covariance)), np.sqrt(np.diag(case.covariance)))
        if fails:
            with pytest.raises(AssertionError):
                np.testing.assert_allclose(state.covariance / scale, twin / scale, atol=1e-9)
        else:
            np.testing.assert_allclose(state.covariance / scale, twin / scale, atol=1e-9)
