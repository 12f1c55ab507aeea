"""The phone's attitude filter's kernel data (pdr_pocket.compiled_attitude): the rows of
its error state (:data:`ATT_EAST` ... :data:`ACCEL_BIAS`), its updates' and detectors'
columns and names, what the configuration sets (:class:`AttitudeParams`), what every
sample changes (:class:`AttitudeState`, its scalars in one record, :data:`SCALARS`;
:func:`initial_state`) and the scratch arrays (:class:`Workspace`).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache, lowpass
from pdr_pocket import compiled_gait_window
from pdr_pocket.compiled_gait_window import GaitWindow, WindowParams, new_gait_window

kernel_cache.forget_if_changed(__file__, compiled_gait_window.__file__, lowpass.__file__)

TILT_STAGES = 2                         # first-order stages of the tilt's low-pass
# the error state's rows
N_STATE = 14
ATT_EAST, ATT_NORTH, ATT_UP = 0, 1, 2   # δθ, a small rotation in the navigation frame
BIAS = 3                                # δb_x, δb_y, δb_z [rad/s], body
BIAS_Z = BIAS + 2
OFFSET = 6                              # δo_x, δo_y, δo_z [T], body
FIELD_HORIZONTAL, FIELD_DOWN = 9, 10    # δB_h, δB_v [T]
ACCEL_BIAS = 11                         # δb_a,x, δb_a,y, δb_a,z [m/s²], body
N_OUTPUT = 6                            # the rows written out per sample: δθ and δb
# updates (columns of the "ran" output) and external corrections
TILT, CYCLE, REST, FIELD = range(4)
N_UPDATES = 4
UPDATE_NAMES = ("tilt", "cycle", "rest", "field")
YAW_CORRECTION, BIAS_Z_CORRECTION = 7, 8    # as in pdr_pocket.compiled_orientation
# detectors (columns of the "detected" output)
AT_REST, FIELD_UNDISTURBED, FIELD_DISTURBED, FIELD_IMPLAUSIBLE, SATURATED = range(5)
N_DETECTORS = 5
DETECTOR_NAMES = ("rest", "field_undisturbed", "field_disturbed", "field_implausible",
                  "saturated")
# a magnetometer reading, as mag_step judged it: the column of "detected" it sets
NO_READING = -1
# how :func:`start_field` takes the field
HEADING_FROM_FIELD, AZIMUTH_FROM_FIELD, MAGNITUDES_ONLY = range(3)

# AttitudeState.scalars: one record, the scalars that change per sample
SCALARS = np.dtype([
    ("t_gyro", np.float64),         # the last gyro sample's stamp [s]
    ("t_accel", np.float64),        # ... the accelerometer's
    ("t_mag", np.float64),          # ... the magnetometer's (its last new reading)
    ("gyro_started", np.bool_),     # a gyro sample has been seen
    ("accel_started", np.bool_),
    ("field_started", np.bool_),    # B_h, B_v taken from a reading
    ("at_rest", np.bool_),          # the rest detector holds
    ("rest_s", np.float64),         # how long both signals have been still [s]
    ("gyro_deviation2", np.float64),    # ‖ω − ω̄‖² of the last gyro sample [rad²/s²]
    ("field_azimuth", np.float64),  # γ [rad], ENU, counter-clockwise from east
    ("refused_s", np.float64),      # how long the field has failed its gate [s]
    ("gaps", np.int64),             # gyro gaps longer than max_gap_s
    ("held_readings", np.int64),    # magnetometer readings equal to the one before
    ("field_resets", np.int64),     # field magnitudes taken again after refusals
    ("field_norm", np.float64),     # ‖μ − o‖ low-passed over field_norm_tau_s [T]
    ("marker", np.bool_),           # the last gyro sample was a swing marker
    ("t_cycle", np.float64),        # when the last window of whole gait cycles closed [s]
    ("window_saturated", np.bool_), # a sample of the window saturated
])


class AttitudeParams(NamedTuple):
    """What the configuration sets (pdr_pocket.config), SI units, built once."""

    gyro_noise_var: float           # σ_ν² [rad²/s²] per sample at the nominal rate
    gyro_noise_density2: float      # σ_ν² per second [rad²/s]: Q = this·δt
    gyro_scale_var: float           # σ_s² of the rate's scale and cross-axis errors
    bias_tau_s: float               # τ of the AR(1) bias [s] (inf: random constant)
    bias_sigma: float               # σ_bias [rad/s]
    bias_mean_decays: bool          # Eq. (3.8) as written: the estimate decays to 0
    earth_rate_n: np.ndarray        # ω_ie^n (3,) [rad/s], zeros when off
    gravity: float                  # [m/s²]
    max_gap_s: float                # a longer step between gyro samples is a gap
    use_tilt: bool
    use_cycles: bool                # the tilt from windows of whole gait cycles
    window: WindowParams            # ... (pdr_pocket.compiled_gait_window)
    cycle_velocity_var: float       # [m²/s²] the velocity change over whole gait cycles
    walking_speed: float            # v [m/s]: a turn by Δψ changes the velocity by v·Δψ
    cycle_turn_max: float           # [rad] a window that turned further is no reference
    cycle_gate_nis: float           # a window beyond this NIS (2 dof) changed speed: refused
    cycle_timeout_s: float          # a cycle closed this recently: the low-pass rests
    tilt_tau_s: float               # τ of each of the two low-pass stages [s]
    tilt_var: float                 # σ_tilt² [rad²] of the low-passed direction
    use_rest: bool
    rest_tau_s: float               # the rest detector's low-passes [s]
    rest_gyro_threshold2: float     # ‖ω − ω̄‖² below this [rad²/s²] ...
    rest_accel_threshold2: float    # ... and ‖α − ᾱ‖² below this [m²/s⁴] ...
    rest_min_s: float               # ... for this long: at rest
    rest_sway_var: float            # σ_sway² [rad²/s²] of a hand or thigh at rest
    rest_gate_nis: float            # the rest update is refused beyond this NIS (3 dof)
    rest_tilt_var: float            # [rad²] of the still specific force's direction, per
                                    # rest_tau_s (its correlation time)
    use_field: bool
    heading_from_field: bool        # the heading is taken from the field's first reading
    field_azimuth: float            # γ [rad] for it: 90° − declination
    field_var: float                # σ_field² [T²] per axis: the field's local spread
    field_tau_s: float              # the spread's correlation time [s]
    field_gate_nis: float           # a reading beyond this NIS (3 dof) is disturbed
    field_reset_s: float            # refused this long: the magnitudes are taken again
    field_norm_min: float           # [T] a magnetometer whose low-passed ‖μ − o‖ is below
    field_norm_max: float           # ... or above these is no Earth field: left out
    field_norm_tau_s: float         # [s] of that low-pass
    field_start_var: float          # [T²] of B_h, B_v beyond what the offset explains
    field_change_var_per_s: float   # [T²/s] the magnitudes' random walk (moving about)
    offset_change_var_per_s: float  # [T²/s] the offset's random walk
    offset_reset_var: float         # [T²] added to the offset's variance when the field is
                                    # taken anew (a field refused that long may be the
                                    # phone's own: a magnet, an uncalibrated magnetometer)
    accel_bias_change_var_per_s: float  # [m²/s⁵] the accelerometer bias's random walk
    heading_start_var: float        # [rad²] of a heading taken from the field, beyond
                                    # what the offset explains


class AttitudeState(NamedTuple):
    """The filter's memory, changed in place by the entry points (a live node feeds it a
    sample at a time and gets the offline result)."""

    attitude: np.ndarray            # (3, 3) C_b^n
    bias: np.ndarray                # (3,) b [rad/s]
    offset: np.ndarray              # (3,) o [T]
    accel_bias: np.ndarray          # (3,) b_a [m/s²]
    field: np.ndarray               # (2,) B_h, B_v [T]
    covariance: np.ndarray          # (N_STATE, N_STATE) P
    tilt_lowpass: np.ndarray        # (TILT_STAGES, 3) the stages' C·α [m/s²], navigation frame
    tilt_memory: np.ndarray         # (TILT_STAGES, 3, 3) D_k = ∫C dt less its low-pass [s]
    tilt_attitude: np.ndarray       # (TILT_STAGES, 3, 3) the stages' low-passed C
    rest_gyro: np.ndarray           # (3,) ω̄, the rest detector's low-passed rate
    rest_spread: np.ndarray         # (3,) the low-passed (ω − ω̄)² per axis [rad²/s²]
    rate_peak: np.ndarray           # (3,) the leaky peak of |ω| per axis [rad/s]
    rest_accel: np.ndarray          # (3,) ᾱ, its low-passed specific force
    previous_gyro: np.ndarray       # (3,) ω of the last gyro sample
    previous_mag: np.ndarray        # (3,) μ of the last magnetometer reading
    gait: GaitWindow                # the window of whole gait cycles
    scalars: np.ndarray             # (1,) record of SCALARS


class Workspace(NamedTuple):
    """Scratch reused by every update (no allocation per sample)."""

    h: np.ndarray                   # (3, N_STATE) the measurement matrix
    ph: np.ndarray                  # (N_STATE, 3) P·Hᵀ
    s: np.ndarray                   # (3, 3) H·P·Hᵀ (+ R)
    s_inv: np.ndarray               # (3, 3)
    gain: np.ndarray                # (N_STATE, 3) K
    ks: np.ndarray                  # (N_STATE, 3) K·S
    dx: np.ndarray                  # (N_STATE,) the correction
    frozen: np.ndarray              # (N_STATE,) bool: rows the update must not reach
    innovation: np.ndarray          # (3,)
    m1: np.ndarray                  # (3, 3) scratch
    m2: np.ndarray                  # (3, 3) scratch
    g: np.ndarray                   # (3, 3) the prediction's −C·δt
    rows: np.ndarray                # (3, N_STATE) the prediction's δθ rows of F·P
    q_att: np.ndarray               # (3, 3) Q's attitude part
    q: np.ndarray                   # (3,) Q's per-axis terms
    force: np.ndarray               # (3,) f = α − b_a


@njit(cache=True)
def workspace():
    return Workspace(np.zeros((3, N_STATE)), np.zeros((N_STATE, 3)), np.zeros((3, 3)),
                     np.zeros((3, 3)), np.zeros((N_STATE, 3)), np.zeros((N_STATE, 3)),
                     np.zeros(N_STATE), np.zeros(N_STATE, dtype=np.bool_), np.zeros(3),
                     np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3)),
                     np.zeros((3, N_STATE)), np.zeros((3, 3)), np.zeros(3), np.zeros(3))


def initial_state(attitude: np.ndarray, covariance: np.ndarray) -> AttitudeState:
    """A state at C_b^n (3, 3) with the covariance P (N_STATE, N_STATE), zero bias and
    offset, the field not yet read."""
    return AttitudeState(
        attitude=np.ascontiguousarray(attitude, dtype=float), bias=np.zeros(3),
        offset=np.zeros(3), accel_bias=np.zeros(3), field=np.zeros(2),
        covariance=np.ascontiguousarray(covariance, dtype=float),
        tilt_lowpass=np.zeros((TILT_STAGES, 3)), tilt_memory=np.zeros((TILT_STAGES, 3, 3)),
        tilt_attitude=np.tile(np.eye(3), (TILT_STAGES, 1, 1)),
        rest_gyro=np.zeros(3), rest_spread=np.zeros(3), rate_peak=np.zeros(3),
        rest_accel=np.zeros(3),
        previous_gyro=np.zeros(3), previous_mag=np.full(3, np.nan),
        gait=new_gait_window(), scalars=_first_scalars())


def _first_scalars() -> np.ndarray:
    scalars = np.zeros(1, dtype=SCALARS)
    scalars[0]["t_cycle"] = -np.inf
    return scalars
