"""PNG figures of the foot navigator (Matplotlib, Agg backend): the path against the truth,
the filter against the smoother."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from pdr_core.evaluation.metrics import aligned
from pdr_core.evaluation.plot_layout import (
    figure_title,
    height_axis,
    lay_out,
    top_view,
    walk_summary,
)


def path_png(t: np.ndarray, estimate: np.ndarray, truth: np.ndarray | None, path: Path,
             source: str | Path, *, steps: int | None = None,
             shows: str = "the estimated path") -> None:
    """Top view and height of the estimate (aligned as the report) against the truth, and
    the error over time. The top view is to scale unless it is a strip and the height
    axis fits the heights (pdr_core.evaluation.plot_layout); the title gives ``source``'s name,
    what it ``shows``, the ``steps`` and the report's final error, or without truth the
    loop gap."""
    fig, ax = plt.subplots(1, 3 if truth is not None else 2, figsize=(16, 5))
    est = aligned(estimate, truth) if truth is not None else estimate - estimate[0]
    ax[0].plot(est[:, 0], est[:, 1], label="estimate")
    ax[1].plot(t, est[:, 2], label="estimate")
    heights = est[:, 2]
    final_error = None
    if truth is not None:
        ref = truth - truth[0]
        ax[0].plot(ref[:, 0], ref[:, 1], "k--", label="truth")
        ax[1].plot(t, ref[:, 2], "k--", label="truth")
        error = np.linalg.norm(est - ref, axis=1)
        ax[2].plot(t, error)
        ax[2].set(xlabel="t [s]", ylabel="3D error [m]", title="error")
        heights, final_error = np.r_[heights, ref[:, 2]], float(error[-1])
    ax[0].set_title("top view")
    top_view(ax[0], "x [m]", "y [m]")
    ax[1].set(xlabel="t [s]", ylabel="z [m]", title="height")
    height_axis(ax[1], heights, "y")
    for a in ax[:2]:
        a.legend()
    lay_out(fig, figure_title(source, shows, walk_summary(
        steps, final_error, float(np.linalg.norm(est[-1] - est[0])))))
    fig.savefig(path, dpi=100)
    plt.close(fig)


def smoothing_png(t: np.ndarray, run_, path: Path, steps: int = 6) -> None:
    """Filtered against smoothed trajectory over a few steps in the middle of the walk,
    top view and height (Simón Colomar et al. 2012, Figs. 3–4): the filter jumps at every
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
