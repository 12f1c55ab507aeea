"""Monte-Carlo error analysis of pure INS mechanization, batched over runs
(Zampella et al. 2011, section III-B, Eqs. (13)–(14), Table I).

N noise realisations of one noiseless simulated walk are mechanized in one compiled call,
parallel over runs (:func:`ins_batch`); each run is exactly :func:`ins_loop`, the
single-run mechanization, on the same noisy samples. The spread over runs gives

    σ_p(t) = √(1/N·Σᵢ ‖pᵢ(t) − p(t)‖²)   (Eq. (13), p from the start position)
    σ_ψ(t) = √(1/N·Σᵢ (ψᵢ(t) − ψ(t))²)   (Eq. (14), wrapped to ±π)

and a straight line in log-log, σ(t) ≈ c·tᵉ, per error source (:func:`power_law`).

Error sources (SI, units in the names): white noise densities ``acc_noise_mps2_per_sqrt_hz``
and ``gyro_noise_radps_per_sqrt_hz`` (per-sample std density/√Δt), and constant biases
``acc_bias_mps2`` and ``gyro_bias_radps`` drawn per run and axis from N(0, σ²), and the
gyro bias random walk ``gyro_rrw_radps_per_sqrt_s`` (RRW of Wang et al. 2020).

Each run draws its errors from its own generator, seeded by the study's seed and its index
(:func:`pdr_core.evaluation.parallel.run_generator`): the runs can be split into batches, here or on
a Dask cluster (``scheduler``), and the study is the same.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np
from numba import njit, prange

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.evaluation.parallel import run_batches, run_generator
from pdr_core.maths import kernel_cache, small_matrix
from pdr_core.maths.angles import wrap_angle
from pdr_ins_ekf import compiled_filter, kernel_data
from pdr_ins_ekf.compiled_filter import mechanize, new_state, start
from pdr_sim.scenario import scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

kernel_cache.forget_if_changed(__file__, compiled_filter.__file__, small_matrix.__file__,
                               kernel_data.__file__)

SOURCES = ("acc_noise", "gyro_noise", "acc_bias", "gyro_bias")


@njit(cache=True)
def ins_loop(t, accel, gyro, C0, gravity):
    """Pure strapdown INS from rest at the origin with attitude C0: position (T, 3) and
    yaw (T,) [rad], with the filter's trapezoidal mechanization."""
    n = t.shape[0]
    state = new_state(C0, np.zeros(6), np.zeros((0, 0)))  # no covariance: no filter
    start(state, accel[0], gyro[0])
    pos, yaw = np.empty((n, 3)), np.empty(n)
    for k in range(n):
        mechanize(state, accel[k], gyro[k], t[k] - t[k - 1] if k else 0.0, gravity)
        pos[k] = state.p
        yaw[k] = np.arctan2(state.C[1, 0], state.C[0, 0])
    return pos, yaw


@njit(cache=True, parallel=True)
def ins_batch(t, accel, gyro, C0, gravity, keep):
    """:func:`ins_loop` for every run of accel, gyro (runs, T, 3); position (runs, K, 3)
    and yaw (runs, K) at the sample indices ``keep`` (K,)."""
    runs = accel.shape[0]
    pos = np.empty((runs, keep.shape[0], 3))
    yaw = np.empty((runs, keep.shape[0]))
    for r in prange(runs):
        p, y = ins_loop(t, accel[r], gyro[r], C0, gravity)
        for i in range(keep.shape[0]):
            pos[r, i] = p[keep[i]]
            yaw[r, i] = y[keep[i]]
    return pos, yaw


@dataclass(frozen=True)
class NoiseLevels:
    """The error sources of one study (zero: off)."""

    acc_noise_mps2_per_sqrt_hz: float = 0.0
    gyro_noise_radps_per_sqrt_hz: float = 0.0
    acc_bias_mps2: float = 0.0
    gyro_bias_radps: float = 0.0
    gyro_rrw_radps_per_sqrt_s: float = 0.0

    def __post_init__(self) -> None:
        for name, value in self.__dict__.items():
            if not np.isfinite(value) or value < 0:
                raise ValueError(f"{name} must be a finite value >= 0, got {value}")

    @classmethod
    def only(cls, source: str, level: float) -> NoiseLevels:
        """One source of :data:`SOURCES` at ``level`` (in that field's unit), others off."""
        field = next(f for f in cls.__dataclass_fields__ if f.startswith(source))
        return cls(**{field: level})


def noisy_signals(accel: np.ndarray, gyro: np.ndarray, rate_hz: float, noise: NoiseLevels,
                  seed: int, runs: range) -> tuple[np.ndarray, np.ndarray]:
    """Noisy copies (len(runs), T, 3) of the noiseless specific force and rate, run k from
    its own generator (:func:`pdr_core.evaluation.parallel.run_generator`), whatever the batch."""
    a = np.empty((len(runs), *accel.shape))
    w = np.empty_like(a)
    for i, run in enumerate(runs):
        a[i], w[i] = _noisy_run(accel, gyro, rate_hz, noise, run_generator(seed, run))
    return a, w


def _noisy_run(accel: np.ndarray, gyro: np.ndarray, rate_hz: float, noise: NoiseLevels,
               rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """One run's specific force and rate (T, 3): white noise, a constant bias, and the
    gyro's rate random walk."""
    root_rate = np.sqrt(rate_hz)
    a = accel + rng.standard_normal(accel.shape) * noise.acc_noise_mps2_per_sqrt_hz * root_rate
    a += rng.standard_normal(3) * noise.acc_bias_mps2
    w = gyro + rng.standard_normal(gyro.shape) * noise.gyro_noise_radps_per_sqrt_hz * root_rate
    w += rng.standard_normal(3) * noise.gyro_bias_radps
    if noise.gyro_rrw_radps_per_sqrt_s > 0:
        steps = rng.standard_normal(gyro.shape) * noise.gyro_rrw_radps_per_sqrt_s / root_rate
        w += np.cumsum(steps, axis=0)
    return a, w


@dataclass(frozen=True)
class ErrorGrowth:
    """σ_p [m] and σ_ψ [rad] (Eqs. (13)–(14)) at times t [s] from the start."""

    t_s: np.ndarray
    sigma_p_m: np.ndarray
    sigma_yaw_rad: np.ndarray


def error_growth(t_s: np.ndarray, position: np.ndarray, yaw: np.ndarray,
                 true_position: np.ndarray, true_yaw: np.ndarray) -> ErrorGrowth:
    """Eqs. (13)–(14) over runs: position (runs, K, 3) and yaw (runs, K) against the
    truth (K, 3) and (K,), both from the start."""
    dp = position - true_position
    dyaw = wrap_angle(yaw - true_yaw)
    return ErrorGrowth(t_s, np.sqrt(np.mean(np.sum(dp**2, axis=2), axis=0)),
                       np.sqrt(np.mean(dyaw**2, axis=0)))


def power_law(t_s: np.ndarray, sigma: np.ndarray) -> tuple[float, float]:
    """(c, e) of σ ≈ c·tᵉ by least squares in log-log over the samples with σ > 0."""
    ok = (t_s > 0) & (sigma > 0)
    if ok.sum() < 2:
        return 0.0, 0.0
    exponent, log_c = np.polyfit(np.log(t_s[ok]), np.log(sigma[ok]), 1)
    return float(np.exp(log_c)), float(exponent)


def log_spaced(n: int, first: int, count: int) -> np.ndarray:
    """About ``count`` sample indices from ``first`` to n − 1, evenly spaced in log."""
    return np.unique(np.geomspace(first, n - 1, count).astype(np.int64))


@dataclass(frozen=True)
class Walk:
    """The noiseless signals of one simulated walk and its truth, from the start:
    stamps t (T,) [s], specific force and rate (T, 3), attitude C_b^n at the start,
    position (T, 3) [m], yaw (T,) [rad], the foot pitch (T,) [rad], whether the foot is
    at rest (T,) and the standing time before the first stride [s]."""

    t_s: np.ndarray
    accel: np.ndarray
    gyro: np.ndarray
    rate_hz: float
    start_attitude: np.ndarray
    position: np.ndarray
    yaw: np.ndarray
    pitch: np.ndarray
    at_rest: np.ndarray
    rest_s: float = 0.0


def straight_walk(steps: int, rate_hz: float, rest_s: float = 0.0,
                  step: dict | None = None) -> Walk:
    """The noiseless simulated straight walk of ``steps`` strides (basic pattern, the
    scenario ``step`` mapping if given), after ``rest_s`` seconds standing."""
    segments = [{"type": "straight", "steps": steps}]
    if rest_s > 0:
        segments.insert(0, {"type": "standing", "duration_s": rest_s})
    data = {"segments": segments, **({"step": step} if step else {})}
    sim = simulate(SimulationConfig(scenario_from_dict(data, "walk"), data, "ideal", {},
                                    rate_hz))
    attitude = sim.trajectory.matrix
    position = sim.trajectory.position - sim.trajectory.position[0]
    moved = np.any(np.diff(position, axis=0) != 0, axis=1)
    return Walk(sim.imu.t_s - sim.imu.t_s[0], sim.imu["linear_acceleration"],
                sim.imu["angular_velocity"], rate_hz, attitude[0], position,
                np.arctan2(attitude[:, 1, 0], attitude[:, 0, 0]),
                np.arcsin(np.clip(-attitude[:, 2, 0], -1, 1)),
                ~np.r_[moved, moved[-1]] & ~np.r_[moved[0], moved], rest_s)


@dataclass(frozen=True)
class InsStudy:
    """σ(t) against the truth (Eq. (13)–(14) as written) and against the noiseless
    mechanization of the same walk (the error the source alone adds: the trapezoidal
    mechanization has its own, deterministic error, which Eq. (13) includes)."""

    against_truth: ErrorGrowth
    noise_only: ErrorGrowth


def ins_study(walk: Walk, noise: NoiseLevels, runs: int, seed: int = 0, block: int = 100,
              points: int = 200, gravity_mps2: float = STANDARD_GRAVITY_MPS2,
              progress=None, scheduler: str | None = None) -> InsStudy:
    """``runs`` pure-INS runs in blocks of ``block`` (memory: block × T × 6 doubles),
    sampled at ``points`` log-spaced times from 1 s; ``progress(done, runs)`` after each
    block. The blocks run here, or on the Dask ``scheduler`` (pdr_core.evaluation.parallel)."""
    if runs < 2:
        raise ValueError(f"runs must be >= 2, got {runs}")
    keep = log_spaced(len(walk.t_s), int(np.ceil(walk.rate_hz)), points)
    clean_p, clean_yaw = ins_loop(walk.t_s, walk.accel, walk.gyro, walk.start_attitude,
                                  gravity_mps2)
    parts = run_batches(partial(ins_block, walk, noise, seed, keep, gravity_mps2), runs,
                        block, scheduler, progress, "pdr-ekf-montecarlo-ins")
    p = np.concatenate([part[0] for part in parts])
    y = np.concatenate([part[1] for part in parts])
    t = walk.t_s[keep]
    return InsStudy(error_growth(t, p, y, walk.position[keep], walk.yaw[keep]),
                    error_growth(t, p, y, clean_p[keep], clean_yaw[keep]))


def ins_block(walk: Walk, noise: NoiseLevels, seed: int, keep: np.ndarray,
              gravity_mps2: float, first: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Runs first … first + count − 1 of :func:`ins_study`: position [m] (count, K, 3) and
    yaw [rad] (count, K) at the samples ``keep``."""
    a, w = noisy_signals(walk.accel, walk.gyro, walk.rate_hz, noise, seed,
                         range(first, first + count))
    return ins_batch(walk.t_s, a, w, walk.start_attitude, gravity_mps2, keep)
