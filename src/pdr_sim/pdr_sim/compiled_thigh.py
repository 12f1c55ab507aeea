"""The per-sample kinematics of the thigh model, compiled with numba.

:func:`thigh_kinematics` evaluates the channels of the pocket model's cubic spline (pelvis
x, y, z, route heading, thigh pitch θ, sway; :mod:`pdr_sim.thigh_trajectory`) with their
first two derivatives, and turns them into the sensor's position, velocity, acceleration,
attitude and body rate, one sample at a time without temporaries. The same equations in
NumPy are in ``test_twins_thigh.py`` (``sensor_motion``), asserted equal.

With ψ = heading + sway, α = −θ and C_t = Rz(ψ)·Ry(α) (thigh → ENU):
    ω_t = (−sin α·ψ̇, α̇, cos α·ψ̇),
    ω̇_t = (−cos α·α̇·ψ̇ − sin α·ψ̈, α̈, −sin α·α̇·ψ̇ + cos α·ψ̈),
    p = p_pelvis + Rz(ψ)·h + C_t·r,
    ṗ = ṗ_pelvis + Rz(ψ)·(ψ̇ e_z × h) + C_t·(ω_t × r),
    p̈ = p̈_pelvis + Rz(ψ)·(ψ̈ e_z × h + ψ̇ e_z × (ψ̇ e_z × h)) + C_t·(ω̇_t × r + ω_t × (ω_t × r)),
with h the hip joint from the pelvis centre (pelvis frame) and r the sensor from the hip
joint (thigh frame). The sensor attitude is q_t ⊗ q_m (mounting C_s^t) and its body rate
ω_s = C_s^tᵀ·ω_t.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache

kernel_cache.forget_if_changed(__file__)

X, Y, Z, HEADING, PITCH, SWAY = range(6)       # spline channels


class ThighBody(NamedTuple):
    """The body of the model, SI units: hip joint from the pelvis centre (pelvis frame,
    (3,)), sensor from the hip joint (thigh frame, (3,)), mounting C_s^t (3, 3) and its
    quaternion (x, y, z, w), and the share of the thigh's pitch the sensor's body follows
    (1 in a front pocket, less on the buttock, 0 in a hand: the pelvis' frame)."""

    hip_offset: np.ndarray
    lever_arm: np.ndarray
    mounting: np.ndarray
    mounting_quaternion: np.ndarray
    pitch_coupling: float


class ThighSpline(NamedTuple):
    """The channels' cubic spline in scipy's PPoly layout: ``breaks`` (K+1,) [s] and
    ``coeffs`` (4, K, 6), highest power first, channels X … SWAY [m, rad]."""

    breaks: np.ndarray
    coeffs: np.ndarray


class SensorMotion(NamedTuple):
    """The sensor at N times, filled by :func:`thigh_kinematics`."""

    position: np.ndarray        # (N, 3) ENU [m]
    velocity: np.ndarray        # (N, 3) ENU [m/s]
    acceleration: np.ndarray    # (N, 3) ENU [m/s²]
    quaternion: np.ndarray      # (N, 4) x, y, z, w of C_s^n
    body_rate: np.ndarray       # (N, 3) ω_s, sensor frame [rad/s]

    @classmethod
    def empty(cls, n: int) -> SensorMotion:
        return cls(np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 4)),
                   np.empty((n, 3)))


@njit(cache=True)
def _channels(t, breaks, coeffs, out):
    """Spline value, 1st and 2nd derivative of every channel at time t: out (3, 6)."""
    n = breaks.shape[0] - 1
    i = np.searchsorted(breaks, t, side="right") - 1
    i = min(max(i, 0), n - 1)
    dt = t - breaks[i]
    for ch in range(coeffs.shape[2]):
        c0, c1, c2, c3 = coeffs[0, i, ch], coeffs[1, i, ch], coeffs[2, i, ch], coeffs[3, i, ch]
        out[0, ch] = ((c0 * dt + c1) * dt + c2) * dt + c3
        out[1, ch] = (3.0 * c0 * dt + 2.0 * c1) * dt + c2
        out[2, ch] = 6.0 * c0 * dt + 2.0 * c1


@njit(cache=True)
def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit(cache=True)
def _thigh_to_nav(cp, sp, ca, sa, u0, u1, u2):
    """C_t·u with C_t = Rz(ψ)·Ry(α), from cos/sin of ψ and α."""
    x = ca * u0 + sa * u2
    return cp * x - sp * u1, sp * x + cp * u1, -sa * u0 + ca * u2


@njit(cache=True, nogil=True)
def thigh_kinematics(t, spline: ThighSpline, body: ThighBody, out: SensorMotion):
    """Fill ``out`` with the sensor's motion at the times ``t`` (N,) [s], from the
    channels' ``spline``. Releases the GIL, so blocks of samples run in parallel threads."""
    ch = np.empty((3, 6))
    breaks, coeffs = spline.breaks, spline.coeffs
    h, r, m, qm = body.hip_offset, body.lever_arm, body.mounting, body.mounting_quaternion
    position, velocity, acceleration = out.position, out.velocity, out.acceleration
    quaternion, body_rate = out.quaternion, out.body_rate
    for k in range(t.shape[0]):
        _channels(t[k], breaks, coeffs, ch)
        psi, psi_d, psi_dd = ch[0, HEADING] + ch[0, SWAY], ch[1, HEADING] + ch[1, SWAY], \
            ch[2, HEADING] + ch[2, SWAY]
        k_p = body.pitch_coupling
        a, a_d, a_dd = -k_p * ch[0, PITCH], -k_p * ch[1, PITCH], -k_p * ch[2, PITCH]
        cp, sp, ca, sa = np.cos(psi), np.sin(psi), np.cos(a), np.sin(a)
        w0, w1, w2 = -sa * psi_d, a_d, ca * psi_d
        wd0, wd1, wd2 = -ca * a_d * psi_d - sa * psi_dd, a_dd, -sa * a_d * psi_d + ca * psi_dd
        # hip joint: rotates with the yaw only
        hp = _thigh_to_nav(cp, sp, 1.0, 0.0, h[0], h[1], h[2])
        hv = _thigh_to_nav(cp, sp, 1.0, 0.0, -psi_d * h[1], psi_d * h[0], 0.0)
        ha = _thigh_to_nav(cp, sp, 1.0, 0.0, -psi_dd * h[1] - psi_d * psi_d * h[0],
                           psi_dd * h[0] - psi_d * psi_d * h[1], 0.0)
        # sensor: rotates with the thigh
        wr = _cross(w0, w1, w2, r[0], r[1], r[2])
        wwr = _cross(w0, w1, w2, wr[0], wr[1], wr[2])
        wdr = _cross(wd0, wd1, wd2, r[0], r[1], r[2])
        sp_ = _thigh_to_nav(cp, sp, ca, sa, r[0], r[1], r[2])
        sv = _thigh_to_nav(cp, sp, ca, sa, wr[0], wr[1], wr[2])
        sa_ = _thigh_to_nav(cp, sp, ca, sa, wdr[0] + wwr[0], wdr[1] + wwr[1], wdr[2] + wwr[2])
        for i in range(3):
            position[k, i] = ch[0, i] + hp[i] + sp_[i]
            velocity[k, i] = ch[1, i] + hv[i] + sv[i]
            acceleration[k, i] = ch[2, i] + ha[i] + sa_[i]
            body_rate[k, i] = m[0, i] * w0 + m[1, i] * w1 + m[2, i] * w2
        # q_t = q_z(ψ) ⊗ q_y(α), then ⊗ q_m
        s_a, c_a, s_p, c_p = np.sin(a / 2), np.cos(a / 2), np.sin(psi / 2), np.cos(psi / 2)
        ax, ay, az, aw = -s_a * s_p, s_a * c_p, c_a * s_p, c_a * c_p
        bx, by, bz, bw = qm[0], qm[1], qm[2], qm[3]
        quaternion[k, 0] = aw * bx + ax * bw + ay * bz - az * by
        quaternion[k, 1] = aw * by - ax * bz + ay * bw + az * bx
        quaternion[k, 2] = aw * bz + ax * by - ay * bx + az * bw
        quaternion[k, 3] = aw * bw - ax * bx - ay * by - az * bz
