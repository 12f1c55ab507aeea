"""The step detectors' per-sample loops, compiled with numba: the confirmed maxima of
the thigh pitch θ (Muñoz Díaz 2016, Section 4.1.1) and, without a gyroscope, the gait
cycles closed by footfalls (:class:`pdr_pocket.steps.PitchMaximumDetector` and
:class:`~pdr_pocket.steps.FootfallDetector` wrap them). Both carry their state between
calls, so one sample at a time (the live node) and a whole record give the same events:
rows of the ``EV_*`` columns. θ itself comes from :mod:`pdr_pocket.compiled_mounting`.

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
  only in a run of at least :data:`~pdr_core.gait.GAIT_MIN_FOOTFALLS`, each within
  ``max_interval_s`` (half the longest gait cycle) of the last; the first ones of a run
  wait for it, and a shorter run (the phone taken out, a stumble, a bump) is dropped.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core import gait, kernel_cache
from pdr_core.gait import GAIT_MIN_FOOTFALLS

kernel_cache.forget_if_changed(__file__, gait.__file__)

# peak detector scalars (PeakState.scalars)
SEEKING_MAX, CUR_MAX, T_MAX, CUR_MIN, T_MIN, LAST_AMPLITUDE, LAST_STEP_T = range(7)
N_PEAK_SCALARS = 7
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
    scalars: np.ndarray         # (N_PEAK_SCALARS,)


def new_peak_state() -> PeakState:
    """Seeking a minimum first: a step needs one before its maximum."""
    scalars = np.zeros(N_PEAK_SCALARS)
    scalars[CUR_MIN] = np.inf
    scalars[CUR_MAX] = -np.inf
    scalars[LAST_STEP_T] = -np.inf
    return PeakState(scalars)


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


# footfall detector scalars (a (N_FOOTFALL_SCALARS,) array): FF_LAST_T is the last
# footfall, counted or waiting for its run; FF_RUN the footfalls of the run; the first
# GAIT_MIN_FOOTFALLS − 1 of a run wait from FF_WAITING on, WAITING_FIELDS each
(FF_SEEKING_MAX, FF_CUR_MIN, FF_CUR_MAX, FF_T_MAX, FF_HELD_T, FF_HELD_VALUE, FF_LAST_T,
 FF_COUNT, FF_PITCH_MAX, FF_PITCH_MIN, FF_T_PITCH_MIN, FF_RUN, FF_WAITING) = range(13)
# a waiting footfall: its time [s], whether it closes a cycle (1/0), and if so the cycle's
# θ_max, θ_min [rad] and the time of θ_min [s]
W_T, W_CLOSES, W_PITCH_MAX, W_PITCH_MIN, W_T_PITCH_MIN = range(5)
WAITING_FIELDS = 5
N_FOOTFALL_SCALARS = FF_WAITING + WAITING_FIELDS * (GAIT_MIN_FOOTFALLS - 1)


def new_footfall_state() -> np.ndarray:
    """Seeking a minimum, nothing held, no footfall yet."""
    s = np.zeros(N_FOOTFALL_SCALARS)
    s[FF_CUR_MIN], s[FF_CUR_MAX] = np.inf, -np.inf
    s[FF_HELD_T] = s[FF_LAST_T] = -np.inf
    s[FF_PITCH_MAX], s[FF_PITCH_MIN] = -np.inf, np.inf
    return s


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
def _in_rhythm(s, t_ff, t_now, max_interval_s, events, count):
    """A footfall at ``t_ff`` found at ``t_now``, counted once its run holds
    GAIT_MIN_FOOTFALLS (the run's waiting ones first); a footfall farther than
    ``max_interval_s`` from the last starts a new run, dropping a shorter one. Every
    second footfall counted closes a gait cycle of the sensor leg with the pitch's
    extremes since the last: a waiting footfall that will close one keeps them."""
    if t_ff - s[FF_LAST_T] > max_interval_s:
        s[FF_RUN] = 0.0
    s[FF_LAST_T] = t_ff
    s[FF_RUN] += 1.0
    run = int(s[FF_RUN])
    uncounted = run if run <= GAIT_MIN_FOOTFALLS else 1     # this one and those waiting
    closes = (s[FF_COUNT] + uncounted) % 2 == 0.0
    if run < GAIT_MIN_FOOTFALLS:
        w = FF_WAITING + WAITING_FIELDS * (run - 1)
        s[w + W_T], s[w + W_CLOSES] = t_ff, 1.0 if closes else 0.0
        if closes:
            s[w + W_PITCH_MAX], s[w + W_PITCH_MIN] = s[FF_PITCH_MAX], s[FF_PITCH_MIN]
            s[w + W_T_PITCH_MIN] = s[FF_T_PITCH_MIN]
            s[FF_PITCH_MAX], s[FF_PITCH_MIN] = -np.inf, np.inf
        return count
    if run == GAIT_MIN_FOOTFALLS:
        for i in range(GAIT_MIN_FOOTFALLS - 1):
            w = FF_WAITING + WAITING_FIELDS * i
            if s[w + W_CLOSES] > 0:
                count = _cycle(events, count, s[w + W_T], t_now, s[w + W_PITCH_MAX],
                               s[w + W_PITCH_MIN], s[w + W_T_PITCH_MIN])
        s[FF_COUNT] += GAIT_MIN_FOOTFALLS - 1
    s[FF_COUNT] += 1.0
    if closes:
        count = _cycle(events, count, t_ff, t_now, s[FF_PITCH_MAX], s[FF_PITCH_MIN],
                       s[FF_T_PITCH_MIN])
        s[FF_PITCH_MAX], s[FF_PITCH_MIN] = -np.inf, np.inf
    return count


@njit(cache=True)
def footfall_loop(s, prominence, min_interval_s, max_interval_s, t, force, pitch, events):
    """Footfalls in the low-passed specific force's norm ``force`` [m/s²] (N,), and the
    gait cycles they close into ``events`` (rows of EV_* columns, every second footfall;
    returns how many). A footfall is a peak standing ``prominence`` above the troughs on
    both sides (risen that much since the last trough, fallen that much since), at least
    ``min_interval_s`` from the last one: a peak is held that long, and a higher one
    within it takes its place (scipy.signal.find_peaks' ``distance``, causally, with
    ``min_interval_s`` of latency), and in a run of them (:func:`_in_rhythm`, spaced at
    most ``max_interval_s``). ``pitch`` [rad] (NaN: unknown) gives each cycle its θ_max
    and θ_min."""
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
            count = _in_rhythm(s, s[FF_HELD_T], t[k], max_interval_s, events, count)
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
