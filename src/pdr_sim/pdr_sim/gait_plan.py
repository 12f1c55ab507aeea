"""The gait plan of a pocket scenario: every gait cycle of the sensor leg, every rest.

A pocket *step* is one gait cycle of the leg that carries the sensor (two footfalls,
Muñoz Díaz 2016, Section 4.1.1), from one heel strike of that leg to the next. The plan
turns a :class:`~pdr_sim.pocket_scenario.PocketScenario` into

- :class:`Cycles`: per step its start time, duration, activity, target thigh pitch
  extremes (θ_max, θ_min), risers climbed, heading change and, for stairs, the stride;
- :class:`Rest` intervals: standing or sitting, with the thigh pitch held;
- the landmarks the route was built with (corners, flights of stairs) and the floors;
- the lift rides (:class:`pdr_sim.lift.LiftRide`), each inside a rest of its own: the
  person stands while the car carries them, and the floor index follows the ride.

Strides on level ground are not fixed here: they follow from the thigh pitch the model
actually produces, by the person's line s = a_H·Δθ + b_H (Eq. (4.2)), see
:mod:`pdr_sim.thigh_trajectory`. On stairs the building fixes the vertical displacement
v = n·riser and the person's line gives the pitch amplitude, Δθ = (v − b)/a
(Eqs. (4.4)–(4.5)). All draws use the scenario's seed, in plan order.

Units: time [s], angles [rad] unless named ``_deg``, lengths [m].
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.vocabulary import Activity, LandmarkType
from pdr_sim.lift import LiftMotion, LiftRide
from pdr_sim.pocket_scenario import (
    DEFAULT_SPEED_KMH,
    KMH,
    PocketScenario,
    PocketSegment,
    cadence_hz,
    nominal_stride_m,
)

DEFAULT_STAIRS_SPEED_KMH = 3.0      # level steps on landings
REST_KNOT_S = 0.5                   # spacing of the pose knots while resting
SIT_TRANSITION_S = 1.5              # sitting down and standing up
SETTLE_FRACTION = 0.7               # after a bout's last heel strike, the thigh comes to
                                    # rest within this fraction of the last cycle


@dataclass
class Cycles:
    """Per gait cycle (step), arrays of length K once :meth:`frozen`."""

    start: list = field(default_factory=list)          # [s]
    duration: list = field(default_factory=list)       # [s]
    activity: list = field(default_factory=list)       # Activity: WALKING, UPSTAIRS, DOWNSTAIRS
    pitch_max: list = field(default_factory=list)      # target θ_max [rad]
    pitch_min: list = field(default_factory=list)      # target θ_min [rad]
    risers: list = field(default_factory=list)         # signed riser count (+ up)
    riser_m: list = field(default_factory=list)
    stair_stride_m: list = field(default_factory=list)  # horizontal, stairs only (else nan)
    heading: list = field(default_factory=list)        # route heading at the start [rad]
    turn: list = field(default_factory=list)           # heading change over the step [rad]
    first_of_bout: list = field(default_factory=list)  # starts from rest
    last_of_bout: list = field(default_factory=list)   # ends at rest
    scatter_m: list = field(default_factory=list)      # level stride scatter about s(Δθ)
    group: list = field(default_factory=list)          # walk segment or flight of the step

    def frozen(self) -> Cycles:
        return Cycles(**{k: np.asarray(v) for k, v in self.__dict__.items()})

    def __len__(self) -> int:
        return len(self.start)


@dataclass(frozen=True)
class Rest:
    """A period without steps: standing (pitch 0) or sitting (pitch held), or a turn in
    place (standing, the heading turning by ``turn``)."""

    start: float
    duration: float
    activity: int
    pitch: float                    # [rad]
    heading: float                  # route heading at the start [rad]
    turn: float = 0.0               # heading change over the rest [rad]


@dataclass(frozen=True)
class PlannedLandmark:
    """A landmark of the route, located by the cycle index where it happens."""

    type: int
    first_cycle: int                # the landmark spans cycles [first_cycle, last_cycle]
    last_cycle: int
    floor: int
    rest: int | None = None         # a turn in place: the index of its rest instead


@dataclass(frozen=True)
class GaitPlan:
    cycles: Cycles
    rests: tuple[Rest, ...]
    landmarks: tuple[PlannedLandmark, ...]
    end_time: float
    rides: tuple[LiftRide, ...] = ()


class _Planner:
    """Walks the segments once, appending cycles and rests (a loop over steps, not
    samples)."""

    def __init__(self, scenario: PocketScenario) -> None:
        self.person = scenario.person
        self.rng = np.random.default_rng(scenario.seed)
        self.cycles = Cycles()
        self.rests: list[Rest] = []
        self.landmarks: list[PlannedLandmark] = []
        self.rides: list[LiftRide] = []
        self.t = 0.0
        self.heading = np.radians(scenario.initial.yaw_deg)
        self.group = 0
        self.pitch_scatter: list[float] = []
        self.speed_kmh = DEFAULT_SPEED_KMH
        self.floor = 0                  # floor index (0 = start floor)
        self.flights_above = 0          # flights climbed above ``floor`` (a mid landing)
        self.walking = False
        # the person's level swing at DEFAULT_SPEED_KMH [rad] (level_pitch_min)
        self.normal_amplitude = self.level_amplitude(
            nominal_stride_m(self.person, DEFAULT_SPEED_KMH))

    # rests ---------------------------------------------------------------------------
    def rest(self, duration: float, activity: int, pitch: float, turn: float = 0.0) -> None:
        self._end_bout()
        self.rests.append(Rest(self.t, duration, activity, pitch, self.heading, turn))
        self.t += duration
        self.heading += turn

    def _end_bout(self) -> None:
        if self.walking:
            self.cycles.last_of_bout[-1] = True
            self.t += SETTLE_FRACTION * self.cycles.duration[-1]
            self.walking = False

    # cycles --------------------------------------------------------------------------
    def _cycle(self, duration: float, activity: int, pitch_max: float, pitch_min: float,
               risers: int = 0, riser_m: float = 0.0, stair_stride: float = np.nan,
               turn: float = 0.0, scatter: float = 0.0, pitch_scatter: float = 0.0) -> None:
        c = self.cycles
        if not self.walking:        # from rest the thigh starts at 0°: no higher minimum
            pitch_min = min(pitch_min, 0.0)
        c.start.append(self.t)
        c.duration.append(duration)
        c.activity.append(activity)
        c.pitch_max.append(pitch_max)
        c.pitch_min.append(pitch_min)
        c.heading.append(self.heading)
        self.heading += turn
        c.risers.append(risers)
        c.riser_m.append(riser_m)
        c.stair_stride_m.append(stair_stride)
        c.turn.append(turn)
        c.first_of_bout.append(not self.walking)
        c.last_of_bout.append(False)
        c.scatter_m.append(scatter)
        c.group.append(self.group)
        self.pitch_scatter.append(pitch_scatter)
        self.walking = True
        self.t += duration

    def level_step(self, speed_kmh: float, turn: float = 0.0) -> None:
        """One level cycle at about ``speed_kmh``: Δθ from the person's line at the
        stride this speed and cadence give; the stride itself follows the pitch, θ_min
        from :meth:`level_pitch_min`."""
        p = self.person
        v = speed_kmh * KMH * (1.0 + p.speed_scatter * self.rng.standard_normal())
        period = 1.0 / cadence_hz(p, v)
        amplitude = self.level_amplitude(v * period)
        pitch_min = self.level_pitch_min(amplitude)
        scatter = p.stride_scatter_m * self.rng.standard_normal()
        self._cycle(period, Activity.WALKING, pitch_min + amplitude, pitch_min, turn=turn,
                    scatter=scatter)

    def level_amplitude(self, stride_m: float) -> float:
        """Δθ [rad] of a level stride [m] by the person's line (Eq. (4.2))."""
        p = self.person
        return np.radians((stride_m - p.b_h_m) / p.a_h_m_per_deg)

    def level_pitch_min(self, amplitude: float) -> float:
        """θ_Hmin [rad] of a level swing Δθ [rad]: −``pitch_min_fraction``·Δθ (the thesis'
        H1, θ_Hmax 26° of Δθ_H 32°) up to the swing at ``DEFAULT_SPEED_KMH``; a swing
        beyond it grows ``faster_swing_back_fraction`` of its excess behind the vertical.
        So does the real thigh board (docs/simulator.md): from its normal to its fast walk
        Δθ grows from 31.3° to 39.5°, θ_min from −8.2° to −12.6°, θ_max only from 23.1°
        to 26.9°. A fixed fraction would put the whole growth forward: at 4.8 km/h a flat
        line's level step (Δθ 45°) shaped like a step up (θ_max 39°, θ_min −7°)."""
        p = self.person
        faster = max(amplitude - self.normal_amplitude, 0.0)
        return -p.pitch_min_fraction * (amplitude - faster) - \
            p.faster_swing_back_fraction * faster

    def stair_step(self, direction: str, risers: int, riser_m: float, tread_m: float) -> None:
        """One cycle on stairs over ``risers`` risers: v = risers·riser fixes Δθ through
        Eq. (4.4) or (4.5), with the person's scatter on Δθ."""
        p = self.person
        v_cm = 100.0 * risers * riser_m
        if direction == "up":
            amplitude_deg = (v_cm - p.b_u_cm) / p.a_u_cm_per_deg
            pitch_min_deg = p.up_pitch_min_sigma_deg * self.rng.standard_normal()
        else:
            amplitude_deg = (v_cm - p.b_d_cm) / p.a_d_cm_per_deg
            pitch_min_deg = p.down_pitch_min_deg
        scatter = np.radians(p.stair_pitch_scatter_deg * self.rng.standard_normal())
        activity = Activity.UPSTAIRS if direction == "up" else Activity.DOWNSTAIRS
        sign = 1 if direction == "up" else -1
        self._cycle(1.0 / p.stair_cadence_hz, activity, np.radians(pitch_min_deg + amplitude_deg),
                    np.radians(pitch_min_deg), sign * risers, riser_m, risers * tread_m,
                    pitch_scatter=scatter)

    # segments ------------------------------------------------------------------------
    def segment(self, seg: PocketSegment) -> None:
        self.group += 1
        if seg.speed_kmh is not None and seg.type in ("walk", "turn"):
            self.speed_kmh = seg.speed_kmh
        getattr(self, f"_{seg.type}")(seg)

    def _standing(self, seg: PocketSegment) -> None:
        self.rest(seg.duration_s, Activity.STANDING, 0.0)

    def _sitting(self, seg: PocketSegment) -> None:
        self.rest(seg.duration_s, Activity.SITTING, np.radians(seg.pitch_deg))

    def _walk(self, seg: PocketSegment) -> None:
        steps = seg.steps or max(1, round(seg.distance_m / nominal_stride_m(self.person,
                                                                           self.speed_kmh)))
        for _ in range(steps):
            self.level_step(self.speed_kmh)

    def _turn(self, seg: PocketSegment) -> None:
        if seg.duration_s:
            self.rest(seg.duration_s, Activity.STANDING, 0.0, np.radians(seg.angle_deg))
            self._corner(seg.angle_deg, len(self.cycles), len(self.rests) - 1)
            return
        steps = seg.steps or 2
        first = len(self.cycles)
        for _ in range(steps):
            self.level_step(self.speed_kmh, np.radians(seg.angle_deg) / steps)
        self._corner(seg.angle_deg, first)

    def _corner(self, angle_deg: float, first: int, rest: int | None = None) -> None:
        """A corner landmark when the turn is one (60–120° or 150–210°)."""
        a = abs(angle_deg)
        if 60.0 <= a <= 120.0 or 150.0 <= a <= 210.0:
            self.landmarks.append(PlannedLandmark(LandmarkType.CORNER, first,
                                                  len(self.cycles) - 1,
                                                  self.floor, rest))

    def _climb(self, direction: str, flights_per_floor: int) -> int:
        """Account for one flight; returns the flight's lower floor (the same whichever
        way it is walked)."""
        if direction == "up":
            lower = self.floor
            self.flights_above += 1
            if self.flights_above == flights_per_floor:
                self.floor, self.flights_above = self.floor + 1, 0
            return lower
        if self.flights_above == 0:
            self.floor, self.flights_above = self.floor - 1, flights_per_floor
        self.flights_above -= 1
        return self.floor

    def _stairs(self, seg: PocketSegment) -> None:
        speed = seg.speed_kmh or DEFAULT_STAIRS_SPEED_KMH
        for flight in range(seg.flights):
            if flight:
                first = len(self.cycles)
                self.group += 1
                for _ in range(seg.landing_steps):
                    self.level_step(speed, np.radians(seg.landing_turn_deg) / seg.landing_steps)
                self._corner(seg.landing_turn_deg, first)
            first = len(self.cycles)
            self.group += 1
            pairs, odd = divmod(seg.risers, 2)
            for _ in range(pairs):
                self.stair_step(seg.direction, 2, seg.riser_m, seg.tread_m)
            if odd:
                self.stair_step(seg.direction, 1, seg.riser_m, seg.tread_m)
            lower = self._climb(seg.direction, seg.flights_per_floor)
            self.landmarks.append(PlannedLandmark(LandmarkType.STAIRS, first,
                                                  len(self.cycles) - 1, lower))

    def _platform(self, seg: PocketSegment) -> None:
        self.stair_step(seg.direction, 1, seg.riser_m, 2 * seg.tread_m)

    def _lift(self, seg: PocketSegment) -> None:
        """A lift ride: standing, ``dwell_s`` before the car moves and after it stops; the
        floor index changes by the floors ridden (a landing between floors is kept)."""
        self._end_bout()
        sign = 1 if seg.direction == "up" else -1
        ride = LiftRide(self.t + seg.dwell_s, seg.rise_m, sign * seg.floors,
                        LiftMotion(seg.speed_mps, seg.acceleration_mps2, seg.jerk_mps3))
        self.rides.append(ride)
        self.rest(2 * seg.dwell_s + ride.duration_s, Activity.STANDING, 0.0)
        self.floor += ride.floors

    def finish(self) -> GaitPlan:
        """Close the last bout and centre the scatter on each walk segment and flight, so
        that the person's lines hold exactly for every segment's and flight's mean (the
        thesis averages each staircase, Section 4.3.2) while single steps scatter; with
        the person's ``centre_scatter`` false, the scatter stays as drawn, a real walk's
        deviation from its line (what a calibration must average out, issue 57)."""
        self._end_bout()
        c = self.cycles
        group = np.asarray(c.group, dtype=int)
        for name, values in (("scatter_m", np.asarray(c.scatter_m, float)),
                             ("pitch_scatter", np.asarray(self.pitch_scatter, float))):
            means = np.bincount(group, values) / np.maximum(np.bincount(group), 1)
            centred = values - means[group] if self.person.centre_scatter else values
            if name == "scatter_m":
                c.scatter_m = list(centred)
            else:
                c.pitch_max = list(np.asarray(c.pitch_max, float) + centred)
        return GaitPlan(self.cycles.frozen(), tuple(self.rests), tuple(self.landmarks), self.t,
                        tuple(self.rides))


def plan_gait(scenario: PocketScenario) -> GaitPlan:
    """The gait plan of a scenario (deterministic given its seed)."""
    planner = _Planner(scenario)
    for seg in scenario.segments:
        planner.segment(seg)
    return planner.finish()
