"""Inertial and magnetic sensor error models, applied to whole signals at once.

A :class:`TriadErrors` describes one sensor triad (gyroscope, accelerometer or
magnetometer) per axis, in SI units (gyro rad/s, accelerometer m/s², magnetometer T).
:func:`corrupt` turns true signals into measurements, vectorised over samples and over
Monte-Carlo runs (no Python loop over either):

    y = sat_q( (I + S + M)·x + b_c + b_gm + b_rw + w )

- w: white noise of density ``white_density`` [unit/√Hz], std ``white_density·√fs`` per
  sample (ARW for gyros, VRW for accelerometers);
- b_c: constant bias, ``bias`` plus a per-run draw with std ``bias_sigma`` (turn-on bias);
- b_gm: first-order Gauss–Markov (AR(1)) bias of std ``gm_sigma`` and correlation time
  ``gm_tau_s``: b_k = c·b_{k−1} + n_k, c = exp(−Δt/τ), σ_n² = σ²(1 − c²)
  (Muñoz Díaz 2016, Eqs. (3.8)–(3.9), with τ in seconds instead of samples);
- b_rw: random walk of density ``random_walk_density`` [unit/s/√Hz] (rate random walk,
  acceleration random walk);
- S, M: scale-factor errors (diagonal) and misalignment (off-diagonal, small angles);
- sat_q: saturation at ±``saturation`` and quantisation to multiples of ``quantum``.

Random numbers are drawn in a fixed order from one ``numpy.random.Generator``, so a seed
fixes every realisation.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

Axes = tuple[float, float, float]
ZERO3: Axes = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class TriadErrors:
    """Error parameters of one three-axis sensor, SI units, each given per axis."""

    white_density: Axes = ZERO3
    bias: Axes = ZERO3
    bias_sigma: Axes = ZERO3
    gm_sigma: Axes = ZERO3
    gm_tau_s: Axes = (1.0, 1.0, 1.0)
    random_walk_density: Axes = ZERO3
    scale_factor: Axes = ZERO3
    misalignment: tuple[Axes, Axes, Axes] = (ZERO3, ZERO3, ZERO3)
    saturation: float = float("inf")
    quantum: float = 0.0

    def __post_init__(self) -> None:
        for name in ("white_density", "bias_sigma", "gm_sigma", "random_walk_density"):
            if min(getattr(self, name)) < 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if min(self.gm_tau_s) <= 0:
            raise ValueError(f"gm_tau_s must be > 0, got {self.gm_tau_s}")
        if self.saturation <= 0 or self.quantum < 0:
            raise ValueError("saturation must be > 0 and quantum >= 0")

    @property
    def distortion(self) -> np.ndarray:
        """3x3 matrix I + S + M applied to the true signal."""
        return np.eye(3) + np.diag(self.scale_factor) + np.asarray(self.misalignment)


@dataclass(frozen=True)
class ImuErrors:
    """Errors of a full IMU: gyroscope, accelerometer and magnetometer triads."""

    gyro: TriadErrors = field(default_factory=TriadErrors)
    accel: TriadErrors = field(default_factory=TriadErrors)
    mag: TriadErrors = field(default_factory=TriadErrors)


def _normal(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    # float32 draws halve the cost; noise needs no more than 7 significant digits.
    return rng.standard_normal(shape, dtype=np.float32)


def gauss_markov(rng: np.random.Generator, shape: tuple[int, int, int], sigma: np.ndarray,
                 tau_s: np.ndarray, dt: float) -> np.ndarray:
    """Stationary first-order Gauss–Markov sequences, (runs, N, 3), per-axis σ and τ [s].

    Muñoz Díaz 2016, Eqs. (3.8)–(3.9): b_k = c·b_{k−1} + n_k with c = e^{−Δt/τ}
    and σ_n² = σ²·(1 − c²); the first value is drawn from the stationary distribution.
    """
    from scipy.signal import lfilter  # 0.3 s to import; only noise with τ needs it

    runs = shape[0]
    out = np.empty(shape)
    start = _normal(rng, (runs, 3)) * sigma
    innovations = _normal(rng, shape)
    for axis in range(3):
        c = np.exp(-dt / tau_s[axis])
        drive = innovations[:, :, axis] * (sigma[axis] * np.sqrt(1.0 - c * c))
        out[:, :, axis] = lfilter([1.0], [1.0, -c], drive, axis=1,
                                  zi=(c * start[:, axis])[:, None])[0]
    return out


def turn_on_bias(errors: TriadErrors, rng: np.random.Generator, runs: int = 1) -> np.ndarray:
    """The constant bias of each run, (runs, 1, 3) [SI]: the fixed part plus the per-run
    (turn-on) part drawn with σ ``bias_sigma``."""
    return np.asarray(errors.bias) + _normal(rng, (runs, 1, 3)) * np.asarray(errors.bias_sigma)


def corrupt(true: np.ndarray, errors: TriadErrors, rate_hz: float, rng: np.random.Generator,
            runs: int | None = None, bias: np.ndarray | None = None) -> np.ndarray:
    """Measurements from true signals.

    Args:
        true: (N, 3) true signal in SI units (body frame).
        errors: the triad's error model.
        rate_hz: sample rate [Hz].
        rng: random generator (its state advances).
        runs: number of independent realisations; None returns (N, 3), else (runs, N, 3).
        bias: the runs' constant biases (:func:`turn_on_bias`, drawn from ``rng`` first),
            when the caller needs to know them; None draws them here.
    """
    n_runs = 1 if runs is None else runs
    n = len(true)
    dt = 1.0 / rate_hz
    shape = (n_runs, n, 3)
    distorted = true if np.array_equal(errors.distortion, np.eye(3)) else true @ errors.distortion.T
    out = np.empty(shape)
    out[:] = distorted
    out += turn_on_bias(errors, rng, n_runs) if bias is None else bias
    if any(errors.gm_sigma):
        out += gauss_markov(rng, shape, np.asarray(errors.gm_sigma),
                            np.asarray(errors.gm_tau_s), dt)
    if any(errors.random_walk_density):
        steps = _normal(rng, shape)
        steps *= (np.asarray(errors.random_walk_density) * np.sqrt(dt)).astype(np.float32)
        out += np.cumsum(steps, axis=1, dtype=np.float64)
    if any(errors.white_density):
        white = _normal(rng, shape)
        white *= (np.asarray(errors.white_density) * np.sqrt(rate_hz)).astype(np.float32)
        out += white
    if np.isfinite(errors.saturation):
        np.clip(out, -errors.saturation, errors.saturation, out=out)
    if errors.quantum > 0:
        out = np.round(out / errors.quantum) * errors.quantum
    return out[0] if runs is None else out
