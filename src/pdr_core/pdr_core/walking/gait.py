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
- :data:`THIGH_SWING_MIN_RATIO`: the least pitch swing of a thigh, as a fraction of the
  swing the population's pitch and cadence lines give at the cycle's cadence (Muñoz Díaz
  2016, Eqs. (4.2)-(4.3); pdr_pocket.placement). People's own pitch lines lie up to
  14 cm per stride from the population's (Section 4.2.3), about 14 % of a 1.4 m stride,
  and a cadence line fitted to one person scatters as much again over others: a thigh's
  swing lies within about a quarter of the lines' one. On the evidence we have, windows of
  the shared thigh walks lie at 0.82–1.17 (5–95 %), the shared back pocket at 0.55–0.68,
  the simulated one at 0.38.
- :data:`PLACEMENT_MIN_CADENCE_HZ`: the slowest gait cycle [Hz] the placement is judged
  at, 90 steps/min, about 3 km/h. Slower, the cadence line no longer holds (the thesis'
  museum walk at 2 km/h: 9.6 % off by it, 1.2 % by the pitch line, Table 4.4), and a
  slow thigh swings as little as a back pocket at a normal pace (the simulated museum
  walk's windows at 0.48–0.69 of the lines' swing, the shared back pocket's at
  0.55–0.70).
- :data:`GAIT_MIN_FOOTFALLS`: the fewest footfalls, each within half the longest gait
  cycle of the last, that are walking (left, right, left: one whole gait cycle); fewer is
  a bump or the phone handled, not a gait (pdr_pocket.compiled_peaks' footfall loop).
- :data:`PLACEMENT_WINDOW_STEPS`: the level gait cycles the placement is judged over
  (their medians): a straight stretch of about 10 m, short of a corridor.
- :data:`FOOT_STRIDE_MIN_M`: the shortest horizontal stride of a foot that is a step with
  a direction of travel [m]. Stepping in place, shuffling and a turn on the spot move the
  foot by centimetres; the shortest walking strides, at 2 km/h, are about 0.8 m, and a
  stair stride spans two treads, about half a metre (IBC 2015, Section 1011.5.2: 11 in
  at least). A foot INS puts a stride's end within about a centimetre, so at 0.2 m its
  direction is good to 3°.
"""
from __future__ import annotations

POPULATION_HEIGHT_M = 1.70
WALK_RATIO_MAX_M_PER_SPM = 0.010
MAX_WALKING_SPEED_MPS = 2.5
SECONDS_PER_MINUTE = 60.0
THIGH_SWING_MIN_RATIO = 0.75
GAIT_MIN_FOOTFALLS = 3
PLACEMENT_WINDOW_STEPS = 8
PLACEMENT_MIN_CADENCE_HZ = 0.75
FOOT_STRIDE_MIN_M = 0.2


def stride_bound_m(duration_s: float, height_m: float | None = None) -> float:
    """The longest stride [m] of a gait cycle lasting ``duration_s`` [s]: two steps at the
    cadence 2·60/duration steps/min and :data:`WALK_RATIO_MAX_M_PER_SPM`, times
    height/:data:`POPULATION_HEIGHT_M` (1 for an unknown height)."""
    cadence_spm = 2.0 * SECONDS_PER_MINUTE / duration_s
    scale = 1.0 if height_m is None else height_m / POPULATION_HEIGHT_M
    return 2.0 * WALK_RATIO_MAX_M_PER_SPM * cadence_spm * scale
