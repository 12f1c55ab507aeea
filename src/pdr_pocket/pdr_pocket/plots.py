"""PNG figures of pdr_pocket (Matplotlib, Agg backend): the attitude errors and the gyro
biases with their ±σ, as Muñoz Díaz 2016, Figs. 3.10 and 3.14-3.17; the magnetometer's
raw cloud and the fitted sphere, as Fig. 3.20."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt

AXES = ("x", "y", "z")
COLOURS = ("tab:blue", "tab:red", "tab:green")


def attitude_png(t_s: np.ndarray, errors_deg: np.ndarray | None, sigma_deg: np.ndarray,
                 bias_deg_per_s: np.ndarray, bias_sigma: np.ndarray,
                 true_bias: np.ndarray | None, path: Path, title: str) -> None:
    """Top: roll, pitch, yaw errors [°] with ±σ (or ±σ alone without a truth); bottom:
    the three gyro biases [°/s] with ±σ and the true values, against minutes."""
    step = max(1, len(t_s) // 20000)
    t = t_s[::step] / 60.0
    fig, ax = plt.subplots(2, 1, figsize=(12, 9), sharex=True)
    for i, name in enumerate(("roll", "pitch", "yaw")):
        s = sigma_deg[::step, i]
        if errors_deg is not None:
            ax[0].plot(t, errors_deg[::step, i], color=COLOURS[i], lw=0.8, label=f"{name} error")
        ax[0].plot(t, s, ":", color=COLOURS[i], lw=0.8)
        ax[0].plot(t, -s, ":", color=COLOURS[i], lw=0.8)
    ax[0].set(ylabel="[deg]", title="attitude error (dotted: ±σ)" if errors_deg is not None
              else "attitude ±σ (no truth in the bag)")
    if errors_deg is not None:
        ax[0].legend(loc="upper left")
    for i, name in enumerate(AXES):
        b, s = bias_deg_per_s[::step, i], bias_sigma[::step, i]
        ax[1].plot(t, b, color=COLOURS[i], label=f"b_{name}")
        ax[1].plot(t, b + s, ":", color=COLOURS[i], lw=0.8)
        ax[1].plot(t, b - s, ":", color=COLOURS[i], lw=0.8)
        if true_bias is not None:
            ax[1].axhline(true_bias[i], color=COLOURS[i], ls="--", lw=0.8)
    ax[1].set(xlabel="t [min]", ylabel="[deg/s]", title="gyroscope biases (dotted: ±σ, "
              "dashed: truth)")
    ax[1].legend(loc="upper left")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def magnetometer_png(raw_ut: np.ndarray, calibrated_ut: np.ndarray, path: Path,
                     title: str) -> None:
    """The raw readings and the calibrated ones, which the fit brings to a sphere."""
    step = max(1, len(raw_ut) // 5000)
    fig = plt.figure(figsize=(12, 6))
    for k, (points, name) in enumerate(((raw_ut, "raw"), (calibrated_ut, "calibrated"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        ax.scatter(*points[::step].T, s=2, color="tab:blue" if k == 0 else "tab:red")
        if k == 1:
            radius = float(np.median(np.linalg.norm(calibrated_ut, axis=1)))
            u, v = np.mgrid[0:2 * np.pi:30j, 0:np.pi:15j]
            ax.plot_wireframe(radius * np.cos(u) * np.sin(v), radius * np.sin(u) * np.sin(v),
                              radius * np.cos(v), color="grey", lw=0.3)
        ax.set(xlabel="x [µT]", ylabel="y [µT]", zlabel="z [µT]", title=name)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
