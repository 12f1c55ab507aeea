"""The gravity direction without a gyroscope, compiled with numba: the specific force through
two first-order low-passes in cascade (backward Euler gains,
:func:`pdr_core.maths.lowpass.backward_euler_gain`), and a motion measure, for the pocket
navigator's pitch from the gravity direction alone (pdr_pocket.pitch_source). Its state is
:class:`GravityState` (a record of scalars, :data:`GRAVITY_SCALARS`).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache, lowpass
from pdr_core.maths.lowpass import backward_euler_gain

kernel_cache.forget_if_changed(__file__, lowpass.__file__)


# GravityState.scalars, one record
GRAVITY_SCALARS = np.dtype([
    ("started", np.bool_),          # a sample has been seen (last_t holds its time)
    ("last_t", np.float64),         # the time of the last sample [s]
    ("motion", np.float64),         # the motion measure, ‖α − gravity‖ low-passed [m/s²]
], align=True)


class GravityState(NamedTuple):
    scalars: np.ndarray         # () GRAVITY_SCALARS record
    first: np.ndarray           # (3,) the specific force through the first low-pass [m/s²]
    gravity: np.ndarray         # (3,) ... and through the second: gravity, sensor frame


def new_gravity_state() -> GravityState:
    """Nothing seen: the first sample starts both stages at its specific force."""
    return GravityState(np.zeros((), GRAVITY_SCALARS), np.zeros(3), np.zeros(3))


@njit(cache=True)
def gravity_loop(state, tau_s, motion_tau_s, t, accel, out_gravity, out_motion):
    """Without a gyroscope: the gravity direction as the specific force ``accel`` [m/s²]
    (N, 3) at times ``t`` [s] (N,) through two first-order low-passes in cascade (time
    constant ``tau_s`` each, any sample rate) into ``out_gravity`` (N, 3) [m/s²], and a
    motion measure, ‖α − gravity‖ through one low-pass of ``motion_tau_s``, into
    ``out_motion`` (N,) [m/s²]."""
    s = state.scalars[()]
    first, gravity = state.first, state.gravity
    for k in range(len(t)):
        a = accel[k]
        if not s.started:
            first[:] = a
            gravity[:] = a
            s.started = True
            dt = 0.0
        else:
            dt = t[k] - s.last_t
        s.last_t = t[k]
        alpha = backward_euler_gain(dt, tau_s)
        first += alpha * (a - first)
        gravity += alpha * (first - gravity)
        out_gravity[k] = gravity
        d = a - gravity
        beta = backward_euler_gain(dt, motion_tau_s)
        s.motion += beta * (np.sqrt(d @ d) - s.motion)
        out_motion[k] = s.motion
