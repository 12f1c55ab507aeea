"""Monte-Carlo error analysis of the ZUPT EKF, batched over runs
(Zampella et al. 2011, section IV-B, Tables II–III; Wang et al. 2020, section IV-A).

N noise realisations of one noiseless simulated walk (standing first, to align on) are
processed as one batch with no Python loop over runs: the stance detector sees all runs at
once (time on axis 0, runs on axis 1, see :mod:`pdr_ins_ekf.zero_velocity`) and
:func:`ekf_batch` runs :func:`pdr_ins_ekf.compiled_filter.filter_loop`, the single-run
filter, on every run in parallel (numba ``prange``). Each run is therefore exactly
``zupt_ekf.run`` on its own samples, aligned on the standing period.

Besides σ_p and σ_ψ against the truth (Eqs. (13)–(14)) the study keeps the filter's own
predicted standard deviations (their mean and 5–95 % spread over runs) and the position
NEES, ε = δpᵀ·P_pp⁻¹·δp averaged over runs (3 for a consistent filter).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np
from numba import njit, prange

from pdr_core import units
from pdr_core.evaluation.parallel import run_batches
from pdr_core.maths import kernel_cache, small_matrix
from pdr_ins_ekf import compiled_filter, kernel_data
from pdr_ins_ekf.compiled_filter import filter_loop
from pdr_ins_ekf.kernel_data import GYRO, HEADING, NAV_AND_BIAS_STATES, NAV_STATES, Samples
from pdr_ins_ekf.studies.montecarlo import (
    ErrorGrowth,
    NoiseLevels,
    Walk,
    error_growth,
    noisy_signals,
)
from pdr_ins_ekf.zero_velocity import ConditionVoteDetector, StanceDetector
from pdr_ins_ekf.zupt_ekf import (
    FilterConfig,
    initial_attitude,
    initial_covariance,
    kernel_params,
    record_samples,
)

kernel_cache.forget_if_changed(__file__, compiled_filter.__file__, small_matrix.__file__,
                               kernel_data.__file__)

# Zampella et al. 2011, section IV-B: the XSens MTi of Tables II-III (3 °/√h, 122 µg/√Hz;
# constant biases drawn per axis with σ 1.23 mg and 0.5 °/s)
XSENS_MTI = NoiseLevels(acc_noise_mps2_per_sqrt_hz=units.ug_per_sqrt_hz_to_si(122.0),
                        gyro_noise_radps_per_sqrt_hz=units.arw_to_si(3.0),
                        acc_bias_mps2=units.mg_to_si(1.23),
                        gyro_bias_radps=np.radians(0.5))


def filter_for(noise: NoiseLevels, zupt_sigma_mps: float = 0.01,
               states: int = NAV_AND_BIAS_STATES) -> FilterConfig:
    """The ZUPT filter matched to an IMU's noise: 15 states with ZUPT and ZARU (Zampella
    et al. 2011, section IV; Wang et al. 2020, Eq. (2)), white noise densities as process
    noise, the bias σ as initial bias uncertainty, the RRW as the gyro bias random walk (a
    floor keeps every density > 0); or 9 states, ZUPT only, biases not estimated. As in
    the paper, the ZARU runs in every detected stance (no innovation gate:
    ``zaru_gate_nis`` infinite), so the detectors' windows are compared on the paper's
    filter."""
    if states not in (NAV_STATES, NAV_AND_BIAS_STATES):
        raise ValueError(f"states must be {NAV_STATES} or {NAV_AND_BIAS_STATES}, "
                         f"got {states}")
    floor = 1e-9
    return FilterConfig(
        acc_noise_mps2_per_sqrt_hz=max(noise.acc_noise_mps2_per_sqrt_hz, 1e-5),
        gyro_noise_radps_per_sqrt_hz=max(noise.gyro_noise_radps_per_sqrt_hz, 1e-7),
        zupt_sigma_mps=zupt_sigma_mps, zaru=states == NAV_AND_BIAS_STATES,
        zaru_gate_nis=np.inf,
        bias_model="random_walk" if states == NAV_AND_BIAS_STATES else "none",
        acc_bias_noise_mps2_per_sqrt_s=floor,
        gyro_bias_noise_radps_per_sqrt_s=max(noise.gyro_rrw_radps_per_sqrt_s, floor),
        init_acc_bias_sigma_mps2=max(noise.acc_bias_mps2, 1e-4),
        init_gyro_bias_sigma_radps=max(noise.gyro_bias_radps, 1e-5))


@njit(cache=True, parallel=True)
def ekf_batch(samples, C0, b0, P0, params, keep):
    """``filter_loop`` on every run of ``samples``, a
    :class:`~pdr_ins_ekf.kernel_data.Samples` with the intervals dt (T,) [s] shared by
    all runs, accel [m/s²] and gyro [rad/s] (runs, T, 3) and stance (runs, T), from the
    per-run attitude C0 (runs, 3, 3) and bias b0 (runs, 6) and the covariance P0 (n, n);
    at the sample indices ``keep`` (K,): position [m] (runs, K, 3), yaw [rad] (runs, K),
    the covariance diagonal (runs, K, n) and the position covariance [m²]
    (runs, K, 3, 3)."""
    runs, count = samples.accel.shape[0], keep.shape[0]
    pos = np.empty((runs, count, 3))
    yaw = np.empty((runs, count))
    var = np.empty((runs, count, P0.shape[0]))
    pcov = np.empty((runs, count, 3, 3))
    for r in prange(runs):
        run = Samples(samples.dt, samples.accel[r], samples.gyro[r], samples.stance[r])
        p, _, att, _, v, pc, _, _, _, _, _ = filter_loop(run, C0[r], b0[r], P0, params)
        for i in range(count):
            j = keep[i]
            pos[r, i] = p[j]
            yaw[r, i] = np.arctan2(att[j, 1, 0], att[j, 0, 0])
            var[r, i] = v[j]
            pcov[r, i] = pc[j]
    return pos, yaw, var, pcov


@dataclass(frozen=True)
class BatchResult:
    """One block of runs at the kept samples (see :func:`ekf_batch`)."""

    position: np.ndarray
    yaw: np.ndarray
    variance: np.ndarray
    position_cov: np.ndarray


def detect_runs(detector: StanceDetector, accel: np.ndarray, gyro: np.ndarray,
                rate_hz: float) -> np.ndarray:
    """The stance masks (runs, T) of accel, gyro (runs, T, 3), all runs in one call."""
    mask = detector.detect(accel.transpose(1, 0, 2), gyro.transpose(1, 0, 2), rate_hz).mask
    return np.ascontiguousarray(mask.T)


def run_batch(walk: Walk, accel: np.ndarray, gyro: np.ndarray, stance: np.ndarray,
              config: FilterConfig, keep: np.ndarray, rest_gyro_bias: bool = True
              ) -> BatchResult:
    """Align each run on the standing period (roll and pitch; the gyro bias from the mean
    rate if ``rest_gyro_bias``, else zero, left to the ZARU updates) and filter every run
    (accel, gyro: (runs, T, 3); stance (runs, T))."""
    rest = rest_samples(walk)
    attitude = initial_attitude(accel[:, rest], walk.yaw[0])
    bias = np.zeros((len(accel), 6))
    if rest_gyro_bias:
        bias[:, GYRO] = gyro[:, rest].mean(axis=1)
    return BatchResult(*ekf_batch(
        record_samples(walk.t_s, accel, gyro, stance), attitude, bias,
        initial_covariance(config), kernel_params(config), keep))


def rest_samples(walk: Walk) -> slice:
    """The standing samples before the first stride, to align on."""
    count = int(np.searchsorted(walk.t_s, walk.rest_s))
    if count < 2:
        raise ValueError("the walk needs a standing period to align on (rest_s > 0)")
    return slice(0, count)


def stance_times(walk: Walk, first_s: float, points: int) -> np.ndarray:
    """About ``points`` sample indices at rest, from ``first_s`` seconds of walking on,
    evenly spaced in log time (Zampella et al. 2011, section IV-B: the errors "during the
    stance phase")."""
    candidates = np.flatnonzero(walk.at_rest & (walk.t_s >= walk.rest_s + first_s))
    if candidates.size == 0:
        raise ValueError(f"no stance after {first_s} s of walking")
    wanted = np.geomspace(walk.t_s[candidates[0]] - walk.rest_s,
                          walk.t_s[candidates[-1]] - walk.rest_s, points) + walk.rest_s
    at = np.searchsorted(walk.t_s[candidates], wanted).clip(0, candidates.size - 1)
    return np.unique(candidates[at])


@dataclass(frozen=True)
class Consistency:
    """The filter's own view at the kept times: the mean and 5 / 95 % quantiles over runs
    of its predicted σ_p = √tr P_pp [m] and σ_ψ [rad], and the mean position NEES."""

    sigma_p_m: np.ndarray
    sigma_p_q05_m: np.ndarray
    sigma_p_q95_m: np.ndarray
    sigma_yaw_rad: np.ndarray
    nees_position: np.ndarray


@dataclass(frozen=True)
class EkfStudy:
    """σ_p, σ_ψ against the truth (Eqs. (13)–(14)), t from the first stride [s], and the
    filter's consistency."""

    growth: ErrorGrowth
    consistency: Consistency


def consistency(result: BatchResult, truth: np.ndarray) -> Consistency:
    """:class:`Consistency` of a batch against the true positions (K, 3)."""
    sigma_p = np.sqrt(np.trace(result.position_cov, axis1=2, axis2=3))
    error = result.position - truth
    nees = np.einsum("rki,rki->rk", error,
                     np.linalg.solve(result.position_cov, error[..., None])[..., 0])
    return Consistency(sigma_p.mean(axis=0), np.quantile(sigma_p, 0.05, axis=0),
                       np.quantile(sigma_p, 0.95, axis=0),
                       np.sqrt(result.variance[..., HEADING]).mean(axis=0), nees.mean(axis=0))


def ekf_study(walk: Walk, noise: NoiseLevels, runs: int, detector: StanceDetector,
              config: FilterConfig, seed: int = 0, block: int = 20, points: int = 200,
              progress=None, rest_gyro_bias: bool = True, scheduler: str | None = None
              ) -> EkfStudy:
    """``runs`` EKF runs in blocks of ``block`` (memory: block × T × 6 doubles for the
    signals, plus one filter history per thread); ``progress(done, runs)`` per block.
    ``rest_gyro_bias``: see :func:`run_batch`. The blocks run here, or on the Dask
    ``scheduler`` (pdr_core.evaluation.parallel); a run's noise depends on its index only."""
    if runs < 2:
        raise ValueError(f"runs must be >= 2, got {runs}")
    keep = stance_times(walk, 1.0, points)
    parts = run_batches(partial(ekf_block, walk, noise, seed, detector, config, keep,
                                rest_gyro_bias), runs, block, scheduler, progress,
                        "pdr-ekf-montecarlo-ekf")
    result = BatchResult(*(np.concatenate([getattr(p, f) for p in parts])
                           for f in BatchResult.__dataclass_fields__))
    t = walk.t_s[keep] - walk.rest_s
    growth = error_growth(t, result.position, result.yaw, walk.position[keep],
                          walk.yaw[keep])
    return EkfStudy(growth, consistency(result, walk.position[keep]))


def ekf_block(walk: Walk, noise: NoiseLevels, seed: int, detector: StanceDetector,
              config: FilterConfig, keep: np.ndarray, rest_gyro_bias: bool, first: int,
              count: int) -> BatchResult:
    """Runs first … first + count − 1 of :func:`ekf_study`, detected and filtered."""
    a, w = noisy_signals(walk.accel, walk.gyro, walk.rate_hz, noise, seed,
                         range(first, first + count))
    stance = detect_runs(detector, a, w, walk.rate_hz)
    return run_batch(walk, a, w, stance, config, keep, rest_gyro_bias)


# Zampella et al. 2011, Tables II (σ_p [m]) and III (σ_ψ [rad]), t [s] of walking, per
# source and window (original, limited, retarded)
PUBLISHED_EKF_GROWTH = {
    "sigma_p": {
        "acc_noise": ("2e-2·t^1.11", "6e-4·t", "3e-4·t"),
        "gyro_noise": ("3e-2·t + 1.5e-4·t²", "2e-3·t + 1.5e-4·t²", "2e-3·t + 1.5e-4·t²"),
        "acc_bias": ("3e-1·t + 1e-4·t²", "1e-3·t + 3e-6·t²", "1e-3·t + 2e-6·t²"),
        "gyro_bias": ("3e-2·t + 6e-4·t²", "1.3e-2·t + 6e-4·t²", "1.3e-2·t + 6e-4·t²")},
    "sigma_yaw": {
        "acc_noise": ("2e-4·t", "5e-6·t", "7e-7·t + 6e-9·t²"),
        "gyro_noise": ("2.7e-4·t", "2.3e-4·t", "2.3e-4·t"),
        "acc_bias": ("2e-4·t", "6e-6·t", "1.3e-7·t"),
        "gyro_bias": ("1.25e-3·t + 1e-2", "1.25e-3·t + 1e-2", "1.25e-3·t + 1e-2")},
}
VOTE_WINDOWS = ("original", "limited", "retarded")
ESTIMATORS = ("ins", *(f"ekf_{w}" for w in VOTE_WINDOWS))


def estimator_detector(estimator: str) -> StanceDetector:
    """The detector of ``ekf_<window>``: Zampella et al. 2011's condition vote
    (:class:`~pdr_ins_ekf.zero_velocity.ConditionVoteDetector`) with that window."""
    window = estimator.removeprefix("ekf_")
    if window not in VOTE_WINDOWS:
        raise ValueError(f"unknown estimator {estimator!r}; one of {', '.join(ESTIMATORS)}")
    return ConditionVoteDetector(variant=window)


def polynomial_fit(t_s: np.ndarray, sigma: np.ndarray) -> tuple[float, float]:
    """(a, b) ≥ 0 of σ ≈ a·t + b·t², the form of Tables II–III, by least squares on the
    relative error (each sample weighted 1/σ)."""
    from scipy.optimize import nnls  # imported when used: pdr-ekf starts faster

    ok = (t_s > 0) & (sigma > 0)
    design = np.column_stack([t_s[ok], t_s[ok] ** 2]) / sigma[ok, None]
    (a, b), _ = nnls(design, np.ones(ok.sum()))
    return float(a), float(b)
