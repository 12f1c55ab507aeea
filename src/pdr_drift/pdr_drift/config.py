"""Configuration of the drift estimator: a typed dataclass from YAML, units in the names.

The dataclass defaults are the shipped ``config/landmark_drift.yaml`` (tested), the
default of the landmark_drift node (:func:`default_config_path`).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from pdr_core.config_files import dataclass_from_mapping, read_config_file, shipped_config_dir

CORNER_DETECTORS = ("turn", "buffer")
ASSOCIATIONS = ("nearest", "multi_hypothesis")


@dataclass(frozen=True)
class DriftConfig:
    """Muñoz Díaz 2016, chapter 5: corners (Eqs. (5.2)-(5.3), Fig. 5.3), association
    (Eq. (5.4), Section 5.2; or several hypotheses, pdr_drift.hypotheses, whose commit
    margin is a −2 log-likelihood ratio) and drift (Section 5.3, Eq. (6.5))."""

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
    landmark_yaw_sigma_deg: float = 4.0     # each landmark yaw (Section 5.3: a thigh's)
    association: str = "nearest"            # nearest (Section 5.2) or multi_hypothesis
    hypotheses_k: int = 8                   # multi_hypothesis: the best k kept
    commit_margin: float = 6.0              # ... committed when the next is this much worse
    drift_sigma_deg_per_s: float = 0.1      # ... drift plausible between corrections
    turn_scale_sigma: float = 0.01          # ... heading error per angle turned
    heading_wander_deg_per_sqrt_s: float = 0.5   # ... heading random walk
    place_sigma_m: float = 1.5              # ... two visits of one place this far apart
    places_per_km2: float = 300.0           # ... how densely corners and stairs lie
    max_drift_deg_per_s: float = 0.5        # offline: a drift beyond this is an outlier
    outlier_spread: float = 3.0             # offline: robust σ from the median

    def __post_init__(self) -> None:
        if self.corner_detector not in CORNER_DETECTORS:
            raise ValueError(f"corner_detector must be one of {', '.join(CORNER_DETECTORS)}, "
                             f"got {self.corner_detector!r}")
        if self.association not in ASSOCIATIONS:
            raise ValueError(f"association must be one of {', '.join(ASSOCIATIONS)}, "
                             f"got {self.association!r}")
        for name in ("q_steps", "m_steps", "r1_deg", "r2_deg", "turn_rate_min_deg_per_step",
                     "turn_tolerance_deg", "gate_probability", "gate_dof", "min_revisit_s",
                     "landmark_yaw_sigma_deg",
                     "hypotheses_k", "commit_margin", "drift_sigma_deg_per_s", "turn_scale_sigma",
                     "heading_wander_deg_per_sqrt_s",
                     "place_sigma_m", "places_per_km2",
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
