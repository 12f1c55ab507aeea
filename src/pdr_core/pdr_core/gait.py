"""What a person can walk: the limits a navigator's strides and speed are checked against.

- :data:`POPULATION_HEIGHT_M`: the adult an uncalibrated stride model stands for [m].
- :data:`WALK_RATIO_MAX_M_PER_SPM`: the largest walk ratio, step length [m] over cadence
  [steps/min]. Sekiya and Nagasaki ("Reproducibility of the walking patterns of normal
  young adults", Gait & Posture 1998) find it constant over a person's slow to fast
  walking, 0.0064 m/(steps/min) for men and 0.0057 for women (σ about 0.0005); a sprint
  (a 2.4 m step at 280 steps/min) stays under 0.0086. 0.010 bounds them all with room.
- :func:`stride_bound_m`: the longest gait cycle (two steps) at a cycle's duration, from
  it, scaled by height as an uncalibrated stride line is.
- :data:`MAX_WALKING_SPEED_MPS`: faster than this over a walk is implausible for walking
  (a brisk walk is 1.6–2.0 m/s; race walkers reach about 4 m/s, and runners are not
  walking) [m/s].
"""
from __future__ import annotations

POPULATION_HEIGHT_M = 1.70
WALK_RATIO_MAX_M_PER_SPM = 0.010
MAX_WALKING_SPEED_MPS = 2.5
SECONDS_PER_MINUTE = 60.0


def stride_bound_m(duration_s: float, height_m: float | None = None) -> float:
    """The longest stride [m] of a gait cycle lasting ``duration_s`` [s]: two steps at the
    cadence 2·60/duration steps/min and :data:`WALK_RATIO_MAX_M_PER_SPM`, times
    height/:data:`POPULATION_HEIGHT_M` (1 for an unknown height)."""
    cadence_spm = 2.0 * SECONDS_PER_MINUTE / duration_s
    scale = 1.0 if height_m is None else height_m / POPULATION_HEIGHT_M
    return 2.0 * WALK_RATIO_MAX_M_PER_SPM * cadence_spm * scale
