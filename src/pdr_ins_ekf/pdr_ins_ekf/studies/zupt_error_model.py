"""Closed-form error levels of ZUPT-aided foot navigation due to IMU noise
(Wang et al. 2020, section III, Eqs. (37)–(57)).

The model balances, over one gait cycle, the covariance a 15-state ZUPT EKF gains in the
swing (Eqs. (8)–(25)) against what the stance updates remove (Eqs. (26)–(36)), for a
straight walk with 2-D foot motion. Inputs, SI inside (the CLI converts the paper's
units): ARW [rad/√s], VRW [m/s²/√Hz], RRW [rad/s/√s] (gyro bias random walk), the ZUPT
velocity uncertainty r [m/s], the sample rate f_s [Hz], the stance and stride durations
[s], the gait-cycle means a_c = ⟨cos θ⟩ and a_s = ⟨sin θ⟩ of the foot pitch and the
stride length s_N [m].

With K = r²·t_stride/(f_s·t_stance) (the covariance of velocity and position errors,
Eq. (53)) the steady levels are

- σ_v² = P22(1,1): the admissible root of the quartic a·x⁴ + b·x² + c·x + d = 0 (Eq. (44));
- P12(1,2) and P41(1,1) (Eqs. (45)–(46)), σ_gN² = P44(1,1) (Eq. (48)) and
  σ_θ² = P11(1,1) (Eq. (50));

and the unobservable and integrated terms grow as

- σ_ψ² = ARW²·t + RRW²·t³/3 (Eq. (38)),
- σ_∥² = (2 − t_stride/4)·K·t (Eq. (56)),
- σ_⊥² = (2 − t_stride/4)·K·t + ARW²·v̄²·t³/3 + a_s²·σ_gN²·v̄²·t⁴/12
  + (1/30 + a_c²/60)·RRW²·v̄²·t⁵ (Eq. (57)).

Reading of Eq. (57): the paper sums the per-cycle integrals Σᵢ tᵢ·s_N as ½·t²·s_N, which
holds for t_stride = 1 s; for any stride time the sum is ½·t²·s_N/t_stride, so s_N enters
as the mean walking speed v̄ = s_N/t_stride (the only dimensionally consistent reading;
equal to the printed formula at t_stride = 1 s).

Eq. (56) is used as printed. Its factor (2 − t_stride/4) does not follow from the first
line of Eq. (55): with P23 = K (Eq. (53)) and N_stance = f_s·t_stance,
2·K·t_stride − K²·N_stance/r² = K·t_stride, a factor of 1. ``rederived_eq56=True`` uses 1;
on the paper's walk the filter's own along-track σ agrees with it within a few per cent
and sits 24 % below the printed form (``pdr-ekf study sweep``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from pdr_core.constants import STANDARD_GRAVITY_MPS2


def _require(condition: bool, message: str) -> None:
    if not condition:
        raise ValueError(message)


@dataclass(frozen=True)
class NoiseDensities:
    """IMU noise (SI): angle random walk [rad/√s], velocity random walk [m/s²/√Hz] and
    rate random walk, the gyro bias's random walk [rad/s/√s]."""

    arw_rad_per_sqrt_s: float
    vrw_mps2_per_sqrt_hz: float
    rrw_radps_per_sqrt_s: float

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            _require(math.isfinite(value) and value >= 0,
                     f"{f.name} must be a finite density >= 0, got {value}")


@dataclass(frozen=True)
class Gait:
    """One gait cycle of the foot: stance and stride durations [s], the means of cos and
    sin of the foot pitch over the cycle (a_c, a_s) and the stride length [m]."""

    t_stance_s: float
    t_stride_s: float
    cos_pitch_mean: float = 0.84
    sin_pitch_mean: float = 0.0
    stride_m: float = 0.77

    def __post_init__(self) -> None:
        _require(math.isfinite(self.t_stride_s) and self.t_stride_s > 0,
                 f"t_stride_s must be > 0, got {self.t_stride_s}")
        _require(math.isfinite(self.t_stance_s) and 0 < self.t_stance_s < self.t_stride_s,
                 f"t_stance_s must be in (0, t_stride_s = {self.t_stride_s}): the stance is "
                 f"part of the stride, got {self.t_stance_s}")
        _require(0 < self.cos_pitch_mean <= 1,
                 f"cos_pitch_mean (a_c) must be in (0, 1], got {self.cos_pitch_mean}")
        _require(-1 <= self.sin_pitch_mean <= 1,
                 f"sin_pitch_mean (a_s) must be in [-1, 1], got {self.sin_pitch_mean}")
        _require(math.isfinite(self.stride_m) and self.stride_m >= 0,
                 f"stride_m must be >= 0, got {self.stride_m}")

    @property
    def speed_mps(self) -> float:
        """Mean walking speed v̄ = s_N / t_stride [m/s]."""
        return self.stride_m / self.t_stride_s


@dataclass(frozen=True)
class SteadyState:
    """The steady levels of Eqs. (44)–(50): σ_v [m/s], σ_θ [rad] (roll or pitch), σ_gN
    [rad/s] (horizontal gyro bias), and the cross terms P12(1,2) [rad·m/s] and P41(1,1)
    [rad²/s]."""

    sigma_v_mps: float
    sigma_theta_rad: float
    sigma_gn_radps: float
    p12: float
    p41: float


@dataclass(frozen=True)
class ZuptErrorModel:
    """Wang et al. 2020, section III: IMU noise, gait, ZUPT velocity uncertainty r [m/s] and sample
    rate f_s [Hz]."""

    noise: NoiseDensities
    gait: Gait
    zupt_sigma_mps: float = 0.02
    rate_hz: float = 800.0
    gravity_mps2: float = STANDARD_GRAVITY_MPS2
    rederived_eq56: bool = False

    def __post_init__(self) -> None:
        _require(math.isfinite(self.zupt_sigma_mps) and self.zupt_sigma_mps > 0,
                 f"zupt_sigma_mps (r) must be > 0, got {self.zupt_sigma_mps}")
        _require(math.isfinite(self.rate_hz) and self.rate_hz > 0,
                 f"rate_hz must be > 0, got {self.rate_hz}")
        _require(self.rate_hz * self.gait.t_stance_s >= 1,
                 f"the stance ({self.gait.t_stance_s} s) holds no sample at "
                 f"{self.rate_hz} Hz")

    @property
    def stance_samples(self) -> float:
        """N_stance = f_s·t_stance, the ZUPT updates per stride."""
        return self.rate_hz * self.gait.t_stance_s

    @property
    def k(self) -> float:
        """K = r²·t_stride / N_stance = P23(1,1) (Eq. (53)) [m²/s]."""
        return self.zupt_sigma_mps**2 * self.gait.t_stride_s / self.stance_samples

    def quartic(self) -> tuple[float, float, float, float]:
        """(a, b, c, d) of Eq. (44) in x = P22(1,1) = σ_v²."""
        n = self.noise
        g, k = self.gravity_mps2, self.k
        return (1 / (4 * g**2 * k**2), -n.vrw_mps2_per_sqrt_hz**2 / (2 * g**2 * k),
                -2 * self.gait.cos_pitch_mean * n.rrw_radps_per_sqrt_s * math.sqrt(k) / g,
                n.vrw_mps2_per_sqrt_hz**4 / (4 * g**2) - n.arw_rad_per_sqrt_s**2 * k)

    def velocity_variance(self) -> float:
        """σ_v² [m²/s²]: the largest real root of Eq. (44) with P12(1,2) < 0, i.e.
        x² ≥ K·VRW² (Eq. (43) with the sign of Eq. (45))."""
        a, b, c, d = self.quartic()
        roots = np.roots([1.0, 0.0, b / a, c / a, d / a])
        scale = max(np.abs(roots).max(), np.finfo(float).tiny)
        real = roots.real[np.abs(roots.imag) <= 1e-6 * scale]
        floor = math.sqrt(self.k) * self.noise.vrw_mps2_per_sqrt_hz
        admissible = real[(real > 0) & (real >= floor * (1 - 1e-6))]
        if admissible.size == 0:
            raise ValueError(f"Eq. (44) has no admissible root for {self}")
        return float(admissible.max())

    def steady_state(self) -> SteadyState:
        """Eqs. (44)–(50) (see the module docstring)."""
        n, g, k, a_c = self.noise, self.gravity_mps2, self.k, self.gait.cos_pitch_mean
        x = self.velocity_variance()
        rrw, arw = n.rrw_radps_per_sqrt_s, n.arw_rad_per_sqrt_s
        p12 = -math.sqrt(arw**2 * k + 2 * a_c * rrw * x * math.sqrt(k) / g)  # Eq. (45)
        p41 = -rrw * x / (g * math.sqrt(k))                                  # Eq. (46)
        p44 = math.sqrt((rrw * arw / a_c) ** 2
                        + 2 * x * rrw**3 / (a_c * g * math.sqrt(k)))         # Eq. (48)
        p11 = -p12 * x / (g * k)                                             # Eq. (50)
        return SteadyState(math.sqrt(x), math.sqrt(p11), math.sqrt(p44), p12, p41)

    def sigma_yaw_rad(self, t_s: np.ndarray) -> np.ndarray:
        """σ_ψ(t) [rad], Eq. (38)."""
        t = _times(t_s)
        n = self.noise
        return np.sqrt(n.arw_rad_per_sqrt_s**2 * t + n.rrw_radps_per_sqrt_s**2 * t**3 / 3)

    def _along_variance(self, t: np.ndarray) -> np.ndarray:
        factor = 1.0 if self.rederived_eq56 else 2 - self.gait.t_stride_s / 4
        return factor * self.k * t

    def sigma_par_m(self, t_s: np.ndarray) -> np.ndarray:
        """σ_∥(t) [m], along the walk, Eq. (56)."""
        return np.sqrt(self._along_variance(_times(t_s)))

    def sigma_perp_m(self, t_s: np.ndarray) -> np.ndarray:
        """σ_⊥(t) [m], across the walk, Eq. (57) with s_N read as v̄ (module docstring)."""
        t = _times(t_s)
        n, gait = self.noise, self.gait
        v2 = gait.speed_mps**2
        sigma_gn = self.steady_state().sigma_gn_radps
        return np.sqrt(self._along_variance(t)
                       + n.arw_rad_per_sqrt_s**2 * v2 * t**3 / 3
                       + gait.sin_pitch_mean**2 * sigma_gn**2 * v2 * t**4 / 12
                       + (1 / 30 + gait.cos_pitch_mean**2 / 60)
                       * n.rrw_radps_per_sqrt_s**2 * v2 * t**5)


def _times(t_s) -> np.ndarray:
    t = np.asarray(t_s, float)
    _require(bool(np.all(np.isfinite(t)) and np.all(t >= 0)),
             f"times must be finite and >= 0 s, got {t_s}")
    return t
