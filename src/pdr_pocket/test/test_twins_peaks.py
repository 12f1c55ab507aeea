"""The NumPy twins of the step detectors' loops (:mod:`pdr_pocket.compiled_peaks`):

- :func:`~pdr_pocket.compiled_peaks.peak_loop` (the confirmed maxima of the thigh pitch θ,
  Muñoz Díaz 2016, Section 4.1.1, with the thresholds of Figs. 4.1–4.3 and the limits
  beyond the thesis) against :func:`confirmed_maxima`,
- :func:`~pdr_pocket.compiled_peaks.footfall_loop` (beyond the thesis: footfalls in the
  specific force's norm, counted in runs of GAIT_MIN_FOOTFALLS, every second closing a
  gait cycle) against :class:`FootfallRhythm`,

plain Python written from the kernels' docstrings, on hypothesis-drawn series and
parameters, in one call or split anywhere with the state carried over, and on realistic
signals: the same events, to the last bit (the kernels compare and copy samples, and add
nothing up). For each, one line of the kernel changed makes its twin fail.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.walking.gait import GAIT_MIN_FOOTFALLS
from pdr_pocket import compiled_peaks
from pdr_pocket.compiled_peaks import (
    N_EVENT_COLUMNS,
    PeakParams,
    footfall_loop,
    new_footfall_state,
    new_peak_state,
    peak_loop,
)
from pdr_pocket.config import StepsConfig
from pdr_pocket.steps import peak_params


def confirmed_maxima(t, theta, params: PeakParams) -> np.ndarray:
    """The docstring's rule: rows (t_max, θ_max, θ_min, t_min, t_confirmed)."""
    events = []
    seeking_max, top, t_top, bottom, t_bottom = False, -math.inf, 0.0, math.inf, 0.0
    amplitude, last_step = 0.0, -math.inf       # of the last accepted step
    for now, x in zip(t, theta, strict=True):
        if not math.isfinite(x):
            continue                            # NaN samples are skipped
        if now - last_step > params.forget_s:
            amplitude = 0.0                     # no step for so long: forgotten
        if seeking_max:
            if x > top:
                top, t_top = x, now
            if top - x >= max(params.drop_min, params.drop_fraction * amplitude):
                rise = top - bottom             # confirmed: fallen enough below the top
                if (params.min_amplitude <= rise <= params.max_amplitude
                        and t_top - t_bottom <= params.max_rise_s
                        and now - t_top <= params.max_hold_s
                        and t_top - last_step >= params.min_period_s):
                    events.append((t_top, top, bottom, t_bottom, now))
                    amplitude, last_step = rise, t_top
                seeking_max, bottom, t_bottom = False, x, now
        else:
            if x < bottom:
                bottom, t_bottom = x, now
            if x - bottom >= max(params.rise_min, params.rise_fraction * amplitude):
                seeking_max, top, t_top = True, x, now      # risen enough: re-armed
    return np.array(events, dtype=float).reshape(-1, N_EVENT_COLUMNS)


def kernel_events(kernel, t, theta, params: PeakParams, split: int | None = None) -> np.ndarray:
    """``kernel``'s events over the series, in two calls split at ``split`` (the state
    carried between them, as the live node feeds it) or in one."""
    state, rows = new_peak_state(), []
    for part in (slice(0, split), slice(split, None)) if split is not None else (slice(None),):
        events = np.empty((len(t) + 1, N_EVENT_COLUMNS))
        count = kernel(state, params, np.ascontiguousarray(t[part]),
                       np.ascontiguousarray(theta[part]), events)
        rows.append(events[:count])
    return np.concatenate(rows)


def walking_swing(seconds: float = 60.0, seed: int = 3):
    """θ [rad] of a thigh at 100 Hz: 0.5 rad swings of a 1.1 s gait cycle with a second
    heel-strike bump, noise, a 3 s stop and NaN readings."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 0.01)
    phase = 2.0 * np.pi * t / 1.1
    theta = 0.5 * np.sin(phase) + 0.08 * np.sin(2.0 * phase + 1.0) + 0.02 * rng.normal(size=t.size)
    theta[(t > 20.0) & (t < 23.0)] = 0.05
    theta[rng.random(t.size) < 0.01] = np.nan
    return t, theta


REAL = peak_params(StepsConfig())
drawn_params = st.builds(
    PeakParams, drop_min=st.floats(0.01, 0.3), drop_fraction=st.floats(0.0, 0.8),
    rise_min=st.floats(0.01, 0.3), rise_fraction=st.floats(0.0, 0.8),
    min_amplitude=st.floats(0.0, 0.5), max_amplitude=st.floats(0.5, 3.0),
    max_rise_s=st.floats(0.1, 3.0), max_hold_s=st.floats(0.1, 3.0),
    min_period_s=st.floats(0.0, 1.5), forget_s=st.floats(0.5, 5.0))


@settings(max_examples=100, deadline=None)
@given(steps=st.lists(st.floats(-0.3, 0.3) | st.just(math.nan), min_size=1, max_size=300),
       dt=st.lists(st.floats(0.001, 0.3), min_size=300, max_size=300),
       params=st.one_of(st.just(REAL), drawn_params), data=st.data())
def test_peak_loop_is_its_twin(steps, dt, params, data):
    """A random walk of θ (NaN steps leave a NaN reading), split anywhere."""
    theta = np.cumsum(np.nan_to_num(steps))
    theta[np.isnan(steps)] = np.nan
    t = np.cumsum(dt[:len(theta)])
    split = data.draw(st.integers(0, len(t)))
    twin = confirmed_maxima(t, theta, params)
    np.testing.assert_array_equal(kernel_events(peak_loop, t, theta, params), twin)
    np.testing.assert_array_equal(kernel_events(peak_loop, t, theta, params, split), twin)


def test_peak_loop_is_its_twin_on_a_walking_swing():
    t, theta = walking_swing()
    twin = confirmed_maxima(t, theta, REAL)
    assert 45 <= len(twin) <= 55                    # one per gait cycle, none at the stop
    np.testing.assert_array_equal(kernel_events(peak_loop, t, theta, REAL), twin)
    np.testing.assert_array_equal(kernel_events(peak_loop, t, theta, REAL, 2000), twin)


def test_a_factor_slipped_in_peak_loop_fails_its_twin(perturb):
    """The amplitude remembered at half the rise: every later confirmation comes early."""
    wrong = perturb(peak_loop, compiled_peaks, "s.last_amplitude = rise",
                    "s.last_amplitude = 0.5 * rise")
    t, theta = walking_swing()
    with pytest.raises(AssertionError, match="Arrays are not equal"):
        np.testing.assert_array_equal(kernel_events(wrong, t, theta, REAL),
                                      confirmed_maxima(t, theta, REAL))


# --- footfalls ------------------------------------------------------------------------
class FootfallRhythm:
    """The footfall docstring's rule: prominent peaks of the force's norm, held for
    min_interval_s (a higher one within takes their place), counted in a run of
    GAIT_MIN_FOOTFALLS each within max_interval_s of the last; every second counted one
    closes a gait cycle with θ's extremes since the last cycle (kept by a waiting one)."""

    def __init__(self, prominence, min_interval_s, max_interval_s) -> None:
        self.prominence, self.min_s, self.max_s = prominence, min_interval_s, max_interval_s
        self.seeking_max, self.low, self.high, self.t_high = False, math.inf, -math.inf, 0.0
        self.held: tuple[float, float] | None = None          # (t, value)
        self.last = -math.inf                   # the last footfall, counted or waiting
        self.counted, self.run = 0, 0
        self.waiting: list[tuple[float, bool, tuple]] = []    # (t, closes, extremes)
        self.top, self.bottom, self.t_bottom = -math.inf, math.inf, 0.0
        self.events: list[tuple] = []

    def push(self, t, force, pitch) -> np.ndarray:
        self.events = []
        for now, x, theta in zip(t, force, pitch, strict=True):
            if math.isfinite(theta):
                if theta > self.top:
                    self.top = theta
                if theta < self.bottom:
                    self.bottom, self.t_bottom = theta, now
            if self.held is not None and now - self.held[0] >= self.min_s:
                self.footfall(self.held[0], now)
                self.held = None
            if not math.isfinite(x):
                continue
            if self.seeking_max:
                if x > self.high:
                    self.high, self.t_high = x, now
                if self.high - x >= self.prominence:        # a peak: fallen enough
                    if self.t_high - self.last >= self.min_s and (
                            self.held is None or self.high > self.held[1]):
                        self.held = (self.t_high, self.high)
                    self.seeking_max, self.low = False, x
            else:
                self.low = min(self.low, x)
                if x - self.low >= self.prominence:         # risen enough: seek the peak
                    self.seeking_max, self.high, self.t_high = True, x, now
        return np.array(self.events, dtype=float).reshape(-1, N_EVENT_COLUMNS)

    def footfall(self, t_ff, now) -> None:
        if t_ff - self.last > self.max_s:
            self.run, self.waiting = 0, []      # out of rhythm: a new run, a short one dropped
        self.last, self.run = t_ff, self.run + 1
        closes = (self.counted + len(self.waiting) + 1) % 2 == 0
        extremes = (self.top, self.bottom, self.t_bottom)
        if closes:
            self.top, self.bottom = -math.inf, math.inf
        if self.run < GAIT_MIN_FOOTFALLS:
            self.waiting.append((t_ff, closes, extremes))
            return
        for t_waiting, closes_waiting, kept in [*self.waiting, (t_ff, closes, extremes)]:
            self.counted += 1
            if closes_waiting:
                top, bottom, t_bottom = kept
                self.events.append((t_waiting, top, bottom, t_bottom, now))
        self.waiting = []


def kernel_cycles(kernel, args, t, force, pitch, split: int | None = None):
    """``kernel``'s cycles and footfall count, in one call or two split at ``split``."""
    state, rows = new_footfall_state(), []
    for part in (slice(0, split), slice(split, None)) if split is not None else (slice(None),):
        events = np.empty((len(t) + GAIT_MIN_FOOTFALLS, N_EVENT_COLUMNS))
        count = kernel(state, *args, *(np.ascontiguousarray(x[part]) for x in (t, force, pitch)),
                       events)
        rows.append(events[:count])
    return np.concatenate(rows), state.scalars[0].footfalls


def twin_cycles(args, t, force, pitch, split: int | None = None):
    twin = FootfallRhythm(*args)
    parts = (slice(0, split), slice(split, None)) if split is not None else (slice(None),)
    return np.concatenate([twin.push(t[p], force[p], pitch[p]) for p in parts]), twin.counted


def striding_force(seconds: float = 60.0, seed: int = 4):
    """A low-passed specific force's norm [m/s²] at 100 Hz: two footfalls per 1.1 s gait
    cycle with a lesser bump between, noise, a 4 s stop, a lone bump in it and NaN
    readings; θ [rad] swinging with the cycle."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 0.01)
    phase = 2.0 * np.pi * t / 0.55
    force = STANDARD_GRAVITY_MPS2 + 2.5 * np.sin(phase) + 0.8 * np.sin(2.0 * phase + 0.7) + \
        0.2 * rng.normal(size=t.size)
    stop = (t > 20.0) & (t < 24.0)
    force[stop] = STANDARD_GRAVITY_MPS2 + 0.05 * rng.normal(size=stop.sum())
    force += 4.0 * np.exp(-0.5 * ((t - 22.0) / 0.05) ** 2)
    force[rng.random(t.size) < 0.01] = np.nan
    pitch = 0.5 * np.sin(phase / 2.0) + 0.02 * rng.normal(size=t.size)
    pitch[rng.random(t.size) < 0.02] = np.nan
    return t, force, pitch


SHIPPED = (StepsConfig().footfall_prominence_mps2, StepsConfig().footfall_min_interval_s,
           0.5 * StepsConfig().max_step_period_s)


@settings(max_examples=100, deadline=None)
@given(samples=st.lists(st.tuples(st.floats(-1.5, 1.5) | st.just(math.nan),
                                   st.floats(0.005, 0.4),
                                   st.floats(-1.0, 1.0) | st.just(math.nan)),
                         min_size=1, max_size=300),
       args=st.one_of(st.just(SHIPPED), st.tuples(st.floats(0.2, 3.0), st.floats(0.0, 1.0),
                                                  st.floats(0.3, 2.0))),
       data=st.data())
def test_footfall_loop_is_its_twin(samples, args, data):
    """A random walk of the force (NaN steps leave a NaN reading), any θ, split anywhere."""
    steps, dt, theta = (np.array(x) for x in zip(*samples, strict=True))
    force = STANDARD_GRAVITY_MPS2 + np.cumsum(np.nan_to_num(steps))
    force[np.isnan(steps)] = np.nan
    t = np.cumsum(dt)
    split = data.draw(st.integers(0, len(t)))
    events, counted = twin_cycles(args, t, force, theta)
    for kernel_split, twin_split in ((None, None), (split, split)):
        kernel_events, kernel_count = kernel_cycles(footfall_loop, args, t, force, theta,
                                                    kernel_split)
        np.testing.assert_array_equal(kernel_events, twin_cycles(args, t, force, theta,
                                                                 twin_split)[0])
        np.testing.assert_array_equal(kernel_events, events)
        assert kernel_count == counted


def test_footfall_loop_is_its_twin_on_a_striding_force():
    t, force, pitch = striding_force()
    events, counted = twin_cycles(SHIPPED, t, force, pitch)
    assert 45 <= len(events) <= 55 and 90 <= counted <= 110     # the lone bump not counted
    for split in (None, 2200, 3000):
        kernel_events, kernel_count = kernel_cycles(footfall_loop, SHIPPED, t, force, pitch,
                                                    split)
        np.testing.assert_array_equal(kernel_events, events)
        assert kernel_count == counted


def test_a_parity_slipped_in_the_rhythm_fails_its_twin(perturb):
    """Every odd footfall closing the cycle instead of every second: the cycles end a
    footfall early, at the other leg's."""
    rhythm = perturb(compiled_peaks._in_rhythm, compiled_peaks,
                     "closes = (s.footfalls + uncounted) % 2 == 0",
                     "closes = (s.footfalls + uncounted) % 2 == 1")
    wrong = perturb(footfall_loop, compiled_peaks, "count = _in_rhythm(", "count = rhythm(",
                    calls={"rhythm": rhythm})
    t, force, pitch = striding_force()
    with pytest.raises(AssertionError, match="Arrays are not equal"):
        np.testing.assert_array_equal(kernel_cycles(wrong, SHIPPED, t, force, pitch)[0],
                                      twin_cycles(SHIPPED, t, force, pitch)[0])
