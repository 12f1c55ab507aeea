"""Allan deviation of static inertial data and the noise parameters read from it.

:func:`allan_deviation` computes the overlapping Allan deviation of a rate signal
(gyroscope [rad/s] or accelerometer [m/s²]), vectorised over the cluster times with
cumulative sums (``allantools`` would do the same, but it pulls numpydoc and an old
Sphinx whose distutils hook breaks colcon's setup.py calls). :func:`noise_parameters`
reads the classic parameters off the curve:

- white noise density N (ARW / VRW) = σ_A(τ = 1 s);
- bias instability β = the minimum of σ_A, at τ = t_β
  (Muñoz Díaz 2016, section 3.1: "the bias stability, β, is located at the
  minimum of each curve"). The first minimum is taken: a Gauss–Markov bias makes the
  curve dip where the white noise gives way to the bias, rise to a bump near 2 T_c and
  fall again beyond the record's reach;
- random walk K from the +1/2 slope region after the minimum, σ_A(τ) = K·√(τ/3);
- the AR(1) parameters of Muñoz Díaz 2016, Eqs. (3.10)–(3.11):
  τ = t_β·f_s (in samples) and σ_bias = β/√τ.

:func:`allan_deviation_model` is the analytic curve of white noise, a first-order
Gauss–Markov process and a random walk; :func:`gm_sigma_for_bias_instability` uses it to
give a Gauss–Markov bias the configured bias instability.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def allan_deviation(rate: np.ndarray, rate_hz: float, points_per_decade: int = 12
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Overlapping Allan deviation of one axis: (τ [s], σ_A [unit]), τ from 1/f_s to N/(10 f_s).

    With θ the cumulative integral of the rate and m samples per cluster (τ = m/f_s):
    σ²(τ) = Σ_k (θ_{k+2m} − 2θ_{k+m} + θ_k)² / (2 τ² (N − 2m)).
    """
    n = len(rate)
    decades = np.log10(max(n / 10, 2))
    clusters = np.unique(np.round(np.logspace(0, decades, int(decades * points_per_decade) + 1))
                         ).astype(int)
    theta = np.concatenate([[0.0], np.cumsum(np.asarray(rate, float))]) / rate_hz
    taus = clusters / rate_hz
    adev = np.empty(len(clusters))
    for i, m in enumerate(clusters):
        d = theta[2 * m:] - 2 * theta[m:-m] + theta[:-2 * m]
        adev[i] = np.sqrt(np.mean(d * d) / (2 * taus[i] ** 2))
    return taus, adev


@dataclass(frozen=True)
class NoiseParameters:
    """Noise parameters of one axis read from its Allan deviation (SI units)."""

    white_density: float          # σ_A(1 s) [unit/√Hz]
    bias_instability: float       # min σ_A [unit]
    bias_instability_tau_s: float  # t_β [s]
    random_walk_density: float    # K [unit/s/√Hz], NaN if the +1/2 slope is not reached
    ar1_tau_samples: float        # Muñoz Díaz 2016, Eq. (3.10)
    ar1_sigma_bias: float         # Muñoz Díaz 2016, Eq. (3.11)


def noise_parameters(taus: np.ndarray, adev: np.ndarray, rate_hz: float) -> NoiseParameters:
    """Read N, β, t_β and K off an Allan deviation curve."""
    log_t, log_a = np.log(taus), np.log(adev)
    white = float(np.exp(np.interp(0.0, log_t, log_a)))
    i_min = first_minimum(adev)
    beta, t_beta = float(adev[i_min]), float(taus[i_min])
    slope = np.gradient(log_a, log_t)
    rising = (np.arange(len(taus)) > i_min) & (slope > 0.35)
    # A random walk keeps rising to the end of the curve; a Gauss–Markov bump does not.
    walk = rising.any() and bool(rising[-3:].all())
    k = float(np.median(adev[rising] * np.sqrt(3.0 / taus[rising]))) if walk else np.nan
    tau_samples = t_beta * rate_hz
    return NoiseParameters(white, beta, t_beta, k, tau_samples, beta / np.sqrt(tau_samples))


def first_minimum(curve: np.ndarray) -> int:
    """Index of the first local minimum of a curve (its last point if it only falls)."""
    rising = np.flatnonzero(np.diff(curve) >= 0)
    return int(rising[0]) if len(rising) else len(curve) - 1


def allan_deviation_model(taus: np.ndarray, white_density: float = 0.0, gm_sigma: float = 0.0,
                          gm_tau_s: float = 1.0, random_walk_density: float = 0.0) -> np.ndarray:
    """Analytic Allan deviation [unit] of white noise + Gauss–Markov + random walk.

    σ² = N²/τ + K²τ/3 + (2σ_gm²T/τ)·[1 − T/(2τ)·(3 − 4e^{−τ/T} + e^{−2τ/T})].
    """
    taus = np.asarray(taus, float)
    x = taus / gm_tau_s
    gm = (2 * gm_sigma**2 * gm_tau_s / taus) * (
        1 - (3 - 4 * np.exp(-x) + np.exp(-2 * x)) / (2 * x))
    gm = np.maximum(gm, 0.0)          # its rounding at τ ≪ T (the bracket is x²/3 there)
    return np.sqrt(white_density**2 / taus + random_walk_density**2 * taus / 3 + gm)


def gm_sigma_for_bias_instability(bias_instability: float, gm_tau_s: float,
                                  white_density: float, random_walk_density: float = 0.0
                                  ) -> float:
    """σ of a Gauss–Markov bias with correlation time ``gm_tau_s`` such that the first
    minimum of the modelled Allan deviation (white + GM + RW) equals ``bias_instability``.

    A dip of depth β needs β > N·√(2/T_c): the white noise N must give way to the bias
    before the bias's own Allan bump. Raises ValueError when it cannot, when the white
    noise and random walk alone already put the minimum above β, or when there is no
    white noise (the curve then rises from zero: it has no first minimum to set).
    """
    if not white_density > 0:
        raise ValueError("a bias instability is the dip of the Allan deviation below the "
                         "white noise, and there is none: give the white noise too, or the "
                         "Gauss-Markov sigma directly")
    taus = np.logspace(-3, 5, 1600)

    def excess(sigma: float) -> float:
        curve = allan_deviation_model(taus, white_density, sigma, gm_tau_s, random_walk_density)
        return curve[first_minimum(curve)] - bias_instability

    if excess(0.0) >= 0:
        raise ValueError(f"bias instability {bias_instability:g} is below the Allan floor "
                         "of the white noise and random walk alone")
    floor = white_density * np.sqrt(2.0 / gm_tau_s)
    if bias_instability <= 1.05 * floor:
        raise ValueError(
            f"bias instability {bias_instability:g} leaves no dip in the Allan deviation with "
            f"correlation time {gm_tau_s:g} s; use a correlation time above "
            f"{2.2 * (white_density / bias_instability) ** 2:.3g} s")
    from scipy.optimize import brentq  # 0.1-0.3 s to import, for a bias given by its instability

    upper = bias_instability
    while excess(upper) < 0:
        upper *= 2.0
    return brentq(excess, 0.0, upper, xtol=bias_instability * 1e-9)
