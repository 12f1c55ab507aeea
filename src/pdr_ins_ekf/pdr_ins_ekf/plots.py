"""PNG figures of pdr_ins_ekf (Matplotlib, Agg backend)."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from pdr_ins_ekf.mechanization_study import MechanizationStudy


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
