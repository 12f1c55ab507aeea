"""Vertical displacement on stairs and floors (Muñoz Díaz 2016, Section 4.3).

Per stairs step (one gait cycle, two risers), from its pitch amplitude Δθ in degrees:
v_U = a_U·Δθ_U + b_U up (Eq. (4.4)) and v_D = a_D·Δθ_D + b_D down (Eq. (4.5)), in cm.
Section 4.3.2 averages the riser height over each staircase: the lines are linear, so the
staircase's mean of v equals v of its mean Δθ and the height gained is the same whether
each step takes its own v or the staircase's mean. :class:`Staircases` keeps that mean
per staircase (a flight: consecutive stairs steps of one direction; a landing ends it, so
a staircase of two flights counts twice, harmless as Section 5.5.1 says) for the report,
and the floor the person is on: round(Δz / ``floor_height_m``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.vocabulary import STAIRS_ACTIVITIES, Activity
from pdr_pocket.config import StairsConfig


def vertical_displacement_m(activity: int, amplitude_deg: float, config: StairsConfig) -> float:
    """v [m], + up, of one step (0 unless on stairs)."""
    if activity == Activity.UPSTAIRS:
        return (config.a_u_cm_per_deg * amplitude_deg + config.b_u_cm) / 100.0
    if activity == Activity.DOWNSTAIRS:
        return -(config.a_d_cm_per_deg * amplitude_deg + config.b_d_cm) / 100.0
    return 0.0


@dataclass
class Staircase:
    """One staircase: direction (UPSTAIRS or DOWNSTAIRS), its steps' indices and v [m]."""

    direction: int
    start_s: float
    end_s: float
    steps: list = field(default_factory=list)
    heights_m: list = field(default_factory=list)

    @property
    def riser_m(self) -> float:
        """The mean riser height (each step climbs two, Section 4.3.2)."""
        return float(np.mean(np.abs(self.heights_m))) / 2.0

    @property
    def height_m(self) -> float:
        return float(np.sum(self.heights_m))


class Staircases:
    """The staircases of a walk as the steps come, and the floor."""

    def __init__(self, config: StairsConfig | None = None) -> None:
        self.config = config or StairsConfig()
        self.done: list[Staircase] = []
        self.on_stairs = False

    def add(self, index: int, t: float, activity: int, v_m: float) -> None:
        if activity not in STAIRS_ACTIVITIES:
            self.on_stairs = False
            return
        last = self.done[-1] if self.done else None
        if last is None or last.direction != activity or not self.on_stairs:
            last = Staircase(activity, t, t)
            self.done.append(last)
        last.steps.append(index)
        last.heights_m.append(v_m)
        last.end_s = t
        self.on_stairs = True

    def floor(self, z_m: float) -> int:
        """The floor at height ``z_m`` above the start [m]."""
        return int(np.round(z_m / self.config.floor_height_m))
