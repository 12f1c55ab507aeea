"""The phone's attitude filter's Kalman update (pdr_pocket.compiled_attitude), written
once for every update: the innovation covariance S = H·P·Hᵀ (:func:`innovation_covariance`),
its normalised innovation squared (:func:`nis`), the gain K = P·Hᵀ·S⁻¹ with the rows
zeroed where an update must not reach and the Joseph form P ← P − K·H·P − P·Hᵀ·Kᵀ +
K·S·Kᵀ, valid for any gain (:func:`kalman_update`), and the correction fed back into the
nominal state, the tilt's low-pass and the gait window turned with the attitude
(:func:`apply_correction`).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache, lowpass, small_matrix
from pdr_core.maths.small_matrix import product3, rodrigues
from pdr_pocket import compiled_attitude_data, compiled_gait_window
from pdr_pocket.compiled_attitude_data import (
    ACCEL_BIAS,
    ATT_EAST,
    ATT_NORTH,
    ATT_UP,
    BIAS,
    FIELD_DOWN,
    FIELD_HORIZONTAL,
    N_STATE,
    OFFSET,
    TILT_STAGES,
)
from pdr_pocket.compiled_gait_window import turn_window

kernel_cache.forget_if_changed(__file__, small_matrix.__file__, compiled_gait_window.__file__,
                               lowpass.__file__, compiled_attitude_data.__file__)

# --- the Kalman update -------------------------------------------------------------------
@njit(cache=True)
def _inverse_small(s, m, out):
    """out = s⁻¹ for a symmetric m × m matrix, m ≤ 3 (by cofactors); False when singular."""
    if m == 1:
        if not s[0, 0] > 0.0:
            return False
        out[0, 0] = 1.0 / s[0, 0]
        return True
    if m == 2:
        det = s[0, 0] * s[1, 1] - s[0, 1] * s[1, 0]
        if not det > 0.0:
            return False
        out[0, 0], out[1, 1] = s[1, 1] / det, s[0, 0] / det
        out[0, 1] = out[1, 0] = -s[0, 1] / det
        return True
    c00 = s[1, 1] * s[2, 2] - s[1, 2] * s[2, 1]
    c01 = s[1, 2] * s[2, 0] - s[1, 0] * s[2, 2]
    c02 = s[1, 0] * s[2, 1] - s[1, 1] * s[2, 0]
    det = s[0, 0] * c00 + s[0, 1] * c01 + s[0, 2] * c02
    if not det > 0.0:
        return False
    out[0, 0], out[0, 1], out[0, 2] = c00 / det, (s[0, 2] * s[2, 1] - s[0, 1] * s[2, 2]) / det, \
        (s[0, 1] * s[1, 2] - s[0, 2] * s[1, 1]) / det
    out[1, 0], out[1, 1], out[1, 2] = c01 / det, (s[0, 0] * s[2, 2] - s[0, 2] * s[2, 0]) / det, \
        (s[0, 2] * s[1, 0] - s[0, 0] * s[1, 2]) / det
    out[2, 0], out[2, 1], out[2, 2] = c02 / det, (s[0, 1] * s[2, 0] - s[0, 0] * s[2, 1]) / det, \
        (s[0, 0] * s[1, 1] - s[0, 1] * s[1, 0]) / det
    return True


@njit(cache=True)
def innovation_covariance(p, work, m):
    """P·Hᵀ into ``work.ph`` and H·P·Hᵀ into ``work.s`` for the first ``m`` rows of
    ``work.h``."""
    h, ph, s = work.h, work.ph, work.s
    for a in range(N_STATE):
        for j in range(m):
            v = 0.0
            for b in range(N_STATE):
                v += p[a, b] * h[j, b]
            ph[a, j] = v
    for i in range(m):
        for j in range(m):
            v = 0.0
            for b in range(N_STATE):
                v += h[i, b] * ph[b, j]
            s[i, j] = v


@njit(cache=True)
def nis(work, m, r_var):
    """νᵀ·(H·P·Hᵀ + r·I)⁻¹·ν of ``work.innovation`` (inf when singular); ``work.s`` must
    hold H·P·Hᵀ (:func:`innovation_covariance`) and is left as it was."""
    s, s_inv, nu = work.s, work.s_inv, work.innovation
    for i in range(m):
        s[i, i] += r_var
    ok = _inverse_small(s, m, s_inv)
    for i in range(m):
        s[i, i] -= r_var
    if not ok:
        return np.inf
    total = 0.0
    for i in range(m):
        for j in range(m):
            total += nu[i] * s_inv[i, j] * nu[j]
    return total


@njit(cache=True)
def kalman_update(p, work, m, r_var):
    """The update of the module docstring with H·P·Hᵀ and P·Hᵀ in ``work``
    (:func:`innovation_covariance`), R = r·I, the innovation and the frozen rows in
    ``work``: the correction δx into ``work.dx`` and P in place; False (nothing changed)
    when S is singular."""
    s, s_inv, ph, gain, ks, dx = work.s, work.s_inv, work.ph, work.gain, work.ks, work.dx
    for i in range(m):
        s[i, i] += r_var
    if not _inverse_small(s, m, s_inv):
        return False
    for a in range(N_STATE):
        for j in range(m):
            v = 0.0
            if not work.frozen[a]:
                for c in range(m):
                    v += ph[a, c] * s_inv[c, j]
            gain[a, j] = v
    for a in range(N_STATE):
        v = 0.0
        for j in range(m):
            v += gain[a, j] * work.innovation[j]
        dx[a] = v
        for j in range(m):
            w = 0.0
            for c in range(m):
                w += gain[a, c] * s[c, j]
            ks[a, j] = w
    for a in range(N_STATE):
        for b in range(a, N_STATE):
            v = p[a, b]
            for c in range(m):
                v += -gain[a, c] * ph[b, c] - ph[a, c] * gain[b, c] + ks[a, c] * gain[b, c]
            p[a, b] = v
            p[b, a] = v
    return True


@njit(cache=True)
def apply_correction(state, work):
    """Add ``work.dx`` to the nominal state: C ← exp([δθ×])·C, b, o, B_h, B_v, b_a; the
    tilt's low-pass and the window of gait cycles turn with the attitude."""
    dx, rot, turned = work.dx, work.m1, work.m2
    rodrigues(dx[ATT_EAST], dx[ATT_NORTH], dx[ATT_UP], rot)
    product3(rot, state.attitude, turned)
    state.attitude[:, :] = turned
    for stage in range(TILT_STAGES):
        v = state.tilt_lowpass[stage]
        v0 = rot[0, 0] * v[0] + rot[0, 1] * v[1] + rot[0, 2] * v[2]
        v1 = rot[1, 0] * v[0] + rot[1, 1] * v[1] + rot[1, 2] * v[2]
        v2 = rot[2, 0] * v[0] + rot[2, 1] * v[1] + rot[2, 2] * v[2]
        v[0], v[1], v[2] = v0, v1, v2
        product3(rot, state.tilt_memory[stage], turned)
        state.tilt_memory[stage][:, :] = turned
        product3(rot, state.tilt_attitude[stage], turned)
        state.tilt_attitude[stage][:, :] = turned
    turn_window(state.gait, rot)
    for m in range(3):
        state.bias[m] += dx[BIAS + m]
        state.offset[m] += dx[OFFSET + m]
        state.accel_bias[m] += dx[ACCEL_BIAS + m]
    state.field[0] += dx[FIELD_HORIZONTAL]
    state.field[1] += dx[FIELD_DOWN]


@njit(cache=True, inline='always')
def clear_work(work):
    work.h[:, :] = 0.0
    work.frozen[:] = False
