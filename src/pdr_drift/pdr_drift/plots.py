"""PNG figures of pdr_drift (Matplotlib, Agg backend)."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from pdr_core.evaluation.plot_layout import figure_title, top_view

SAME_M = 0.01       # two paths closer than this at a step are drawn as one there [m]
SHARED_NOTE = 0.1   # the legend says how many steps the paths share beyond this share


def shared_steps(a: np.ndarray, b: np.ndarray) -> int:
    """How many rows two paths (N, ≥2) share from their start, within :data:`SAME_M`
    horizontally."""
    n = min(len(a), len(b))
    apart = np.flatnonzero(np.linalg.norm(a[:n, :2] - b[:n, :2], axis=1) > SAME_M)
    return int(apart[0]) if len(apart) else n


def paths_png(corrected: np.ndarray, uncorrected: np.ndarray, landmarks: np.ndarray,
              path: Path, source: str | Path, *, truth: np.ndarray | None = None,
              corrected_label: str = "corrected", uncorrected_label: str = "uncorrected",
              corrections: np.ndarray | None = None, shows: str = "the drift corrections"
              ) -> None:
    """Top view [m] of a path with the drift corrections and without, and the truth.

    Each path is (N + 1, ≥2): the walk's start, then one row per step. The corrected
    path is drawn wide and solid, the uncorrected one over it thin and dashed, so the
    part they share stays visible (its label says for how many steps when they share
    more than :data:`SHARED_NOTE` of them, within :data:`SAME_M`); ``corrections``
    (K, ≥2) marks where corrections were applied (★), ``landmarks`` (M, ≥2) the
    landmarks (○). The title: ``source``'s name, what it ``shows``, the steps and the
    final error of both paths against ``truth`` (the distance between the last rows, in
    the columns all three have), or without one their final loop gaps (start to end, as
    :func:`pdr_core.evaluation.metrics.walk_figures`)."""
    fig, ax = plt.subplots(figsize=(9, 7.5))
    if truth is not None:
        ax.plot(truth[:, 0], truth[:, 1], color="k", lw=1.0, label="truth")
    ax.plot(corrected[:, 0], corrected[:, 1], color="tab:blue", lw=3.0, alpha=0.7,
            label=corrected_label)
    shared = shared_steps(corrected, uncorrected) - 1
    ax.plot(uncorrected[:, 0], uncorrected[:, 1], "--", color="tab:red", lw=1.2,
            label=f"{uncorrected_label} (dashed; the same for the first {shared} of "
                  f"{len(uncorrected) - 1} steps)"
            if shared > SHARED_NOTE * (len(uncorrected) - 1) else uncorrected_label)
    if len(landmarks):
        ax.plot(landmarks[:, 0], landmarks[:, 1], "o", mfc="none", color="tab:green", ms=9,
                label="landmarks")
    if corrections is not None and len(corrections):
        ax.plot(corrections[:, 0], corrections[:, 1], "*", color="tab:purple", ms=14,
                mec="k", label="corrections applied")
    ax.plot(*corrected[0, :2], "s", color="k", ms=6, label="start")
    top_view(ax)
    ax.legend(loc="best", fontsize=8)
    if truth is None:
        gap = [float(np.linalg.norm(p[-1] - p[0])) for p in (uncorrected, corrected)]
        summary = f"no truth, final loop gap {gap[0]:.2f} m → {gap[1]:.2f} m corrected"
    else:
        axes = min(truth.shape[1], corrected.shape[1], uncorrected.shape[1])
        error = [float(np.linalg.norm(p[-1, :axes] - truth[-1, :axes]))
                 for p in (uncorrected, corrected)]
        summary = f"final error {error[0]:.2f} m → {error[1]:.2f} m corrected"
    fig.suptitle(figure_title(source, shows, f"{len(corrected) - 1} steps, {summary}"))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
