"""The trailing windows of the thesis' orientation filter's detectors
(pdr_pocket.compiled_orientation; Muñoz Díaz 2016, Section 3.2), causal so that the live
node gives the offline result: a ring of the last :data:`RING` samples' |‖α‖ − g|, ‖ω‖, ω
and C·μ, and the tests over a window of it: the largest value (:func:`window_max`, zero
acceleration), every rate within a threshold of the window's mean (:func:`at_rest`, zero
angular rate) and a steady field (:func:`mag_steady`), all of them at a sample by
:func:`detect`. The ring's count and head are fields of the filter state's scalars
(``ring_count``, ``ring_head`` of pdr_pocket.compiled_orientation_data.FILTER_SCALARS),
which the window tests are given as ``scalars`` (the state's (1,) record array).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache
from pdr_pocket import compiled_orientation_data
from pdr_pocket.compiled_orientation_data import (
    ATT_EAST,
    ATT_NORTH,
    RING,
    Detected,
)

kernel_cache.forget_if_changed(__file__, compiled_orientation_data.__file__)



@njit(cache=True)
def push_ring(state, params, t, sample):
    """Add the sample to the trailing windows: |‖α‖ − g|, ‖ω‖ and C·μ (NaN: no reading);
    returns its row."""
    s = state.scalars[0]
    head = s.ring_head
    a, w, mu, c = sample.accel, sample.gyro, sample.mag, state.attitude
    state.ring_t[head] = t
    state.ring_acc[head] = abs(np.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2) - params.gravity)
    state.ring_rate[head] = np.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2)
    state.ring_gyro[head, 0], state.ring_gyro[head, 1], state.ring_gyro[head, 2] = \
        w[0], w[1], w[2]
    nav = state.ring_mag[head]
    if np.isfinite(mu[0]):
        for m in range(3):
            nav[m] = c[m, 0] * mu[0] + c[m, 1] * mu[1] + c[m, 2] * mu[2]
    else:
        nav[:] = np.nan
    s.ring_head = (head + 1) % RING
    s.ring_count = min(RING, s.ring_count + 1)
    return head


@njit(cache=True)
def window_count(ring_t, scalars, t, window_s):
    """How many of the ring's newest samples lie within the last ``window_s`` seconds before
    ``t`` (−1 while the ring does not yet reach back that far)."""
    count, head = scalars[0].ring_count, scalars[0].ring_head
    for j in range(count):
        if t - ring_t[(head - 1 - j) % RING] > window_s + 1e-9:
            return j
    return -1


@njit(cache=True)
def window_max(ring_t, values, scalars, t, window_s):
    """Max of ``values`` (a ring of the state) over the samples of the last ``window_s``
    seconds (−1 when the window is not yet full)."""
    n, head = window_count(ring_t, scalars, t, window_s), scalars[0].ring_head
    if n < 0:
        return -1.0
    best = -np.inf
    for j in range(n):
        best = max(best, values[(head - 1 - j) % RING])
    return best


@njit(cache=True)
def at_rest(ring_t, ring_gyro, scalars, t, window_s, threshold, out):
    """Whether every ω of the last ``window_s`` seconds lies within ``threshold`` of their
    mean (False while the window is not yet full); then into ``out`` (2, 3) ω̄, the mean of
    the window's older half (a stop's last samples, the thigh starting to move below the
    threshold, are not in it), and the variance of ω over it per axis."""
    n, head = window_count(ring_t, scalars, t, window_s), scalars[0].ring_head
    if n <= 0:
        return False
    m0 = m1 = m2 = 0.0
    for j in range(n):
        i = (head - 1 - j) % RING
        m0 += ring_gyro[i, 0]
        m1 += ring_gyro[i, 1]
        m2 += ring_gyro[i, 2]
    m0, m1, m2 = m0 / n, m1 / n, m2 / n
    limit = threshold * threshold
    o0 = o1 = o2 = 0.0
    older = 0
    for j in range(n):
        i = (head - 1 - j) % RING
        if (ring_gyro[i, 0] - m0) ** 2 + (ring_gyro[i, 1] - m1) ** 2 + \
                (ring_gyro[i, 2] - m2) ** 2 > limit:
            return False
        if t - ring_t[i] >= 0.5 * window_s:
            o0 += ring_gyro[i, 0]
            o1 += ring_gyro[i, 1]
            o2 += ring_gyro[i, 2]
            older += 1
    if older == 0:
        return False
    out[0, 0], out[0, 1], out[0, 2] = o0 / older, o1 / older, o2 / older
    out[1, :] = 0.0
    for j in range(n - older, n):
        i = (head - 1 - j) % RING
        for m in range(3):
            out[1, m] += (ring_gyro[i, m] - out[0, m]) ** 2 / older
    return True


@njit(cache=True)
def mag_steady(ring_t, ring_mag, scalars, t, params):
    """Norm spread and angle to the mean direction of C·μ over the trailing window."""
    n, head = window_count(ring_t, scalars, t, params.mag_window_s), scalars[0].ring_head
    if n < 2:
        return False
    total = np.zeros(3)
    lo, hi = np.inf, -np.inf
    for j in range(n):
        v = ring_mag[(head - 1 - j) % RING]
        if not np.isfinite(v[0]):
            return False
        norm = np.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
        lo, hi = min(lo, norm), max(hi, norm)
        total += v / max(norm, 1e-12)
    if hi - lo > params.mag_norm_threshold:
        return False
    mean = total / max(np.sqrt(total[0] ** 2 + total[1] ** 2 + total[2] ** 2), 1e-12)
    min_cos = np.cos(params.mag_direction_threshold)
    for j in range(n):
        i = (head - 1 - j) % RING
        v = ring_mag[i]
        if v[0] * mean[0] + v[1] * mean[1] + v[2] * mean[2] < min_cos * np.sqrt(
                v[0] ** 2 + v[1] ** 2 + v[2] ** 2):
            return False
    return True


@njit(cache=True)
def detect(state, params, t, sample):
    """Push the sample into the trailing windows and read the detectors there; take the
    field reference μ̄_r at the start of a steady period."""
    s, ring_t, ring_rate = state.scalars, state.ring_t, state.ring_rate
    newest = push_ring(state, params, t, sample)
    zero_acc = 0.0 <= window_max(ring_t, state.ring_acc, s, t, params.zero_acc_window_s) \
        <= params.zero_acc_threshold and window_max(
            ring_t, ring_rate, s, t, params.zero_acc_window_s) <= params.zero_acc_max_rate
    zero_rate = at_rest(ring_t, state.ring_gyro, s, t, params.zero_rate_window_s,
                         params.zero_rate_threshold, state.rest_rate)
    steady = np.isfinite(sample.mag[0]) and mag_steady(ring_t, state.ring_mag, s, t, params)
    # the absolute field update holds the attitude to the field's direction taken at
    # the start of the steady period: taken while the tilt is uncertain (after a gap)
    # it would hold an error as if it were known
    p = state.covariance
    was_steady = s[0].mag_was_steady
    anchored = steady and (was_steady or max(
        p[ATT_EAST, ATT_EAST], p[ATT_NORTH, ATT_NORTH]) <= params.mag_reference_max_var)
    if anchored and not was_steady:
        state.mag_reference[:] = state.ring_mag[newest]
    s[0].mag_was_steady = anchored
    return Detected(zero_acc, zero_rate, steady, anchored)
