"""The step detectors' per-sample loops, compiled with numba: the confirmed maxima of
the thigh pitch θ (Muñoz Díaz 2016, Section 4.1.1) and, without a gyroscope, the gait
cycles closed by footfalls (:class:`pdr_pocket.steps.PitchMaximumDetector` and
:class:`~pdr_pocket.steps.FootfallDetector` wrap them). Both carry their state between
calls, so one sample at a time (the live node) and a whole record give the same events:
rows of the ``EV_*`` columns. θ itself comes from :mod:`pdr_pocket.compiled_mounting`.
Each state's scalars are one record (:data:`PEAK_SCALARS`, :data:`FOOTFALL_SCALARS`: one
comment per field, read and written by name, ``s = state.scalars[0]``, ``s.seeking_max``),
in a NumPy record array, whose fields read by name in plain Python as in numba (a kernel
run uncompiled, as the twin tests' perturbed ones are, reads the same state).

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
- :func:`footfall_loop`, beyond the thesis: footfalls as prominent peaks of the
  low-passed specific force's norm, every second one closing a gait cycle of the sensor
  leg with the pitch's extremes since the last. A gait is a rhythm: a footfall counts
  only in a run of at least :data:`~pdr_core.walking.gait.GAIT_MIN_FOOTFALLS`, each within
  ``max_interval_s`` (half the longest gait cycle) of the last; the first ones of a run
  wait for it, and a shorter run (the phone taken out, a stumble, a bump) is dropped.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache
from pdr_core.walking import gait
from pdr_core.walking.gait import GAIT_MIN_FOOTFALLS

kernel_cache.forget_if_changed(__file__, gait.__file__)

# PeakState.scalars: one record; angles [rad], times [s]
PEAK_SCALARS = np.dtype([
    ("seeking_max", np.bool_),      # risen enough above the minimum: a maximum is sought
    ("cur_max", np.float64),        # the highest θ since then
    ("t_max", np.float64),          # ... and its time
    ("cur_min", np.float64),        # the lowest θ since the last maximum
    ("t_min", np.float64),          # ... and its time
    ("last_amplitude", np.float64),  # the last step's rise, θ_max − θ_min (0: forgotten)
    ("last_step_t", np.float64),    # the last step's t of θ_max
])
# columns of the events (a confirmed maximum, or a gait cycle closed by footfalls):
# t of θ_max [s], θ_max and θ_min [rad], t of θ_min and when the event was known [s]
EV_T_MAX, EV_MAX, EV_MIN, EV_T_MIN, EV_T_CONFIRM = range(5)
N_EVENT_COLUMNS = 5


class PeakParams(NamedTuple):
    """Angles [rad], times [s]."""

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


class PeakState(NamedTuple):
    scalars: np.ndarray         # (1,) record of PEAK_SCALARS


def new_peak_state() -> PeakState:
    """Seeking a minimum first: a step needs one before its maximum."""
    scalars = np.zeros(1, dtype=PEAK_SCALARS).view(np.recarray)
    s = scalars[0]
    s.cur_min, s.cur_max, s.last_step_t = np.inf, -np.inf, -np.inf
    return PeakState(scalars)


@njit(cache=True)
def peak_loop(state, params, t, signal, events):
    """Confirmed maxima of ``signal`` (module docstring) into ``events`` (rows of
    EV_* columns); returns how many. NaN samples are skipped."""
    s = state.scalars[0]
    count = 0
    for k in range(len(t)):
        x = signal[k]
        if not np.isfinite(x):
            continue
        if t[k] - s.last_step_t > params.forget_s:
            s.last_amplitude = 0.0
        amplitude = s.last_amplitude
        if s.seeking_max:
            if x > s.cur_max:
                s.cur_max = x
                s.t_max = t[k]
            if s.cur_max - x >= max(params.drop_min, params.drop_fraction * amplitude):
                rise = s.cur_max - s.cur_min
                if (params.min_amplitude <= rise <= params.max_amplitude
                        and s.t_max - s.t_min <= params.max_rise_s
                        and t[k] - s.t_max <= params.max_hold_s
                        and s.t_max - s.last_step_t >= params.min_period_s):
                    events[count, EV_T_MAX] = s.t_max
                    events[count, EV_MAX] = s.cur_max
                    events[count, EV_MIN] = s.cur_min
                    events[count, EV_T_MIN] = s.t_min
                    events[count, EV_T_CONFIRM] = t[k]
                    count += 1
                    s.last_amplitude = rise
                    s.last_step_t = s.t_max
                s.seeking_max = False
                s.cur_min = x
                s.t_min = t[k]
        else:
            if x < s.cur_min:
                s.cur_min = x
                s.t_min = t[k]
            if x - s.cur_min >= max(params.rise_min, params.rise_fraction * amplitude):
                s.seeking_max = True
                s.cur_max = x
                s.t_max = t[k]
    return count


# FootfallState.scalars: one record; the force [m/s²], angles [rad], times [s]
FOOTFALL_SCALARS = np.dtype([
    ("seeking_max", np.bool_),      # risen prominence above the trough: a peak is sought
    ("cur_min", np.float64),        # the trough since the last peak
    ("cur_max", np.float64),        # the highest force since the trough
    ("t_max", np.float64),          # ... and its time
    ("held_t", np.float64),         # the peak held for min_interval_s (−inf: none)
    ("held_value", np.float64),     # ... and its force
    ("last_t", np.float64),         # the last footfall, counted or waiting for its run
    ("footfalls", np.int64),        # the footfalls counted
    ("pitch_max", np.float64),      # θ_max since the last cycle closed
    ("pitch_min", np.float64),      # θ_min since then
    ("t_pitch_min", np.float64),    # ... and its time
    ("run", np.int64),              # the footfalls of the current run
])
# FootfallState.waiting: the first GAIT_MIN_FOOTFALLS − 1 footfalls of a run, one record
# each, waiting for the run to hold
WAITING_FOOTFALL = np.dtype([
    ("t", np.float64),              # the footfall's time [s]
    ("closes", np.bool_),           # it closes a gait cycle of the sensor leg ...
    ("pitch_max", np.float64),      # ... whose θ_max [rad]
    ("pitch_min", np.float64),      # ... θ_min [rad]
    ("t_pitch_min", np.float64),    # ... and the time of θ_min [s]
])


class FootfallState(NamedTuple):
    scalars: np.ndarray         # (1,) record of FOOTFALL_SCALARS
    waiting: np.ndarray         # (GAIT_MIN_FOOTFALLS − 1,) records of WAITING_FOOTFALL


def new_footfall_state() -> FootfallState:
    """Seeking a minimum, nothing held, no footfall yet."""
    scalars = np.zeros(1, dtype=FOOTFALL_SCALARS).view(np.recarray)
    s = scalars[0]
    s.cur_min, s.cur_max = np.inf, -np.inf
    s.held_t = s.last_t = -np.inf
    s.pitch_max, s.pitch_min = -np.inf, np.inf
    return FootfallState(scalars, np.zeros(GAIT_MIN_FOOTFALLS - 1,
                                           dtype=WAITING_FOOTFALL).view(np.recarray))


@njit(cache=True)
def _cycle(events, count, t_ff, t_now, pitch_max, pitch_min, t_pitch_min):
    """A gait cycle closed by the footfall at ``t_ff``, counted at ``t_now``: its row."""
    events[count, EV_T_MAX] = t_ff
    events[count, EV_MAX] = pitch_max
    events[count, EV_MIN] = pitch_min
    events[count, EV_T_MIN] = t_pitch_min
    events[count, EV_T_CONFIRM] = t_now
    return count + 1


@njit(cache=True)
def _in_rhythm(state, t_ff, t_now, max_interval_s, events, count):
    """A footfall at ``t_ff`` found at ``t_now``, counted once its run holds
    GAIT_MIN_FOOTFALLS (the run's waiting ones first); a footfall farther than
    ``max_interval_s`` from the last starts a new run, dropping a shorter one. Every
    second footfall counted closes a gait cycle of the sensor leg with the pitch's
    extremes since the last: a waiting footfall that will close one keeps them."""
    s = state.scalars[0]
    if t_ff - s.last_t > max_interval_s:
        s.run = 0
    s.last_t = t_ff
    s.run += 1
    run = s.run
    uncounted = run if run <= GAIT_MIN_FOOTFALLS else 1     # this one and those waiting
    closes = (s.footfalls + uncounted) % 2 == 0
    if run < GAIT_MIN_FOOTFALLS:
        w = state.waiting[run - 1]
        w.t, w.closes = t_ff, closes
        if closes:
            w.pitch_max, w.pitch_min, w.t_pitch_min = s.pitch_max, s.pitch_min, s.t_pitch_min
            s.pitch_max, s.pitch_min = -np.inf, np.inf
        return count
    if run == GAIT_MIN_FOOTFALLS:
        for i in range(GAIT_MIN_FOOTFALLS - 1):
            w = state.waiting[i]
            if w.closes:
                count = _cycle(events, count, w.t, t_now, w.pitch_max, w.pitch_min,
                               w.t_pitch_min)
        s.footfalls += GAIT_MIN_FOOTFALLS - 1
    s.footfalls += 1
    if closes:
        count = _cycle(events, count, t_ff, t_now, s.pitch_max, s.pitch_min, s.t_pitch_min)
        s.pitch_max, s.pitch_min = -np.inf, np.inf
    return count


@njit(cache=True)
def footfall_loop(state, prominence, min_interval_s, max_interval_s, t, force, pitch, events):
    """Footfalls in the low-passed specific force's norm ``force`` [m/s²] (N,), and the
    gait cycles they close into ``events`` (rows of EV_* columns, every second footfall;
    returns how many). A footfall is a peak standing ``prominence`` above the troughs on
    both sides (risen that much since the last trough, fallen that much since), at least
    ``min_interval_s`` from the last one: a peak is held that long, and a higher one
    within it takes its place (scipy.signal.find_peaks' ``distance``, causally, with
    ``min_interval_s`` of latency), and in a run of them (:func:`_in_rhythm`, spaced at
    most ``max_interval_s``). ``pitch`` [rad] (NaN: unknown) gives each cycle its θ_max
    and θ_min. ``state``: a :class:`FootfallState`, changed in place."""
    s = state.scalars[0]
    count = 0
    for k in range(len(t)):
        x = force[k]
        if np.isfinite(pitch[k]):
            if pitch[k] > s.pitch_max:
                s.pitch_max = pitch[k]
            if pitch[k] < s.pitch_min:
                s.pitch_min = pitch[k]
                s.t_pitch_min = t[k]
        if s.held_t > -np.inf and t[k] - s.held_t >= min_interval_s:
            count = _in_rhythm(state, s.held_t, t[k], max_interval_s, events, count)
            s.held_t = -np.inf
        if not np.isfinite(x):
            continue
        if s.seeking_max:
            if x > s.cur_max:
                s.cur_max = x
                s.t_max = t[k]
            if s.cur_max - x >= prominence:
                if (s.t_max - s.last_t >= min_interval_s
                        and (s.held_t == -np.inf or s.cur_max > s.held_value)):
                    s.held_t, s.held_value = s.t_max, s.cur_max
                s.seeking_max = False
                s.cur_min = x
        else:
            if x < s.cur_min:
                s.cur_min = x
            if x - s.cur_min >= prominence:
                s.seeking_max = True
                s.cur_max = x
                s.t_max = t[k]
    return count
