"""What a drift estimator did over a walk, for the reports of ``pdr-pocket run --drift``
(:mod:`pdr_drift.drift_report`)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.vocabulary import LandmarkType
from pdr_drift.drift import DriftEstimate
from pdr_drift.landmarks import Landmark


@dataclass
class DriftLog:
    """What the drift estimator did: landmarks, drift estimates, corrections with their
    time (the step's or stride's, from the first IMU sample [s]) and outcome (accepted,
    message), and offline ε₀ [rad/s] with the estimates kept."""

    landmarks: list[Landmark] = field(default_factory=list)
    drifts: list[DriftEstimate] = field(default_factory=list)
    corrections: list[tuple[float, bool, str]] = field(default_factory=list)
    offline_drift: float | None = None
    kept: list[DriftEstimate] = field(default_factory=list)

    def summary(self) -> dict:
        accepted = sum(1 for _, ok, _ in self.corrections if ok)
        return {"landmarks": len(self.landmarks),
                "corners": sum(1 for m in self.landmarks if m.type == LandmarkType.CORNER),
                "stairs": sum(1 for m in self.landmarks if m.type == LandmarkType.STAIRS),
                "associations": len(self.drifts),
                "drift_deg_per_s": [float(np.degrees(d.drift)) for d in self.drifts],
                "corrections_accepted": accepted,
                "corrections_refused": len(self.corrections) - accepted,
                "correction_messages": [m for _, _, m in self.corrections],
                "correction_times_s": [float(t) for t, _, _ in self.corrections],
                "offline_drift_deg_per_s": None if self.offline_drift is None
                else float(np.degrees(self.offline_drift))}
