"""Constructed step sequences for the drift estimator's tests (pdr_drift): legs of
steps with turns, a drifting heading and hip sway, as the navigator would report them."""
from __future__ import annotations

import numpy as np

from pdr_core.maths.angles import wrap_angle
from pdr_drift.corners import StepSample

LEVEL, UP, DOWN = 1, 2, 3


def walk(legs, drift_radps=0.0, sway_deg=1.0, seed=0, period_s=1.1, stride_m=1.3):
    """Steps along ``legs``: (heading change at its start [deg], steps, activity);
    turns spread over 2 steps; the heading drifts by ``drift_radps``; the covariance grows
    as 0.02 m² per step."""
    rng = np.random.default_rng(seed)
    steps, heading, position, t = [], 0.0, np.zeros(3), 0.0
    for turn_deg, count, activity in legs:
        for k in range(count):
            if k < 2:
                heading += np.radians(turn_deg) / 2
            t += period_s
            position = position + [stride_m * np.cos(heading), stride_m * np.sin(heading),
                                   0.34 if activity == UP else -0.34 if activity == DOWN
                                   else 0.0]
            estimated = heading + drift_radps * t + np.radians(sway_deg) * rng.standard_normal()
            steps.append(StepSample(t, float(wrap_angle(estimated)), activity, position.copy(),
                                    np.diag([0.02, 0.02, 0.001]) * len(steps), 0))
    return steps


# The three sides after the first of a block (each turning left by 90°).
SIDES = [(90, 30, LEVEL), (90, 45, LEVEL), (90, 30, LEVEL)]
