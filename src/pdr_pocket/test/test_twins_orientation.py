"""NumPy twins of the pocket orientation filter (Muñoz Díaz 2016, chapter 3).

The unscented Kalman filter of :mod:`pdr_pocket.compiled_orientation`, written again as
plain NumPy from the thesis' equations, one symbol per line, and asserted equal to the
compiled kernels (to 1e-12 of each value and of its scale: :func:`assert_twins`) on
hypothesis-drawn states: attitude, gyro biases, a correlated covariance, δt (with gaps),
rates, specific force, field, and the noise settings (random-constant and AR(1) bias,
Earth rate on and off, scale error).

The thesis gives the models and names the filter; the twin wraps them in the textbook
unscented transform: 2n sigma points x ± the columns of L, L·Lᵀ = n·P, weights 1/2n
(λ = 0). The attitude is carried as the kernel carries it: C = C_b^n (ENU, body FLU)
with a navigation-frame error δθ, the sigma points C_i = exp([δθ_i×])·C.

- :func:`predict`: C^k = C^{k−1}·A^k (Eq. (3.3)), A^k by Rodrigues' formula (Eq. (3.4))
  from B^k = [ω̄·δt×] (Eq. (3.5)), ω̄ = ω − b − Cᵀ·ω_ie^n (Eqs. (3.23)–(3.24)) taken by
  the trapezoidal rule with the coning term; b^k = c·b^{k−1} (Eq. (3.8), c = 1 unless the
  mean decays); Q = diag(σ_ν²δt² + σ_s²·(ω·δt)², σ_n²) (Eq. (3.7) and the scale error),
  σ_n² = σ_bias²(1 − c²) (Eq. (3.9)), plus the trapezoid's guess across a gap.
- the measurements (z, R) and models h(x), one function each: absolute gravity
  (Eqs. (3.12)–(3.14)), differential gravity (Eqs. (3.15)–(3.16)), absolute magnetic field
  (Eq. (3.17)), differential magnetic field (Eqs. (3.18)–(3.19)), compass
  (Eqs. (3.20)–(3.21)), ZARU (Eq. (3.22)), the mean gravity update (beyond the thesis:
  the kernel's module docstring) and the external yaw and z-bias corrections (Eq. (6.2)).
- :func:`update`: ẑ, S, P_xz from the sigma points, K = P_xz·S⁻¹ (the bias rows zeroed on a
  saturated sample, the tilt rows for the compass and the yaw correction), the attitude
  corrected by exp([δθ×]), P − K·P_xzᵀ − P_xz·Kᵀ + K·S·Kᵀ, and the NIS νᵀ·S⁻¹·ν.

The last tests copy the kernel's predict and update with one line changed (a factor of
the process noise, a sign of the covariance update) and show that the twins then fail.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from pdr_core.constants import earth_rate_enu
from pdr_core.maths.rotations import rotation_from_euler
from pdr_pocket import compiled_orientation as k
from pdr_pocket import compiled_orientation_data as kd
from pdr_pocket import compiled_orientation_measurements as km
from pdr_pocket.compiled_orientation_data import (
    ATT_EAST,
    ATT_NORTH,
    ATT_ROWS,
    BIAS_ROWS,
    BIAS_Z,
    N_STATE,
    Sample,
)
from pdr_pocket.compiled_orientation_measurements import (
    ABS_GRAVITY,
    ABS_MAG,
    BIAS_Z_CORRECTION,
    COMPASS,
    DIFF_GRAVITY,
    DIFF_MAG,
    MEAN_GRAVITY,
    YAW_CORRECTION,
    ZARU,
)
from pdr_pocket.orientation_config import OrientationConfig

RTOL = 1e-12
TWINS = settings(max_examples=40, deadline=None)
DEFAULTS = OrientationConfig(filter="thesis").params()
TILT = [ATT_EAST, ATT_NORTH]                            # the tilt rows of δθ
BIASES = list(range(BIAS_ROWS.start, BIAS_ROWS.stop))   # the rows of δb


# --- the thesis' equations, plain NumPy ---------------------------------------------------
def skew(w: np.ndarray) -> np.ndarray:
    """[w×]: B^k of Eq. (3.5) for w = ω^k·δt."""
    return np.array([[0.0, -w[2], w[1]],
                     [w[2], 0.0, -w[0]],
                     [-w[1], w[0], 0.0]])


def exp_rotation(w: np.ndarray) -> np.ndarray:
    """A = I + sin σ/σ·B + (1 − cos σ)/σ²·B², B = [w×], σ = |w| (Eq. (3.4))."""
    sigma = np.linalg.norm(w)
    b = skew(w)
    sin_term = np.sinc(sigma / np.pi)                      # sin σ / σ
    cos_term = 0.5 * np.sinc(sigma / (2.0 * np.pi)) ** 2   # (1 − cos σ) / σ²
    return np.eye(3) + sin_term * b + cos_term * b @ b


def rotation_vector(r: np.ndarray) -> np.ndarray:
    """w with exp([w×]) = r, the inverse of Eq. (3.4), for rotations short of π."""
    angle = np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0))
    sin_axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / 2.0
    return sin_axis / np.sinc(angle / np.pi)               # sin·axis / (sin / angle)


def euler(c: np.ndarray) -> np.ndarray:
    """φ, θ, ψ of C = Rz(ψ)·Ry(θ)·Rx(φ) (the state of Eq. (3.1))."""
    roll = np.arctan2(c[2, 1], c[2, 2])
    pitch = -np.arcsin(np.clip(c[2, 0], -1.0, 1.0))
    yaw = np.arctan2(c[1, 0], c[0, 0])
    return np.array([roll, pitch, yaw])


def wrap(a):
    """Angles to (−π, π]."""
    w = (a + np.pi) % (2.0 * np.pi) - np.pi
    return np.where(w == -np.pi, np.pi, w)


def body_rate(gyro, c, b, earth_n) -> np.ndarray:
    """ω_nb^b = ω − b − Cᵀ·ω_ie^n (Eqs. (3.7), (3.23))."""
    return gyro - b - c.T @ earth_n


def increment(c, b, sample: Sample, earth_n) -> np.ndarray:
    """A^k over δt (Eqs. (3.3)–(3.5)): the rotation vector of the rate at both ends of the
    interval by the trapezoidal rule, with the coning term."""
    dt = sample.dt
    before = body_rate(sample.previous_gyro, c, b, earth_n)     # ω̄^{k−1}
    now = body_rate(sample.gyro, c, b, earth_n)                 # ω̄^k
    turned = (before + now) * dt / 2.0 + np.cross(before, now) * dt**2 / 12.0
    return exp_rotation(turned)


def sigma_points(c, b, p):
    """Deviations (2n, n), ±the columns of L (L·Lᵀ = n·P) in turn; the points'
    attitudes exp([δθ_i×])·C and biases b + δb_i."""
    root = np.linalg.cholesky(N_STATE * p)
    deviations = np.stack([root.T, -root.T], axis=1).reshape(2 * N_STATE, N_STATE)
    attitudes = [exp_rotation(d[ATT_ROWS]) @ c for d in deviations]
    biases = b + deviations[:, BIAS_ROWS]
    return deviations, attitudes, biases


def process_noise(params, sample: Sample, decay: float) -> np.ndarray:
    """Q over δt: σ_ν²·δt² (Eq. (3.7)) plus the scale error σ_s² of the angle turned on the
    attitude, across a gap the trapezoid's guess too; σ_n² = σ_bias²(1 − c²) (Eq. (3.9))
    on the biases."""
    dt = sample.dt
    turned = (sample.gyro + sample.previous_gyro) / 2.0 * dt
    q_att = params.gyro_noise_var * dt**2 + params.gyro_scale_var * turned**2
    if dt > params.max_gap_s:
        guessed = (sample.gyro - sample.previous_gyro) / 2.0 * dt
        q_att = q_att + guessed**2
    q_bias = np.full(3, params.bias_sigma**2 * (1.0 - decay**2))
    return np.diag(np.concatenate([q_att, q_bias]))


def predict(c, b, p, params, sample: Sample):
    """The prediction stage (Section 3.1) as an unscented transform: C, b, P after δt.
    The mean is the propagated centre (C·A^k, c·b), not the points' average, as the
    kernel's comment in its predict explains; P is their spread about their average."""
    earth = params.earth_rate_n
    decay = np.exp(-sample.dt / params.bias_tau_s)             # c of Eq. (3.8); 1 for τ = ∞
    c_mean = decay if params.bias_mean_decays else 1.0
    c_new = c @ increment(c, b, sample, earth)                   # Eq. (3.3)
    b_new = c_mean * b                                          # Eq. (3.8)
    _, attitudes, biases = sigma_points(c, b, p)
    chi = []
    for ci, bi in zip(attitudes, biases, strict=True):
        ci_new = ci @ increment(ci, bi, sample, earth)           # Eq. (3.3), each point
        bi_new = c_mean * bi                                    # Eq. (3.8), each point
        chi.append(np.concatenate([rotation_vector(ci_new @ c_new.T), bi_new - b_new]))
    chi = np.array(chi)                                         # the points' [δθ_i, δb_i]
    centre = chi.mean(axis=0)
    p_new = (chi - centre).T @ (chi - centre) / len(chi)        # Σ (χ_i − χ̄)(χ_i − χ̄)ᵀ / 2n
    p_new = p_new + process_noise(params, sample, decay)        # + Q
    return c_new, b_new, (p_new + p_new.T) / 2.0


class TwinMeasurement(NamedTuple):
    """z, R, h(C, b), and which rows of the gain stay zero."""

    z: np.ndarray
    r: np.ndarray
    h: Callable[[np.ndarray, np.ndarray], np.ndarray]
    angular: bool               # z and h are angles (wrapped)
    frozen: list                # state rows the update leaves alone


def update(c, b, p, measurement: TwinMeasurement, saturated: bool):
    """The unscented update: C, b, P and the NIS νᵀ·S⁻¹·ν."""
    z, r, h = measurement.z, measurement.r, measurement.h
    deviations, attitudes, biases = sigma_points(c, b, p)
    h_mean = h(c, b)
    spread = np.array([h(ci, bi) - h_mean for ci, bi in zip(attitudes, biases, strict=True)])
    if measurement.angular:
        spread = wrap(spread)
    mean_spread = spread.mean(axis=0)
    z_hat = h_mean + mean_spread                                 # ẑ = Σ h_i / 2n
    centred = spread - mean_spread
    s = r + centred.T @ centred / len(centred)                   # S = R + P_zz
    pxz = deviations.T @ centred / len(centred)                  # P_xz
    nu = z - z_hat                                               # ν
    if measurement.angular:
        nu = wrap(nu)
    gain = pxz @ np.linalg.inv(s)                                # K = P_xz·S⁻¹
    gain[measurement.frozen + (BIASES if saturated else []), :] = 0.0
    dx = gain @ nu
    c_new = exp_rotation(dx[ATT_ROWS]) @ c
    b_new = b + dx[BIAS_ROWS]
    p_new = p - gain @ pxz.T - pxz @ gain.T + gain @ s @ gain.T
    nis = nu @ np.linalg.inv(s) @ nu
    return c_new, b_new, p_new, nis


# --- the measurements, one per update -----------------------------------------------------
class Case(NamedTuple):
    """A drawn state, its settings, a sample and what the updates read besides."""

    attitude: np.ndarray        # C_b^n
    bias: np.ndarray            # [rad/s]
    covariance: np.ndarray      # (N_STATE, N_STATE), SPD
    params: kd.FilterParams
    sample: Sample
    previous_accel: np.ndarray  # α^{k−1} [m/s²]
    previous_mag: np.ndarray    # μ^{k−1} [T]
    mag_reference: np.ndarray   # μ̄_r, navigation frame [T]
    force_sum: np.ndarray       # Σ C·α·δt over a window [m/s]
    window_s: float
    cycles: bool


def absolute_gravity(params, case) -> TwinMeasurement:
    """z = [φ̄, θ̄] (Eqs. (3.12)–(3.14)) against [φ, θ] of C; R: σ² on θ̄, σ²/cos²θ̄ on φ̄."""
    a = case.sample.accel
    roll = np.arctan2(a[1], a[2])                                # φ̄, Eq. (3.12)
    pitch = np.arctan2(-a[0], np.hypot(a[1], a[2]))             # θ̄, Eq. (3.13)
    cos_pitch = max(np.cos(pitch), 1e-6)
    r = np.diag([params.gravity_angle_var / cos_pitch**2, params.gravity_angle_var])
    return TwinMeasurement(np.array([roll, pitch]), r, lambda c, b: euler(c)[:2], True, [])


def differential_gravity(params, case) -> TwinMeasurement:
    """z = α^k against A^kᵀ·α^{k−1} (Eqs. (3.15)–(3.16), A^kᵀ maps the previous body frame
    to the current one)."""
    sample, earth = case.sample, params.earth_rate_n
    return TwinMeasurement(sample.accel, params.diff_gravity_var * np.eye(3),
                           lambda c, b: increment(c, b, sample, earth).T @ case.previous_accel,
                           False, [])


def absolute_magnetic(params, case) -> TwinMeasurement:
    """z = μ^k against Cᵀ·μ̄_r, μ̄_r in the navigation frame (Eq. (3.17))."""
    return TwinMeasurement(case.sample.mag, params.mag_var * np.eye(3),
                           lambda c, b: c.T @ case.mag_reference, False, [])


def differential_magnetic(params, case) -> TwinMeasurement:
    """z = μ^k against A^kᵀ·μ^{k−1} (Eqs. (3.18)–(3.19))."""
    sample, earth = case.sample, params.earth_rate_n
    return TwinMeasurement(sample.mag, params.mag_var * np.eye(3),
                           lambda c, b: increment(c, b, sample, earth).T @ case.previous_mag,
                           False, [])


def horizontal_field(c, mu) -> np.ndarray:
    """μ_h = Ry(θ)·Rx(φ)·μ: the body field turned to the horizontal plane."""
    roll, pitch, _ = euler(c)
    rx = np.array([[1.0, 0.0, 0.0],
                   [0.0, np.cos(roll), -np.sin(roll)],
                   [0.0, np.sin(roll), np.cos(roll)]])
    ry = np.array([[np.cos(pitch), 0.0, np.sin(pitch)],
                   [0.0, 1.0, 0.0],
                   [-np.sin(pitch), 0.0, np.cos(pitch)]])
    return ry @ rx @ mu


def compass(params, case) -> TwinMeasurement:
    """z = ψ̄ (Eqs. (3.20)–(3.21) in ENU, ψ from east: ψ̄ = γ − atan2(μ_h,y, μ_h,x), γ the
    field's azimuth) against ψ of C; heading only."""
    mu_h = horizontal_field(case.attitude, case.sample.mag)
    psi = wrap(params.field_azimuth - np.arctan2(mu_h[1], mu_h[0]))
    return TwinMeasurement(np.array([psi]), np.array([[params.compass_var]]),
                           lambda c, b: euler(c)[2:], True, TILT)


def across(v):
    """Two unit vectors orthogonal to v and to each other."""
    d = v / np.linalg.norm(v)
    e = np.eye(3)[np.argmin(np.abs(d))]
    b1 = np.cross(d, e)
    b1 = b1 / np.linalg.norm(b1)
    return b1, np.cross(d, b1)


def mean_gravity(params, case) -> TwinMeasurement:
    """Beyond the thesis: the window's summed force Σ C·α·δt turned to the body frame is
    the vertical there, so the up row of C across it is zero: z = [0, 0] against
    [C[2, :]·b₁, C[2, :]·b₂], R = σ_Δv²/(g·W)²·I."""
    b1, b2 = across(case.attitude.T @ case.force_sum)
    velocity_var = (params.cycle_velocity_var if case.cycles
                    else params.mean_gravity_velocity_var)
    r = velocity_var / (params.gravity * case.window_s) ** 2 * np.eye(2)
    return TwinMeasurement(np.zeros(2), r, lambda c, b: np.array([c[2] @ b1, c[2] @ b2]),
                           False, [])


def zaru(params, case) -> TwinMeasurement:
    """z = [0, 0, 0] against ω − b − Cᵀ·ω_ie^n (Eqs. (3.22), (3.23))."""
    gyro, earth = case.sample.gyro, params.earth_rate_n
    return TwinMeasurement(np.zeros(3), params.zaru_var * np.eye(3),
                           lambda c, b: body_rate(gyro, c, b, earth), False, [])


def yaw_correction(value, variance) -> TwinMeasurement:
    """z = ψ_L against ψ of C (Eq. (6.2)); heading only."""
    return TwinMeasurement(np.array([value]), np.array([[variance]]),
                           lambda c, b: euler(c)[2:], True, TILT)


def bias_z_correction(value, variance) -> TwinMeasurement:
    """z = the drift ε against b_z (Eq. (6.2))."""
    return TwinMeasurement(np.array([value]), np.array([[variance]]),
                           lambda c, b: b[2:], False, [])


TWIN_BUILDERS = {ABS_GRAVITY: absolute_gravity, DIFF_GRAVITY: differential_gravity,
                 ABS_MAG: absolute_magnetic, DIFF_MAG: differential_magnetic,
                 COMPASS: compass, MEAN_GRAVITY: mean_gravity, ZARU: zaru}


def kernel_measurement(kind: int, params, case) -> km.Measurement:
    """The kernel's builder of ``kind``."""
    if kind == ABS_GRAVITY:
        return k.absolute_gravity(params, case.sample)
    if kind == DIFF_GRAVITY:
        return k.differential_gravity(params, case.sample, case.previous_accel)
    if kind == ABS_MAG:
        return k.absolute_magnetic(params, case.sample, case.mag_reference)
    if kind == DIFF_MAG:
        return k.differential_magnetic(params, case.sample, case.previous_mag)
    if kind == COMPASS:
        return k.compass(params, case.sample, case.attitude)
    if kind == MEAN_GRAVITY:
        return k.mean_gravity(params, case.attitude, case.force_sum, case.window_s,
                              case.cycles)
    return k.zaru(params)


# --- drawn states ---------------------------------------------------------------------------
def vectors(scale: float):
    return arrays(float, 3, elements=st.floats(-scale, scale))


@st.composite
def cases(draw) -> Case:
    """Any attitude whose sigma points stay short of θ = ±90° (where φ of Eq. (3.14) is
    ill-defined), σ of 0.06–6° and 0.006–0.6 °/s, any correlation, any δt up to 0.5 s
    (gaps included), rates up to 6 rad/s, a specific force and a horizontal field not
    nil, and both bias models."""
    roll, pitch, yaw = draw(st.floats(-3.0, 3.0)), draw(st.floats(-1.2, 1.2)), \
        draw(st.floats(-3.1, 3.1))
    sigma = np.concatenate([draw(arrays(float, 3, elements=st.floats(1e-3, 0.1))),     # rad
                            draw(arrays(float, 3, elements=st.floats(1e-4, 1e-2)))])   # rad/s
    mixing = draw(arrays(float, (N_STATE, N_STATE), elements=st.floats(-1.0, 1.0)))
    shape = mixing @ mixing.T + 0.5 * np.eye(N_STATE)
    correlation = shape / np.sqrt(np.outer(np.diag(shape), np.diag(shape)))
    latitude = draw(st.none() | st.floats(-89.0, 89.0))
    scale = draw(st.floats(0.1, 10.0))                      # of every measurement variance
    params = DEFAULTS._replace(
        gyro_noise_var=draw(st.floats(1e-8, 1e-3)),
        bias_tau_s=draw(st.just(np.inf) | st.floats(1.0, 1e4)),
        bias_sigma=draw(st.floats(1e-5, 1e-2)),
        bias_mean_decays=draw(st.booleans()),
        earth_rate_n=np.zeros(3) if latitude is None else earth_rate_enu(latitude),
        gyro_scale_var=draw(st.floats(0.0, 1e-2)),
        gravity_angle_var=scale * DEFAULTS.gravity_angle_var,
        diff_gravity_var=scale * DEFAULTS.diff_gravity_var, mag_var=scale * DEFAULTS.mag_var,
        compass_var=scale * DEFAULTS.compass_var, zaru_var=scale * DEFAULTS.zaru_var,
        field_azimuth=draw(st.floats(-np.pi, np.pi)))
    accel = draw(vectors(20.0))
    assume(np.linalg.norm(accel) > 1.0)
    sample = Sample(draw(st.floats(1e-3, 0.5)), draw(vectors(6.0)), draw(vectors(6.0)), accel,
                    draw(vectors(60e-6)), draw(st.booleans()))
    force_sum = draw(vectors(200.0))
    assume(np.linalg.norm(force_sum) > 1.0)
    attitude = rotation_from_euler(roll, pitch, yaw).as_matrix()
    assume(np.linalg.norm(horizontal_field(attitude, sample.mag)[:2]) > 1e-7)
    return Case(attitude, draw(vectors(0.05)), correlation * np.outer(sigma, sigma), params,
                sample, draw(vectors(20.0)), draw(vectors(60e-6)), draw(vectors(60e-6)),
                force_sum, draw(st.floats(1.0, 20.0)), draw(st.booleans()))


def kernel_state(case: Case) -> kd.FilterState:
    state = kd.initial_state(case.attitude.copy(), case.covariance.copy())
    state.bias[:] = case.bias
    return state


def assert_twins(state: kd.FilterState, prior: np.ndarray, c, b, p, nis: float = 0.0) -> None:
    """The kernel's state equals the twin's, to RTOL of each value and of its scale: 1 for
    C, σ for the biases and √(P_aa·P_bb) for P_ab, σ and P those of the ``prior``
    covariance (an update that shrinks P a hundredfold subtracts numbers that much larger
    than its result). After an update, C and b to RTOL of their move K·ν too: a rounding
    error δK moves them by δK·ν, up to (1 + √NIS) times their scale."""
    moved = 1.0 + np.sqrt(nis)
    np.testing.assert_allclose(state.attitude, c, rtol=RTOL, atol=RTOL * moved)
    sigma = np.sqrt(np.diag(prior))
    np.testing.assert_allclose(state.bias / sigma[BIAS_ROWS], b / sigma[BIAS_ROWS], rtol=RTOL,
                               atol=RTOL * moved)
    scale = np.outer(sigma, sigma)
    np.testing.assert_allclose(state.covariance / scale, p / scale, rtol=RTOL, atol=RTOL)


def assert_nis(nis: float, twin_nis: float) -> None:
    """ν = z − ẑ holds rounding errors of RTOL·√S: the NIS to RTOL of (1 + √NIS)²."""
    np.testing.assert_allclose(nis, twin_nis, rtol=RTOL, atol=RTOL * (1.0 + np.sqrt(twin_nis)) ** 2)


# --- the twins against the kernels ------------------------------------------------------------
def check_predict(kernel_predict, case: Case) -> None:
    state = kernel_state(case)
    kernel_predict(state, case.params, case.sample, k.workspace())
    twin = predict(case.attitude, case.bias, case.covariance, case.params, case.sample)
    assert_twins(state, case.covariance, *twin)


def check_update(kernel_update, kind: int, case: Case) -> None:
    """The builder's z and R, then the update, against the twin's."""
    measurement = kernel_measurement(kind, case.params, case)
    twin = TWIN_BUILDERS[kind](case.params, case)
    np.testing.assert_allclose(measurement.z, twin.z, rtol=RTOL, atol=RTOL * np.abs(twin.z).max())
    np.testing.assert_allclose(measurement.r, twin.r, rtol=RTOL)
    state = kernel_state(case)
    nis = kernel_update(state, case.params, measurement, case.sample, k.workspace())
    c, b, p, twin_nis = update(case.attitude, case.bias, case.covariance, twin,
                               case.sample.saturated)
    assert_twins(state, case.covariance, c, b, p, twin_nis)
    assert_nis(nis, twin_nis)


@TWINS
@given(cases())
def test_predict_is_its_twin(case):
    check_predict(k.predict, case)


@pytest.mark.parametrize("kind", list(TWIN_BUILDERS), ids=lambda kind: TWIN_BUILDERS[kind].__name__)
@TWINS
@given(case=cases())
def test_each_update_and_its_builder_are_their_twins(kind, case):
    check_update(k.update, kind, case)


@TWINS
@given(case=cases(), value=st.floats(-1.0, 1.0), sigma=st.floats(1e-3, 1.0),
       kind=st.sampled_from([YAW_CORRECTION, BIAS_Z_CORRECTION]))
def test_external_corrections_are_their_twins(case, value, sigma, kind):
    """Eq. (6.2) through :func:`pdr_pocket.compiled_orientation.correct`: a yaw [rad] or a
    z bias [rad/s] (scaled to the bias's σ)."""
    state = kernel_state(case)
    if kind == YAW_CORRECTION:
        twin = yaw_correction(value, sigma**2)
    else:
        value, sigma = value * 1e-2, sigma * np.sqrt(case.covariance[BIAS_Z, BIAS_Z])
        twin = bias_z_correction(value, sigma**2)
    nis = k.correct(state, case.params, kind, value, sigma**2)
    c, b, p, twin_nis = update(case.attitude, case.bias, case.covariance, twin, False)
    assert_twins(state, case.covariance, c, b, p, twin_nis)
    assert_nis(nis, twin_nis)


# --- one perturbed kernel line fails its twin ------------------------------------------------
WALKING = Case(             # a thigh mid-swing, tilt known to 0.3°, yaw to 1.1°
    attitude=rotation_from_euler(0.1, -0.4, 2.0).as_matrix(), bias=np.array([2e-3, -1e-3, 4e-3]),
    covariance=np.diag([3e-5, 3e-5, 4e-4, 1e-6, 1e-6, 2e-6]) + 1e-7 * (1.0 - np.eye(N_STATE)),
    params=DEFAULTS._replace(bias_mean_decays=True, earth_rate_n=earth_rate_enu(48.0)),
    sample=Sample(0.01, np.array([0.3, 1.8, -0.2]), np.array([0.25, 1.7, -0.1]),
                  np.array([-1.0, 0.4, 9.7]), np.array([21e-6, 1e-6, -43e-6]), False),
    previous_accel=np.array([-1.1, 0.3, 9.75]), previous_mag=np.array([21e-6, 2e-6, -43e-6]),
    mag_reference=np.array([0.0, 21e-6, -43e-6]), force_sum=np.array([3.0, -1.0, 98.0]),
    window_s=10.0, cycles=False)
PREDICT_SLIP = ("gyro_noise_var * dt * dt", "gyro_noise_var * dt")    # σ_ν²·δt² as σ_ν²·δt
UPDATE_SLIP = ("+ ks[a, c] * gain[b, c]", "- ks[a, c] * gain[b, c]")  # + K·S·Kᵀ turned to −


def test_the_twins_hold_on_the_walking_case_for_the_kernels_and_their_copies(perturb):
    """The compiled kernels, and the copies :func:`perturbed` makes with no line changed."""
    for predict_kernel in (k.predict, perturb(k.predict, k, PREDICT_SLIP[0], PREDICT_SLIP[0])):
        check_predict(predict_kernel, WALKING)
    for update_kernel in (k.update, perturb(k.update, k, UPDATE_SLIP[0], UPDATE_SLIP[0])):
        check_update(update_kernel, ABS_GRAVITY, WALKING)


def test_a_factor_slipped_in_the_predict_fails_its_twin(perturb):
    """The white noise's σ_ν²·δt² slipped to σ_ν²·δt: one line of the predict."""
    wrong = perturb(k.predict, k, *PREDICT_SLIP)
    with pytest.raises(AssertionError, match="Not equal to tolerance"):
        check_predict(wrong, WALKING)


def test_a_sign_slipped_in_the_update_fails_its_twin(perturb):
    """The covariance update's + K·S·Kᵀ turned to −: one line of the update."""
    wrong = perturb(k.update, k, *UPDATE_SLIP)
    with pytest.raises(AssertionError, match="Not equal to tolerance"):
        check_update(wrong, ABS_GRAVITY, WALKING)
