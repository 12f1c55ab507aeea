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
- b_w: the warm-up, ``warmup``·(1 − e^{−t/τ}) with τ = ``warmup_tau_s`` [s] from the first
  sample: the bias a sensor takes on while it warms after power-on (a MEMS gyro's bias
  follows its temperature). A navigator that calibrates its biases at rest at the start
  does not see it;
- S, M: scale-factor errors (diagonal) and misalignment (off-diagonal, small angles);
- sat_q: saturation at ±``saturation`` and quantisation to multiples of ``quantum``.

Random numbers are drawn in a fixed order from one ``numpy.random.Generator``, so a seed
fixes every realisation.

A barometer (:class:`BarometerErrors`, pressures in Pa) is one scalar channel at its own
output rate; :func:`barometer_readings` turns the true pressure into its readings:

    p̃_k = hold( q( L( p(t_k) + ḋ·t_k + b_w(t_k) + Σ_j o_j·[t_j ≤ t_k < t_j + T_j] + w_k ) ) )

- w: white noise of std ``noise_pa`` per reading;
- b_w: the settling after the start, ``warmup_pa``·(1 − e^{−t/τ}) with τ =
  ``warmup_tau_s`` [s], as the triads' warm-up (an iPhone's Barometer.csv, Sensor Logger,
  rises 0.095 hPa with τ ≈ 3 s over its first seconds: 0.8 m of barometric height);
- L: the phone's own low-pass (its fusion or the app's filtering), first order with time
  constant ``lag_s`` [s], run on the readings: y_k = y_{k−1} + α·(x_k − y_{k−1}),
  α = 1 − e^{−Δt/lag_s}, y_0 = x_0 (0: none);
- hold: a reading repeats the one before with probability ``hold_share`` (the app sampled
  the sensor before it had a new value: 4 of 15 of an iPhone's 1 Hz readings, 25 of 176
  of an Android's 10 Hz ones, repeat exactly);
- ḋ: the weather's drift of the ambient pressure [Pa/s], ``drift_pa_per_s`` plus a per-run
  draw with std ``drift_sigma_pa_per_s`` (like a turn-on bias);
- o_k: sudden offsets of ``size_pa`` from ``start_s`` for ``duration_s`` (a ventilated
  stairwell or lift lobby holding its own pressure), the ``offsets`` given plus a Poisson
  number at ``offsets_per_s``, uniform in time, of a size uniform in ``offset_size_pa``
  with a random sign, each lasting ``offset_duration_s``;
- q: quantisation to multiples of ``quantum_pa``.

The figures of a phone's barometer, with their sources, are in
:data:`pdr_core.sensors.imu_profiles.PROFILES` (``consumer_phone``, section ``baro``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.sensors.atmosphere import SEA_LEVEL_PRESSURE_PA

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
    warmup: Axes = ZERO3
    warmup_tau_s: Axes = (1.0, 1.0, 1.0)
    scale_factor: Axes = ZERO3
    misalignment: tuple[Axes, Axes, Axes] = (ZERO3, ZERO3, ZERO3)
    saturation: float = float("inf")
    quantum: float = 0.0

    def __post_init__(self) -> None:
        for name in ("white_density", "bias_sigma", "gm_sigma", "random_walk_density"):
            if min(getattr(self, name)) < 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        for name in ("gm_tau_s", "warmup_tau_s"):
            if min(getattr(self, name)) <= 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        if self.saturation <= 0 or self.quantum < 0:
            raise ValueError("saturation must be > 0 and quantum >= 0")

    @property
    def distortion(self) -> np.ndarray:
        """3x3 matrix I + S + M applied to the true signal."""
        return np.eye(3) + np.diag(self.scale_factor) + np.asarray(self.misalignment)


@dataclass(frozen=True)
class PressureOffset:
    """A sudden offset of the pressure at the sensor: ``size_pa`` [Pa] (signed) from
    ``start_s`` [s from the start of the run] for ``duration_s`` [s]."""

    start_s: float
    duration_s: float
    size_pa: float

    def __post_init__(self) -> None:
        if self.start_s < 0 or self.duration_s <= 0:
            raise ValueError(f"an offset starts at >= 0 s and lasts > 0 s, got {self}")


@dataclass(frozen=True)
class BarometerErrors:
    """Error parameters of a barometer, SI units (module docstring for the model).

    rate_hz: output rate [Hz]; noise_pa: white noise std per reading [Pa]; quantum_pa:
    output resolution [Pa] (0: none); reference_pa: the true pressure at the map frame's
    z = 0 when the run starts [Pa] (the standard atmosphere's sea level by default);
    drift_pa_per_s: the weather's drift [Pa/s], signed; drift_sigma_pa_per_s: std of a
    per-run drift rate added to it [Pa/s]; offsets: sudden offsets at given times;
    offsets_per_s: the rate of random sudden offsets [1/s]; offset_size_pa: (least,
    largest) size of a random one [Pa]; offset_duration_s: how long a random one lasts
    [s]; warmup_pa, warmup_tau_s: the settling after the start [Pa] and its time
    constant [s]; lag_s: the phone's own low-pass time constant [s] (0: none);
    hold_share: the probability that a reading repeats the one before. The defaults are
    an ideal barometer at 25 Hz.
    """

    rate_hz: float = 25.0
    noise_pa: float = 0.0
    quantum_pa: float = 0.0
    reference_pa: float = SEA_LEVEL_PRESSURE_PA
    drift_pa_per_s: float = 0.0
    drift_sigma_pa_per_s: float = 0.0
    offsets: tuple[PressureOffset, ...] = ()
    offsets_per_s: float = 0.0
    offset_size_pa: tuple[float, float] = (0.0, 0.0)
    offset_duration_s: float = 60.0
    warmup_pa: float = 0.0
    warmup_tau_s: float = 1.0
    lag_s: float = 0.0
    hold_share: float = 0.0

    def __post_init__(self) -> None:
        if self.rate_hz <= 0 or self.reference_pa <= 0 or self.offset_duration_s <= 0 \
                or self.warmup_tau_s <= 0:
            raise ValueError("rate_hz, reference_pa, offset_duration_s and warmup_tau_s "
                             "must be > 0")
        if not 0 <= self.hold_share < 1:
            raise ValueError(f"hold_share must be within [0, 1), got {self.hold_share}")
        for name in ("noise_pa", "quantum_pa", "drift_sigma_pa_per_s", "offsets_per_s",
                     "lag_s"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        low, high = self.offset_size_pa
        if not 0 <= low <= high:
            raise ValueError(f"offset_size_pa must be 0 <= least <= largest, got "
                             f"{self.offset_size_pa}")


@dataclass(frozen=True)
class BarometerRun:
    """What one run's barometer drew: its drift rate [Pa/s] (the fixed one plus the
    per-run draw) and every sudden offset, given or drawn, in time order."""

    drift_pa_per_s: float
    offsets: tuple[PressureOffset, ...]


@dataclass(frozen=True)
class ImuErrors:
    """Errors of a full IMU: gyroscope, accelerometer and magnetometer triads, and the
    barometer beside them."""

    gyro: TriadErrors = field(default_factory=TriadErrors)
    accel: TriadErrors = field(default_factory=TriadErrors)
    mag: TriadErrors = field(default_factory=TriadErrors)
    baro: BarometerErrors = field(default_factory=BarometerErrors)


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
    if any(errors.warmup):
        t = np.arange(n)[:, None] * dt
        out += np.asarray(errors.warmup) * -np.expm1(-t / np.asarray(errors.warmup_tau_s))
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


def barometer_run(errors: BarometerErrors, duration_s: float,
                  rng: np.random.Generator) -> BarometerRun:
    """The drift rate and the sudden offsets of one run of ``duration_s`` [s]: the drift
    drawn first, then the number of random offsets (Poisson), their start times (uniform
    over the run), sizes (uniform in ``offset_size_pa``) and signs, in that order."""
    drift = errors.drift_pa_per_s + errors.drift_sigma_pa_per_s * rng.standard_normal()
    count = rng.poisson(errors.offsets_per_s * duration_s)
    starts = rng.uniform(0.0, duration_s, count)
    sizes = rng.uniform(*errors.offset_size_pa, count) * rng.choice((-1.0, 1.0), count)
    drawn = [PressureOffset(float(t), errors.offset_duration_s, float(size))
             for t, size in zip(starts, sizes, strict=True)]
    return BarometerRun(float(drift), tuple(sorted((*errors.offsets, *drawn),
                                                   key=lambda o: o.start_s)))


def barometer_readings(true_pa: np.ndarray, t_s: np.ndarray, errors: BarometerErrors,
                       rng: np.random.Generator) -> tuple[np.ndarray, BarometerRun]:
    """Readings [Pa] (N,) of the true pressures ``true_pa`` [Pa] (N,) at the times ``t_s``
    [s from the start of the run] (N,), and what the run drew (:func:`barometer_run`,
    drawn from ``rng`` before the white noise, the holds drawn last)."""
    t_s = np.asarray(t_s, float)
    run = barometer_run(errors, float(t_s[-1]) if len(t_s) else 0.0, rng)
    out = np.asarray(true_pa, float) + run.drift_pa_per_s * t_s \
        - errors.warmup_pa * np.expm1(-t_s / errors.warmup_tau_s)
    for offset in run.offsets:
        out[(t_s >= offset.start_s) & (t_s < offset.start_s + offset.duration_s)] += \
            offset.size_pa
    if errors.noise_pa > 0:
        out += rng.standard_normal(len(t_s)) * errors.noise_pa
    if errors.lag_s > 0:
        out = low_passed(out, t_s, errors.lag_s)
    if errors.quantum_pa > 0:
        out = np.round(out / errors.quantum_pa) * errors.quantum_pa
    if errors.hold_share > 0 and len(out):
        held = rng.random(len(out)) < errors.hold_share
        held[0] = False
        out = out[np.maximum.accumulate(np.where(held, 0, np.arange(len(out))))]
    return out, run


def low_passed(x: np.ndarray, t_s: np.ndarray, tau_s: float) -> np.ndarray:
    """A first-order low-pass of time constant ``tau_s`` [s] run on samples ``x`` (N,)
    at times ``t_s`` [s] (N,): y_k = y_{k−1} + α_k·(x_k − y_{k−1}), α_k =
    1 − e^{−(t_k − t_{k−1})/τ} (pdr_core.maths.lowpass), y_0 = x_0."""
    # numba: only a lagging barometer needs it
    from pdr_core.maths.lowpass import lowpass_gain

    y = np.array(x, float)
    for k in range(1, len(y)):
        y[k] = y[k - 1] + lowpass_gain(t_s[k] - t_s[k - 1], tau_s) * (y[k] - y[k - 1])
    return y
