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
  * The phone turned in the pocket while walking (beyond the thesis): a turn rate outside
    span{f, vertical}, which the thigh cannot make, or a swing axis that stays away from
    f; the new axes come from the swing after the turn (:func:`_foreign_turn`,
    :func:`_check_turned`, :func:`_remount`).
  * θ = atan2(−ℓ·h, ℓ_z) with ℓ = C·u the long axis in ENU (hip above knee) and h the
    unit horizontal direction of C·(f × u), the thigh's forward axis: the knee ahead tilts
    ℓ backwards. The heading is atan2(h_y, h_x).

- :func:`peak_loop`: a hysteresis extremum detector. A maximum is confirmed once the
  signal has fallen ``drop`` below it, and the next one is sought once the signal has
  risen ``rise`` above the minimum since (both the larger of a floor and a fraction of the
  last accepted amplitude, so the heel-strike's second peak and the double minimum on
  stairs, Figs. 4.1–4.3, never count). A maximum is a step when its amplitude over the
  preceding minimum is at least ``min_amplitude`` (at most ``max_amplitude``), it was
  reached within ``max_rise_s`` of that minimum and left within ``max_hold_s`` (sitting
  down and getting up are not steps),
  and it comes at least ``min_period_s`` after the last step's maximum (beyond the thesis:
  a gait cycle shorter than that is running; on the real ``s_both_thigh_1`` stairs walk
  the turn at the top otherwise gives two extra steps). After ``forget_s`` without a step
  the last amplitude is forgotten, so one huge swing (the phone turned in the pocket)
  cannot raise the thresholds beyond every later step.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

# mounting scalars (MountingState.scalars)
LAST_T, REST_S, REST_N, MOVING_S, UP_PROVISIONAL, FLEX_KNOWN, MEAN_PITCH, CHANGES, \
    STARTED, RECENT_S, LAST_CHECK_T, TURNED_S, RING_POS, RING_N, FOREIGN, TURN_SEEN, \
    TURN_T, FLIP_S, RATE2, RATE3, SEATED_S = range(21)
N_MOUNTING_SCALARS = 21
# the swing of the last moved_tau_s is a plane (the remount check) when its middle
# eigenvalue is at least SWING_MIN (a pitch swing of about ±4°) and its smallest at most
# PLANAR_RATIO of the middle one
SWING_MIN = 0.003
PLANAR_RATIO = 0.25
CHECK_PERIOD_S = 0.1
FOREIGN_TAU_S = 1.0             # leak of the turn integrated outside the thigh's axes
TURN_HOLD_S = 2.0               # a phone is turned in the pocket within this
FLIP_MIN_S = 5.0                # walking with a negative mean pitch this long: f flipped
SEATED_MIN_S = 2.0              # walking this far above standing this long: u was seated
SKEW_TAU_S = 4.0                # the pitch rate's moments, over about three gait cycles
SKEW_FLIP = 0.3                 # a pitch-rate skewness below −SKEW_FLIP: f is reversed
ANCHOR_RING = 80                # the checks of the last 8 s of walking (see _anchor)
ANCHOR_LEAD_S = 1.0             # the anchor taken is this long before the turn was seen
ANCHOR_PHI, ANCHOR_HEADING, ANCHOR_T = range(3)
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
    turned_min_angle: float     # walking about an axis this far from f: moved [rad]
    turned_min_s: float         # ... for this long
    turned_tau_s: float         # time constant of the recent swing
    turned_angle: float         # turned outside span{f, vertical} this far, at once [rad]
    turned_pitch_angle: float   # the mean walking pitch moved this far: turned about f [rad]
    walking_pitch: float        # the mean pitch of level walking (u placed from it) [rad]
    skew_check: bool            # f's sign from the pitch rate's skew (off without a gyro)


class MountingState(NamedTuple):
    scalars: np.ndarray         # (N_MOUNTING_SCALARS,)
    rest_sum: np.ndarray        # (3,) specific force summed over the current rest
    up: np.ndarray              # (3,) u, sensor frame
    flex_raw: np.ndarray        # (3,) power-iteration vector
    flex_sign: np.ndarray       # (1,) ±1
    moment: np.ndarray          # (3, 3) weighted ∑g gᵀ of the vertical while walking
    mean: np.ndarray            # (3,) weighted ∑g
    recent: np.ndarray          # (3, 3) the same over turned_tau_s
    recent_mean: np.ndarray     # (3,)
    anchors: np.ndarray         # (ANCHOR_RING, 3) φ, thigh heading and t of the last checks
    last_attitude: np.ndarray   # (3, 3) C_b^n of the previous sample


class PeakParams(NamedTuple):
    drop_min: float             # confirmation drop: max(drop_min, drop_fraction·amplitude)
    drop_fraction: float
    rise_min: float             # re-arming rise: max(rise_min, rise_fraction·amplitude)
    rise_fraction: float
    min_amplitude: float
    max_amplitude: float        # beyond what a thigh can swing
    max_rise_s: float
    max_hold_s: float
    min_period_s: float         # from the previous step's maximum
    forget_s: float             # no step this long: the last amplitude is forgotten


def new_mounting_state(up=None, flexion=None) -> MountingState:
    """A fresh state; with ``up`` and ``flexion`` (a configured mounting) they are used."""
    state = MountingState(np.zeros(N_MOUNTING_SCALARS), np.zeros(3), np.zeros(3),
                          np.zeros(3), np.ones(1), np.zeros((3, 3)), np.zeros(3),
                          np.zeros((3, 3)), np.zeros(3), np.zeros((ANCHOR_RING, 3)),
                          np.eye(3))
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
                  out_known, out_up, out_flex, out_changes):
    """The thigh frame per sample (module docstring); θ and heading NaN until known;
    ``out_changes``: the mounting changes found so far.
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
            _foreign_turn(state, params, w, dt, attitude[k],
                          _sample_turn(state.last_attitude, attitude[k]))
            state.last_attitude[:, :] = attitude[k]
            _motion(state, params, w, dt, attitude[k])
        known = s[FLEX_KNOWN] > 0
        up, flex = _thigh_axes(state.up, state.flex_raw, state.flex_sign[0])
        out_up[k] = up
        out_flex[k] = flex
        out_known[k] = known
        out_changes[k] = s[CHANGES]
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
    lam = np.exp(-dt / params.turned_tau_s)
    for i in range(3):
        state.recent_mean[i] = lam * state.recent_mean[i] + (1.0 - lam) * g[i]
        for j in range(3):
            state.recent[i, j] = lam * state.recent[i, j] + (1.0 - lam) * g[i] * g[j]
    s[RECENT_S] += dt
    spread = state.moment - np.outer(state.mean, state.mean)
    v = _least_swung_axis(spread, state.up)
    if v @ state.flex_raw < 0:
        v = -v
    state.flex_raw[:] = v
    if s[FLEX_KNOWN] > 0:
        _check_turned(state, params, c)
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
def _check_turned(state, params, c):
    """A phone turned in the pocket while walking. Right after a turn seen by
    :func:`_foreign_turn`, the axes are derived again (:func:`_remount`). Otherwise a
    slower turn: for ``turned_min_s`` of walking, the axis the vertical swung about over
    the last ``turned_tau_s`` (the least axis of its second moment, g tracing a great circle
    about f; the hip's yaw sway leaves g alone) stays more than ``turned_min_angle`` from f
    or from orthogonal to u, or the mean pitch (φ) moves more than ``turned_pitch_angle``
    from what it was (a turn about f itself; stairs move it by about 15°, sitting down is
    not walking); the swing then starts afresh as after a turn seen at once. A mean
    walking pitch that stays negative, or a pitch rate skewed the wrong way, for FLIP_MIN_S
    turns f or u round (:func:`_reorient`). A mean walking pitch beyond
    ``turned_pitch_angle`` for SEATED_MIN_S (the first rest was sitting, not standing: a
    walk that starts from a chair, or the phone turned about f while standing) puts u
    where level walking has its mean pitch ``walking_pitch``. Checked every
    CHECK_PERIOD_S."""
    s = state.scalars
    now = s[LAST_T]
    if s[RECENT_S] < params.turned_tau_s or now - s[LAST_CHECK_T] < CHECK_PERIOD_S:
        return
    s[LAST_CHECK_T] = now
    values, vectors = np.linalg.eigh(state.recent)
    if values[1] < SWING_MIN or values[0] > PLANAR_RATIO * values[1]:
        return
    up, flex = _thigh_axes(state.up, state.flex_raw, state.flex_sign[0])
    axis = vectors[:, 0].copy()
    if s[TURN_SEEN] > 0:
        _remount(state, params, c, axis, up, flex)
        return
    phi = _swing_angle(state.recent_mean, up, flex)
    skew = s[RATE2] ** 1.5 * SKEW_FLIP if params.skew_check else np.inf
    s[FLIP_S] = s[FLIP_S] + CHECK_PERIOD_S if phi > 0 or s[RATE3] < -skew else 0.0
    s[SEATED_S] = s[SEATED_S] + CHECK_PERIOD_S if -phi > params.turned_pitch_angle else 0.0
    if s[SEATED_S] >= SEATED_MIN_S:
        s[SEATED_S] = 0.0
        _reorient(state, False, params.walking_pitch, flex)
        return
    same_axis = abs(axis @ flex) >= np.cos(params.turned_min_angle) and \
        abs(axis @ up) <= np.sin(params.turned_min_angle)
    d = phi - _oldest_anchor(state)[0]
    same_pitch = s[RING_N] == 0 or abs(np.arctan2(np.sin(d), np.cos(d))) <= \
        params.turned_pitch_angle
    if same_axis and same_pitch:
        s[TURNED_S] = 0.0
        if s[FLIP_S] >= FLIP_MIN_S:
            _reorient(state, s[RATE3] <= skew, params.walking_pitch, flex)
            return
        _anchor(state, c, up, flex)
        return
    s[TURNED_S] += CHECK_PERIOD_S
    if s[TURNED_S] >= params.turned_min_s:
        _seen_turn(state, s[LAST_T] - params.turned_min_s - params.turned_tau_s)


@njit(cache=True)
def _sample_turn(last, c):
    """The turn over a sample, ω·δt in the sensor frame [rad], from the attitudes C_b^n
    before and after it: twice it is the antisymmetric part of C_{k−1}ᵀ·C_k."""
    r = np.zeros(3)
    for i in range(3):
        r[0] += 0.5 * (last[i, 1] * c[i, 2] - last[i, 2] * c[i, 1])
        r[1] += 0.5 * (last[i, 2] * c[i, 0] - last[i, 0] * c[i, 2])
        r[2] += 0.5 * (last[i, 0] * c[i, 1] - last[i, 1] * c[i, 0])
    return r


@njit(cache=True)
def _foreign_turn(state, params, wn, dt, c, turn):
    """The phone turning in the pocket, seen at once: the thigh turns only about f (its
    pitch) and the vertical (its yaw), so a turn about n = f × (vertical ⊥ f), outside
    that span, is the phone's own. Its rate (``turn``, :func:`_sample_turn`) integrated
    with a leak of FOREIGN_TAU_S beyond ``turned_angle`` is a turn: the thigh's own
    abduction swings back and forth and integrates to a few degrees. Integrated while
    moving (``wn`` above ``moving_rate``).
    The recent swing then starts afresh TURN_HOLD_S after it began (a turn of the phone is
    over by then, and the old axes see the thigh's own swing as foreign too), and
    :func:`_check_turned` decides on it with the anchors from before."""
    s = state.scalars
    if dt > 0 and s[FLEX_KNOWN] > 0 and wn > params.moving_rate:
        _, f = _thigh_axes(state.up, state.flex_raw, state.flex_sign[0])
        g = c[2, :]
        normal = _unit(np.cross(f, g - (g @ f) * f))
        s[FOREIGN] = np.exp(-dt / FOREIGN_TAU_S) * s[FOREIGN] + turn @ normal
        if s[TURN_SEEN] == 0.0 and abs(s[FOREIGN]) > params.turned_angle:
            _seen_turn(state, s[LAST_T])
        _pitch_rate_moments(state, dt, turn @ f / dt)
    if s[TURN_SEEN] > 0 and s[LAST_T] - s[TURN_T] < TURN_HOLD_S:
        _forget_recent(state)


@njit(cache=True)
def _pitch_rate_moments(state, dt, rate):
    """The second and third moments of the rate about f [rad/s], weighted over SKEW_TAU_S.
    The thigh swings forward fast (the swing, about 40 % of the gait cycle) and back slowly
    (the stance, about 60 %), so the rate of θ is skewed positive, whatever the offset of
    u (beyond the thesis: it tells f's sign where the mean pitch cannot, :func:`_reorient`).
    Not used without a gyroscope: the pitch from the low-passed gravity loses the swing's
    fast rise (on the real Oxford phone it read reversed and flipped f)."""
    s = state.scalars
    lam = np.exp(-dt / SKEW_TAU_S)
    s[RATE2] = lam * s[RATE2] + (1.0 - lam) * rate * rate
    s[RATE3] = lam * s[RATE3] + (1.0 - lam) * rate * rate * rate


@njit(cache=True)
def _seen_turn(state, t):
    """A turn of the phone that began at t: the recent swing starts afresh TURN_HOLD_S
    after it, for :func:`_remount`."""
    s = state.scalars
    s[TURN_SEEN] = 1.0
    s[TURN_T] = t
    s[TURNED_S] = 0.0
    _forget_recent(state)


@njit(cache=True)
def _forget_recent(state):
    state.scalars[RECENT_S] = 0.0
    state.recent[:, :] = 0.0
    state.recent_mean[:] = 0.0


@njit(cache=True)
def _swing_angle(g, up, flex):
    """φ: the angle about f from the mean vertical g (its part ⊥ f) to u [rad]."""
    gp = _unit(g - (g @ flex) * flex)
    return np.arctan2(np.cross(gp, up) @ flex, gp @ up)


@njit(cache=True)
def _anchor(state, c, up, flex):
    """Keep φ of the mean vertical (the gait's mean pitch) and the thigh heading of each
    check in a ring: a remount takes the oldest, from before the phone began to turn (it
    is found turned_tau_s + turned_min_s later)."""
    s = state.scalars
    _, heading = thigh_angles(c, up, flex)
    if not np.isfinite(heading):
        return
    k = int(s[RING_POS])
    state.anchors[k, ANCHOR_PHI] = _swing_angle(state.mean, up, flex)
    state.anchors[k, ANCHOR_HEADING] = heading
    state.anchors[k, ANCHOR_T] = s[LAST_T]
    s[RING_POS] = (k + 1) % ANCHOR_RING
    s[RING_N] = min(s[RING_N] + 1.0, ANCHOR_RING)


@njit(cache=True)
def _reorient(state, flip, pitch, flex):
    """The walking pitch stayed negative (φ > 0) or its rate skewed negative: f is the
    other way round (``flip``; the phone turned about u, f followed it the short way), or
    u is on the wrong side of the mean vertical, or far from it (a seated start). f takes
    the sign the skew of the pitch rate gives (:func:`_pitch_rate_moments`), and u is put
    about it so that the mean walking pitch is ``pitch`` (level walking's, positive by the
    thesis' asymmetry θ_max ≫ |θ_min|)."""
    s = state.scalars
    f = -flex if flip else flex
    gp = _unit(state.recent_mean - (state.recent_mean @ f) * f)
    angle = -abs(pitch)
    state.up[:] = np.cos(angle) * gp + np.sin(angle) * np.cross(f, gp)
    state.flex_raw[:] = f
    state.flex_sign[0] = 1.0
    if flip:
        s[RATE3] = -s[RATE3]
    s[FLIP_S] = 0.0
    s[RING_N] = 0.0
    s[RING_POS] = 0.0
    s[CHANGES] += 1.0


@njit(cache=True)
def _oldest_anchor(state):
    """φ, heading and t of the oldest check in the ring (zeros while it is empty)."""
    s = state.scalars
    return state.anchors[int(s[RING_POS]) if s[RING_N] == ANCHOR_RING else 0]


@njit(cache=True)
def _anchor_before(state, t):
    """The newest check at least ANCHOR_LEAD_S before t, else the oldest."""
    s = state.scalars
    for back in range(1, int(s[RING_N]) + 1):
        row = state.anchors[int(s[RING_POS] - back) % ANCHOR_RING]
        if row[ANCHOR_T] <= t - ANCHOR_LEAD_S:
            return row
    return _oldest_anchor(state)


@njit(cache=True)
def _remount(state, params, c, axis, up, flex):
    """The thigh frame after the phone turned (at TURN_T): f along the recent swing axis,
    u at the anchored φ from the recent mean vertical about it; of the two signs of f, the
    one that keeps the thigh heading of the anchor (the thigh does not turn with the
    phone). Taken when u or f moves by more than ``turned_min_angle``/2 (a turn seen that
    was the thigh's own changes nothing)."""
    s = state.scalars
    s[TURNED_S] = 0.0
    s[TURN_SEEN] = 0.0
    if s[RING_N] == 0:
        return
    phi, before, _ = _anchor_before(state, s[TURN_T])
    g = _unit(state.recent_mean.copy())
    best = -np.inf
    new_up, new_flex = up.copy(), flex.copy()
    for sign in (1.0, -1.0):
        f = sign * axis
        gp = _unit(g - (g @ f) * f)
        u = np.cos(phi) * gp + np.sin(phi) * np.cross(f, gp)
        _, heading = thigh_angles(c, u, f)
        score = np.cos(heading - before)
        if score > best:
            best = score
            new_up[:], new_flex[:] = u, f
    material = np.cos(params.turned_min_angle / 2)
    if new_up @ up >= material and new_flex @ flex >= material:
        return
    state.up[:] = new_up
    state.flex_raw[:] = new_flex
    state.flex_sign[0] = 1.0
    state.moment[:, :] = state.recent
    state.mean[:] = state.recent_mean
    s[RATE2] = s[RATE3] = 0.0
    s[UP_PROVISIONAL] = 0.0
    s[RING_N] = 0.0
    s[RING_POS] = 0.0
    s[CHANGES] += 1.0


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
        if t[k] - s[LAST_STEP_T] > params.forget_s:
            s[LAST_AMPLITUDE] = 0.0
        amplitude = s[LAST_AMPLITUDE]
        if s[SEEKING_MAX] > 0:
            if x > s[CUR_MAX]:
                s[CUR_MAX] = x
                s[T_MAX] = t[k]
            if s[CUR_MAX] - x >= max(params.drop_min, params.drop_fraction * amplitude):
                rise = s[CUR_MAX] - s[CUR_MIN]
                if (params.min_amplitude <= rise <= params.max_amplitude
                        and s[T_MAX] - s[T_MIN] <= params.max_rise_s
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


# footfall detector scalars (a (N_FOOTFALL_SCALARS,) array)
(FF_SEEKING_MAX, FF_CUR_MIN, FF_CUR_MAX, FF_T_MAX, FF_HELD_T, FF_HELD_VALUE, FF_LAST_T,
 FF_COUNT, FF_PITCH_MAX, FF_PITCH_MIN, FF_T_PITCH_MIN) = range(11)
N_FOOTFALL_SCALARS = 11


def new_footfall_state() -> np.ndarray:
    """Seeking a minimum, nothing held, no footfall yet."""
    s = np.zeros(N_FOOTFALL_SCALARS)
    s[FF_CUR_MIN], s[FF_CUR_MAX] = np.inf, -np.inf
    s[FF_HELD_T] = s[FF_LAST_T] = -np.inf
    s[FF_PITCH_MAX], s[FF_PITCH_MIN] = -np.inf, np.inf
    return s


@njit(cache=True)
def _footfall(s, t_ff, t_now, events, count):
    """A footfall at ``t_ff`` confirmed at ``t_now``: every second one closes a gait
    cycle of the sensor leg, an event row (the pitch's extremes since the last one)."""
    s[FF_COUNT] += 1.0
    s[FF_LAST_T] = t_ff
    if s[FF_COUNT] % 2 == 0.0:
        events[count, EV_T_MAX] = t_ff
        events[count, EV_MAX] = s[FF_PITCH_MAX]
        events[count, EV_MIN] = s[FF_PITCH_MIN]
        events[count, EV_T_MIN] = s[FF_T_PITCH_MIN]
        events[count, EV_T_CONFIRM] = t_now
        s[FF_PITCH_MAX], s[FF_PITCH_MIN] = -np.inf, np.inf
        return count + 1
    return count


@njit(cache=True)
def footfall_loop(s, prominence, min_interval_s, t, force, pitch, events):
    """Footfalls in the low-passed specific force's norm ``force`` [m/s²] (N,), and the
    gait cycles they close into ``events`` (rows of EV_* columns, every second footfall;
    returns how many). A footfall is a peak standing ``prominence`` above the troughs on
    both sides (risen that much since the last trough, fallen that much since), at least
    ``min_interval_s`` from the last one: a peak is held that long, and a higher one
    within it takes its place (scipy.signal.find_peaks' ``distance``, causally, with
    ``min_interval_s`` of latency). ``pitch`` [rad] (NaN: unknown) gives each cycle its
    θ_max and θ_min."""
    count = 0
    for k in range(len(t)):
        x = force[k]
        if np.isfinite(pitch[k]):
            if pitch[k] > s[FF_PITCH_MAX]:
                s[FF_PITCH_MAX] = pitch[k]
            if pitch[k] < s[FF_PITCH_MIN]:
                s[FF_PITCH_MIN] = pitch[k]
                s[FF_T_PITCH_MIN] = t[k]
        if s[FF_HELD_T] > -np.inf and t[k] - s[FF_HELD_T] >= min_interval_s:
            count = _footfall(s, s[FF_HELD_T], t[k], events, count)
            s[FF_HELD_T] = -np.inf
        if not np.isfinite(x):
            continue
        if s[FF_SEEKING_MAX] > 0:
            if x > s[FF_CUR_MAX]:
                s[FF_CUR_MAX] = x
                s[FF_T_MAX] = t[k]
            if s[FF_CUR_MAX] - x >= prominence:
                if (s[FF_T_MAX] - s[FF_LAST_T] >= min_interval_s
                        and (s[FF_HELD_T] == -np.inf or s[FF_CUR_MAX] > s[FF_HELD_VALUE])):
                    s[FF_HELD_T], s[FF_HELD_VALUE] = s[FF_T_MAX], s[FF_CUR_MAX]
                s[FF_SEEKING_MAX] = 0.0
                s[FF_CUR_MIN] = x
        else:
            if x < s[FF_CUR_MIN]:
                s[FF_CUR_MIN] = x
            if x - s[FF_CUR_MIN] >= prominence:
                s[FF_SEEKING_MAX] = 1.0
                s[FF_CUR_MAX] = x
                s[FF_T_MAX] = t[k]
    return count
