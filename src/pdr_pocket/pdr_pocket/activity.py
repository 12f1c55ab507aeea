"""Physical activities from the thigh pitch (Muñoz Díaz 2016, Section 4.1.3).

Per step, θ_min, θ_max and Δθ = θ_max − θ_min (Eq. (4.1)) are compared with the running
means of the last level steps, learned as the person walks (the walk starts on level
ground) and so adapted to their gait, mood and hurry:

- upstairs when Δθ ≫ mean Δθ_H and θ_max ≫ mean θ_Hmax: Δθ above the mean by
  ``up_amplitude_margin_deg`` and θ_max above it by ``up_max_margin_deg``. Beyond the
  thesis, θ_min must also not fall below its mean by more than ``up_min_tolerance_deg``:
  a faster level stride swings the leg further both ways (θ_min drops), a step up only
  forwards (|θ_Umin| slightly smaller than |θ_Hmin|, Section 4.1.2). Without it a change
  from 2.5 to 4.8 km/h (scenario H2) reads as stairs;
- downstairs when Δθ ≪ mean Δθ_H and θ_min ≫ mean θ_Hmin: Δθ below
  ``down_amplitude_ratio`` times the mean and θ_min above it by ``down_min_margin_deg``.
  Beyond the thesis, θ_min must stay below mean θ_Hmax: a step down swings the leg
  through the level swing's range (θ_Dmax only slightly above θ_Hmax, Section 4.1.2), and
  a swing wholly above it is the phone turned about the flexion axis in the pocket;
- else walking (level), and the step joins the running means.

The first ``level_history_steps`` steps are level by the thesis' assumption (the walk
starts on level ground): a reference made of one step, the first from standing whose θ_min
is the standing pitch, read every later step of a real walk (the Oxford pocket recording)
as downstairs.

Standing and sitting are decided only when no step has come for ``rest_after_s``: from
the pitch, about 0° standing, 45°–90° sitting (:func:`rest_activity`).
Activities are the pdr_msgs/Step constants.
"""
from __future__ import annotations

from collections import deque

import numpy as np

from pdr_pocket.config import ActivityConfig

STANDING, WALKING, UPSTAIRS, DOWNSTAIRS, SITTING = range(5)
ACTIVITY_NAMES = ("standing", "walking", "upstairs", "downstairs", "sitting")


class ActivityClassifier:
    """Step activities with the running level-step means (the thesis' algorithm)."""

    def __init__(self, config: ActivityConfig | None = None) -> None:
        self.config = config or ActivityConfig()
        self.level: deque = deque(maxlen=self.config.level_history_steps)

    def restart(self) -> None:
        """Forget the level steps (the phone was moved: θ is measured anew, and the steps
        while it turned were not the gait's)."""
        self.level.clear()

    def classify(self, pitch_max: float, pitch_min: float) -> int:
        """WALKING, UPSTAIRS or DOWNSTAIRS for one step (θ in rad)."""
        c = self.config
        hi, lo = np.degrees(pitch_max), np.degrees(pitch_min)
        amplitude = hi - lo
        if len(self.level) == self.level.maxlen:
            mean_hi, mean_lo, mean_amp = np.mean(np.asarray(self.level), axis=0)
            if amplitude > mean_amp + c.up_amplitude_margin_deg and \
                    hi > mean_hi + c.up_max_margin_deg and \
                    lo > mean_lo - c.up_min_tolerance_deg:
                return UPSTAIRS
            if amplitude < c.down_amplitude_ratio * mean_amp and \
                    mean_lo + c.down_min_margin_deg < lo < mean_hi:
                return DOWNSTAIRS
        self.level.append((hi, lo, amplitude))
        return WALKING


def rest_activity(pitch: np.ndarray, config: ActivityConfig) -> np.ndarray:
    """STANDING or SITTING per sample from |θ| [rad] (N,)."""
    sitting = np.abs(np.degrees(pitch)) >= config.sitting_min_pitch_deg
    return np.where(sitting, SITTING, STANDING).astype(np.uint8)
