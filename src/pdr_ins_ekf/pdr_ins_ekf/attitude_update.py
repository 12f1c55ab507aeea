"""Attitude increments of a strapdown INS: the methods compared in
Zampella et al. 2011, section III-A.

Over one sample interval ΔT with body rate ω (constant), the attitude C_b^n is updated by
C(t + ΔT) = C(t)·exp(Ω·ΔT), Ω = [ω×] (Eq. (9)). The exponential is computed by

- ``pade11``, ``pade22``, ``pade33``: Padé [p, p] approximants N(A)/D(A) of exp(A),
  A = Ω·ΔT (Eq. (11) is [1, 1]: (2I + A)(2I − A)⁻¹);
- ``closed_form``: Eq. (12), I + sin(‖ωΔT‖)/‖ω‖·Ω + (1 − cos(‖ωΔT‖))/‖ω‖²·Ω²;
- ``expm``: ``scipy.linalg.expm`` (scaling and squaring with a [13/13] Padé);
- ``quaternion``: Simón Colomar et al. 2012, Eqs. (1)–(2), applied to the quaternion
  (x, y, z, w) and converted to C at the end.

All functions are vectorised over samples: ω is (N, 3) [rad/s], increments (N, 3, 3).
"""
from __future__ import annotations

from math import factorial

import numpy as np

from pdr_core.maths.rotations import skew

METHODS = ("pade11", "pade22", "pade33", "closed_form", "expm", "quaternion")


def pade_coefficients(p: int, q: int) -> tuple[np.ndarray, np.ndarray]:
    """Numerator and denominator coefficients (in powers of A) of the [p, q] Padé
    approximant of exp(A): N = Σ n_j A^j, D = Σ d_j (−A)^j."""
    n = np.array([factorial(p + q - j) * factorial(p)
                  / (factorial(p + q) * factorial(j) * factorial(p - j)) for j in range(p + 1)])
    d = np.array([factorial(p + q - j) * factorial(q)
                  / (factorial(p + q) * factorial(j) * factorial(q - j)) for j in range(q + 1)])
    return n, d


def pade_increments(omega: np.ndarray, dt: float, order: int) -> np.ndarray:
    """exp(Ω·ΔT) by the [order, order] Padé approximant, (N, 3, 3)."""
    a = skew(omega * dt)
    n_coef, d_coef = pade_coefficients(order, order)
    eye = np.broadcast_to(np.eye(3), a.shape)
    num, den, power = eye * n_coef[0], eye * d_coef[0], eye
    for j in range(1, order + 1):
        power = power @ a
        num = num + n_coef[j] * power
        den = den + d_coef[j] * (-1) ** j * power
    return np.linalg.solve(den, num)


def closed_form_increments(omega: np.ndarray, dt: float) -> np.ndarray:
    """exp(Ω·ΔT) by Zampella et al. 2011, Eq. (12) (Rodrigues), (N, 3, 3)."""
    norm = np.linalg.norm(omega, axis=1)
    angle = norm * dt
    safe = np.where(norm > 0, norm, 1.0)
    s = np.where(norm > 0, np.sin(angle) / safe, dt)
    c = np.where(norm > 0, (1 - np.cos(angle)) / safe**2, dt**2 / 2)
    big_omega = skew(omega)
    return np.eye(3) + s[:, None, None] * big_omega + c[:, None, None] * big_omega @ big_omega


def expm_increments(omega: np.ndarray, dt: float) -> np.ndarray:
    """exp(Ω·ΔT) by ``scipy.linalg.expm`` (batched), (N, 3, 3)."""
    from scipy.linalg import expm  # 0.12 s to import; only the mechanization study uses it

    return expm(skew(omega * dt))


def quaternion_increments(omega: np.ndarray, dt: float) -> np.ndarray:
    """The 4x4 update matrices of Simón Colomar et al. 2012, Eq. (1):
    cos(‖ω‖T/2)·I₄ + 2/(‖ω‖T)·sin(‖ω‖T/2)·Ω_n, with Ω_n of Eq. (2), for quaternions
    (x, y, z, w). (N, 4, 4)."""
    x, y, z = (omega * dt / 2).T
    zero = np.zeros_like(x)
    big = np.stack([np.stack([zero, z, -y, x], -1), np.stack([-z, zero, x, y], -1),
                    np.stack([y, -x, zero, z], -1), np.stack([-x, -y, -z, zero], -1)], -2)
    half = np.linalg.norm(omega, axis=1) * dt / 2
    scale = np.where(half > 0, np.sin(half) / np.where(half > 0, half, 1.0), 1.0)
    return np.cos(half)[:, None, None] * np.eye(4) + scale[:, None, None] * big


def increments(method: str, omega: np.ndarray, dt: float) -> np.ndarray:
    """Attitude increments of ``method`` (rotation matrices, or 4x4 quaternion updates)."""
    if method.startswith("pade"):
        return pade_increments(omega, dt, int(method[-1]))
    return {"closed_form": closed_form_increments, "expm": expm_increments,
            "quaternion": quaternion_increments}[method](omega, dt)
