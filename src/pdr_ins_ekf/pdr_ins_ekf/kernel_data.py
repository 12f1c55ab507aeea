"""The named data of the foot filter's compiled kernels (:mod:`compiled_filter`,
:mod:`compiled_smoother`): the rows of the error state, the filter's state, its
parameters and the samples of a record, as NamedTuples that numba passes into and out of
compiled code (gaitmap's ``SimpleZuptParameter`` does the same).

The error state δx = [δp, δv, δθ (, δb_a, δb_g)] (Simón Colomar et al. 2012, Eq. (8);
with the biases Wang et al. 2020, Eq. (2)) has three rows per block, starting at
:data:`POSITION`, :data:`VELOCITY`, :data:`ATTITUDE`, :data:`ACC_BIAS` and
:data:`GYRO_BIAS`: :data:`NAV_STATES` without the biases, :data:`NAV_AND_BIAS_STATES`
with them. Frames and units: ENU navigation frame, FLU body frame, SI.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

# first row of each three-row block of the error state δx (and of P)
POSITION = 0       # δp [m], navigation frame
VELOCITY = 3       # δv [m/s], navigation frame
ATTITUDE = 6       # δθ [rad]: C = (I − [δθ×])·Ĉ
ACC_BIAS = 9       # δb_a [m/s²], body frame (15 states)
GYRO_BIAS = 12     # δb_g [rad/s], body frame (15 states)
HEADING = ATTITUDE + 2   # δθ about the navigation frame's up axis
NAV_STATES = 9            # δp, δv, δθ: the biases not estimated
NAV_AND_BIAS_STATES = 15  # and δb_a, δb_g
AXES = 3                  # rows per block

# the bias vector b (6,): accelerometer [m/s²], then gyroscope [rad/s]
ACC = slice(0, 3)
GYRO = slice(3, 6)

# the entries of NavState.nis: the touchdown innovations the published covariance is
# scaled by (pdr_ins_ekf.compiled_filter.covariance_scale)
NIS_SUM = 0         # Σ νᵀ·S⁻¹·ν / 3 over the first ZUPT of each stance
NIS_COUNT = 1       # how many stances are in the sum

# the rows of NavState.prev: what the trapezoidal mechanization keeps of the last sample
PREV_FORCE = 0      # bias-corrected specific force f − b_a [m/s²], body frame
PREV_RATE = 1       # bias-corrected angular rate ω − b_g [rad/s], body frame
PREV_NAV_FORCE = 2  # the specific force in the navigation frame, Ĉ·(f − b_a) [m/s²]

# FilterParams.bias_model
BIAS_MODEL_CODES = {"none": 0, "random_walk": 1, "gauss_markov": 2}
GAUSS_MARKOV = BIAS_MODEL_CODES["gauss_markov"]


class NavState(NamedTuple):
    """The filter's state; the kernels change its arrays in place."""

    p: np.ndarray     # (3,) position p̂ [m], navigation frame
    v: np.ndarray     # (3,) velocity v̂ [m/s], navigation frame
    C: np.ndarray     # (3, 3) attitude Ĉ = C_b^n
    b: np.ndarray     # (6,) biases b̂ [b_a m/s², b_g rad/s] (ACC, GYRO), body frame
    P: np.ndarray     # (n, n) error-state covariance, rows as δx
    prev: np.ndarray  # (3, 3) the last sample's PREV_FORCE, PREV_RATE, PREV_NAV_FORCE
    dx: np.ndarray    # (n,) error-state estimate δx̂: 0 between the closed-loop filter's
    #                   steps (each update feeds it back); the smoother's open-loop pass
    #                   carries it to the segment's end
    nis: np.ndarray   # (2,) NIS_SUM, NIS_COUNT: the touchdown innovations so far
    stance: np.ndarray  # (1,) bool: the last sample was a stance sample (the next is no
    #                     touchdown)
    Pb: np.ndarray    # (n, n) the biases' share of P: what the initial bias variance and
    #                   the bias driving noise alone put into it through the filter's own
    #                   F and gains (zeros with 9 states; compiled_filter.bias_share)


class FilterParams(NamedTuple):
    """The filter's settings (:class:`pdr_ins_ekf.zupt_ekf.FilterConfig`, whose
    :func:`pdr_ins_ekf.zupt_ekf.kernel_params` makes this)."""

    acc_noise: float         # accelerometer white noise density [m/s²/√Hz]
    gyro_noise: float        # gyroscope white noise density [rad/s/√Hz]
    acc_bias_noise: float    # accelerometer bias driving noise [m/s²/√s]
    gyro_bias_noise: float   # gyroscope bias driving noise [rad/s/√s]
    bias_tau_s: float        # Gauss–Markov correlation time [s]
    bias_model: int          # BIAS_MODEL_CODES
    gravity_mps2: float      # gravity [m/s²], along the navigation frame's −z
    zupt_sigma_mps: float    # ZUPT noise σ per axis [m/s]
    zaru: bool               # ZARU in stance (15 states)
    zaru_sigma_radps: float  # ZARU noise σ per axis [rad/s]
    zaru_gate_nis: float     # ZARU only where νᵀS⁻¹ν is below this (χ², 3 dof)
    innovation_scale: bool   # publish P times the mean touchdown NIS / 3 (covariance_scale)


class Samples(NamedTuple):
    """The inputs of a record or a block of it, N samples (with a leading runs axis in
    :func:`pdr_ins_ekf.studies.ekf_montecarlo.ekf_batch`)."""

    dt: np.ndarray      # (N,) interval to the previous sample [s], 0 for a record's first
    accel: np.ndarray   # (N, 3) specific force f [m/s²], body frame
    gyro: np.ndarray    # (N, 3) angular rate ω [rad/s], body frame
    stance: np.ndarray  # (N,) bool: the foot at rest (ZUPT, and ZARU if enabled)


def intervals(t: np.ndarray) -> np.ndarray:
    """Samples.dt from stamps t (N,) [s]: t[k] − t[k − 1], 0 for the first."""
    dt = np.zeros(len(t))
    dt[1:] = np.diff(t)
    return dt
