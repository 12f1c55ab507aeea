"""The thigh's frame in the sensor's, learned sample by sample, compiled with numba.

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
    ℓ backwards. The heading is atan2(h_y, h_x) (:func:`thigh_angles`).

- :func:`gravity_loop`, beyond the thesis, for an IMU without gyroscope: the gravity
  direction as the low-passed specific force (the attitude the thigh frame then reads),
  and a motion measure in place of the turn rate.

The state of each is a :class:`typing.NamedTuple` of arrays whose scalars are one NumPy
record (a 0-d structured array, ``MOUNTING_SCALARS`` and ``GRAVITY_SCALARS``: one comment
per field), read and written by name inside the kernels (``s = state.scalars[()]``,
``s.rest_s``). The step detectors that read θ are in :mod:`pdr_pocket.compiled_peaks`.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core.maths import angles, kernel_cache, lowpass
from pdr_core.maths.angles import wrap_angle_jit
from pdr_core.maths.lowpass import lowpass_decay

kernel_cache.forget_if_changed(__file__, angles.__file__, lowpass.__file__)

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
CHANGE_WAIT_S = 1.5             # new axes wait this long at most for the swing's minimum
NO_CHANGE, REORIENT, REORIENT_FLIPPED, REMOUNT = range(4)   # MOUNTING_SCALARS.change_due
SKEW_TAU_S = 4.0                # the pitch rate's moments, over about three gait cycles
SKEW_FLIP = 0.3                 # a pitch-rate skewness below −SKEW_FLIP: f is reversed
ANCHOR_RING = 80                # the checks of the last 8 s of walking (see _anchor)
ANCHOR_LEAD_S = 1.0             # the anchor taken is this long before the turn was seen
ANCHOR_PHI, ANCHOR_HEADING, ANCHOR_T = range(3)     # columns of MountingState.anchors

# MountingState.scalars, one record; times [s], angles [rad]
MOUNTING_SCALARS = np.dtype([
    ("started", np.bool_),          # a sample has been seen (last_t holds its time)
    ("last_t", np.float64),         # the time of the last sample [s]
    ("rest_s", np.float64),         # how long the current rest has lasted [s]
    ("up_provisional", np.bool_),   # u is still the first sample's specific force
    ("flex_known", np.bool_),       # f and its sign are known: θ and the heading are given
    ("flex_sign", np.float64),      # ±1, the sign of f (MountingState.flex_raw is unsigned)
    ("moving_s", np.float64),       # time walking while f is learned [s]
    ("mean_pitch", np.float64),     # ∫θ dt over that time, whose sign gives f's [rad·s]
    ("changes", np.int64),          # the mounting changes found so far
    ("recent_s", np.float64),       # time the recent swing (turned_tau_s) has gathered [s]
    ("last_check_t", np.float64),   # the last check of a turned phone (_check_turned) [s]
    ("turned_s", np.float64),       # walking about an axis away from f this long [s]
    ("ring_pos", np.int64),         # the next row of MountingState.anchors
    ("ring_n", np.int64),           # the rows of MountingState.anchors filled
    ("foreign", np.float64),        # the leaky integral of the turn outside span{f, vertical} [rad]
    ("turn_seen", np.bool_),        # a turn of the phone seen, its axes not yet derived again
    ("turn_t", np.float64),         # when that turn began [s]
    ("flip_s", np.float64),         # the walking pitch negative (or its rate skewed) this long [s]
    ("seated_s", np.float64),       # the walking pitch beyond turned_pitch_angle this long [s]
    ("rate2", np.float64),          # the pitch rate's weighted second moment [rad²/s²]
    ("rate3", np.float64),          # ... and third [rad³/s³]
    ("last_pitch", np.float64),     # the last θ given, NaN before any and after new axes [rad]
    ("change_due", np.int64),       # new axes decided, waiting for the swing's minimum:
                                    # NO_CHANGE, REORIENT, REORIENT_FLIPPED or REMOUNT
    ("change_t", np.float64),       # when they were decided [s]
    ("falling", np.bool_),          # θ fell from the sample before to the last one
], align=True)
CHANGES = "changes"                 # the field counting the mounting changes


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
    scalars: np.ndarray         # () MOUNTING_SCALARS record
    rest_sum: np.ndarray        # (3,) specific force summed over the current rest
    up: np.ndarray              # (3,) u, sensor frame
    flex_raw: np.ndarray        # (3,) f before its sign (scalars' flex_sign), sensor frame
    moment: np.ndarray          # (3, 3) weighted ∑g gᵀ of the vertical while walking
    mean: np.ndarray            # (3,) weighted ∑g
    recent: np.ndarray          # (3, 3) the same over turned_tau_s
    recent_mean: np.ndarray     # (3,)
    anchors: np.ndarray         # (ANCHOR_RING, 3) φ, thigh heading and t of the last checks


class MountingInputs(NamedTuple):
    """N samples."""

    t: np.ndarray               # (N,) [s]
    rate: np.ndarray            # (N,) ‖ω‖ [rad/s], or without a gyroscope the
                                # accelerometer's motion measure scaled to it
    accel: np.ndarray           # (N, 3) specific force, sensor frame [m/s²]
    attitude: np.ndarray        # (N, 3, 3) C_b^n, sensor → ENU
    turn: np.ndarray            # (N, 3) the phone's turn over each sample, ω·δt in the
                                # sensor frame [rad] (pdr_pocket.pitch_source.sample_turns)


class MountingOutputs(NamedTuple):
    """Per sample of :class:`MountingInputs`, filled by :func:`mounting_loop`."""

    pitch: np.ndarray           # (N,) θ [rad], NaN while the axes are unknown
    heading: np.ndarray         # (N,) the thigh's heading [rad], NaN likewise
    known: np.ndarray           # (N,) bool: the axes are known
    up: np.ndarray              # (N, 3) u, sensor frame
    flex: np.ndarray            # (N, 3) f (signed), sensor frame
    changes: np.ndarray         # (N,) the mounting changes found so far

    @classmethod
    def empty(cls, n: int) -> MountingOutputs:
        return cls(np.full(n, np.nan), np.full(n, np.nan), np.zeros(n, dtype=np.bool_),
                   np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n))


def new_mounting_state(up=None, flexion=None) -> MountingState:
    """A fresh state; with ``up`` and ``flexion`` (a configured mounting) they are used."""
    scalars = np.zeros((), MOUNTING_SCALARS)
    scalars["flex_sign"] = 1.0
    scalars["last_pitch"] = np.nan
    state = MountingState(scalars, np.zeros(3), np.zeros(3), np.zeros(3), np.zeros((3, 3)),
                          np.zeros(3), np.zeros((3, 3)), np.zeros(3),
                          np.zeros((ANCHOR_RING, 3)))
    if up is not None:
        state.up[:] = up
        state.flex_raw[:] = flexion
        scalars["flex_known"] = True
        scalars["started"] = True
    return state


@njit(cache=True)
def _continued(last, angle):
    """``angle`` [rad] taken 2π at a time to the nearest of ``last`` (NaN: as it is), so
    that θ runs on through ±180° instead of jumping by 360° (a stride of 9 m from one
    flip of a thigh frame still being learned)."""
    if np.isnan(last) or np.isnan(angle):
        return angle
    return last + wrap_angle_jit(angle - last)


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
def mounting_loop(state, params, inputs, out):
    """The thigh frame per sample of ``inputs`` (:class:`MountingInputs`; module
    docstring) into ``out`` (:class:`MountingOutputs`): θ and heading NaN until known."""
    s = state.scalars[()]
    t, rate, accel, attitude = inputs.t, inputs.rate, inputs.accel, inputs.attitude
    for k in range(len(t)):
        w, a = rate[k], accel[k]
        dt = t[k] - s.last_t if s.started else 0.0
        s.last_t = t[k]
        changes = s.changes
        if not params.fixed:
            if not s.started:
                state.up[:] = _unit(a)
                s.up_provisional = True
                s.started = True
            _rest(state, params, w, a, dt)
            _foreign_turn(state, params, w, dt, attitude[k], inputs.turn[k])
            _motion(state, params, w, dt, attitude[k])
            _change_when_due(state, params, attitude[k])
        if s.changes != changes:            # new axes: θ starts afresh from them
            s.last_pitch = np.nan
        known = s.flex_known
        up, flex = _thigh_axes(state.up, state.flex_raw, s.flex_sign)
        out.up[k] = up
        out.flex[k] = flex
        out.known[k] = known
        out.changes[k] = s.changes
        if known:
            pitch, out.heading[k] = thigh_angles(attitude[k], up, flex)
            out.pitch[k] = _continued(s.last_pitch, pitch)
            s.falling = out.pitch[k] < s.last_pitch
            s.last_pitch = out.pitch[k]
        else:
            out.pitch[k], out.heading[k] = np.nan, np.nan


@njit(cache=True)
def _rest(state, params, wn, a, dt):
    """Standing refines u, a rest out of the swing plane resets the mounting."""
    s = state.scalars[()]
    an = np.sqrt(a @ a)
    if wn >= params.rest_rate or abs(an - params.gravity) >= params.rest_acc:
        s.rest_s = 0.0
        state.rest_sum[:] = 0.0
        return
    s.rest_s += dt
    state.rest_sum[:] += a
    if s.rest_s < params.rest_min_s:
        return
    g = _unit(state.rest_sum.copy())
    if s.up_provisional:
        state.up[:] = g
        s.up_provisional = False
        return
    if g @ state.up >= np.cos(params.standing_max_angle):
        state.up[:] = g
        return
    if s.flex_known:
        _, flex = _thigh_axes(state.up, state.flex_raw, 1.0)
        if abs(g @ flex) > np.sin(params.moved_min_angle):
            state.up[:] = g
            s.flex_known = False
            s.moving_s = 0.0
            s.mean_pitch = 0.0
            s.changes += 1
            state.moment[:, :] = 0.0
            state.mean[:] = 0.0
            state.flex_raw[:] = 0.0


@njit(cache=True)
def _motion(state, params, wn, dt, c):
    """Learn f from the scatter of the vertical; fix its sign once it is known."""
    s = state.scalars[()]
    if wn <= params.moving_rate or dt <= 0:
        return
    lam = lowpass_decay(dt, params.flexion_tau_s)
    g = c[2, :]                                  # the vertical in the sensor frame
    for i in range(3):
        state.mean[i] = lam * state.mean[i] + (1.0 - lam) * g[i]
        for j in range(3):
            state.moment[i, j] = lam * state.moment[i, j] + (1.0 - lam) * g[i] * g[j]
    lam = lowpass_decay(dt, params.turned_tau_s)
    for i in range(3):
        state.recent_mean[i] = lam * state.recent_mean[i] + (1.0 - lam) * g[i]
        for j in range(3):
            state.recent[i, j] = lam * state.recent[i, j] + (1.0 - lam) * g[i] * g[j]
    s.recent_s += dt
    spread = state.moment - np.outer(state.mean, state.mean)
    v = _least_swung_axis(spread, state.up)
    if v @ state.flex_raw < 0:
        v = -v
    state.flex_raw[:] = v
    if s.flex_known:
        _check_turned(state, params, c)
        return
    s.moving_s += dt
    up, flex = _thigh_axes(state.up, state.flex_raw, 1.0)
    pitch, _ = thigh_angles(c, up, flex)
    if np.isfinite(pitch):
        s.mean_pitch += pitch * dt
    if s.moving_s >= params.flexion_min_s:
        s.flex_sign = 1.0 if s.mean_pitch >= 0 else -1.0
        s.flex_known = True


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
    walk that starts from a chair, the phone turned about f while standing, or without a
    gyroscope a phone put in the pocket while walking) puts u
    where level walking has its mean pitch ``walking_pitch``. Checked every
    CHECK_PERIOD_S."""
    s = state.scalars[()]
    now = s.last_t
    if s.change_due or s.recent_s < params.turned_tau_s or \
            now - s.last_check_t < CHECK_PERIOD_S:
        return
    s.last_check_t = now
    values, vectors = np.linalg.eigh(state.recent)
    if values[1] < SWING_MIN or values[0] > PLANAR_RATIO * values[1]:
        return
    up, flex = _thigh_axes(state.up, state.flex_raw, s.flex_sign)
    axis = vectors[:, 0].copy()
    if s.turn_seen:
        _change_at_minimum(state, REMOUNT)
        return
    phi = _swing_angle(state.recent_mean, up, flex)
    skew = s.rate2 ** 1.5 * SKEW_FLIP if params.skew_check else np.inf
    s.flip_s = s.flip_s + CHECK_PERIOD_S if phi > 0 or s.rate3 < -skew else 0.0
    s.seated_s = s.seated_s + CHECK_PERIOD_S if -phi > params.turned_pitch_angle else 0.0
    if s.seated_s >= SEATED_MIN_S:
        s.seated_s = 0.0
        _change_at_minimum(state, REORIENT)
        return
    same_axis = abs(axis @ flex) >= np.cos(params.turned_min_angle) and \
        abs(axis @ up) <= np.sin(params.turned_min_angle)
    d = phi - _oldest_anchor(state)[ANCHOR_PHI]
    same_pitch = s.ring_n == 0 or abs(wrap_angle_jit(d)) <= \
        params.turned_pitch_angle
    if same_axis and same_pitch:
        s.turned_s = 0.0
        if s.flip_s >= FLIP_MIN_S:
            _change_at_minimum(state, REORIENT_FLIPPED if s.rate3 <= skew else REORIENT)
            return
        _anchor(state, c, up, flex)
        return
    s.turned_s += CHECK_PERIOD_S
    if s.turned_s >= params.turned_min_s:
        _seen_turn(state, s.last_t - params.turned_min_s - params.turned_tau_s)


@njit(cache=True)
def _foreign_turn(state, params, wn, dt, c, turn):
    """The phone turning in the pocket, seen at once: the thigh turns only about f (its
    pitch) and the vertical (its yaw), so a turn about n = f × (vertical ⊥ f), outside
    that span, is the phone's own. Its rate (``turn``, the sample's ω·δt) integrated
    with a leak of FOREIGN_TAU_S beyond ``turned_angle`` is a turn: the thigh's own
    abduction swings back and forth and integrates to a few degrees. Integrated while
    moving (``wn`` above ``moving_rate``).
    The recent swing then starts afresh TURN_HOLD_S after it began (a turn of the phone is
    over by then, and the old axes see the thigh's own swing as foreign too), and
    :func:`_check_turned` decides on it with the anchors from before."""
    s = state.scalars[()]
    if dt > 0 and s.flex_known and wn > params.moving_rate:
        _, f = _thigh_axes(state.up, state.flex_raw, s.flex_sign)
        g = c[2, :]
        normal = _unit(np.cross(f, g - (g @ f) * f))
        s.foreign = lowpass_decay(dt, FOREIGN_TAU_S) * s.foreign + turn @ normal
        if not s.turn_seen and abs(s.foreign) > params.turned_angle:
            _seen_turn(state, s.last_t)
        _pitch_rate_moments(state, dt, -(turn @ f) / dt)   # θ̇ = −ω·f: a swing forward
                                                            # turns about −f (f left)
    if s.turn_seen and s.last_t - s.turn_t < TURN_HOLD_S:
        _forget_recent(state)


@njit(cache=True)
def _pitch_rate_moments(state, dt, rate):
    """The second and third moments of the rate about f [rad/s], weighted over SKEW_TAU_S.
    The thigh swings forward fast (the swing, about 40 % of the gait cycle) and back slowly
    (the stance, about 60 %), so the rate of θ is skewed positive, whatever the offset of
    u (beyond the thesis: it tells f's sign where the mean pitch cannot, :func:`_reorient`).
    Not used without a gyroscope: the pitch from the low-passed gravity loses the swing's
    fast rise (on the real Oxford phone it read reversed and flipped f)."""
    s = state.scalars[()]
    lam = lowpass_decay(dt, SKEW_TAU_S)
    s.rate2 = lam * s.rate2 + (1.0 - lam) * rate * rate
    s.rate3 = lam * s.rate3 + (1.0 - lam) * rate * rate * rate


@njit(cache=True)
def _seen_turn(state, t):
    """A turn of the phone that began at t: the recent swing starts afresh TURN_HOLD_S
    after it, for :func:`_remount`."""
    s = state.scalars[()]
    s.turn_seen = True
    s.turn_t = t
    s.turned_s = 0.0
    _forget_recent(state)


@njit(cache=True)
def _forget_recent(state):
    """The recent swing (turned_tau_s) starts afresh."""
    s = state.scalars[()]
    s.recent_s = 0.0
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
    s = state.scalars[()]
    _, heading = thigh_angles(c, up, flex)
    if not np.isfinite(heading):
        return
    k = s.ring_pos
    state.anchors[k, ANCHOR_PHI] = _swing_angle(state.mean, up, flex)
    state.anchors[k, ANCHOR_HEADING] = heading
    state.anchors[k, ANCHOR_T] = s.last_t
    s.ring_pos = (k + 1) % ANCHOR_RING
    s.ring_n = min(s.ring_n + 1, ANCHOR_RING)


@njit(cache=True)
def _change_at_minimum(state, change):
    """Decide on new axes (``change``: REORIENT, REORIENT_FLIPPED, REMOUNT), to be taken
    at the swing's next minimum (:func:`_change_when_due`)."""
    s = state.scalars[()]
    s.change_due = change
    s.change_t = s.last_t


@njit(cache=True)
def _change_when_due(state, params, c):
    """Take the new axes decided (:func:`_reorient`, :func:`_remount`) at the swing's
    minimum (θ, in the axes still in use, stops falling) or after CHANGE_WAIT_S: θ jumps
    with the new axes where the step detector seeks a minimum anyway, not in the middle
    of a step's rise, which a fresh detector would cut in two and lose (a walk from a
    chair, the timed up-and-go)."""
    s = state.scalars[()]
    if s.change_due == NO_CHANGE:
        return
    up, flex = _thigh_axes(state.up, state.flex_raw, s.flex_sign)
    pitch, _ = thigh_angles(c, up, flex)
    at_minimum = s.falling and _continued(s.last_pitch, pitch) >= s.last_pitch
    if not (at_minimum or s.last_t - s.change_t >= CHANGE_WAIT_S):
        return
    if s.change_due == REMOUNT:
        _, vectors = np.linalg.eigh(state.recent)
        _remount(state, params, c, vectors[:, 0].copy(), up, flex)
    else:
        _reorient(state, s.change_due == REORIENT_FLIPPED, params.walking_pitch, flex)
    s.change_due = NO_CHANGE


@njit(cache=True)
def _reorient(state, flip, pitch, flex):
    """The walking pitch stayed negative (φ > 0) or its rate skewed negative: f is the
    other way round (``flip``; the phone turned about u, f followed it the short way), or
    u is on the wrong side of the mean vertical, or far from it (a seated start). f takes
    the sign the skew of the pitch rate gives (:func:`_pitch_rate_moments`), and u is put
    about it so that the mean walking pitch is ``pitch`` (level walking's, positive by the
    thesis' asymmetry θ_max ≫ |θ_min|)."""
    s = state.scalars[()]
    f = -flex if flip else flex
    gp = _unit(state.recent_mean - (state.recent_mean @ f) * f)
    angle = -abs(pitch)
    state.up[:] = np.cos(angle) * gp + np.sin(angle) * np.cross(f, gp)
    state.flex_raw[:] = f
    s.flex_sign = 1.0
    if flip:
        s.rate3 = -s.rate3
    s.flip_s = 0.0
    s.ring_n = 0
    s.ring_pos = 0
    s.changes += 1


@njit(cache=True)
def _oldest_anchor(state):
    """φ, heading and t of the oldest check in the ring (zeros while it is empty)."""
    s = state.scalars[()]
    return state.anchors[s.ring_pos if s.ring_n == ANCHOR_RING else 0]


@njit(cache=True)
def _anchor_before(state, t):
    """The newest check at least ANCHOR_LEAD_S before t, else the oldest."""
    s = state.scalars[()]
    for back in range(1, s.ring_n + 1):
        row = state.anchors[(s.ring_pos - back) % ANCHOR_RING]
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
    s = state.scalars[()]
    s.turned_s = 0.0
    s.turn_seen = False
    if s.ring_n == 0:
        return
    phi, before, _ = _anchor_before(state, s.turn_t)
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
    s.flex_sign = 1.0
    state.moment[:, :] = state.recent
    state.mean[:] = state.recent_mean
    s.rate2 = s.rate3 = 0.0
    s.up_provisional = False
    s.ring_n = 0
    s.ring_pos = 0
    s.changes += 1


@njit(cache=True)
def _least_swung_axis(spread, up):
    """The axis orthogonal to u about which the vertical swings (spread: its weighted
    covariance in the sensor frame): u × d, d the major axis of the spread within the
    plane orthogonal to u (closed-form 2 × 2 eigenvector)."""
    ref = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = _unit(np.cross(up, ref))
    e2 = np.cross(up, e1)
    e1_spread = e1 @ spread
    s11, s22, s12 = e1_spread @ e1, e2 @ spread @ e2, e1_spread @ e2
    phi = 0.5 * np.arctan2(2.0 * s12, s11 - s22)
    return _unit(np.cross(up, np.cos(phi) * e1 + np.sin(phi) * e2))
