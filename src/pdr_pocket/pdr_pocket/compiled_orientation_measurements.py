"""The measurements of the thesis' orientation filter (pdr_pocket.compiled_orientation),
one builder per update (Muñoz Díaz 2016, Section 3.3): each returns the
:class:`Measurement` the filter's unscented update applies (the update kinds select h(x)
there):

1. absolute gravity [φ̄, θ̄] (Eqs. (3.12)–(3.14)), :func:`absolute_gravity`;
2. differential gravity (Eqs. (3.15)–(3.16)), :func:`differential_gravity`;
3. absolute magnetic field (Eq. (3.17)), :func:`absolute_magnetic`;
4. differential magnetic field (Eqs. (3.18)–(3.19)), :func:`differential_magnetic`;
5. absolute compass ψ̄ (Eqs. (3.20)–(3.21), in ENU: :func:`compass_yaw`), :func:`compass`;
6. mean gravity over whole windows (beyond the thesis), :func:`mean_gravity`;
7. the ZARU (Eq. (3.22)), :func:`zaru`;

and an external correction of the yaw or the z gyro bias (Eq. (6.2)),
:func:`external_correction`.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from pdr_core.maths import angles, kernel_cache, small_matrix
from pdr_core.maths.angles import wrap_angle_jit
from pdr_core.maths.small_matrix import euler_of
from pdr_pocket import compiled_gait_window
from pdr_pocket.compiled_gait_window import across, force_in_body

kernel_cache.forget_if_changed(__file__, small_matrix.__file__, angles.__file__,
                               compiled_gait_window.__file__)

# update kinds (columns of the "ran" output), then the external corrections (Eq. (6.2))
ABS_GRAVITY, DIFF_GRAVITY, ABS_MAG, DIFF_MAG, COMPASS, ZARU, MEAN_GRAVITY = range(7)
YAW_CORRECTION, BIAS_Z_CORRECTION = 7, 8
N_UPDATES = 7


class Measurement(NamedTuple):
    """One update's measurement, made by its builder (:func:`absolute_gravity` ...
    :func:`external_correction`) and applied by :func:`update`."""

    kind: int                       # ABS_GRAVITY ... BIAS_Z_CORRECTION: selects h(x)
    z: np.ndarray                   # (m,) the measurement
    r: np.ndarray                   # (m, m) its noise covariance R
    vectors: np.ndarray             # (2, 3) the vectors h(x) reads (see each builder)


@njit(cache=True)
def _diagonal(m_dim, variance):
    """R = variance·I (m_dim, m_dim)."""
    return np.eye(m_dim) * variance


@njit(cache=True)
def absolute_gravity(params, sample):
    """Roll and pitch from the specific force at rest, z = [φ̄, θ̄] (Muñoz Díaz 2016,
    Eqs. (3.12)–(3.14)) against h(x) = [φ, θ] of C; the roll's variance grows as
    1/cos²θ."""
    a = sample.accel
    z = np.empty(2)
    z[0] = np.arctan2(a[1], a[2])
    z[1] = np.arctan2(-a[0], np.sqrt(a[1] ** 2 + a[2] ** 2))
    cos_t = max(np.cos(z[1]), 1e-6)
    r = np.zeros((2, 2))
    r[0, 0] = params.gravity_angle_var / (cos_t * cos_t)
    r[1, 1] = params.gravity_angle_var
    return Measurement(ABS_GRAVITY, z, r, np.zeros((2, 3)))


@njit(cache=True)
def differential_gravity(params, sample, previous_accel):
    """z = α^k against h(x) = A(ω − b)ᵀ·α^{k−1} (Muñoz Díaz 2016, Eqs. (3.15)–(3.16));
    vectors[0] = α^{k−1} (body frame)."""
    vectors = np.zeros((2, 3))
    vectors[0] = previous_accel
    return Measurement(DIFF_GRAVITY, sample.accel.copy(), _diagonal(3, params.diff_gravity_var),
                       vectors)


@njit(cache=True)
def absolute_magnetic(params, sample, reference):
    """z = μ^k against h(x) = Cᵀ·μ̄_r, μ̄_r the field in the navigation frame taken at the
    start of the quasi-constant period (Muñoz Díaz 2016, Eq. (3.17)); vectors[0] = μ̄_r."""
    vectors = np.zeros((2, 3))
    vectors[0] = reference
    return Measurement(ABS_MAG, sample.mag.copy(), _diagonal(3, params.mag_var), vectors)


@njit(cache=True)
def differential_magnetic(params, sample, previous_mag):
    """z = μ^k against h(x) = A(ω − b)ᵀ·μ^{k−1} (Muñoz Díaz 2016, Eqs. (3.18)–(3.19));
    vectors[0] = μ^{k−1} (body frame)."""
    vectors = np.zeros((2, 3))
    vectors[0] = previous_mag
    return Measurement(DIFF_MAG, sample.mag.copy(), _diagonal(3, params.mag_var), vectors)


@njit(cache=True)
def compass(params, sample, attitude):
    """z = ψ̄ from the field tilt-compensated with the roll and pitch of ``attitude``
    (Muñoz Díaz 2016, Eqs. (3.20)–(3.21), in ENU: see :func:`compass_yaw`) against
    h(x) = ψ of C."""
    z = np.empty(1)
    z[0] = compass_yaw(attitude, sample.mag, params.field_azimuth)
    return Measurement(COMPASS, z, _diagonal(1, params.compass_var), np.zeros((2, 3)))


@njit(cache=True)
def mean_gravity(params, attitude, force_sum, window_s, cycles):
    """Beyond the thesis (the module docstring derives it): over a window of ``window_s``
    seconds, the up row of C across the summed force turned to the body frame,
    Cᵀ·Σ C·α·δt: z = [0, 0] against h(x) = [C[2, :]·b₁, C[2, :]·b₂], vectors = [b₁, b₂]
    two unit vectors across the sum, R = σ_Δv²/(g·W)² I, σ_Δv that of a window of whole
    gait cycles when ``cycles``."""
    total = params.gravity * window_s
    velocity_var = params.cycle_velocity_var if cycles else params.mean_gravity_velocity_var
    r = np.zeros((2, 2))
    r[0, 0] = r[1, 1] = velocity_var / (total * total)
    vectors = np.empty((2, 3))
    vectors[0], vectors[1] = across(force_in_body(attitude, force_sum))
    return Measurement(MEAN_GRAVITY, np.zeros(2), r, vectors)


@njit(cache=True)
def zaru(params):
    """z = [0, 0, 0] against h(x) = ω − b − Cᵀ·ω_ie^n (Muñoz Díaz 2016, Eq. (3.22))."""
    return Measurement(ZARU, np.zeros(3), _diagonal(3, params.zaru_var), np.zeros((2, 3)))


@njit(cache=True)
def external_correction(kind, value, variance):
    """An external correction (Muñoz Díaz 2016, Eq. (6.2)): the yaw ψ_L [rad] against
    h(x) = ψ of C (``kind`` YAW_CORRECTION), or the z gyro bias [rad/s] against b_z
    (BIAS_Z_CORRECTION), with its variance."""
    z = np.empty(1)
    z[0] = value
    r = np.empty((1, 1))
    r[0, 0] = variance
    return Measurement(kind, z, r, np.zeros((2, 3)))


@njit(cache=True)
def compass_yaw(attitude, mu, field_azimuth):
    """ψ̄ from the field μ (body) tilt-compensated with the roll and pitch of ``attitude``:
    γ − atan2(μ_h,y, μ_h,x) (the module docstring derives it)."""
    e = np.empty(3)
    euler_of(attitude, e)
    cr, sr, cp, sp = np.cos(e[0]), np.sin(e[0]), np.cos(e[1]), np.sin(e[1])
    # μ_h = Ry(θ)·Rx(φ)·μ: the body field turned to the horizontal plane
    y1 = cr * mu[1] - sr * mu[2]
    z1 = sr * mu[1] + cr * mu[2]
    x2 = cp * mu[0] + sp * z1
    return wrap_angle_jit(field_azimuth - np.arctan2(y1, x2))

