"""Magnetometer hard/soft-iron calibration by least-squares ellipsoid fitting.

Raw readings of a distorted magnetometer turned through many orientations in a
homogeneous field lie on an ellipsoid (Muñoz Díaz 2016, section 3.4.4:
"a least-squares algorithm is used to find the rotation (M), translation (l) and scaling
factor (ξ) to bring the ellipsoid to a sphere with radius equal to 1 centered in the
origin"). :func:`fit_ellipsoid` solves the algebraic quadric fit
uᵀAu + bᵀu + c = 0 (``scipy.linalg.lstsq``), then refines centre and shape with
``scipy.optimize.least_squares`` on the geometric residual ‖ξM(u − l)‖ − 1. Readings are
first normalised by the local field strength, so l is in units of |H∞| as in Table 3.3.
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import lstsq, sqrtm
from scipy.optimize import least_squares

from pdr_core.sensors.magnetic_field import IronDistortion


def _algebraic_fit(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre and shape matrix S (uᵀ-centred: (u−l)ᵀS(u−l) = 1) of the best quadric."""
    x, y, z = u.T
    design = np.column_stack([x * x, y * y, z * z, 2 * x * y, 2 * x * z, 2 * y * z,
                              2 * x, 2 * y, 2 * z])
    coef, *_ = lstsq(design, np.ones(len(u)))
    a = np.array([[coef[0], coef[3], coef[4]], [coef[3], coef[1], coef[5]],
                  [coef[4], coef[5], coef[2]]])
    centre = -np.linalg.solve(a, coef[6:9])
    scale = 1.0 + centre @ a @ centre
    return centre, a / scale


def fit_ellipsoid(raw_t: np.ndarray, field_norm_t: float) -> IronDistortion:
    """(ξ, l, M) from raw readings [T], (N, 3), N ≥ 9, in a field of strength |H∞| [T].

    M is symmetric with unit determinant (the convention of Table 3.3).
    """
    u = np.asarray(raw_t, float) / field_norm_t
    if len(u) < 9:
        raise ValueError(f"ellipsoid fit needs at least 9 readings, got {len(u)}")
    centre, shape = _algebraic_fit(u)
    w0 = np.real(sqrtm(shape))
    iu = np.triu_indices(3)

    def unpack(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        w = np.zeros((3, 3))
        w[iu] = p[3:]
        return p[:3], w + np.triu(w, 1).T

    def residual(p: np.ndarray) -> np.ndarray:
        offset, w = unpack(p)
        return np.linalg.norm((u - offset) @ w.T, axis=1) - 1.0

    fit = least_squares(residual, np.concatenate([centre, w0[iu]]), method="lm")
    offset, w = unpack(fit.x)
    xi = np.cbrt(np.linalg.det(w))
    return IronDistortion(xi=float(xi), offset=tuple(offset), M=tuple(map(tuple, w / xi)))
