"""Magnetic field models in the navigation frame (ENU, tesla) and magnetometer distortion.

- Homogeneous fields H∞: presets of Muñoz Díaz 2016, Table 3.1 (North Pole,
  Equator, Munich), or any vector.
- Fields perturbed by infinite vertical iron cylinders, Muñoz Díaz 2016,
  Eq. (3.29): around one cylinder of radius r_c and relative permeability μ_r, at
  horizontal offset (x, y) from its axis, r = √(x²+y²) and ρ = arctan(x/y):
      H = |H∞|·k·(r_c/r)·sin(2ρ)·u_E + |H∞|·(1 + k·(r_c/r)·cos(2ρ))·u_N,  k = (μ_r−1)/(μ_r+1)
  for H∞ pointing north. Here the horizontal part of any H∞ is perturbed, with ρ measured
  from its horizontal direction; the vertical part is unchanged (the thesis' argument);
  several cylinders add their perturbations (the thesis patches one cylinder per area,
  which is the same where they are far apart). Inside a cylinder (r < r_c) the field is
  not defined; it is clamped to r = r_c.
- Hard- and soft-iron distortion of the sensor (Table 3.3's ξ, l, M): a calibrated
  reading is ξ·M·(μ_raw/|H∞| − l), so a distorted reading is
  μ_raw = |H∞|·(M⁻¹·(μ/|H∞|)/ξ + l). M has unit determinant; ξ carries the scale.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

UT = 1e-6
_COS64, _SIN64 = np.cos(np.radians(64.0)), np.sin(np.radians(64.0))
PRESETS_T = {  # Muñoz Díaz 2016, Table 3.1, ENU
    "north_pole": 65.0 * UT * np.array([0.0, 0.0, -1.0]),
    "equator": 25.0 * UT * np.array([0.0, 1.0, 0.0]),
    "munich": 48.0 * UT * np.array([0.0, _COS64, -_SIN64]),
}
TABLE_3_3 = {  # Muñoz Díaz 2016, Table 3.3 (M made symmetric: M32 = M23)
    "xi": 0.9472,
    "offset": (-0.0860, -0.0871, -0.1537),
    "M": ((0.9958, 0.0017, -0.0006), (0.0017, 0.9992, -0.0007), (-0.0006, -0.0007, 1.0050)),
}


@dataclass(frozen=True)
class Cylinder:
    """An infinite vertical iron cylinder: axis at (east, north) [m], radius [m], μ_r."""

    east_m: float
    north_m: float
    radius_m: float
    permeability: float = 200.0

    def __post_init__(self) -> None:
        if self.radius_m <= 0 or self.permeability < 1:
            raise ValueError(f"cylinder needs radius > 0 and permeability >= 1, got {self}")


@dataclass(frozen=True)
class MagneticField:
    """H∞ [T] (ENU) plus perturbing cylinders."""

    h_inf_t: tuple[float, float, float]
    cylinders: tuple[Cylinder, ...] = field(default_factory=tuple)

    def at(self, position_m: np.ndarray) -> np.ndarray:
        """Field [T], (N, 3) ENU, at positions (N, 3) ENU [m]."""
        position_m = np.atleast_2d(position_m)
        h_inf = np.asarray(self.h_inf_t, float)
        out = np.broadcast_to(h_inf, position_m.shape).copy()
        horizontal = np.hypot(h_inf[0], h_inf[1])
        if not self.cylinders or horizontal == 0:
            return out
        # In complex form, w = y + i·x (offsets along u_N and u_E) gives
        # w² = (y² − x²) + i·2xy = r²·(cos 2ρ + i·sin 2ρ) for ρ = arctan(x/y): no trigonometry.
        u = complex(h_inf[1], h_inf[0]) / horizontal       # north + i·east of H∞'s direction
        axes = np.array([complex(c.north_m, c.east_m) for c in self.cylinders])
        here = position_m[:, 1] + 1j * position_m[:, 0]
        w = (here[:, None] - axes) * u.conjugate()
        radius = np.array([c.radius_m for c in self.cylinders])
        mu_r = np.array([c.permeability for c in self.cylinders])
        r2 = np.maximum(w.real * w.real + w.imag * w.imag, radius * radius)
        k = horizontal * (mu_r - 1) / (mu_r + 1) * radius / (r2 * np.sqrt(r2))
        delta = (k * (w * w)).sum(axis=1) * u              # back to north + i·east
        out[:, 0] += delta.imag
        out[:, 1] += delta.real
        return out


def homogeneous(name_or_vector: str | tuple[float, float, float]) -> np.ndarray:
    """H∞ [T] from a preset name of Table 3.1 or an ENU vector already in tesla."""
    if isinstance(name_or_vector, str):
        if name_or_vector not in PRESETS_T:
            raise ValueError(f"unknown field preset '{name_or_vector}' "
                             f"(known: {', '.join(PRESETS_T)})")
        return PRESETS_T[name_or_vector].copy()
    return np.asarray(name_or_vector, float)


@dataclass(frozen=True)
class IronDistortion:
    """Hard/soft-iron distortion as Table 3.3: ξ, the offset l [in units of |H∞|], M."""

    xi: float
    offset: tuple[float, float, float]
    M: tuple[tuple[float, float, float], ...]

    def distort(self, mu_t: np.ndarray, field_norm_t: float) -> np.ndarray:
        """Raw readings [T] from calibrated ones μ [T], (N, 3)."""
        m_inv = np.linalg.inv(np.asarray(self.M))
        return field_norm_t * ((mu_t / field_norm_t) @ m_inv.T / self.xi
                               + np.asarray(self.offset))

    def correct(self, raw_t: np.ndarray, field_norm_t: float) -> np.ndarray:
        """Calibrated readings [T] from raw ones: |H∞|·ξ·M·(raw/|H∞| − l)."""
        return field_norm_t * self.xi * ((raw_t / field_norm_t - np.asarray(self.offset))
                                         @ np.asarray(self.M).T)
