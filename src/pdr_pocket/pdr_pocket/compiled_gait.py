"""The pocket navigator's per-sample gait loops, compiled with numba.

Two causal loops carry their state between calls, so one sample at a time (the live node)
and a whole record give the same result:

- :func:`mounting_loop`: the thigh's frame in the sensor's, for a phone in any
  orientation in the pocket, and from it the thigh pitch θ (Muñoz Díaz 2016, Fig. 4.1:
  the opening angle of the leg, positive with the knee ahead) and the thigh's heading.

  * The long axis u (up along the thigh) is the specific force's direction while standing
    still (Section 4.1.3: standing, the legs are closed and θ = 0). Until a first rest of
    ``rest_min_s`` it is the first sample's specific force. A later rest within
    ``standing_max_angle`` of u refines it (standing); a rest farther from u but in the
    leg's swing plane is sitting and leaves it alone; a rest out of the swing plane means
    the phone was moved: u is taken from it and the flexion axis is learned again.
  * The flexion axis f is the axis the leg swings about while walking. The vertical seen
    in the sensor frame, g = C_b^nᵀ·e_z from the attitude filter (no linear acceleration
    in it), turns about f as the thigh pitches and is left alone by the hip's yaw sway, so
    f = u × d with d the major axis of g's exponentially weighted covariance (time
    constant ``flexion_tau_s``, moving samples) within the plane orthogonal to u. The
    covariance, not the second moment: a tilt error of the filter shifts g's mean
    sideways, and with the mean in it 1° of roll error turned the axis by about 2°. (The principal
    axis of ∑ωωᵀ, tried first, leans about 3° forward: the sway seen by a pitched thigh
    puts sin θ·ψ̇ on the forward axis, correlated with the pitch rate, and the pitch
    amplitudes came out 0.2–0.5° short.) It is known after ``flexion_min_s`` of motion.
    Its sign makes the mean pitch while walking positive (the thesis' asymmetry
    θ_max ≫ |θ_min|).
  * θ = atan2(−ℓ·h, ℓ_z) with ℓ = C·u the long axis in ENU (hip above knee) and h the
    unit horizontal direction of C·(f × u), the thigh's forward axis: the knee ahead tilts
    ℓ backwards. The heading is atan2(h_y, h_x).

- :func:`peak_loop`: a hysteresis extremum detector. A maximum is confirmed once the
  signal has fallen ``drop`` below it, and the next one is sought once the signal has
  risen ``rise`` above the minimum since (both the larger of a floor and a fraction of the
  last accepted amplitude, so the heel-strike's second peak and the double minimum on
  stairs, Figs. 4.1–4.3, never count). A maximum is a step when its amplitude over the
  preceding minimum is at least ``min_amplitude``, it was reached within ``max_rise_s`` of
  that minimum and left within ``max_hold_s`` (sitting down and getting up are not steps),
  and it comes at least ``min_period_s`` after the last step's maximum (beyond the thesis:
  a gait cycle shorter than that is running; on the real ``s_both_thigh_1`` stairs walk
  the turn at the top otherwise gives two extra steps).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

# mounting scalars (MountingState.scalars)
LAST_T, REST_S, REST_N, MOVING_S, UP_PROVISIONAL, FLEX_KNOWN, MEAN_PITCH, CHANGES, \
    STARTED = range(9)
N_MOUNTING_SCALARS = 9
# peak detector scalars (PeakState.scalars)
SEEKING_MAX, CUR_MAX, T_MAX, CUR_MIN, T_MIN, LAST_AMPLITUDE, LAST_STEP_T = range(7)
N_PEAK_SCALARS = 7
# columns of the peak events
EV_T_MAX, EV_MAX, EV_MIN, EV_T_MIN, EV_T_CONFIRM = range(5)
N_EVENT_COLUMNS = 5


class MountingParams(NamedTuple):
    """SI units; ``fixed`` True: use ``up`` and ``flexion`` of the state as given."""

    fixed: bool
    gravity: float              # [m/s²]
    rest_rate: float            # ‖ω‖ below this is still [rad/s]
    rest_acc: float             # |‖α‖ − g| below this is still [m/s²]
    rest_min_s: float
    standing_max_angle: float   # [rad]
    moved_min_angle: float      # a rest this far out of the swing plane: phone moved [rad]
    moving_rate: float          # ‖ω‖ above this is walking motion [rad/s]
    flexion_tau_s: float
    flexion_min_s: float


class MountingState(NamedTuple):
    scalars: np.ndarray         # (N_MOUNTING_SCALARS,)
    rest_sum: np.ndarray        # (3,) specific force summed over the current rest
    up: np.ndarray              # (3,) u, sensor frame
    flex_raw: np.ndarray        # (3,) power-iteration vector
    flex_sign: np.ndarray       # (1,) ±1
    moment: np.ndarray          # (3, 3) weighted ∑g gᵀ of the vertical while walking
    mean: np.ndarray            # (3,) weighted ∑g


class PeakParams(NamedTuple):
    drop_min: float             # confirmation drop: max(drop_min, drop_fraction·amplitude)
    drop_fraction: float
    rise_min: float             # re-arming rise: max(rise_min, rise_fraction·amplitude)
    rise_fraction: float
    min_amplitude: float
    max_rise_s: float
    max_hold_s: float
    min_period_s: float         # from the previous step's maximum


def new_mounting_state(up=None, flexion=None) -> MountingState:
    """A fresh state; with ``up`` and ``flexion`` (a configured mounting) they are used."""
    state = MountingState(np.zeros(N_MOUNTING_SCALARS), np.zeros(3), np.zeros(3),
                          np.zeros(3), np.ones(1), np.zeros((3, 3)), np.zeros(3))
    if up is not None:
        state.up[:] = up
        state.flex_raw[:] = flexion
        state.scalars[FLEX_KNOWN] = 1.0
        state.scalars[STARTED] = 1.0
    return state


class PeakState(NamedTuple):
    scalars: np.ndarray         # (N_PEAK_SCALARS,)


def new_peak_state() -> PeakState:
    """Seeking a minimum first: a step needs one before its maximum."""
    scalars = np.zeros(N_PEAK_SCALARS)
    scalars[CUR_MIN] = np.inf
    scalars[CUR_MAX] = -np.inf
    scalars[LAST_STEP_T] = -np.inf
    return PeakState(scalars)


@njit(cache=True)
def _unit(v):
    n = np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return v / n if n > 0 else v


@njit(cache=True)
def _thigh_axes(up, flex_raw, sign):
    """u and f (f orthogonal to u, unit, signed)."""
    f = flex_raw - (flex_raw @ up) * up
    return up, _unit(f) * sign


@njit(cache=True)
def thigh_angles(c, up, flex):
    """θ and the thigh heading [rad] of attitude C_b^n (3, 3) for axes u, f."""
    fwd = np.cross(flex, up)
    long_n = c @ up
    fwd_n = c @ fwd
    h = np.sqrt(fwd_n[0] ** 2 + fwd_n[1] ** 2)
    if h < 1e-9:
        return np.nan, np.nan
    hx, hy = fwd_n[0] / h, fwd_n[1] / h
    return np.arctan2(-(long_n[0] * hx + long_n[1] * hy), long_n[2]), np.arctan2(hy, hx)


@njit(cache=True)
def mounting_loop(state, params, t, rate, accel, attitude, out_pitch, out_heading,
                  out_known, out_up, out_flex):
    """The thigh frame per sample (module docstring); θ and heading NaN until known.
    ``rate``: the turn rate's norm [rad/s] (N,), or without a gyroscope the accelerometer's
    motion measure scaled to it."""
    s = state.scalars
    for k in range(len(t)):
        w, a = rate[k], accel[k]
        dt = t[k] - s[LAST_T] if s[STARTED] > 0 else 0.0
        s[LAST_T] = t[k]
        if not params.fixed:
            if s[STARTED] == 0.0:
                state.up[:] = _unit(a)
                s[UP_PROVISIONAL] = 1.0
                s[STARTED] = 1.0
            _rest(state, params, w, a, dt)
            _motion(state, params, w, dt, attitude[k])
        known = s[FLEX_KNOWN] > 0
        up, flex = _thigh_axes(state.up, state.flex_raw, state.flex_sign[0])
        out_up[k] = up
        out_flex[k] = flex
        out_known[k] = known
        if known:
            out_pitch[k], out_heading[k] = thigh_angles(attitude[k], up, flex)
        else:
            out_pitch[k], out_heading[k] = np.nan, np.nan


@njit(cache=True)
def _rest(state, params, wn, a, dt):
    """Standing refines u, a rest out of the swing plane resets the mounting."""
    s = state.scalars
    an = np.sqrt(a @ a)
    if wn >= params.rest_rate or abs(an - params.gravity) >= params.rest_acc:
        s[REST_S] = 0.0
        s[REST_N] = 0.0
        state.rest_sum[:] = 0.0
        return
    s[REST_S] += dt
    s[REST_N] += 1.0
    state.rest_sum[:] += a
    if s[REST_S] < params.rest_min_s:
        return
    g = _unit(state.rest_sum.copy())
    if s[UP_PROVISIONAL] > 0:
        state.up[:] = g
        s[UP_PROVISIONAL] = 0.0
        return
    if g @ state.up >= np.cos(params.standing_max_angle):
        state.up[:] = g
        return
    if s[FLEX_KNOWN] > 0:
        _, flex = _thigh_axes(state.up, state.flex_raw, 1.0)
        if abs(g @ flex) > np.sin(params.moved_min_angle):
            state.up[:] = g
            s[FLEX_KNOWN] = 0.0
            s[MOVING_S] = 0.0
            s[MEAN_PITCH] = 0.0
            s[CHANGES] += 1.0
            state.moment[:, :] = 0.0
            state.mean[:] = 0.0
            state.flex_raw[:] = 0.0


@njit(cache=True)
def _motion(state, params, wn, dt, c):
    """Learn f from the scatter of the vertical; fix its sign once it is known."""
    s = state.scalars
    if wn <= params.moving_rate or dt <= 0:
        return
    lam = np.exp(-dt / params.flexion_tau_s)
    g = c[2, :]                                  # the vertical in the sensor frame
    for i in range(3):
        state.mean[i] = lam * state.mean[i] + (1.0 - lam) * g[i]
        for j in range(3):
            state.moment[i, j] = lam * state.moment[i, j] + (1.0 - lam) * g[i] * g[j]
    spread = state.moment - np.outer(state.mean, state.mean)
    v = _least_swung_axis(spread, state.up)
    if v @ state.flex_raw < 0:
        v = -v
    state.flex_raw[:] = v
    if s[FLEX_KNOWN] > 0:
        return
    s[MOVING_S] += dt
    up, flex = _thigh_axes(state.up, state.flex_raw, 1.0)
    pitch, _ = thigh_angles(c, up, flex)
    if np.isfinite(pitch):
        s[MEAN_PITCH] += pitch * dt
    if s[MOVING_S] >= params.flexion_min_s:
        state.flex_sign[0] = 1.0 if s[MEAN_PITCH] >= 0 else -1.0
        s[FLEX_KNOWN] = 1.0


@njit(cache=True)
def _least_swung_axis(spread, up):
    """The axis orthogonal to u about which the vertical swings (spread: its weighted
    covariance in the sensor frame): u × d, d the major axis of the spread within the
    plane orthogonal to u (closed-form 2 × 2 eigenvector)."""
    ref = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = _unit(np.cross(up, ref))
    e2 = np.cross(up, e1)
    s11, s22, s12 = e1 @ spread @ e1, e2 @ spread @ e2, e1 @ spread @ e2
    phi = 0.5 * np.arctan2(2.0 * s12, s11 - s22)
    return _unit(np.cross(up, np.cos(phi) * e1 + np.sin(phi) * e2))


@njit(cache=True)
def gravity_loop(state, tau_s, motion_tau_s, t, accel, out_gravity, out_motion):
    """Without a gyroscope: the gravity direction as the specific force through two
    first-order low-passes in cascade (time constant ``tau_s`` each, any sample rate), and
    a motion measure, ‖α − gravity‖ through one low-pass of ``motion_tau_s`` [m/s²].
    ``state``: (9,) last t, started flag, the two filter stages (3 each), the motion."""
    for k in range(len(t)):
        a = accel[k]
        if state[1] == 0.0:
            state[2:5] = a
            state[5:8] = a
            state[1] = 1.0
            dt = 0.0
        else:
            dt = t[k] - state[0]
        state[0] = t[k]
        alpha = dt / (tau_s + dt)
        state[2:5] += alpha * (a - state[2:5])
        state[5:8] += alpha * (state[2:5] - state[5:8])
        out_gravity[k] = state[5:8]
        d = a - state[5:8]
        beta = dt / (motion_tau_s + dt)
        state[8] += beta * (np.sqrt(d @ d) - state[8])
        out_motion[k] = state[8]


@njit(cache=True)
def peak_loop(state, params, t, signal, events):
    """Confirmed maxima of ``signal`` (module docstring) into ``events`` (rows of
    EV_* columns); returns how many. NaN samples are skipped."""
    s = state.scalars
    count = 0
    for k in range(len(t)):
        x = signal[k]
        if not np.isfinite(x):
            continue
        amplitude = s[LAST_AMPLITUDE]
        if s[SEEKING_MAX] > 0:
            if x > s[CUR_MAX]:
                s[CUR_MAX] = x
                s[T_MAX] = t[k]
            if s[CUR_MAX] - x >= max(params.drop_min, params.drop_fraction * amplitude):
                rise = s[CUR_MAX] - s[CUR_MIN]
                if (rise >= params.min_amplitude and s[T_MAX] - s[T_MIN] <= params.max_rise_s
                        and t[k] - s[T_MAX] <= params.max_hold_s
                        and s[T_MAX] - s[LAST_STEP_T] >= params.min_period_s):
                    events[count, EV_T_MAX] = s[T_MAX]
                    events[count, EV_MAX] = s[CUR_MAX]
                    events[count, EV_MIN] = s[CUR_MIN]
                    events[count, EV_T_MIN] = s[T_MIN]
                    events[count, EV_T_CONFIRM] = t[k]
                    count += 1
                    s[LAST_AMPLITUDE] = rise
                    s[LAST_STEP_T] = s[T_MAX]
                s[SEEKING_MAX] = 0.0
                s[CUR_MIN] = x
                s[T_MIN] = t[k]
        else:
            if x < s[CUR_MIN]:
                s[CUR_MIN] = x
                s[T_MIN] = t[k]
            if x - s[CUR_MIN] >= max(params.rise_min, params.rise_fraction * amplitude):
                s[SEEKING_MAX] = 1.0
                s[CUR_MAX] = x
                s[T_MAX] = t[k]
    return count
