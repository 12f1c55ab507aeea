"""PNG figures of pdr_drift (Matplotlib, Agg backend)."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def paths_png(paths: list[tuple[np.ndarray, str, str]], landmarks: np.ndarray, path: Path,
              title: str) -> None:
    """Top view [m] of several paths, each (points (N, ≥2), label, colour), and the
    landmarks (M, ≥2): a path before and after the drift corrections, with the truth."""
    fig, ax = plt.subplots(figsize=(9, 7))
    for points, label, colour in paths:
        ax.plot(points[:, 0], points[:, 1], color=colour, lw=1.2, label=label)
    if len(landmarks):
        ax.plot(landmarks[:, 0], landmarks[:, 1], "o", mfc="none", color="tab:green", ms=9,
                label="landmarks")
    ax.set(xlabel="east [m]", ylabel="north [m]", aspect="equal", title=title)
    ax.legend(loc="best")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
