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
- An indoor disturbance (:class:`IndoorDisturbance`): a building's own field, a smooth
  random vector field δH(p) added to H∞, spatially correlated over about a metre, with
  the spread of azimuth, norm and dip measured in a motion-capture room (OxIOD, Chen et
  al. 2018; the class docstring gives the figures). A statistical model, deterministic
  from a seed and cheap at every sample of a long walk; not a solution of the
  magnetostatic equations (it has neither zero curl nor zero divergence).

Public: :data:`PRESETS_T`, :data:`TABLE_3_3`, :class:`Cylinder`,
:class:`IndoorDisturbance`, :class:`MagneticField`, :func:`homogeneous`,
:class:`IronDistortion`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

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


INDOOR_MODES = 64              # Fourier modes per component of an indoor disturbance
_ROWS_PER_BLOCK = 8192         # positions evaluated at once (bounds the (N, 3·modes) phases)


@dataclass(frozen=True)
class IndoorDisturbance:
    """A building's own magnetic disturbance: a smooth random vector field δH(p) [T]
    added to the Earth's field H∞, with the spread and spatial scale of a real room.

    The three components of δH in a frame of H∞, along H∞ (its norm), horizontal and
    across it (its azimuth) and in its vertical plane across it (its dip), are independent
    stationary Gaussian random fields with the covariance σ²·exp(−d²/ℓ²): correlation 1/e
    at d = ℓ (``correlation_length_m``), 0.5 at 0.83·ℓ. Their σ follow from the spreads
    asked for, to first order: σ_along = ``norm_sigma_ut``, σ_across = |H∞_h|·tan(σ_az),
    σ_dip = |H∞|·tan(σ_dip). Each is a sum of :data:`INDOOR_MODES` random Fourier modes
    (Rahimi and Recht 2007): δ(p) = σ·√(2/M)·Σ cos(k_m·p + φ_m), the wavevectors k drawn
    from N(0, 2/ℓ²·I) (isotropic in 3D, their norms stratified over the χ₃ quantiles so
    that every seed has the covariance's shape), the phases uniform; ``seed`` fixes them.
    The spatial variance is σ² exactly; a small room, walked around for a few minutes,
    sees a little less about its own median (it spans a few ℓ only).

    Defaults: the room of the Oxford Inertial Odometry Dataset (OxIOD, Chen et al. 2018;
    ``shared/data/attitude/oxiod``, three handheld iPhone sequences in a Vicon room of
    about 3.4 m × 5.4 m). Its field C·(μ − o) in the Vicon frame, each phone's constant
    magnetometer offset o and its 0–0.21 s lag behind the truth removed, spreads about its
    median by 5.5–6.8° in azimuth, 1.8–1.9 µT in norm and 2.3–4.3° in dip (std); the
    correlation of its azimuth, norm and dip between visits of the same place more than
    5 s apart halves at 0.35–1.65 m (median 1.15 m), and the azimuth's autocorrelation
    along the walk falls to 1/e in 1.5–2.2 s at 0.8–1 m/s. A room spans a few ℓ only, so a
    walk around it measures less than σ about its own median: with ℓ = 1.6 m, a walk of
    ``indoor_loops`` (3.5 min around 3.4 m × 5.4 m) measures on average 0.89 of the
    azimuth's σ, 0.78 of the norm's and 0.82 of the dip's, over 20 seeds. The defaults
    (7°, 2.4 µT, 3.5°, 1.6 m) are the σ and ℓ whose walk of ``indoor_loops`` measures what
    OxIOD's did: 6.2°, 1.9 µT, 2.9°, the azimuth's autocorrelation at 1/e in 1.7 s, the
    correlation between visits halved at 1.1–1.25 m (docs/simulator.md, "A room that
    breaks the orientation filter"). Spreads beyond 45° are refused (the first-order
    sizing no longer holds).
    """

    azimuth_sigma_deg: float = 7.0
    norm_sigma_ut: float = 2.4
    dip_sigma_deg: float = 3.5
    correlation_length_m: float = 1.6
    seed: int = 0

    def __post_init__(self) -> None:
        for name in ("azimuth_sigma_deg", "dip_sigma_deg"):
            if not 0 <= getattr(self, name) < 45:
                raise ValueError(f"{name} must be within 0-45 degrees, got {getattr(self, name)}")
        if self.norm_sigma_ut < 0 or self.correlation_length_m <= 0 or self.seed < 0:
            raise ValueError(f"norm_sigma_ut must be >= 0, correlation_length_m > 0 and seed "
                             f">= 0, got {self}")

    @cached_property
    def _modes(self) -> tuple[np.ndarray, np.ndarray]:
        """Wavevectors (3·M, 3) [rad/m] and phases (3·M,) [rad], component by component."""
        from scipy.stats import chi  # norms of 3D standard normal vectors

        rng = np.random.default_rng(self.seed)
        m = INDOOR_MODES
        quantiles = (rng.permuted(np.tile(np.arange(m), (3, 1)), axis=1)
                     + rng.uniform(size=(3, m))) / m
        directions = rng.standard_normal((3, m, 3))
        directions /= np.linalg.norm(directions, axis=2, keepdims=True)
        norms = chi.ppf(quantiles, df=3) * np.sqrt(2.0) / self.correlation_length_m
        phases = rng.uniform(0.0, 2.0 * np.pi, size=(3, m))
        return (directions * norms[:, :, None]).reshape(-1, 3), phases.ravel()

    def frame(self, h_inf_t: np.ndarray) -> np.ndarray:
        """(3, 3) columns: unit vectors (ENU) along H∞, horizontal across it, and across it
        in its vertical plane; ValueError for an azimuth spread in a field without a
        horizontal part."""
        h = np.asarray(h_inf_t, float)
        along = h / np.linalg.norm(h)
        horizontal = np.array([-h[1], h[0], 0.0])
        if np.hypot(h[0], h[1]) < 1e-12:
            if self.azimuth_sigma_deg > 0:
                raise ValueError("an azimuth spread needs a field with a horizontal part")
            horizontal = np.array([1.0, 0.0, 0.0])
        horizontal /= np.linalg.norm(horizontal)
        return np.column_stack([along, horizontal, np.cross(along, horizontal)])

    def sigma_t(self, h_inf_t: np.ndarray) -> np.ndarray:
        """σ [T] of the components along H∞, across it horizontally, across it vertically."""
        h = np.asarray(h_inf_t, float)
        return np.array([self.norm_sigma_ut * UT,
                         np.hypot(h[0], h[1]) * np.tan(np.radians(self.azimuth_sigma_deg)),
                         np.linalg.norm(h) * np.tan(np.radians(self.dip_sigma_deg))])

    def at(self, position_m: np.ndarray, h_inf_t: np.ndarray) -> np.ndarray:
        """δH [T], (N, 3) ENU, at positions (N, 3) ENU [m] in the field H∞ ``h_inf_t``."""
        position_m = np.atleast_2d(np.asarray(position_m, float))
        k, phase = self._modes
        # component c is σ_c·√(2/M)·Σ_j cos(k_cj·p + φ_cj), along column c of the frame
        weights = (self.frame(h_inf_t) * (self.sigma_t(h_inf_t)
                                          * np.sqrt(2.0 / INDOOR_MODES))).T
        out = np.empty_like(position_m)
        for start in range(0, len(position_m), _ROWS_PER_BLOCK):
            rows = slice(start, start + _ROWS_PER_BLOCK)
            angle = (position_m[rows] @ k.T + phase).astype(np.float32)
            # cosines in float32 are ten times faster; the angle's rounding, |k·p|·6e-8 rad,
            # stays below 2e-3 of σ within 10 km of the origin
            sums = np.cos(angle).reshape(-1, 3, INDOOR_MODES).sum(axis=2, dtype=np.float64)
            out[rows] = sums @ weights
        return out


@dataclass(frozen=True)
class MagneticField:
    """H∞ [T] (ENU) plus perturbing cylinders and an indoor disturbance."""

    h_inf_t: tuple[float, float, float]
    cylinders: tuple[Cylinder, ...] = field(default_factory=tuple)
    indoor: IndoorDisturbance | None = None

    def at(self, position_m: np.ndarray) -> np.ndarray:
        """Field [T], (N, 3) ENU, at positions (N, 3) ENU [m]."""
        position_m = np.atleast_2d(position_m)
        h_inf = np.asarray(self.h_inf_t, float)
        out = np.broadcast_to(h_inf, position_m.shape).copy()
        if self.indoor is not None:
            out += self.indoor.at(position_m, h_inf)
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
