"""PNG figures of the foot INS studies (Matplotlib, Agg backend): Monte-Carlo error growth,
attitude methods against rate, the closed-form sweep."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from pdr_ins_ekf.studies.mechanization_study import MechanizationStudy


def error_growth_png(growths: dict, path: Path, title: str) -> None:
    """σ_p(t) and σ_ψ(t) per error source, log-log (Zampella et al. 2011, Eqs. (13)–(14))."""
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
    """Final position error against sample rate per attitude method (Zampella et al. 2011,
    Fig. 6)."""
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
    """Wang et al. 2020, Figs. 3–6: σ_v and σ_θ against ARW, VRW and RRW, and σ_∥, σ_⊥
    against RRW; analytic lines, the filter's covariance as points with its fluctuation
    bars."""
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
    fig.suptitle("Wang et al. 2020, Figs. 3-6: analytic error levels against the ZUPT EKF")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def stance_statistic_png(panels: list[dict], path: Path) -> None:
    """One panel per recording (real and simulated): the SHOE statistic over time (log),
    the adaptive threshold without and with the valley-depth rule, the true rest shaded,
    and each detector's stance marked (pdr_ins_ekf.studies.stance_study). A panel is a
    mapping with ``title``, ``t_s``, ``statistic``, ``at_rest``, ``thresholds`` and
    ``stance`` (labels to arrays)."""
    fig, axes = plt.subplots(len(panels), 1, figsize=(12, 4 * len(panels)))
    for ax, panel in zip(np.atleast_1d(axes), panels, strict=True):
        t = panel["t_s"]
        top = float(panel["statistic"].max()) * 3
        ax.fill_between(t, 1.0, top, where=panel["at_rest"], color="0.85",
                        label="at rest (truth)", step="mid")
        ax.semilogy(t, panel["statistic"], color="k", lw=1, label="SHOE statistic T")
        for (label, threshold), colour in zip(panel["thresholds"].items(), ("C3", "C2"),
                                               strict=True):
            ax.semilogy(t, threshold, color=colour, lw=1, ls="--", label=label)
        for row, ((label, stance), colour) in enumerate(zip(
                panel["stance"].items(), ("C3", "C2"), strict=True)):
            level = top / 2.5 ** (row + 1)
            ax.plot(t[stance], np.full(int(stance.sum()), level), "|", color=colour,
                    ms=8, label=label)
        ax.set(xlabel="t [s]", ylabel="T", title=panel["title"], ylim=(1.0, top))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(loc="lower left", fontsize=8, ncols=3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
