"""Attitude conventions and the conversions between them (scipy.spatial.transform).

Frames: navigation frame ENU (x east, y north, z up); body frame FLU (x forward, y left,
z up), REP-103. Attitude is C_b^n (body -> navigation), built from Euler angles as
C_b^n = Rz(ψ)·Ry(θ)·Rx(φ) (roll φ, pitch θ, yaw ψ; yaw 0 = facing east, counter-clockwise
positive). With this convention a positive pitch turns the nose (the toes) down.

Arrays: angles (N,) [rad], rates (N,) [rad/s], vectors (N, 3).
"""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation


def rotation_from_euler(roll: np.ndarray, pitch: np.ndarray, yaw: np.ndarray) -> Rotation:
    """C_b^n from roll, pitch, yaw [rad] (ZYX intrinsic).

    Same as ``Rotation.from_euler("ZYX", [yaw, pitch, roll])``, through the closed-form
    quaternion q = q_z(ψ)·q_y(θ)·q_x(φ), which is several times faster on long arrays.
    """
    cr, sr = np.cos(np.asarray(roll) / 2), np.sin(np.asarray(roll) / 2)
    cp, sp = np.cos(np.asarray(pitch) / 2), np.sin(np.asarray(pitch) / 2)
    cy, sy = np.cos(np.asarray(yaw) / 2), np.sin(np.asarray(yaw) / 2)
    quat = np.stack([sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy], axis=-1)
    return Rotation.from_quat(quat)


def tilt_from_specific_force(force: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Roll φ and pitch θ [rad], (...,) each, of the C_b^n that levels the specific force
    ``force`` (..., 3) [m/s²] measured at rest in the body frame, f = C_b^nᵀ·[0, 0, g]:
    φ = atan2(f_y, f_z), θ = atan2(−f_x, √(f_y² + f_z²)) (Muñoz Díaz 2016,
    Eqs. (3.12)–(3.13)). The yaw is left free: gravity does not show it."""
    f = np.asarray(force)
    return np.arctan2(f[..., 1], f[..., 2]), np.arctan2(-f[..., 0], np.hypot(f[..., 1], f[..., 2]))


def body_rate_from_euler(roll, pitch, yaw, roll_rate, pitch_rate, yaw_rate) -> np.ndarray:
    """ω_nb^b [rad/s], (N, 3), from Euler angles and their time derivatives.

    The analytic route to the turn rate; Zampella et al. 2011, Eq. (10) is the
    numerical one (see :func:`body_rate_from_matrix_log`). For C_b^n = Rz(ψ)Ry(θ)Rx(φ):
    ω = [φ̇ − ψ̇ sinθ, θ̇ cosφ + ψ̇ sinφ cosθ, −θ̇ sinφ + ψ̇ cosφ cosθ].
    """
    sr, cr = np.sin(roll), np.cos(roll)
    sp, cp = np.sin(pitch), np.cos(pitch)
    return np.stack([roll_rate - yaw_rate * sp,
                     pitch_rate * cr + yaw_rate * sr * cp,
                     -pitch_rate * sr + yaw_rate * cr * cp], axis=-1)


def body_rate_from_matrix_log(attitude: Rotation, dt: float) -> np.ndarray:
    """ω_nb^b [rad/s], (N−1, 3), over each sample interval by the matrix logarithm.

    Zampella et al. 2011, Eq. (10): Ω = ln(C_b^n(t)ᵀ·C_b^n(t+ΔT)) / ΔT; the log of a
    rotation matrix is the skew matrix of its rotation vector.
    """
    return (attitude[:-1].inv() * attitude[1:]).as_rotvec() / dt


def about_vertical(points: np.ndarray, angle_rad: float) -> np.ndarray:
    """Points (..., 3) ENU turned by ``angle_rad`` about the up (z) axis, counter-clockwise
    positive; z is kept."""
    points = np.asarray(points, float)
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    x, y = points[..., 0], points[..., 1]
    return np.stack([c * x - s * y, s * x + c * y, points[..., 2]], axis=-1)


def covariance_about_vertical(cov: np.ndarray, angle_rad: float) -> np.ndarray:
    """Covariances (..., 3, 3) of ENU vectors turned by ``angle_rad`` about the up (z)
    axis, counter-clockwise positive, as :func:`about_vertical` turns the vectors:
    R·P·Rᵀ."""
    turn = Rotation.from_euler("z", angle_rad).as_matrix()
    return turn @ cov @ turn.T


def yaw_of(attitude: np.ndarray) -> np.ndarray:
    """The ENU yaw [rad] (the ZYX Euler yaw, counter-clockwise from east) of attitudes
    C_b^n (..., 3, 3)."""
    attitude = np.asarray(attitude, float)
    return np.arctan2(attitude[..., 1, 0], attitude[..., 0, 0])


def skew(v: np.ndarray) -> np.ndarray:
    """Skew-symmetric matrices [v×], (..., 3, 3), of vectors (..., 3)."""
    v = np.asarray(v)
    zero = np.zeros(v.shape[:-1])
    return np.stack([np.stack([zero, -v[..., 2], v[..., 1]], -1),
                     np.stack([v[..., 2], zero, -v[..., 0]], -1),
                     np.stack([-v[..., 1], v[..., 0], zero], -1)], -2)


def quaternion_xyzw(attitude: Rotation) -> np.ndarray:
    """(N, 4) quaternions in ROS order (x, y, z, w), w >= 0."""
    q = attitude.as_quat()
    return np.where(q[..., 3:4] < 0, -q, q)


def quaternion_from_orthonormal(attitude: np.ndarray) -> np.ndarray:
    """(..., 4) quaternions (x, y, z, w), scipy's sign convention, of rotation matrices
    (..., 3, 3) that are orthonormal to rounding (a filter that re-orthonormalises its
    attitude every step): scipy without its projection onto SO(3), which on such
    matrices changes nothing but costs about 7x the time of the conversion."""
    return Rotation.from_matrix(attitude, assume_valid=True).as_quat()
