"""PNG figures of pdr_ins_ekf (Matplotlib, Agg backend)."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from pdr_core.metrics import aligned
from pdr_ins_ekf.mechanization_study import MechanizationStudy


def path_png(t: np.ndarray, estimate: np.ndarray, truth: np.ndarray | None, path: Path,
             title: str) -> None:
    """Top view and height of the estimate (aligned as the report) against the truth, and
    the error over time."""
    fig, ax = plt.subplots(1, 3 if truth is not None else 2, figsize=(16, 5))
    est = aligned(estimate, truth) if truth is not None else estimate - estimate[0]
    ax[0].plot(est[:, 0], est[:, 1], label="estimate")
    ax[1].plot(t, est[:, 2], label="estimate")
    if truth is not None:
        ref = truth - truth[0]
        ax[0].plot(ref[:, 0], ref[:, 1], "k--", label="truth")
        ax[1].plot(t, ref[:, 2], "k--", label="truth")
        ax[2].plot(t, np.linalg.norm(est - ref, axis=1))
        ax[2].set(xlabel="t [s]", ylabel="3D error [m]", title="error")
    ax[0].set(xlabel="x [m]", ylabel="y [m]", title="top view", aspect="equal")
    ax[1].set(xlabel="t [s]", ylabel="z [m]", title="height")
    for a in ax[:2]:
        a.legend()
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def smoothing_png(t: np.ndarray, run_, path: Path, steps: int = 6) -> None:
    """Filtered against smoothed trajectory over a few steps in the middle of the walk,
    top view and height (001_5b5dbf275b14cf0a.txt, Figs. 3–4): the filter jumps at every
    ZUPT onset, the smoother does not."""
    onsets = np.flatnonzero(run_.stance[1:] & ~run_.stance[:-1]) + 1
    middle = len(onsets) // 2
    first = onsets[max(0, middle - steps // 2)] if len(onsets) else 0
    last = onsets[min(len(onsets) - 1, middle + steps // 2)] if len(onsets) else len(t)
    part = slice(first, last + 1)
    filtered, smoothed = run_.output.position[part], run_.smoothed.position[part]
    fig, ax = plt.subplots(1, 2, figsize=(14, 5))
    ax[0].plot(filtered[:, 0], filtered[:, 1], ".-", ms=2, label="filter")
    ax[0].plot(smoothed[:, 0], smoothed[:, 1], ".-", ms=2, label="smoothed")
    ax[1].plot(t[part], filtered[:, 2], label="filter")
    ax[1].plot(t[part], smoothed[:, 2], label="smoothed")
    ax[0].set(xlabel="x [m]", ylabel="y [m]", title="top view", aspect="equal")
    ax[1].set(xlabel="t [s]", ylabel="z [m]", title="height")
    for a in ax:
        a.legend()
    fig.suptitle(f"RTS smoothing, {steps} steps")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def error_growth_png(growths: dict, path: Path, title: str) -> None:
    """σ_p(t) and σ_ψ(t) per error source, log-log (000, Eqs. (13)–(14))."""
    fig, ax = plt.subplots(1, 2, figsize=(14, 5))
    for source, growth in growths.items():
        ax[0].loglog(growth.t_s, growth.sigma_p_m, label=source)
        if growth.sigma_yaw_rad.max() > 0:
            ax[1].loglog(growth.t_s, growth.sigma_yaw_rad, label=source)
    ax[0].set(xlabel="t [s]", ylabel="σ_p [m]", title="position")
    ax[1].set(xlabel="t [s]", ylabel="σ_ψ [rad]", title="yaw")
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
        a.legend()
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def mechanization_png(study: MechanizationStudy, path: Path) -> None:
    """Final position error against sample rate per attitude method (000, Fig. 6)."""
    fig, ax = plt.subplots(figsize=(8, 6))
    for j, method in enumerate(study.methods):
        ax.loglog(study.rates_hz, study.errors_m[:, j], "o-", label=method)
    ax.set(xlabel="sample rate [Hz]", ylabel="final position error [m]",
           title=f"pure INS, noiseless 10-stride walk ({study.integration} integration)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def sweep_png(points: list, path: Path) -> None:
    """004, Figs. 3–6: σ_v and σ_θ against ARW, VRW and RRW, and σ_∥, σ_⊥ against RRW;
    analytic lines, the filter's covariance as points with its fluctuation bars."""
    rows = [(p, q) for p in ("arw", "vrw", "rrw") for q in ("sigma_v_mps", "sigma_theta_rad")]
    rows += [("rrw", "sigma_par_m"), ("rrw", "sigma_perp_m")]
    fig, axes = plt.subplots(4, 2, figsize=(12, 16))
    for ax, (parameter, quantity) in zip(axes.flat, rows, strict=True):
        chosen = [p for p in points if p.parameter == parameter]
        x = [p.value for p in chosen]
        ax.loglog(x, [p.analytic[quantity] for p in chosen], "b-", label="analytic")
        mean, low, high = (np.array([p.simulated[quantity][i] for p in chosen])
                           for i in range(3))
        ax.errorbar(x, mean, yerr=[mean - low, high - mean], fmt="rs", capsize=3,
                    label="EKF covariance")
        if quantity == "sigma_par_m":
            ax.loglog(x, [p.rederived_par_m for p in chosen], "b--",
                      label="analytic, Eq. (56) re-derived")
        carlo = [p.monte_carlo[quantity][0] for p in chosen if quantity in p.monte_carlo]
        if len(carlo) == len(chosen):
            ax.loglog(x, carlo, "g^", label="Monte-Carlo σ")
        ax.set(xlabel=f"{parameter.upper()}", ylabel=quantity)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("004, Figs. 3-6: analytic error levels against the ZUPT EKF")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
