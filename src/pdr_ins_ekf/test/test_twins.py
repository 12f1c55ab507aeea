"""NumPy twins of the foot filter's and smoother's compiled kernels (issue 31).

A twin is the textbook form of an equation, in NumPy, one symbol per line, written from
the papers and not from the kernel; each test asserts twin == kernel on
hypothesis-drawn states (attitude, velocity, biases, an SPD covariance, time step,
specific force, angular rate, noise settings), for 9 states and for 15 states with
random-walk and Gauss–Markov biases (``FilterConfig.bias_model``, through
:func:`pdr_ins_ekf.zupt_ekf.kernel_params`). The kernels are fast, hand-unrolled loops
(:mod:`pdr_ins_ekf.compiled_filter`, :mod:`pdr_ins_ekf.compiled_smoother`); the twins
are what a reviewer checks against the papers. ENU navigation frame, FLU body frame, SI.

- :func:`transition`, F = I + A·dt: the error dynamics of :mod:`pdr_ins_ekf.zupt_ekf`'s
  docstring (Simón Colomar et al. 2012, Eq. (7); with the biases Wang et al. 2020,
  Eq. (2)), discretised to first order as the kernel does; the Gauss–Markov biases decay
  as −δb/τ. Against ``apply_transition`` (F·M), ``transposed_transition_in_place``
  (Fᵀ·y) and ``inverse_transition_in_place`` (F⁻¹·x).
- :func:`process_noise_covariance`, Q = G·diag(σ²)·Gᵀ·dt (Simón Colomar et al. 2012,
  Eq. (8), "G Q Gᵀ"; Wang et al. 2020, Eq. (3)), and P ← F·P·Fᵀ + Q: against
  ``process_noise`` and ``propagate``.
- :func:`joseph_update`: K = P·Hᵀ·(H·P·Hᵀ + R)⁻¹, δx̂ += K·ν,
  P ← (I − K·H)·P·(I − K·H)ᵀ + K·R·Kᵀ (Simón Colomar et al. 2012, Eq. (8), and
  Wang et al. 2020, Eqs. (4)–(6), in Joseph form), H selecting δv (ZUPT) or δb_g
  (ZARU, Zampella et al. 2011, section IV), and the ZARU's χ² gate νᵀ·S⁻¹·ν: against
  ``correct`` and ``within_gate``. The kernels apply no other measurement (no heading or
  attitude pseudo-measurement).
- :func:`compensate`, the closed loop of Simón Colomar et al. 2012, Eq. (8):
  p̂ += δp̂, v̂ += δv̂, Ĉ ← (I − [δθ̂×])·Ĉ (to its polar factor), b̂ += δb̂.
- :func:`filter_twin`: the whole filter over a short drawn record, trapezoidal
  mechanization (Simón Colomar et al. 2012, Eqs. (1)–(5)), then Eq. (8) with ZUPT and
  the gated ZARU, and beside P the biases' share Pb (P₀'s bias block, F·Pb·Fᵀ plus the
  bias driving noise, (I − K·H)·Pb·(I − K·H)ᵀ with each update's gain K): against
  ``filter_loop``.
- :func:`rts_step`, Simón Colomar et al. 2012, Eq. (9): A = P_f·Fᵀ·P_p⁻¹,
  δx̂ₛ = δx̂_f + A·(δx̂ₛ₊₁ − δx̂_p₊₁), Pₛ = P_f + A·(Pₛ₊₁ − P_p₊₁)·Aᵀ: against the
  kernel ``rts_step``; and :func:`smoother_twin`, the 3-pass algorithm (open-loop
  forward pass, Eq. (9) backward, compensation) over one segment, against
  ``smoother_loop`` in its three backward passes (Eq. (9) as written, and the two
  adjoint forms that smooth the states alone).

Tolerances: 1e-12 relative for one step (rounding only); 1e-9 over a record of up to
25 samples and through P⁻¹ in Eq. (9). The records are aligned and gently accelerated
(:func:`record_case`), so that the compensation stays in the small-angle range where the
kernel's orthonormalisation reaches the twin's polar factor.

The mutation tests show the twins can fail: each builds a copy of a kernel module with
one line changed (a sign, a factor 0.5, a swapped noise density), runs it as plain
Python (its ``@njit`` decorators dropped) and asserts that the twin comparison raises;
the unchanged copy, run the same way, passes (``test_the_plain_copies_pass``).

Run: ``python -m pytest -q -p no:cacheprovider src/pdr_ins_ekf/test/test_twins.py``
(about 4 s once the kernels are compiled and cached; the first run compiles them).
"""
from __future__ import annotations

import ast
import inspect
from types import SimpleNamespace
from typing import NamedTuple

import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from pdr_ins_ekf import compiled_filter, compiled_smoother
from pdr_ins_ekf.kernel_data import (
    ACC,
    ACC_BIAS,
    ATTITUDE,
    AXES,
    GAUSS_MARKOV,
    GYRO,
    GYRO_BIAS,
    HEADING,
    NAV_AND_BIAS_STATES,
    NAV_STATES,
    POSITION,
    PREV_FORCE,
    PREV_NAV_FORCE,
    PREV_RATE,
    VELOCITY,
    Samples,
)
from pdr_ins_ekf.zupt_ekf import (
    FilterConfig,
    SmootherConfig,
    initial_covariance,
    kernel_params,
    smoother_params,
)

CONFIGURATIONS = [(NAV_STATES, "none"), (NAV_AND_BIAS_STATES, "random_walk"),
                  (NAV_AND_BIAS_STATES, "gauss_markov")]
CONFIG_IDS = ["9 states", "15 random walk", "15 Gauss-Markov"]
EXACT = 1e-12    # twin == kernel for one step: rounding only
RECORD = 1e-9    # over a record of up to 25 samples, and through P⁻¹ in Eq. (9)
# the scales of position [m], velocity [m/s], attitude, biases (the initial σ) and
# variances in a record, below which a difference is rounding (RECORD of a metre is a
# nanometre): at rest, position and biases are estimated from rounding alone
RECORD_SCALES = (1.0, 1.0, 1.0, 0.01, 0.0, 0.0)
I3 = np.eye(3)


def blocks(n: int) -> np.ndarray:
    """A scale per error state (n,): the drawn covariances and deviations are of this
    order, in the rows' units (m, m/s, rad, m/s², rad/s)."""
    scale = np.repeat([1.0, 0.3, 0.05, 0.1, 0.01], AXES)
    return scale[:n]


def rows(first: int) -> slice:
    """The three rows of the block that starts at ``first``."""
    return slice(first, first + AXES)


# --------------------------------------------------------------------------- twins


def skew(a: np.ndarray) -> np.ndarray:
    """[a×], so that [a×]·b = a × b."""
    return np.array([[0.0, -a[2], a[1]],
                     [a[2], 0.0, -a[0]],
                     [-a[1], a[0], 0.0]])


def dynamics(C: np.ndarray, f_n: np.ndarray, params, n: int) -> np.ndarray:
    """A (n, n) of δẋ = A·δx: δṗ = δv, δv̇ = [fⁿ×]·δθ − Ĉ·δb_a, δθ̇ = Ĉ·δb_g,
    δḃ = 0 (random walk) or −δb/τ (Gauss–Markov)."""
    A = np.zeros((n, n))
    A[rows(POSITION), rows(VELOCITY)] = I3
    A[rows(VELOCITY), rows(ATTITUDE)] = skew(f_n)
    if n == NAV_AND_BIAS_STATES:
        A[rows(VELOCITY), rows(ACC_BIAS)] = -C
        A[rows(ATTITUDE), rows(GYRO_BIAS)] = C
        if params.bias_model == GAUSS_MARKOV:
            A[ACC_BIAS:, ACC_BIAS:] = -np.eye(2 * AXES) / params.bias_tau_s
    return A


def transition(C: np.ndarray, f_n: np.ndarray, dt: float, params, n: int) -> np.ndarray:
    """F = I + A·dt (n, n), the first-order discretisation."""
    A = dynamics(C, f_n, params, n)
    return np.eye(n) + A * dt


def noise_input(C: np.ndarray, n: int) -> np.ndarray:
    """G (n, n) of δẋ = A·δx + G·w, the noise w = [0, n_a, n_g (, n_ba, n_bg)] in the
    rows of the states it drives: δv̇ gets −Ĉ·n_a, δθ̇ gets Ĉ·n_g, each bias its own
    driving noise."""
    G = np.zeros((n, n))
    G[rows(VELOCITY), rows(VELOCITY)] = -C
    G[rows(ATTITUDE), rows(ATTITUDE)] = C
    if n == NAV_AND_BIAS_STATES:
        G[rows(ACC_BIAS), rows(ACC_BIAS)] = I3
        G[rows(GYRO_BIAS), rows(GYRO_BIAS)] = I3
    return G


def process_noise_covariance(C: np.ndarray, dt: float, params, n: int) -> np.ndarray:
    """Q = G·diag(σ²)·Gᵀ·dt (n, n), σ the densities of w (none on position)."""
    densities = [0.0, params.acc_noise, params.gyro_noise, params.acc_bias_noise,
                 params.gyro_bias_noise]
    sigma2 = np.repeat(np.square(densities), AXES)[:n]
    G = noise_input(C, n)
    return G @ np.diag(sigma2) @ G.T * dt


def symmetric(P: np.ndarray) -> np.ndarray:
    """(P + Pᵀ)/2."""
    return (P + P.T) / 2


def propagate(P: np.ndarray, C: np.ndarray, f_n: np.ndarray, dt: float, params
              ) -> np.ndarray:
    """P ← F·P·Fᵀ + Q, symmetrised."""
    n = P.shape[0]
    F = transition(C, f_n, dt, params, n)
    Q = process_noise_covariance(C, dt, params, n)
    return symmetric(F @ P @ F.T + Q)


def selection(first: int, n: int) -> np.ndarray:
    """H (3, n) = [0 … I₃ … 0], picking the three states from row ``first``."""
    H = np.zeros((AXES, n))
    H[:, rows(first)] = I3
    return H


class Update(NamedTuple):
    dx: np.ndarray        # δx̂ + K·ν (n,)
    P: np.ndarray         # the Joseph-form covariance (n, n)
    K: np.ndarray         # gain (n, 3)
    weighted: np.ndarray  # S⁻¹·ν (3,)


def joseph_update(dx: np.ndarray, P: np.ndarray, nu: np.ndarray, first: int, sigma: float
                  ) -> Update:
    """Kalman update with H selecting rows ``first`` to ``first`` + 2, innovation ν (3,)
    and R = σ²·I, covariance in Joseph form, symmetrised."""
    n = P.shape[0]
    H = selection(first, n)
    R = sigma**2 * I3
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    dx_new = dx + K @ nu
    I_KH = np.eye(n) - K @ H
    P_new = I_KH @ P @ I_KH.T + K @ R @ K.T
    return Update(dx_new, symmetric(P_new), K, np.linalg.solve(S, nu))


def normalised_innovation(P: np.ndarray, nu: np.ndarray, first: int, sigma: float) -> float:
    """νᵀ·S⁻¹·ν, S = H·P·Hᵀ + σ²·I: the ZARU's χ² gate statistic."""
    H = selection(first, P.shape[0])
    S = H @ P @ H.T + sigma**2 * I3
    return float(nu @ np.linalg.solve(S, nu))


class Nominal(NamedTuple):
    """The nominal state and what the trapezoidal step keeps of the last sample."""

    p: np.ndarray       # p̂ (3,) [m]
    v: np.ndarray       # v̂ (3,) [m/s]
    C: np.ndarray       # Ĉ = C_b^n (3, 3)
    b: np.ndarray       # b̂ = [b_a, b_g] (6,)
    f_b: np.ndarray     # the last sample's f − b̂_a (3,) [m/s²], body frame
    w_b: np.ndarray     # the last sample's ω − b̂_g (3,) [rad/s], body frame
    f_n: np.ndarray     # the last sample's Ĉ·(f − b̂_a) (3,) [m/s²], navigation frame


def polar(M: np.ndarray) -> np.ndarray:
    """The rotation nearest to M: U·Vᵀ of its SVD M = U·Σ·Vᵀ."""
    U, _, Vt = np.linalg.svd(M)
    return U @ Vt


def compensate(x: Nominal, dx: np.ndarray) -> Nominal:
    """Simón Colomar et al. 2012, Eq. (8): p̂ += δp̂, v̂ += δv̂, Ĉ ← (I − [δθ̂×])·Ĉ made
    orthonormal, b̂ += δb̂; the last navigation-frame force re-rotated by the new Ĉ."""
    p = x.p + dx[rows(POSITION)]
    v = x.v + dx[rows(VELOCITY)]
    C = polar((I3 - skew(dx[rows(ATTITUDE)])) @ x.C)
    b = x.b.copy()
    if dx.shape[0] == NAV_AND_BIAS_STATES:
        b += dx[ACC_BIAS:]
    return x._replace(p=p, v=v, C=C, b=b, f_n=C @ x.f_b)


def first_sample(C0: np.ndarray, b0: np.ndarray, f: np.ndarray, w: np.ndarray) -> Nominal:
    """At the origin at rest, the mechanization's memory set from the first sample."""
    f_b = f - b0[ACC]
    return Nominal(np.zeros(3), np.zeros(3), C0.copy(), b0.copy(), f_b, w - b0[GYRO],
                   C0 @ f_b)


def mechanize(x: Nominal, f: np.ndarray, w: np.ndarray, dt: float, gravity: float
              ) -> Nominal:
    """Trapezoidal strapdown step (Simón Colomar et al. 2012, Eqs. (1)–(5), with the rate
    and the navigation-frame force averaged over the interval):
    Ĉ ← Ĉ·exp([ω̄·dt×]), aₙ = mean of Ĉ·f over the interval − g, v̂ += aₙ·dt,
    p̂ += v̂·dt + aₙ·dt²/2."""
    f_b = f - x.b[ACC]
    w_b = w - x.b[GYRO]
    w_mean = (x.w_b + w_b) / 2
    C = x.C @ scipy.linalg.expm(skew(w_mean * dt))
    f_n = C @ f_b
    g = np.array([0.0, 0.0, gravity])
    a = (x.f_n + f_n) / 2 - g
    p = x.p + x.v * dt + a * dt**2 / 2
    v = x.v + a * dt
    return Nominal(p, v, C, x.b, f_b, w_b, f_n)


def filter_twin(samples: Samples, C0, b0, P0, params) -> tuple:
    """The closed-loop filter (Simón Colomar et al. 2012, Eq. (8)) over a record: per
    sample the mechanization and P ← F·P·Fᵀ + Q; in stance the ZUPT z = −v̂ and its
    compensation, then, with ZARU and where νᵀ·S⁻¹·ν < gate, z = ω − b̂_g and its
    compensation. Returns position, velocity, attitude, bias and covariance diagonal
    after each sample, and the diagonal of the biases' share Pb (zeros with 9 states)."""
    n = P0.shape[0]
    x = first_sample(C0, b0, samples.accel[0], samples.gyro[0])
    P = P0.copy()
    Pb = np.zeros((n, n))
    if n == NAV_AND_BIAS_STATES:
        Pb[ACC_BIAS:, ACC_BIAS:] = P0[ACC_BIAS:, ACC_BIAS:]
    biases_only = params._replace(acc_noise=0.0, gyro_noise=0.0)
    out = {"p": [], "v": [], "C": [], "b": [], "var": [], "bias_var": []}
    for f, w, dt, stance in zip(samples.accel, samples.gyro, samples.dt, samples.stance,
                                strict=True):
        x = mechanize(x, f, w, dt, params.gravity_mps2)
        P = propagate(P, x.C, x.f_n, dt, params)
        Pb = propagate(Pb, x.C, x.f_n, dt, biases_only)
        if stance:
            zupt = joseph_update(np.zeros(n), P, -x.v, VELOCITY, params.zupt_sigma_mps)
            P, Pb = zupt.P, gain_applied(Pb, zupt.K, VELOCITY)
            x = compensate(x, zupt.dx)
            nu = w - x.b[GYRO]
            if params.zaru and normalised_innovation(
                    P, nu, GYRO_BIAS, params.zaru_sigma_radps) < params.zaru_gate_nis:
                zaru = joseph_update(np.zeros(n), P, nu, GYRO_BIAS, params.zaru_sigma_radps)
                P, Pb = zaru.P, gain_applied(Pb, zaru.K, GYRO_BIAS)
                x = compensate(x, zaru.dx)
        for key, value in zip(out, (x.p, x.v, x.C, x.b, np.diag(P), np.diag(Pb)), strict=True):
            out[key].append(value)
    return tuple(np.array(values) for values in out.values())


def gain_applied(Pb: np.ndarray, K: np.ndarray, first: int) -> np.ndarray:
    """(I − K·H)·Pb·(I − K·H)ᵀ, symmetrised: the biases' share of P through an update of
    gain K (n, 3), H selecting rows ``first`` to ``first`` + 2 (no K·R·Kᵀ: R is white)."""
    I_KH = np.eye(Pb.shape[0]) - K @ selection(first, Pb.shape[0])
    return symmetric(I_KH @ Pb @ I_KH.T)


class Forward(NamedTuple):
    """What the open-loop forward pass keeps of sample n."""

    nominal: Nominal       # the nominal state, never compensated
    F: np.ndarray          # Fₙ (n, n)
    dx_pred: np.ndarray    # δx̂ₙ|ₙ₋₁ (n,)
    P_pred: np.ndarray     # Pₙ|ₙ₋₁ (n, n)
    dx_filt: np.ndarray    # δx̂ₙ|ₙ (n,)
    P_filt: np.ndarray     # Pₙ|ₙ (n, n)


class Smoothed(NamedTuple):
    dx: np.ndarray  # δx̂ₙ|ₑ (n,)
    P: np.ndarray   # Pₙ|ₑ (n, n)


def rts_step(dx_f, P_f, dx_p_next, P_p_next, F_next, dx_s_next, P_s_next) -> Smoothed:
    """Simón Colomar et al. 2012, Eq. (9), one sample:
    Aₙ = Pₙ|ₙ·Fₙ₊₁ᵀ·Pₙ₊₁|ₙ⁻¹, δx̂ₙ|ₑ = δx̂ₙ|ₙ + Aₙ·(δx̂ₙ₊₁|ₑ − δx̂ₙ₊₁|ₙ),
    Pₙ|ₑ = Pₙ|ₙ + Aₙ·(Pₙ₊₁|ₑ − Pₙ₊₁|ₙ)·Aₙᵀ."""
    A = P_f @ F_next.T @ np.linalg.inv(P_p_next)
    dx_s = dx_f + A @ (dx_s_next - dx_p_next)
    P_s = P_f + A @ (P_s_next - P_p_next) @ A.T
    return Smoothed(dx_s, P_s)


def smoother_twin(samples: Samples, C0, b0, P0, params, zero_heading_position: bool
                  ) -> tuple:
    """The 3-pass smoother (Simón Colomar et al. 2012, section III-C) over one segment,
    the whole record. 1. Open loop: the nominal state mechanized without feedback,
    δx̂ₙ|ₙ₋₁ = Fₙ·δx̂ₙ₋₁|ₙ₋₁, P ← F·P·Fᵀ + Q (then, if asked, the heading–position
    cross-covariance zeroed), the ZUPT with z = −v̂ (innovation z − δv̂) and the gated
    ZARU with z = ω − b̂_g (innovation z − δb̂_g). 2. Eq. (9) backward from the filtered
    last sample. 3. Each sample compensated: p̂ + δp̂, v̂ + δv̂, exp(−[δθ̂×])·Ĉ.
    Returns smoothed position, velocity, attitude and velocity variances."""
    n = P0.shape[0]
    x = first_sample(C0, b0, samples.accel[0], samples.gyro[0])
    dx = np.zeros(n)
    P = P0.copy()
    kept = []
    for f, w, dt, stance in zip(samples.accel, samples.gyro, samples.dt, samples.stance,
                                strict=True):
        x = mechanize(x, f, w, dt, params.gravity_mps2)
        F = transition(x.C, x.f_n, dt, params, n)
        dx = F @ dx
        P = propagate(P, x.C, x.f_n, dt, params)
        if zero_heading_position:
            P[rows(POSITION), HEADING] = 0.0
            P[HEADING, rows(POSITION)] = 0.0
        dx_pred, P_pred = dx, P
        if stance:
            zupt = joseph_update(dx, P, -x.v - dx[rows(VELOCITY)], VELOCITY,
                                 params.zupt_sigma_mps)
            dx, P = zupt.dx, zupt.P
            if params.zaru:
                nu = w - x.b[GYRO] - dx[rows(GYRO_BIAS)]
                if normalised_innovation(P, nu, GYRO_BIAS, params.zaru_sigma_radps
                                         ) < params.zaru_gate_nis:
                    zaru = joseph_update(dx, P, nu, GYRO_BIAS, params.zaru_sigma_radps)
                    dx, P = zaru.dx, zaru.P
        kept.append(Forward(x, F, dx_pred, P_pred, dx, P))
    smoothed = Smoothed(kept[-1].dx_filt, kept[-1].P_filt)
    out = []
    for j in range(len(kept) - 1, -1, -1):
        if j < len(kept) - 1:
            after = kept[j + 1]
            smoothed = rts_step(kept[j].dx_filt, kept[j].P_filt, after.dx_pred, after.P_pred,
                                after.F, *smoothed)
        x, dxs = kept[j].nominal, smoothed.dx
        out.append((x.p + dxs[rows(POSITION)], x.v + dxs[rows(VELOCITY)],
                    scipy.linalg.expm(-skew(dxs[rows(ATTITUDE)])) @ x.C,
                    np.diag(smoothed.P)[rows(VELOCITY)]))
    return tuple(np.array(values[::-1]) for values in zip(*out, strict=True))


# --------------------------------------------------------------------------- cases


class UnitCase(NamedTuple):
    """One drawn state for the single-step twins."""

    params: object        # FilterParams
    C: np.ndarray         # Ĉ (3, 3)
    f_n: np.ndarray       # navigation-frame specific force (3,) [m/s²]
    dt: float             # [s]
    P: np.ndarray         # SPD (n, n)
    P_other: np.ndarray   # another SPD (n, n): the next sample's smoothed covariance
    dx: np.ndarray        # (3, n): deviations (filtered, predicted, smoothed)
    nu: np.ndarray        # innovation (3,)
    nominal: Nominal      # for the compensation


def rotation(rotvec: np.ndarray) -> np.ndarray:
    """exp([r×]) for a rotation vector r [rad]."""
    return scipy.linalg.expm(skew(rotvec))


def filter_config(states: int, bias_model: str, noise: np.ndarray, **more) -> FilterConfig:
    """A FilterConfig with the drawn noise (8,): white, bias and measurement σ, τ."""
    return FilterConfig(
        acc_noise_mps2_per_sqrt_hz=noise[0], gyro_noise_radps_per_sqrt_hz=noise[1],
        acc_bias_noise_mps2_per_sqrt_s=noise[2], gyro_bias_noise_radps_per_sqrt_s=noise[3],
        zupt_sigma_mps=noise[4], zaru_sigma_radps=noise[5],
        bias_tau_s=noise[6], zaru_gate_nis=noise[7], bias_model=bias_model,
        init_pos_sigma_m=0.01, init_vel_sigma_mps=0.01, init_att_sigma_rad=1e-3,
        init_yaw_sigma_rad=2e-3, init_acc_bias_sigma_mps2=0.01, init_gyro_bias_sigma_radps=0.01,
        **more)


def unit_case(states: int, bias_model: str, noise, rotvec, f_n, dt, B, dx, nu, nominal
              ) -> UnitCase:
    """A UnitCase from raw draws: noise (8,) (see :func:`filter_config`), B (n, n) in
    [−1, 1] whose Gram matrices give the covariances, dx (3, n) and nominal (18,) in
    [−1, 1], scaled per state by :func:`blocks`."""
    params = kernel_params(filter_config(states, bias_model, noise))
    D = np.diag(blocks(states))
    P = D @ symmetric(B @ B.T / states + 0.1 * np.eye(states)) @ D
    P_other = D @ symmetric(B.T @ B / states + 0.1 * np.eye(states)) @ D
    C = rotation(rotvec)
    small_angle = np.concatenate([np.ones(6), np.full(3, 1e-3),
                                  np.ones(states - NAV_STATES)])
    p, v, b, f_b = nominal[0:3], nominal[3:6], nominal[6:12] * 0.1, nominal[12:15]
    x = Nominal(p, v, C, b, f_b, nominal[15:18], C @ f_b)
    return UnitCase(params, C, np.asarray(f_n), dt, P, P_other,
                    dx * blocks(states) * small_angle, np.asarray(nu), x)


def real(low: float, high: float):
    """Floats in [low, high], no subnormals (whose rounding is all relative error)."""
    return st.floats(low, high, allow_subnormal=False)


def unit(states, bias_model):
    """A strategy of UnitCases."""
    return st.builds(
        unit_case, st.just(states), st.just(bias_model),
        noise=st.tuples(*[real(1e-3, 0.5)] * 4, real(1e-3, 0.5),
                        real(1e-3, 0.5), real(1.0, 1e3), real(0.5, 50.0)),
        rotvec=arrays(float, 3, elements=real(-3.0, 3.0)),
        f_n=arrays(float, 3, elements=real(-30.0, 30.0)),
        dt=real(1e-3, 0.05),
        B=arrays(float, (states, states), elements=real(-1.0, 1.0)),
        dx=arrays(float, (3, states), elements=real(-1.0, 1.0)),
        nu=arrays(float, 3, elements=real(-1.0, 1.0)),
        nominal=arrays(float, 18, elements=real(-1.0, 1.0)))


class RecordCase(NamedTuple):
    """A short drawn record and the aligned start of the filter."""

    samples: Samples
    C0: np.ndarray
    b0: np.ndarray
    P0: np.ndarray
    params: object  # FilterParams


def record_case(states: int, bias_model: str, noise, zaru, rotvec, accel, gyro, dt, stance,
                bias) -> RecordCase:
    """A RecordCase from raw draws: N samples of specific force (gravity in the body
    frame of the start attitude, plus ``accel``) and rate, intervals (the first 0), the
    stance mask; biases for 15 states. Aligned at the start, as the filter is, and with
    ``accel`` small, the ZUPT's innovations stay in the filter's linear range and its
    attitude corrections small (below 1e-2 rad), where the kernel's two Newton–Schulz
    steps reach the polar factor of the twin's compensation (an innovation of metres per
    second can correct the attitude by 0.1 rad, where they are 1e-9 apart)."""
    config = filter_config(states, bias_model, noise,
                           zaru=bool(zaru and states == NAV_AND_BIAS_STATES))
    N = len(stance)
    C0 = rotation(rotvec)
    f = np.asarray(accel)[:N] + C0.T @ [0.0, 0.0, config.gravity_mps2]
    intervals = np.concatenate([[0.0], np.asarray(dt)[1:N]])
    samples = Samples(intervals, np.ascontiguousarray(f), np.ascontiguousarray(gyro[:N]),
                      np.asarray(stance, bool))
    b0 = np.asarray(bias) if states == NAV_AND_BIAS_STATES else np.zeros(6)
    return RecordCase(samples, C0, b0, initial_covariance(config),
                      kernel_params(config))


MAX_SAMPLES = 25


def record(states, bias_model):
    """A strategy of RecordCases of 2 to MAX_SAMPLES samples."""
    return st.builds(
        record_case, st.just(states), st.just(bias_model),
        noise=st.tuples(real(1e-3, 0.1), real(1e-4, 5e-3), real(1e-4, 0.01),
                        real(1e-5, 1e-3), real(1e-3, 0.05), real(1e-3, 0.05),
                        real(1.0, 1e3), real(1.0, 1e3)),
        zaru=st.booleans(),
        rotvec=arrays(float, 3, elements=real(-3.0, 3.0)),
        accel=arrays(float, (MAX_SAMPLES, 3), elements=real(-0.5, 0.5)),
        gyro=arrays(float, (MAX_SAMPLES, 3), elements=real(-3.0, 3.0)),
        dt=arrays(float, MAX_SAMPLES, elements=real(1e-3, 0.02)),
        stance=st.lists(st.booleans(), min_size=2, max_size=MAX_SAMPLES),
        bias=arrays(float, 6, elements=real(-0.05, 0.05)))


# --------------------------------------------------------------------------- checks


def same(kernel, twin, rtol: float = EXACT, scale: float = 0.0) -> None:
    """kernel == twin to rtol, entry by entry, or to rtol of the largest entry (or of
    ``scale``, for a quantity that may be all rounding, as a position at rest is)."""
    twin = np.asarray(twin)
    atol = rtol * max(np.abs(twin).max(), scale)
    np.testing.assert_allclose(kernel, twin, rtol=rtol, atol=atol)


def check_transition_and_noise(kernels, case: UnitCase) -> None:
    """F·M, Fᵀ·y, F⁻¹·x, the diagonal of Q and P ← F·P·Fᵀ + Q."""
    n = case.P.shape[0]
    F = transition(case.C, case.f_n, case.dt, case.params, n)
    Q = process_noise_covariance(case.C, case.dt, case.params, n)
    same(kernels.apply_transition(case.P, case.C, case.f_n, case.dt, case.params),
         F @ case.P)
    y = case.dx[0].copy()
    kernels.transposed_transition_in_place(y, case.C, case.f_n, case.dt, case.params)
    same(y, F.T @ case.dx[0])
    x = case.dx[1].copy()
    kernels.inverse_transition_in_place(x, case.C, case.f_n, case.dt, case.params)
    same(x, np.linalg.solve(F, case.dx[1]))
    diagonal = [kernels.process_noise(case.params, i, case.dt) for i in range(n)]
    same(np.diag(diagonal), Q)
    P = case.P.copy()
    kernels.propagate(P, case.C, case.f_n, case.dt, case.params)
    same(P, propagate(case.P, case.C, case.f_n, case.dt, case.params))


def check_update(kernels, case: UnitCase, first: int, sigma: float) -> None:
    """The Joseph update of rows ``first``: δx̂, P, Kᵀ, S⁻¹·ν, and the gate."""
    twin = joseph_update(case.dx[0], case.P, case.nu, first, sigma)
    dx, P = case.dx[0].copy(), case.P.copy()
    K_T, weighted = kernels.correct(dx, P, case.nu, first, sigma)
    same(dx, twin.dx)
    same(P, twin.P)
    same(K_T, twin.K.T)
    same(weighted, twin.weighted)
    nis = normalised_innovation(case.P, case.nu, first, sigma)
    for gate in (nis * (1 - 1e-9), nis * (1 + 1e-9)):
        assert kernels.within_gate(case.P, case.nu, first, sigma, gate) == (nis < gate)


def check_compensation(kernels, case: UnitCase) -> None:
    """Eq. (8)'s compensation (``feed_back``: also δx̂ ← 0 and the last navigation-frame
    force re-rotated)."""
    x, n = case.nominal, case.P.shape[0]
    state = compiled_filter.new_state(x.C, x.b, case.P)
    state.p[:], state.v[:], state.dx[:] = x.p, x.v, case.dx[0]
    state.prev[PREV_FORCE], state.prev[PREV_RATE] = x.f_b, x.w_b
    state.prev[PREV_NAV_FORCE] = x.f_n
    kernels.feed_back(state)
    twin = compensate(x, case.dx[0])
    for kernel, expected in zip((state.p, state.v, state.C, state.b,
                                 state.prev[PREV_NAV_FORCE]),
                                (twin.p, twin.v, twin.C, twin.b, twin.f_n), strict=True):
        same(kernel, expected)
    assert not state.dx.any() and state.dx.shape == (n,)


def check_filter_units(kernels, case: UnitCase) -> None:
    check_transition_and_noise(kernels, case)
    check_update(kernels, case, VELOCITY, case.params.zupt_sigma_mps)
    if case.P.shape[0] == NAV_AND_BIAS_STATES:
        check_update(kernels, case, GYRO_BIAS, case.params.zaru_sigma_radps)
    check_compensation(kernels, case)


def check_filter_record(kernels, case: RecordCase) -> None:
    """``filter_loop`` against :func:`filter_twin`."""
    pos, vel, att, bias, var, pcov, vcov, _, bias_var, bias_pcov, bias_vcov = \
        kernels.filter_loop(case.samples, case.C0, case.b0, case.P0, case.params)
    twin = filter_twin(case.samples, case.C0, case.b0, case.P0, case.params)
    for kernel, expected, scale in zip((pos, vel, att, bias, var, bias_var), twin,
                                       RECORD_SCALES, strict=True):
        same(kernel, expected, RECORD, scale)
    same(np.diagonal(pcov, axis1=1, axis2=2), twin[4][:, rows(POSITION)], RECORD)
    same(np.diagonal(vcov, axis1=1, axis2=2), twin[4][:, rows(VELOCITY)], RECORD)
    same(np.diagonal(bias_pcov, axis1=1, axis2=2), twin[5][:, rows(POSITION)], RECORD)
    same(np.diagonal(bias_vcov, axis1=1, axis2=2), twin[5][:, rows(VELOCITY)], RECORD)


def check_rts_step(kernels, case: UnitCase) -> None:
    """One step of Eq. (9) on a drawn filtered P_f and a consistent P_p = F·P_f·Fᵀ + Q."""
    n = case.P.shape[0]
    F = transition(case.C, case.f_n, case.dt, case.params, n)
    P_p = propagate(case.P, case.C, case.f_n, case.dt, case.params)
    dx_f, dx_p, dx_s = case.dx
    twin = rts_step(dx_f, case.P, dx_p, P_p, F, dx_s, case.P_other)
    dxs, Ps = dx_s.copy(), case.P_other.copy()
    kernels.rts_step(dx_f, case.P, dx_p, P_p, F @ case.P, dxs, Ps)
    same(dxs, twin.dx, RECORD)
    same(Ps, twin.P, RECORD)


BACKWARD_PASSES = {"eq9": (True, False), "adjoint": (False, False),
                   "adjoint_dense": (False, True)}  # covariance, zero_heading_position


def check_smoother_record(kernels, case: RecordCase, backward: str) -> None:
    """``smoother_loop`` over one segment (γs so small that the rule never cuts) against
    :func:`smoother_twin`."""
    covariance, zero_heading_position = BACKWARD_PASSES[backward]
    smoother = smoother_params(SmootherConfig(
        "segmented", gamma_s_m2ps2=1e-300, covariance=covariance,
        zero_heading_position=zero_heading_position))
    pos, vel, att, vel_var, ends = kernels.smoother_loop(
        case.samples, case.C0, case.b0, case.P0, case.params, smoother)
    twin = smoother_twin(case.samples, case.C0, case.b0, case.P0, case.params,
                         zero_heading_position)
    assert list(ends) == [len(case.samples.dt) - 1]
    for kernel, expected, scale in zip((pos, vel, att), twin[:3], RECORD_SCALES[:3], strict=True):
        same(kernel, expected, RECORD, scale)
    if covariance:
        same(vel_var, twin[3], RECORD)
    else:
        assert np.isnan(vel_var).all()


# --------------------------------------------------------------------------- twin == kernel


def for_drawn(cases, check, kernels, *more, examples: int = 15) -> None:
    """``check(kernels, case, *more)`` on ``examples`` cases drawn by hypothesis."""
    @settings(max_examples=examples, deadline=None)
    @given(cases)
    def drawn(case):
        check(kernels, case, *more)

    drawn()


@pytest.mark.parametrize(("states", "bias_model"), CONFIGURATIONS, ids=CONFIG_IDS)
def test_transition_noise_and_updates_are_the_textbook_equations(states, bias_model):
    for_drawn(unit(states, bias_model), check_filter_units, compiled_filter)


@pytest.mark.parametrize(("states", "bias_model"), CONFIGURATIONS, ids=CONFIG_IDS)
def test_the_filter_is_the_textbook_zupt_aided_ins(states, bias_model):
    for_drawn(record(states, bias_model), check_filter_record, compiled_filter)


@pytest.mark.parametrize(("states", "bias_model"), CONFIGURATIONS, ids=CONFIG_IDS)
def test_the_rts_step_is_eq_9(states, bias_model):
    for_drawn(unit(states, bias_model), check_rts_step, compiled_smoother)


@pytest.mark.parametrize("backward", BACKWARD_PASSES)
@pytest.mark.parametrize(("states", "bias_model"), CONFIGURATIONS, ids=CONFIG_IDS)
def test_the_smoother_is_the_textbook_three_pass_algorithm(states, bias_model, backward):
    for_drawn(record(states, bias_model), check_smoother_record, compiled_smoother, backward,
              examples=8)


# --------------------------------------------------------------------------- mutations


def plain_copy(module, line: str | None = None, changed: str | None = None
               ) -> SimpleNamespace:
    """The kernel module's source, with ``line`` (which must occur once) replaced by
    ``changed``, run as plain Python in a namespace of its own: the ``@njit``
    decorators and the cache bookkeeping dropped, the imports as in the module."""
    source = inspect.getsource(module)
    if line is not None:
        assert source.count(line) == 1, line
        source = source.replace(line, changed)
    tree = ast.parse(source)
    tree.body = [node for node in tree.body
                 if not (isinstance(node, ast.Expr) and "forget_if_changed" in ast.unparse(node))]
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            node.decorator_list = [d for d in node.decorator_list
                                   if "njit" not in ast.unparse(d)]
    namespace = {"__name__": f"plain_{module.__name__.rpartition('.')[2]}"}
    exec(compile(tree, f"<plain copy of {module.__name__}>", "exec"), namespace)
    return SimpleNamespace(**namespace)


def fixed_unit_cases() -> list[UnitCase]:
    """One UnitCase per configuration, from a seeded generator."""
    rng = np.random.default_rng(31)
    cases = []
    for states, bias_model in CONFIGURATIONS:
        noise = [0.02, 0.01, 0.005, 0.001, 0.05, 0.02, 20.0, 10.0]
        cases.append(unit_case(states, bias_model, noise, rng.uniform(-3, 3, 3),
                               rng.uniform(-15, 15, 3), 0.01,
                               rng.uniform(-1, 1, (states, states)),
                               rng.uniform(-1, 1, (3, states)), rng.uniform(-1, 1, 3),
                               rng.uniform(-1, 1, 18)))
    return cases


def fixed_record_cases() -> list[RecordCase]:
    """One RecordCase of 20 samples per configuration (15 states with ZARU), from a
    seeded generator: a swing between two stances."""
    rng = np.random.default_rng(31)
    stance = [True] * 6 + [False] * 8 + [True] * 6
    cases = []
    for states, bias_model in CONFIGURATIONS:
        noise = [0.02, 0.01, 0.005, 0.001, 0.02, 0.02, 20.0, 1e3]
        cases.append(record_case(states, bias_model, noise, True, rng.uniform(-3, 3, 3),
                                 rng.uniform(-0.5, 0.5, (20, 3)), rng.uniform(-2, 2, (20, 3)),
                                 np.full(20, 0.01), stance, rng.uniform(-0.05, 0.05, 6)))
    return cases


def check_filter(kernels) -> None:
    for case in fixed_unit_cases():
        check_filter_units(kernels, case)
    for case in fixed_record_cases():
        check_filter_record(kernels, case)


def check_smoother(kernels) -> None:
    for case in fixed_unit_cases():
        check_rts_step(kernels, case)
    for case in fixed_record_cases():
        for backward in BACKWARD_PASSES:
            check_smoother_record(kernels, case, backward)


# name: (a line of the kernel module, the same line changed)
FILTER_MUTATIONS = {
    "F: dp/dv block halved": (
        "M[POSITION, j] += dt * M[VELOCITY, j]",
        "M[POSITION, j] += 0.5 * dt * M[VELOCITY, j]"),
    "F: [f_n x] sign": (
        "M[VELOCITY + 1, j] += dt * (a2 * t0 - a0 * t2)",
        "M[VELOCITY + 1, j] += dt * (a0 * t2 - a2 * t0)"),
    "F: dtheta/db_g sign": (
        "M[ATTITUDE + i, j] += dt * (C[i, 0] * g0",
        "M[ATTITUDE + i, j] -= dt * (C[i, 0] * g0"),
    "F: Gauss-Markov decay halved": (
        "return dt / params.bias_tau_s",
        "return dt / params.bias_tau_s / 2"),
    "Q: accelerometer density on dtheta": (
        "density = params.gyro_noise\n",
        "density = params.acc_noise\n"),
    "Joseph: K R K^T halved": (
        "+ s2 * (K_T[0, i] * K_T[0, j]",
        "+ s2 / 2 * (K_T[0, i] * K_T[0, j]"),
    "update: dx -= K nu": (
        "dx[i] += K_T[0, i] * innovation[0]",
        "dx[i] -= K_T[0, i] * innovation[0]"),
    "compensation: (I + [dtheta x])": (
        "[[1.0, t2, -t1], [-t2, 1.0, t0], [t1, -t0, 1.0]]",
        "[[1.0, -t2, t1], [t2, 1.0, -t0], [-t1, t0, 1.0]]"),
    "ZUPT: z = +v": (
        "update(state, -v, VELOCITY",
        "update(state, v, VELOCITY"),
}
SMOOTHER_MUTATIONS = {
    "Eq. (9): dx gain halved": (
        "acc += X[q, i] * diff[q]",
        "acc += 0.5 * X[q, i] * diff[q]"),
    "Eq. (9): A (Ps - Pp) A^T sign": (
        "Ps[i, c] += t * X[q, c]",
        "Ps[i, c] -= t * X[q, c]"),
    "adjoint: (I - K H)^T lambda sign": (
        "lam[rows] += seg.weighted[j, u, 0] - k0",
        "lam[rows] += seg.weighted[j, u, 0] + k0"),
    "adjoint: Q lambda sign": (
        "dxs[i] -= process_noise(params, i, dt_next) * lam[i]",
        "dxs[i] += process_noise(params, i, dt_next) * lam[i]"),
    "open loop: innovation -v + dv": (
        "-v - dx[VELOCITY:VELOCITY + AXES]",
        "-v + dx[VELOCITY:VELOCITY + AXES]"),
}


def test_the_plain_copies_pass():
    """The unchanged kernels, run as plain Python, pass: a mutant fails by its change."""
    check_filter(plain_copy(compiled_filter))
    check_smoother(plain_copy(compiled_smoother))


@pytest.mark.parametrize("mutation", FILTER_MUTATIONS)
def test_one_changed_filter_line_fails_the_twins(mutation):
    with pytest.raises(AssertionError):
        check_filter(plain_copy(compiled_filter, *FILTER_MUTATIONS[mutation]))


@pytest.mark.parametrize("mutation", SMOOTHER_MUTATIONS)
def test_one_changed_smoother_line_fails_the_twins(mutation):
    with pytest.raises(AssertionError):
        check_smoother(plain_copy(compiled_smoother, *SMOOTHER_MUTATIONS[mutation]))
