"""The thesis' orientation filter's kernel data (pdr_pocket.compiled_orientation): what
the configuration sets (:class:`FilterParams`), what every sample changes
(:class:`FilterState`, :func:`initial_state`; its scalars one record of
:data:`FILTER_SCALARS`), a record in and its estimates out (:class:`FilterInputs`,
:class:`FilterOutputs`, shared with pdr_pocket.compiled_attitude), one sample
(:class:`Sample`), the detectors at it (:class:`Detected`) and the scratch arrays
(:class:`Workspace`). The rows of P are named by :data:`ATT_EAST` ... :data:`BIAS_Z`, the
detectors' columns by :data:`ZERO_ACC` ... :data:`SATURATED`.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache, lowpass
from pdr_pocket import compiled_gait_window
from pdr_pocket.compiled_gait_window import GaitWindow, WindowParams, new_gait_window

kernel_cache.forget_if_changed(__file__, compiled_gait_window.__file__, lowpass.__file__)

# the state's rows: the attitude error δθ (a small rotation in the navigation frame, ENU)
# and the gyro bias error δb (body frame)
N_STATE = 6
ATT, BIAS = 0, 3                        # first rows of the blocks δθ and δb
ATT_EAST, ATT_NORTH, ATT_UP = ATT, ATT + 1, ATT + 2   # δθ about east and north (the tilt)
                                                      # and about up (the yaw)
BIAS_Z = BIAS + 2                       # δb_z
ATT_ROWS, BIAS_ROWS = slice(ATT, ATT + 3), slice(BIAS, BIAS + 3)   # for NumPy code
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
    scalars: np.ndarray             # (1,) record of FILTER_SCALARS (a NumPy record array:
                                    # fields by name in plain Python too)
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


# FilterState.scalars: one record, the scalars that change per sample
FILTER_SCALARS = np.dtype([
    ("t_prev", np.float64),         # the last sample's stamp [s]
    ("started", np.bool_),          # a sample has been seen
    ("ring_count", np.int64),       # samples in the trailing windows' ring
    ("ring_head", np.int64),        # where the next sample goes in it
    ("mag_was_steady", np.bool_),   # the field was steady (and anchored) at the last sample
    ("gaps", np.int64),             # gaps longer than max_gap_s seen
])


def initial_state(attitude: np.ndarray, covariance: np.ndarray) -> FilterState:
    """A state at the attitude C_b^n (3, 3) with the covariance (N_STATE, N_STATE), zero
    biases and empty windows."""
    return FilterState(
        attitude=np.ascontiguousarray(attitude, dtype=float), bias=np.zeros(3),
        covariance=np.ascontiguousarray(covariance, dtype=float),
        scalars=np.zeros(1, dtype=FILTER_SCALARS).view(np.recarray), gait=new_gait_window(),
        previous_gyro=np.zeros(3), previous_accel=np.zeros(3), previous_mag=np.full(3, np.nan),
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
