"""Vertical displacement on stairs and floors (Muñoz Díaz 2016, Section 4.3), and the
staircases a level floor does not have.

Per stairs step (one gait cycle, two risers), from its pitch amplitude Δθ in degrees:
v_U = a_U·Δθ_U + b_U up (Eq. (4.4)) and v_D = a_D·Δθ_D + b_D down (Eq. (4.5)), in cm
(:func:`vertical_displacement_m`). Section 4.3.2 averages the riser height over each
staircase: the lines are linear, so the staircase's mean of v equals v of its mean Δθ and
the height gained is the same whether each step takes its own v or the staircase's mean.
:class:`Staircases` keeps that mean per staircase (a flight: consecutive stairs steps of one
direction; a landing ends it, so a staircase of two flights counts twice, harmless as
Section 5.5.1 says) for the report, and the floor the person is on: round(Δz /
``floor_height_m``).

A staircase must show itself in the height as well as in the pitch (beyond the thesis,
issue 40; :class:`FlightCheck`, ``stairs.check_flights``). The activities come from the
thigh pitch's shape (pdr_pocket.activity); the height a step climbs comes from its
amplitude through Eqs. (4.4)-(4.5), and a run of steps the pitch calls stairs becomes a
staircase only when that height is a staircase's too. With r̄ = mean |v| / 2 the run's
riser (Section 4.3.2's average; a gait cycle is two footfalls, one riser each,
pdr_core.walking.stair_geometry.RISERS_PER_GAIT_CYCLE):

1. every v has the run's sign (up: v > 0);
2. r̄ lies within [``riser_min_m``, ``riser_max_m``]: the building codes' span, IBC 2015's
   4 in to the IRC's spiral 9½ in (0.102–0.241 m, pdr_core.walking.stair_geometry). Eqs. (4.4)-
   (4.5) map a level gait's swing to no stair: a level swing of 30–40° called a step up
   climbs 0.08–0.12 m a riser, called a step down 0.20–0.30 m, where a step up swings
   about 53° and a step down about 27° on 17 cm risers (Section 4.3.1);
3. each step climbs a whole number of risers, one or two (a flight's first and last gait
   cycles may hold one), within ``riser_count_tolerance`` (±50 %): min_k ||v_i|/(k·r̄) − 1|
   ≤ 0.5, k ∈ {1, 2}, so every step climbs 0.25 to 1.5 times the run's mean step. A
   flight's risers are equal (DIN 18065: within 5 mm); the pitch's v of one step is not
   (a real flight's steps scatter by up to ±35 % about their mean, its first and last the
   most), but steps that disagree more are not one flight;
4. it has at least three risers, a flight by DIN 18065: two gait cycles;
5. and at most ``flight_max_risers`` (18, DIN 18065) without a landing: a flight's cycles,
   18/2 + 1 (its two end cycles may hold one riser each). A landing the pitch read as
   stairs (its one or two cycles, or samples lost over it) joins two flights into one run:
   where the heading turned by at least a landing's turn over the run's last flight
   (pdr_core.walking.stair_geometry.LANDING_TURN_MIN_DEG, an L-shaped stair's quarter turn), the
   run is a staircase of several flights and a new flight starts at the step that
   overflows, to be shown again (rule 4); a straight run is refused from there.

The decision is causal, so the live node and ``pdr-pocket run`` publish the same steps
(each step is published once, when it is confirmed): a run's first step is held back
(published with its stairs label and v = 0) until the second shows whether the run is a
staircase; then the second carries both heights, so the staircase's height and its mean
riser (mean |v| over its steps, the held one's 0 among them) come out as without the
check. A run refused there, or a further step that breaks 1–3 or 5, is level from that
step until the pitch says level again (v = 0, activity WALKING); the held step keeps its
label and climbs nothing, and a staircase that climbed nothing is not listed. What was
refused is counted (:attr:`FlightCheck.refused`).

- :func:`vertical_displacement_m`: v [m] of one step;
- :func:`flight_problem`: why heights are not one flight's (None: they are);
- :class:`FlightCheck`: the rule, one step at a time;
- :class:`Staircase`, :class:`Staircases`: the staircases as published, and the floor.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pdr_core.maths.angles import wrap_angle
from pdr_core.vocabulary import STAIRS_ACTIVITIES, Activity
from pdr_core.walking.stair_geometry import (
    FLIGHT_MIN_RISERS,
    LANDING_TURN_MIN_DEG,
    RISERS_PER_GAIT_CYCLE,
)
from pdr_pocket.config import StairsConfig

# the gait cycles a run needs to show a flight's least risers (rule 4): two
CONFIRM_CYCLES = math.ceil(FLIGHT_MIN_RISERS / RISERS_PER_GAIT_CYCLE)


def vertical_displacement_m(activity: int, amplitude_deg: float, config: StairsConfig) -> float:
    """v [m], + up, of one step (0 unless on stairs)."""
    if activity == Activity.UPSTAIRS:
        return (config.a_u_cm_per_deg * amplitude_deg + config.b_u_cm) / 100.0
    if activity == Activity.DOWNSTAIRS:
        return -(config.a_d_cm_per_deg * amplitude_deg + config.b_d_cm) / 100.0
    return 0.0


def max_flight_cycles(config: StairsConfig) -> int:
    """The most gait cycles one flight holds: ``flight_max_risers`` two by two, and its
    first and last cycles may hold one riser each."""
    return config.flight_max_risers // RISERS_PER_GAIT_CYCLE + 1


def flight_problem(direction: int, heights_m, config: StairsConfig, *, whole: bool = True
                   ) -> str | None:
    """Why the steps' heights v [m] (the run's so far, + up) are not one flight's of
    ``direction`` (UPSTAIRS or DOWNSTAIRS) by rules 1–3 and 5 of the module docstring;
    None when they are. ``whole`` False: the run has not yet shown itself (rule 4), and
    only the sign is asked (a flight's first step may be its odd one)."""
    v = np.asarray(heights_m, float)
    sign = 1.0 if direction == Activity.UPSTAIRS else -1.0
    if np.any(v * sign <= 0.0):
        return f"a step climbs {float(v[v * sign <= 0][0]):+.3f} m, against the run"
    if not whole:
        return None
    if len(v) > max_flight_cycles(config):
        return f"{len(v)} gait cycles without a landing, more than a flight's " \
               f"{config.flight_max_risers} risers"
    riser = float(np.mean(np.abs(v))) / RISERS_PER_GAIT_CYCLE
    if not config.riser_min_m <= riser <= config.riser_max_m:
        return f"a riser of {riser:.3f} m, outside {config.riser_min_m}–{config.riser_max_m} m"
    count = np.abs(v) / riser
    whole = np.arange(1, RISERS_PER_GAIT_CYCLE + 1)
    off = np.min(np.abs(count[:, None] / whole - 1.0), axis=1)
    if np.any(off > config.riser_count_tolerance):
        worst = int(np.argmax(off))
        return f"step {worst + 1} climbs {count[worst]:.2f} risers of {riser:.3f} m, not 1 or " \
               f"{RISERS_PER_GAIT_CYCLE} within {config.riser_count_tolerance:.0%}"
    return None


class FlightCheck:
    """The rule of the module docstring, one step at a time: :meth:`step` turns the
    pitch's activity and v of each step into those published. ``refused`` counts the
    runs that never became a staircase and the stairs steps that climbed nothing;
    ``withdrawn_m`` sums the climbs of the held steps refused since it was last taken
    (:meth:`take_withdrawn`): a height filter given them at their own steps must take them
    back."""

    def __init__(self, config: StairsConfig) -> None:
        self.config = config
        self.withdrawn_m = 0.0              # v [m] of held steps refused, not yet taken
        self.direction: int | None = None   # the pitch's run of stairs steps, if one is open
        self.held: list[float] = []         # v [m] of its steps held back
        self.heights: list[float] = []      # ... and of those it climbed
        self.headings: list[float] = []     # the heading [rad] of every step of the run
        self.refusing = False               # the run was refused: level until it ends
        self.refused = {"staircases": 0, "steps": 0}

    def step(self, activity: int, v_m: float, heading_rad: float = 0.0) -> tuple[int, float]:
        """The activity and v [m] to publish for a step the pitch calls ``activity`` with
        v ``v_m`` (Eqs. (4.4)-(4.5)) and heading ``heading_rad`` (ENU yaw)."""
        if not self.config.check_flights:
            return activity, v_m
        if activity not in STAIRS_ACTIVITIES or activity != self.direction:
            self._close()
            if activity not in STAIRS_ACTIVITIES:
                return activity, v_m
            self.direction = activity
        if self.refusing:
            return self._refuse()
        self.headings.append(heading_rad)
        if len(self.heights) >= max_flight_cycles(self.config) and self._landed():
            self._close()
            self.direction, self.headings = activity, [heading_rad]
        run = [*self.held, *self.heights, v_m]
        shown = len(run) >= CONFIRM_CYCLES
        if flight_problem(activity, run, self.config, whole=shown) is not None:
            if not self.heights:
                self.refused["staircases"] += 1
                self.refused["steps"] += len(self.held)
                self.withdrawn_m += sum(self.held)
                self.held = []
            return self._refuse()
        if not shown:
            self.held.append(v_m)
            return activity, 0.0
        climbed = v_m + sum(self.held)
        self.heights, self.held = run, []
        return activity, climbed

    def take_withdrawn(self) -> float:
        """The climbs [m] of the held steps refused since the last call (then 0)."""
        withdrawn, self.withdrawn_m = self.withdrawn_m, 0.0
        return withdrawn

    def _landed(self) -> bool:
        """The heading turned by a landing's turn over the run's last flight (rule 5)."""
        last = np.asarray(self.headings[-max_flight_cycles(self.config) - 1:])
        turned = np.abs(wrap_angle(last[:, None] - last[None, :]))
        return bool(turned.max() >= np.radians(LANDING_TURN_MIN_DEG))

    def _refuse(self) -> tuple[int, float]:
        """This step and the rest of the run are level."""
        self.refusing = True
        self.refused["steps"] += 1
        return Activity.WALKING, 0.0

    def _close(self) -> None:
        """The pitch's run ended: held steps that never showed a staircase are refused."""
        if self.held:
            self.refused["staircases"] += 1
            self.refused["steps"] += len(self.held)
            self.withdrawn_m += sum(self.held)
        self.direction, self.held, self.heights, self.refusing = None, [], [], False
        self.headings = []


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
        return float(np.mean(np.abs(self.heights_m))) / RISERS_PER_GAIT_CYCLE

    @property
    def height_m(self) -> float:
        return float(np.sum(self.heights_m))


class Staircases:
    """The staircases of a walk as the steps come, and the floor. :meth:`admit` checks a
    navigator's steps (:class:`FlightCheck`) and adds them as published; :meth:`add` groups
    steps already published (a recorded run, a simulation's truth)."""

    def __init__(self, config: StairsConfig | None = None) -> None:
        self.config = config or StairsConfig()
        self.done: list[Staircase] = []
        self.on_stairs = False
        self.check = FlightCheck(self.config)

    def admit(self, index: int, t: float, activity: int, v_m: float,
              heading_rad: float = 0.0) -> tuple[int, float]:
        """The step's activity and v [m] as published (:meth:`FlightCheck.step`), added."""
        activity, v_m = self.check.step(activity, v_m, heading_rad)
        self.add(index, t, activity, v_m)
        return activity, v_m

    def add(self, index: int, t: float, activity: int, v_m: float) -> None:
        last = self.done[-1] if self.done else None
        if activity not in STAIRS_ACTIVITIES:
            self._close(last)
            self.on_stairs = False
            return
        if last is None or last.direction != activity or not self.on_stairs:
            self._close(last)
            last = Staircase(activity, t, t)
            self.done.append(last)
        last.steps.append(index)
        last.heights_m.append(v_m)
        last.end_s = t
        self.on_stairs = True

    def _close(self, last: Staircase | None) -> None:
        """A staircase that climbed nothing (its only step held back and refused) is none."""
        if self.on_stairs and last is not None and not any(last.heights_m):
            self.done.pop()

    def floor(self, z_m: float) -> int:
        """The floor at height ``z_m`` above the start [m]."""
        return int(np.round(z_m / self.config.floor_height_m))
