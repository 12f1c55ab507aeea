"""The NumPy twin of the pitch peaks: :func:`pdr_pocket.compiled_peaks.peak_loop` (the
confirmed maxima of the thigh pitch θ, Muñoz Díaz 2016, Section 4.1.1, with the
thresholds of Figs. 4.1–4.3 and the limits beyond the thesis) against
:func:`confirmed_maxima`, a plain Python loop written from the kernel's module docstring,
on hypothesis-drawn pitch series and parameters and on a noisy walking swing: the same
events, to the last bit. The last test changes one line of the kernel and shows that the
twin then fails.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_pocket import compiled_peaks
from pdr_pocket.compiled_peaks import N_EVENT_COLUMNS, PeakParams, new_peak_state, peak_loop
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
