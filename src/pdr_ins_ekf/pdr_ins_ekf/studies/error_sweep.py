"""The numerical verification of Wang et al. 2020, section IV-A (Figs. 3–6):
sweeps of ARW, VRW and RRW, the closed-form levels of :mod:`pdr_ins_ekf.studies.zupt_error_model`
against the ZUPT EKF on the paper's simulated walk.

The walk: 100 strides toward +x, 77 m in 53.6 s (the paper's figures; its stance time is
not given, :data:`SWEEP_STEP` splits the 0.536 s stride into 0.336 s of swing and
0.2 s of stance), after 2 s standing to align on, at 800 Hz. The model's time starts
with the walk; a longer rest adds heading and z-bias drift it does not count (10 s put
σ_⊥ 12–34 % above the model). The filter is the 15-state EKF with
r = 0.02 m/s and its process noise set to the swept IMU (:func:`filter_for`); ZUPTs come
at the true stance samples, so the comparison tests the error model and not a detector.
The gait inputs of the model (t_stance, t_stride, a_c, a_s, s_N) are measured on the walk.

Per sweep point, "simulated" is the filter's own covariance, as the paper's simulation
results are (its Fig. 2 and error bars: "covariances of the estimation errors fluctuated
during the navigation"):

- σ_v: the filter's σ of the horizontal velocity at the stance samples after the first
  ``settle_fraction`` of the walk (the level the ZUPTs balance, Eq. (43)), mean and
  5–95 % quantiles;
- σ_θ: its σ of roll and pitch over all samples after that;
- σ_∥, σ_⊥: its predicted σ along and across the walk at the end.

The Monte-Carlo spread of the final position error is reported beside them. It is far
below σ_∥: the simulated foot is exactly still in stance, while the model and the
filter take the ZUPT as a measurement with noise r. Its runs go in batches of
:data:`SWEEP_BATCH_RUNS`, here or on a Dask cluster (``scheduler``), each run seeded by its
index (pdr_core.evaluation.parallel): the split does not change the figures.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from pdr_core import units
from pdr_core.evaluation.parallel import run_batches
from pdr_core.maths.chi2 import chi2_quantile
from pdr_ins_ekf.studies.ekf_montecarlo import filter_for, run_batch
from pdr_ins_ekf.studies.montecarlo import NoiseLevels, Walk, noisy_signals, straight_walk
from pdr_ins_ekf.studies.zupt_error_model import Gait, NoiseDensities, ZuptErrorModel
from pdr_ins_ekf.zupt_ekf import run

SWEEP_STEP = {"length_m": 0.77, "swing_s": 0.336, "stance_s": 0.2}
SWEEP_RATE_HZ = 800.0
SWEEP_ZUPT_SIGMA_MPS = 0.02
# Wang et al. 2020, section IV-A: the swept ranges and the values held while another is swept
BASELINE = {"arw": 0.21, "vrw": 0.14, "rrw": 48.0}
RANGES = {"arw": (0.01, 10.0), "vrw": (0.01, 10.0), "rrw": (0.6, 600.0)}
UNITS = {"arw": "°/√h", "vrw": "mg/√Hz", "rrw": "mdeg/s/√h"}
# the model assumes a known start: no initial heading or bias uncertainty
KNOWN_START = {"init_yaw_sigma_rad": 1e-6, "init_acc_bias_sigma_mps2": 1e-6,
               "init_gyro_bias_sigma_radps": 1e-7}
SWEEP_BATCH_RUNS = 5   # runs per batch: 5 × 44.5 k samples × 6 doubles ≈ 11 MB of signals
QUANTITIES = ("sigma_v_mps", "sigma_theta_rad", "sigma_par_m", "sigma_perp_m")


def paper_walk(steps: int = 100, rate_hz: float = SWEEP_RATE_HZ,
               rest_s: float = 2.0) -> Walk:
    """The paper's straight walk (module docstring)."""
    return straight_walk(steps, rate_hz, rest_s, SWEEP_STEP)


def gait_of(walk: Walk) -> Gait:
    """The model's gait inputs measured on the walk after standing: stride time and
    length, the stance time per stride (samples at rest / f_s) and a_c, a_s (means of
    cos and sin of the foot pitch)."""
    walking = walk.t_s >= walk.rest_s
    starts = np.flatnonzero(walking[1:] & ~walk.at_rest[1:] & walk.at_rest[:-1]) + 1
    strides = len(starts)
    if strides < 2:
        raise ValueError("the walk needs at least 2 strides")
    t_stride = float(np.mean(np.diff(walk.t_s[starts])))
    rest_per_stride = (walk.at_rest[starts[0]:starts[-1]].sum()) / (strides - 1)
    pitch = walk.pitch[walking]
    return Gait(rest_per_stride / walk.rate_hz, t_stride, float(np.cos(pitch).mean()),
                float(np.sin(pitch).mean()),
                float(walk.position[starts[-1], 0] - walk.position[starts[0], 0])
                / (strides - 1))


def noise_point(arw: float, vrw: float, rrw: float) -> tuple[NoiseDensities, NoiseLevels]:
    """ARW [°/√h], VRW [mg/√Hz], RRW [mdeg/s/√h] as the model's densities and the
    simulator's noise (white noise and a gyro bias random walk)."""
    densities = NoiseDensities(units.arw_to_si(arw), units.mg_to_si(vrw),
                               units.rrw_to_si(rrw * 1e-3))
    return densities, NoiseLevels(acc_noise_mps2_per_sqrt_hz=densities.vrw_mps2_per_sqrt_hz,
                                  gyro_noise_radps_per_sqrt_hz=densities.arw_rad_per_sqrt_s,
                                  gyro_rrw_radps_per_sqrt_s=densities.rrw_radps_per_sqrt_s)


@dataclass(frozen=True)
class SweepPoint:
    """One swept value: per quantity of :data:`QUANTITIES` the analytic value and the
    simulated (mean, low, high); σ_∥ also by the re-derived Eq. (56) (``rederived_par_m``),
    and the Monte-Carlo spread (σ) of the final errors along and across the walk (σ, 90 %
    interval), which the model does not describe (module docstring)."""

    parameter: str
    value: float
    analytic: dict
    simulated: dict
    rederived_par_m: float
    monte_carlo: dict


def sweep_point(walk: Walk, gait: Gait, parameter: str, value: float, runs: int,
                seed: int = 0, settle_fraction: float = 0.2, scheduler: str | None = None
                ) -> SweepPoint:
    """The analytic and simulated levels with ``parameter`` at ``value``, the others at
    :data:`BASELINE`; the Monte-Carlo runs here or on the Dask ``scheduler``."""
    densities, noise = noise_point(**{**BASELINE, parameter: value})
    model = ZuptErrorModel(densities, gait, SWEEP_ZUPT_SIGMA_MPS, walk.rate_hz)
    steady = model.steady_state()
    duration = float(walk.t_s[-1] - walk.rest_s)
    analytic = {"sigma_v_mps": steady.sigma_v_mps, "sigma_theta_rad": steady.sigma_theta_rad,
                "sigma_par_m": float(model.sigma_par_m(duration)),
                "sigma_perp_m": float(model.sigma_perp_m(duration))}
    config = replace(filter_for(noise, SWEEP_ZUPT_SIGMA_MPS), **KNOWN_START)
    rest = slice(0, int(np.searchsorted(walk.t_s, walk.rest_s)))
    filtered = run(walk.t_s, walk.accel, walk.gyro, walk.at_rest, config, rest, walk.yaw[0])
    swing_too = walk.t_s >= walk.rest_s + settle_fraction * duration
    stance = walk.at_rest & swing_too
    sigma_v = np.sqrt(filtered.variance[stance, 3:5].mean(axis=1))
    sigma_theta = np.sqrt(filtered.variance[swing_too, 6:8].mean(axis=1))
    simulated = {"sigma_v_mps": _bar(sigma_v), "sigma_theta_rad": _bar(sigma_theta),
                 "sigma_par_m": (float(np.sqrt(filtered.position_cov[-1, 0, 0])),) * 3,
                 "sigma_perp_m": (float(np.sqrt(filtered.position_cov[-1, 1, 1])),) * 3}
    return SweepPoint(parameter, value, analytic, simulated,
                      float(replace(model, rederived_eq56=True).sigma_par_m(duration)),
                      _monte_carlo(walk, noise, config, runs, seed, scheduler))


def _monte_carlo(walk: Walk, noise: NoiseLevels, config, runs: int, seed: int,
                 scheduler: str | None) -> dict:
    """Spread over ``runs`` of the final position error along (x) and across (y) the
    walk."""
    if runs < 2:
        return {}
    ends = run_batches(partial(final_errors, walk, noise, config, seed), runs,
                       SWEEP_BATCH_RUNS, scheduler, name="pdr-ekf-sweep")
    error = np.concatenate(ends)
    return {"sigma_par_m": _spread(error[:, 0]), "sigma_perp_m": _spread(error[:, 1])}


def final_errors(walk: Walk, noise: NoiseLevels, config, seed: int, first: int, count: int
                 ) -> np.ndarray:
    """The final horizontal position error [m] (count, 2) of runs first … first + count − 1,
    with ZUPTs at the true stance."""
    a, w = noisy_signals(walk.accel, walk.gyro, walk.rate_hz, noise, seed,
                         range(first, first + count))
    stance = np.broadcast_to(walk.at_rest, (count, len(walk.t_s)))
    # the bias starts at zero, as the model and the filter's start (KNOWN_START) assume;
    # its mean over the noisy rest would put an unmodelled heading drift in every run
    result = run_batch(walk, a, w, stance, config, np.array([len(walk.t_s) - 1]),
                       rest_gyro_bias=False)
    return result.position[:, 0, :2] - walk.position[-1, :2]


def _bar(sigma: np.ndarray) -> tuple[float, float, float]:
    """Mean and 5 / 95 % quantiles of a fluctuating σ."""
    return float(sigma.mean()), *(float(q) for q in np.quantile(sigma, (0.05, 0.95)))


def _spread(error: np.ndarray) -> tuple[float, float, float]:
    """Standard deviation of the errors about their mean (the filter's deterministic
    error on this walk is not noise) and its 90 % interval from len(error) runs."""
    n = len(error)
    std = float(np.std(error, ddof=1))
    return (std, std * float(np.sqrt((n - 1) / chi2_quantile(0.95, n - 1))),
            std * float(np.sqrt((n - 1) / chi2_quantile(0.05, n - 1))))


def sweep_values(parameter: str, points: int) -> np.ndarray:
    """``points`` log-spaced values over the paper's range of ``parameter``."""
    low, high = RANGES[parameter]
    return np.geomspace(low, high, points)


def agreement(point: SweepPoint, quantity: str) -> float:
    """Simulated mean / analytic − 1."""
    return point.simulated[quantity][0] / point.analytic[quantity] - 1


def sweep_markdown(points: list[SweepPoint], gait: Gait) -> str:
    """Analytic against simulated per point and quantity, with the difference; for σ_∥
    also the re-derived Eq. (56), for σ_∥ and σ_⊥ the Monte-Carlo σ."""
    text = (f"gait measured on the walk: t_stance {gait.t_stance_s:.3f} s, t_stride "
            f"{gait.t_stride_s:.3f} s, a_c {gait.cos_pitch_mean:.3f}, a_s "
            f"{gait.sin_pitch_mean:.3f}, s_N {gait.stride_m:.2f} m\n\n"
            "| swept | value | quantity | analytic | EKF (low-high) | difference | notes |\n"
            "|---|---:|---|---:|---:|---:|---|\n")
    for p in points:
        for q in QUANTITIES:
            mean, low, high = p.simulated[q]
            notes = []
            if q == "sigma_par_m":
                notes.append(f"Eq. (56) re-derived {p.rederived_par_m:.3g} "
                             f"({p.rederived_par_m / mean - 1:+.0%} from the EKF)")
            if q in p.monte_carlo:
                notes.append(f"Monte-Carlo σ {p.monte_carlo[q][0]:.3g}")
            text += (f"| {p.parameter} | {p.value:.3g} | {q} | {p.analytic[q]:.3g} | "
                     f"{mean:.3g} ({low:.3g}-{high:.3g}) | "
                     f"{agreement(p, q):+.0%} | {'; '.join(notes)} |\n")
    return text


def sweep_csv(points: list[SweepPoint]) -> str:
    """sweep.csv: one row per point and quantity."""
    lines = ["parameter,value,quantity,analytic,simulated_mean,simulated_low,simulated_high,"
             "rederived_eq56,monte_carlo_sigma"]
    for p in points:
        for q in QUANTITIES:
            extra = (p.rederived_par_m if q == "sigma_par_m" else "",
                     p.monte_carlo[q][0] if q in p.monte_carlo else "")
            lines.append(",".join(str(x) for x in (p.parameter, p.value, q, p.analytic[q],
                                                  *p.simulated[q], *extra)))
    return "\n".join(lines) + "\n"
