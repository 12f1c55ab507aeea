"""The magnetometer's entry point of the phone's attitude filter
(pdr_pocket.compiled_attitude): :func:`mag_step`. A field beyond the Earth's is no Earth
field (:func:`_plausible`); the first reading sets the field's magnitudes (and the heading
when it is taken from the field) against the offset still unknown (:func:`start_field`);
then the field update (:func:`field_update`), z = μ against h = Cᵀ·m_n + o, behind a χ²
gate, moving the heading, the offset and the field only. The derivation is
pdr_pocket.compiled_attitude's docstring.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_core.maths import angles, kernel_cache, lowpass, small_matrix
from pdr_core.maths.angles import wrap_angle_jit
from pdr_core.maths.lowpass import lowpass_gain
from pdr_core.maths.small_matrix import product3, rodrigues
from pdr_pocket import compiled_attitude_data, compiled_attitude_kalman
from pdr_pocket.compiled_attitude_data import (
    ATT_EAST,
    ATT_NORTH,
    ATT_UP,
    AZIMUTH_FROM_FIELD,
    BIAS,
    FIELD_DISTURBED,
    FIELD_DOWN,
    FIELD_HORIZONTAL,
    FIELD_IMPLAUSIBLE,
    FIELD_UNDISTURBED,
    HEADING_FROM_FIELD,
    MAGNITUDES_ONLY,
    NO_READING,
    OFFSET,
)
from pdr_pocket.compiled_attitude_kalman import (
    apply_correction,
    clear_work,
    innovation_covariance,
    kalman_update,
    nis,
)

kernel_cache.forget_if_changed(__file__, small_matrix.__file__, angles.__file__, lowpass.__file__,
                               compiled_attitude_data.__file__, compiled_attitude_kalman.__file__)

# --- the magnetometer --------------------------------------------------------------------
@njit(cache=True)
def _field_in_navigation(state, mu, out):
    """C·(μ − o) [T], (3,)."""
    c, o = state.attitude, state.offset
    for m in range(3):
        out[m] = c[m, 0] * (mu[0] - o[0]) + c[m, 1] * (mu[1] - o[1]) + c[m, 2] * (mu[2] - o[2])


@njit(cache=True)
def start_field(state, params, mu, how):
    """Take the field's magnitudes B_h, B_v from the reading μ [T] with the offset as it
    stands, and ``how``: :data:`HEADING_FROM_FIELD` also turns C about the vertical until
    the field's azimuth is γ, :data:`AZIMUTH_FROM_FIELD` takes γ as the field's azimuth
    in the map frame now, :data:`MAGNITUDES_ONLY` keeps both. Their covariance: an error
    δo of the offset makes errors J·δo of [ψ, B_h, B_v], J = [∂az/∂m·C; −e_hᵀ·C; e_upᵀ·C]
    (m = C·(μ − o), az its azimuth, e_h its horizontal direction), so P gets J·P_oo·Jᵀ
    plus the start variances, and the covariance J·P_oo with the offset; every other
    covariance of these rows is cleared."""
    s = state.scalars[0]
    m = np.empty(3)
    _field_in_navigation(state, mu, m)
    horizontal = np.sqrt(m[0] ** 2 + m[1] ** 2)
    if not horizontal > 0.0:
        return
    if how == HEADING_FROM_FIELD:
        rot, moved = np.empty((3, 3)), np.empty((3, 3))
        rodrigues(0.0, 0.0, wrap_angle_jit(params.field_azimuth - np.arctan2(m[1], m[0])), rot)
        product3(rot, state.attitude, moved)
        state.attitude[:, :] = moved
        _field_in_navigation(state, mu, m)
        s.field_azimuth = params.field_azimuth
    elif how == AZIMUTH_FROM_FIELD:
        s.field_azimuth = np.arctan2(m[1], m[0])
    state.field[0], state.field[1] = horizontal, -m[2]
    c, p = state.attitude, state.covariance
    # J (3 × 3) against δo: rows ψ, B_h, B_v
    j = np.empty((3, 3))
    for col in range(3):
        j[0, col] = (-m[1] * c[0, col] + m[0] * c[1, col]) / (horizontal * horizontal)
        j[1, col] = -(m[0] * c[0, col] + m[1] * c[1, col]) / horizontal
        j[2, col] = c[2, col]
    first = 0 if how == HEADING_FROM_FIELD else 1
    rows = np.array([ATT_UP, FIELD_HORIZONTAL, FIELD_DOWN])
    jp = np.zeros((3, 3))           # J·P_oo
    for a in range(3):
        for col in range(3):
            for b in range(3):
                jp[a, col] += j[a, b] * p[OFFSET + b, OFFSET + col]
    for a in range(first, 3):
        p[rows[a], :] = 0.0
        p[:, rows[a]] = 0.0
    for a in range(first, 3):
        for b in range(first, 3):
            p[rows[a], rows[b]] = jp[a, 0] * j[b, 0] + jp[a, 1] * j[b, 1] + jp[a, 2] * j[b, 2]
        for col in range(3):
            p[rows[a], OFFSET + col] = p[OFFSET + col, rows[a]] = jp[a, col]
    if how == HEADING_FROM_FIELD:
        p[ATT_UP, ATT_UP] += params.heading_start_var
    p[FIELD_HORIZONTAL, FIELD_HORIZONTAL] += params.field_start_var
    p[FIELD_DOWN, FIELD_DOWN] += params.field_start_var
    s.field_started = True
    s.refused_s = 0.0


@njit(cache=True, inline='always')
def _field_model(state, work, mu):
    """The field update's innovation μ − (Cᵀ·m_n + o) and H (module docstring) into
    ``work``, the tilt and bias rows frozen."""
    s = state.scalars[0]
    c, o = state.attitude, state.offset
    east, north = np.cos(s.field_azimuth), np.sin(s.field_azimuth)
    m0, m1, m2 = state.field[0] * east, state.field[0] * north, -state.field[1]
    clear_work(work)
    for i in range(3):
        predicted = c[0, i] * m0 + c[1, i] * m1 + c[2, i] * m2 + o[i]
        work.innovation[i] = mu[i] - predicted
        # Cᵀ·[m_n×], row i
        work.h[i, ATT_EAST] = c[1, i] * m2 - c[2, i] * m1
        work.h[i, ATT_NORTH] = c[2, i] * m0 - c[0, i] * m2
        work.h[i, ATT_UP] = c[0, i] * m1 - c[1, i] * m0
        work.h[i, OFFSET + i] = 1.0
        work.h[i, FIELD_HORIZONTAL] = c[0, i] * east + c[1, i] * north
        work.h[i, FIELD_DOWN] = -c[2, i]
    work.frozen[ATT_EAST] = work.frozen[ATT_NORTH] = True
    for m in range(3):
        work.frozen[BIAS + m] = True


@njit(cache=True, inline='always')
def field_update(state, params, work, mu, dt):
    """The field update (the module docstring); (undisturbed, applied)."""
    s = state.scalars[0]
    _field_model(state, work, mu)
    innovation_covariance(state.covariance, work, 3)
    if nis(work, 3, params.field_var) > params.field_gate_nis:
        s.refused_s += dt
        if s.refused_s >= params.field_reset_s:
            s.field_resets += 1
            for m in range(3):
                state.covariance[OFFSET + m, OFFSET + m] += params.offset_reset_var
            start_field(state, params, mu, MAGNITUDES_ONLY)
        return False, False
    s.refused_s = 0.0
    if not kalman_update(state.covariance, work, 3,
                         params.field_var * 2.0 * params.field_tau_s / dt):
        return True, False
    apply_correction(state, work)
    return True, True


@njit(cache=True, inline='always')
def _plausible(state, params, mu, dt):
    """Whether the magnetometer reads an Earth field: ‖μ − o‖, low-passed over
    ``field_norm_tau_s`` (its first value the first reading's), within the range the
    Earth's field spans (pdr_core.constants): an uncalibrated magnetometer, whose phone's
    own hard iron dwarfs the field, or a phone lying on steel reads far beyond it."""
    s, o = state.scalars[0], state.offset
    norm = np.sqrt((mu[0] - o[0]) ** 2 + (mu[1] - o[1]) ** 2 + (mu[2] - o[2]) ** 2)
    if s.field_norm == 0.0:
        s.field_norm = norm
    else:
        s.field_norm += lowpass_gain(dt, params.field_norm_tau_s) * (norm - s.field_norm)
    return params.field_norm_min <= s.field_norm <= params.field_norm_max


@njit(cache=True, inline='always')
def mag_step(state, params, work, t, mu):
    """The magnetometer's reading μ [T] at ``t`` [s] (NaN: none): skipped when it equals
    the one before (the magnetometer's held output), left out while the magnetometer reads
    no Earth field (:func:`_plausible`); the first plausible reading starts the field
    (:func:`start_field`), the others the field update. Returns (the detector column it
    sets, :data:`NO_READING` for none; applied)."""
    s = state.scalars[0]
    if not (params.use_field and np.isfinite(mu[0]) and np.isfinite(mu[1])
            and np.isfinite(mu[2])):
        return NO_READING, False
    if mu[0] == state.previous_mag[0] and mu[1] == state.previous_mag[1] and \
            mu[2] == state.previous_mag[2]:
        s.held_readings += 1
        return NO_READING, False
    state.previous_mag[:] = mu
    dt = t - s.t_mag if s.field_norm > 0.0 else 0.0
    s.t_mag = t
    if not _plausible(state, params, mu, dt):
        return FIELD_IMPLAUSIBLE, False
    if not s.field_started:
        start_field(state, params, mu, HEADING_FROM_FIELD if params.heading_from_field
                    else AZIMUTH_FROM_FIELD)
        return FIELD_UNDISTURBED, False
    if not dt > 0.0:
        return NO_READING, False
    undisturbed, applied = field_update(state, params, work, mu, dt)
    return (FIELD_UNDISTURBED if undisturbed else FIELD_DISTURBED), applied
