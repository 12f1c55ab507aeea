"""Configuration of the drift estimator: a typed dataclass from YAML, units in the names.

The dataclass defaults are the shipped ``config/landmark_drift.yaml`` (tested), the
default of the landmark_drift node (:func:`default_config_path`).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from pdr_core.config_files import dataclass_from_mapping, read_config_file, shipped_config_dir

CORNER_DETECTORS = ("turn", "buffer")


@dataclass(frozen=True)
class DriftConfig:
    """Muñoz Díaz 2016, chapter 5: corners (Eqs. (5.2)-(5.3), Fig. 5.3), association
    (Eq. (5.4), Section 5.2) and drift (Section 5.3, Eq. (6.5))."""

    corner_detector: str = "turn"           # turn (Fig. 5.3) or buffer (Eqs. (5.2)-(5.3))
    q_steps: int = 2                        # heading buffer before and after a corner
    m_steps: int = 5                        # buffer detector: steps between the buffers
    r1_deg: float = 80.0
    r2_deg: float = 100.0
    turn_rate_min_deg_per_step: float = 6.0
    turn_tolerance_deg: float = 15.0        # a turn within this of 90° or 180° is a corner
    gate_probability: float = 0.997         # κ = √χ²(p, n) = 4.48 (Section 5.2)
    gate_dof: int = 6
    min_revisit_s: float = 120.0
    max_drift_deg_per_s: float = 0.5        # offline: a drift beyond this is an outlier
    outlier_spread: float = 3.0             # offline: robust σ from the median

    def __post_init__(self) -> None:
        if self.corner_detector not in CORNER_DETECTORS:
            raise ValueError(f"corner_detector must be one of {', '.join(CORNER_DETECTORS)}, "
                             f"got {self.corner_detector!r}")
        for name in ("q_steps", "m_steps", "r1_deg", "r2_deg", "turn_rate_min_deg_per_step",
                     "turn_tolerance_deg", "gate_probability", "gate_dof", "min_revisit_s",
                     "max_drift_deg_per_s", "outlier_spread"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        if not self.r1_deg < self.r2_deg:
            raise ValueError("r1_deg must be below r2_deg")


def default_config_path() -> Path:
    """The installed ``config/landmark_drift.yaml``."""
    return shipped_config_dir("pdr_drift") / "landmark_drift.yaml"


def load_drift_config(path: str | Path | None) -> DriftConfig:
    """The configuration of a YAML file (``drift:`` section or the keys at the top);
    None: the defaults."""
    if path is None:
        return DriftConfig()
    data = read_config_file(Path(path))
    return dataclass_from_mapping(DriftConfig, data.get("drift", data), str(path))
