"""Windows of whole gait cycles, compiled with numba: the gravity reference of a swinging
thigh, shared by both orientation filters (pdr_pocket.compiled_orientation's mean gravity
update, pdr_pocket.compiled_attitude's cycle update).

Over a window of W seconds the specific force turned to the navigation frame sums to
g·W·e_up plus the window's change of velocity, Σ C·α·δt = g·W·e_up + Δv. Over whole gait
cycles the velocity comes back, so Δv is the cycle-to-cycle change only (0.15 m/s), and
the summed direction, turned to the body frame, is the vertical there to σ_Δv/(g·W): the
thigh's lever-arm and swing accelerations, periodic in the cycle, are gone exactly,
whatever their size. A window runs from one *swing marker* to another: the marker is
where the rate about the swing axis (the principal axis of E[ω·ωᵀ], one power iteration
per sample: a thigh's swing and stance turn it about one axis, the flexion axis, so its
sign stays) turns back through zero after a lobe faster than a threshold, once per gait
cycle at the same phase. A window that did not start at a marker closes by time, first
after 2, 4, 8 s ... up to ``window_max_s`` (a start while walking leaves the first
sample's tilt up to 15° off); one that did closes at the first marker after
``cycle_min_s``. A gap in the samples restarts it (a window across the gap would average
two attitudes).

:class:`GaitWindow` is the window's state (its scalars in a record, :data:`WINDOW_SCALARS`),
:class:`WindowParams` what the configuration sets, :class:`WindowEnd` what a sample did to
it. The window also keeps its attitude memory S = Σ_k δt_k·∫_{t_k}^{t} C ds, from which a
filter that carries its attitude error δθ(t) reads the window's mean error
δθ(t) + (S/W)·δb under a gyro bias error δb (δθ̇ = −C·δb), the sum A = Σ C·δt through
which an accelerometer bias error δb_a adds A·δb_a to the summed force, and its first
attitude, from
which :func:`turned` tells how far the walker turned over it: a walker turning by Δψ at
speed v changes velocity by about v·Δψ, which whole cycles do not bring back.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache, lowpass, small_matrix
from pdr_core.maths.lowpass import forward_euler_gain
from pdr_core.maths.small_matrix import product3

kernel_cache.forget_if_changed(__file__, small_matrix.__file__, lowpass.__file__)

WINDOW_SCALARS = np.dtype([
    ("time_s", np.float64),         # the window's length so far [s]
    ("done", np.int64),             # windows closed
    ("armed", np.bool_),            # a swing lobe was fast enough: the next zero crossing
                                    # of the swing rate is a marker
    ("from_marker", np.bool_),      # the window started at a swing marker
])


class WindowParams(NamedTuple):
    """What the configuration sets (pdr_pocket.config), SI units."""

    window_max_s: float             # a window not started at a marker closes by this
    cycle_min_s: float              # a window of whole cycles: at least this long [s]
    swing_time_constant_s: float    # of the swing axis [s]
    swing_rate_threshold: float     # a swing lobe this fast [rad/s] arms the next marker
    gravity: float                  # [m/s²]


class GaitWindow(NamedTuple):
    """The window's memory, changed in place."""

    force_sum: np.ndarray           # (3,) Σ C·α·δt [m/s], navigation frame
    memory: np.ndarray              # (3, 3) S = Σ_k δt_k·∫_{t_k}^{t} C ds [s²]
    attitude_sum: np.ndarray        # (3, 3) A = Σ C·δt [s]
    start: np.ndarray               # (3, 3) C_b^n at the window's first sample
    swing: np.ndarray               # (3, 3) E[ω·ωᵀ], exponentially weighted [rad²/s²]
    swing_axis: np.ndarray          # (3,) its principal axis (the thigh's flexion axis)
    scalars: np.ndarray             # (1,) record of WINDOW_SCALARS


class WindowEnd(NamedTuple):
    """Whether the window ends at this sample, and how."""

    marker: bool                    # a swing marker (once per gait cycle) at this sample
    closes: bool                    # the window closes: its update is due
    cycles: bool                    # ... from one marker to another (whole gait cycles)


def new_gait_window() -> GaitWindow:
    """An empty window, the swing axis not yet known."""
    return GaitWindow(np.zeros(3), np.zeros((3, 3)), np.zeros((3, 3)), np.eye(3),
                      np.zeros((3, 3)),
                      np.full(3, 1.0 / np.sqrt(3.0)), np.zeros(1, dtype=WINDOW_SCALARS))


@njit(cache=True, inline='always')
def swing_marker(window, params, gyro, dt):
    """True once per gait cycle (the module docstring), at the sample with rate ω
    [rad/s] after δt [s]."""
    s = window.scalars[0]
    alpha = forward_euler_gain(dt, params.swing_time_constant_s)
    m, u = window.swing, window.swing_axis
    for a in range(3):
        for b in range(3):
            m[a, b] += alpha * (gyro[a] * gyro[b] - m[a, b])
    v0 = m[0, 0] * u[0] + m[0, 1] * u[1] + m[0, 2] * u[2]
    v1 = m[1, 0] * u[0] + m[1, 1] * u[1] + m[1, 2] * u[2]
    v2 = m[2, 0] * u[0] + m[2, 1] * u[1] + m[2, 2] * u[2]
    norm = np.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
    if norm > 0.0:
        u[0], u[1], u[2] = v0 / norm, v1 / norm, v2 / norm
    rate = gyro[0] * u[0] + gyro[1] * u[1] + gyro[2] * u[2]
    if rate > params.swing_rate_threshold:
        s.armed = True
    elif rate < 0.0 and s.armed:
        s.armed = False
        return True
    return False


@njit(cache=True, inline='always')
def add_to_window(window, params, attitude, accel, dt, marker):
    """Add C·α·δt to the window's sum and C·δt to its memory; whether it closes now
    (:class:`WindowEnd`)."""
    s, c, total, memory = window.scalars[0], attitude, window.force_sum, window.memory
    if s.time_s == 0.0:
        window.start[:, :] = c
    for i in range(3):
        for j in range(3):
            memory[i, j] += s.time_s * c[i, j] * dt
            window.attitude_sum[i, j] += c[i, j] * dt
    s.time_s += dt
    for m in range(3):
        total[m] += dt * (c[m, 0] * accel[0] + c[m, 1] * accel[1] + c[m, 2] * accel[2])
    longest = min(params.window_max_s, 2.0 * 2.0 ** s.done)
    cycles = marker and s.from_marker and s.time_s >= params.cycle_min_s
    return WindowEnd(marker, cycles or s.time_s >= longest, cycles)


@njit(cache=True, inline='always')
def _empty(window):
    s = window.scalars[0]
    s.time_s = 0.0
    window.force_sum[:] = 0.0
    window.memory[:, :] = 0.0
    window.attitude_sum[:, :] = 0.0


@njit(cache=True, inline='always')
def restart_window(window, end):
    """A new window after one closed, or from the first swing marker of one that did not
    start at a marker."""
    s = window.scalars[0]
    if end.closes or (end.marker and not s.from_marker):
        if end.closes:
            s.done += 1
        s.from_marker = end.marker
        _empty(window)


@njit(cache=True)
def forget_window(window):
    """Drop the window after a gap in the samples."""
    window.scalars[0].from_marker = False
    _empty(window)


@njit(cache=True, inline='always')
def turned(window, attitude):
    """How far the body turned about the vertical since the window's first sample [rad]:
    the up component of the rotation C·C_startᵀ (its sine, exact for a turn about the
    vertical)."""
    c, s = attitude, window.start
    r10 = c[1, 0] * s[0, 0] + c[1, 1] * s[0, 1] + c[1, 2] * s[0, 2]
    r01 = c[0, 0] * s[1, 0] + c[0, 1] * s[1, 1] + c[0, 2] * s[1, 2]
    r00 = c[0, 0] * s[0, 0] + c[0, 1] * s[0, 1] + c[0, 2] * s[0, 2]
    r11 = c[1, 0] * s[1, 0] + c[1, 1] * s[1, 1] + c[1, 2] * s[1, 2]
    return np.arctan2(r10 - r01, r00 + r11)


@njit(cache=True)
def turn_window(window, rot):
    """Turn the window's sums with a correction ``rot`` (3, 3) of the attitude, as if the
    attitudes it summed had been corrected too."""
    f = window.force_sum
    f0 = rot[0, 0] * f[0] + rot[0, 1] * f[1] + rot[0, 2] * f[2]
    f1 = rot[1, 0] * f[0] + rot[1, 1] * f[1] + rot[1, 2] * f[2]
    f2 = rot[2, 0] * f[0] + rot[2, 1] * f[1] + rot[2, 2] * f[2]
    f[0], f[1], f[2] = f0, f1, f2
    turned = np.empty((3, 3))
    for matrix in (window.memory, window.attitude_sum, window.start):
        product3(rot, matrix, turned)
        matrix[:, :] = turned


@njit(cache=True, inline='always')
def force_in_body(attitude, force_sum):
    """The window's summed force Σ C·α·δt turned to the body frame with C [m/s], (3,)."""
    c, f = attitude, force_sum
    body = np.empty(3)
    for m in range(3):
        body[m] = c[0, m] * f[0] + c[1, m] * f[1] + c[2, m] * f[2]
    return body


@njit(cache=True, inline='always')
def holds_gravity(window, params, attitude):
    """Whether the window's summed force is a gravity reference: not far from g·W (free
    fall, or a sensor giving zeros, is not)."""
    body = force_in_body(attitude, window.force_sum)
    return np.sqrt(body[0] ** 2 + body[1] ** 2 + body[2] ** 2) > \
        0.5 * (params.gravity * window.scalars[0].time_s)


@njit(cache=True)
def across(v):
    """Two unit vectors orthogonal to v and to each other."""
    d = v / np.sqrt(v @ v)
    e = np.zeros(3)
    e[np.argmin(np.abs(d))] = 1.0
    b1 = np.cross(d, e)
    b1 /= np.sqrt(b1 @ b1)
    return b1, np.cross(d, b1)
