"""Thigh-mounted (trouser-pocket) IMU trajectory of a pocket scenario, with its truth.

Body model (Muñoz Díaz 2016, chapters 4–5):

- The **pelvis** follows the route step by step: per gait cycle a chord of the stride (level
  ground) or of the treads (stairs), a heading that turns linearly over a turn's steps,
  a vertical bob of ``hip_bob_m`` twice per cycle (low at each footfall) and the risers.
- The **thigh** of the sensor leg hangs from the hip joint (``hip_half_width_m`` to the
  side of the pelvis centre) with yaw ψ_t = ψ_route + sway and pitch θ, the thesis' opening
  angle of the leg (Fig. 4.1: positive with the knee ahead of the hip). Its frame is x
  forward, y left, z up along the thigh when standing; C_t^n = Rz(ψ_t)·Ry(−θ).
- The **sensor** sits at ``lever_arm_m`` from the hip joint in the thigh frame, mounted
  with C_s^t (the scenario's ``mounting``): C_s^n = C_t^n·C_s^t.

Every channel (pelvis x, y, z, route heading, θ, sway) is one cubic spline through knots
placed at fixed phases of each cycle (:data:`KNOT_PHASES`) and every 0.5 s at rest, so
position, attitude, turn rate and specific force are continuous (C², clamped at both
ends). The pitch knots follow a shape per activity (:data:`PITCH_SHAPES`): on level
ground θ_Hmax at full elongation, a second, smaller peak at heel strike and a small
negative θ_Hmin; up- and downstairs no second peak but a double minimum (Figs. 4.1–4.3).
The knots are corrected a few times so that the spline's own extremes are the planned
ones; the truth reports the spline's exact extremes (roots of θ̇).

Turn rate and specific force come from the analytic derivatives: with α = −θ,
ω_t = (−sin α·ψ̇, α̇, cos α·ψ̇), ω̇_t by differentiation, and the sensor acceleration
p̈ = p̈_hip + C_t·(ω̇_t × r + ω_t × (ω_t × r)).

A lift ride (:mod:`pdr_sim.lift`) carries the whole standing body: its height, vertical
speed and acceleration are added to the sensor's, exactly, and the route after it (the
landmarks' positions) is as much higher or lower.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.interpolate import CubicSpline, PPoly
from scipy.spatial.transform import Rotation

from pdr_core.maths.angles import wrap_angle
from pdr_core.vocabulary import Activity, LandmarkType
from pdr_sim.compiled_thigh import (
    HEADING,
    PITCH,
    SWAY,
    SensorMotion,
    ThighBody,
    ThighSpline,
    thigh_kinematics,
)
from pdr_sim.gait_plan import (
    REST_KNOT_S,
    SETTLE_FRACTION,
    SIT_TRANSITION_S,
    GaitPlan,
    plan_gait,
)
from pdr_sim.lift import rides_motion
from pdr_sim.pocket_scenario import CARRIED, PocketScenario
from pdr_sim.trajectory import Trajectory

KNOT_PHASES = np.array([0.0, 0.08, 0.30, 0.44, 0.58, 0.72, 0.86, 0.94])
# Pitch at each knot phase, as a fraction of Δθ above θ_min, per Step activity
# (WALKING, UPSTAIRS, DOWNSTAIRS). Level: heel-strike peak (0.0), decline through stance,
# θ_min at toe-off (0.58), θ_max in the swing (0.86), the dip before heel strike.
# Stairs: no heel-strike peak; two minima (0.30 and 0.58) around a small rise.
PITCH_SHAPES = {
    Activity.WALKING: np.array([0.80, 0.72, 0.45, 0.20, 0.00, 0.40, 1.00, 0.70]),
    Activity.UPSTAIRS: np.array([0.70, 0.55, 0.06, 0.14, 0.00, 0.45, 1.00, 0.88]),
    Activity.DOWNSTAIRS: np.array([0.70, 0.55, 0.06, 0.14, 0.00, 0.45, 1.00, 0.88]),
}
MIN_PHASE = KNOT_PHASES[4]
PITCH_ITERATIONS = 3
REVISIT_RADIUS_M = 3.0              # a landmark this close to an earlier one revisits it
REVISIT_MIN_S = 120.0               # ... if at least this much later (Section 5.3)
Z = 2                               # spline channel of the pelvis height


@dataclass(frozen=True)
class TrueSteps:
    """One row per gait cycle of the sensor leg (pdr_msgs/Step fields, SI units)."""

    end_s: np.ndarray               # [s] the cycle's closing heel strike
    length: np.ndarray              # horizontal displacement of the pelvis [m]
    vertical_displacement: np.ndarray   # [m], + up
    heading: np.ndarray             # direction of travel, ENU yaw [rad] in (−π, π]
    pitch_max: np.ndarray           # [rad], the spline's exact extremes
    pitch_min: np.ndarray
    duration: np.ndarray            # [s]
    activity: np.ndarray            # pdr_msgs/Step activity

    @property
    def pitch_amplitude(self) -> np.ndarray:
        return self.pitch_max - self.pitch_min


@dataclass(frozen=True)
class TrueLandmark:
    """A corner or a flight of stairs of the route (pdr_msgs/Landmark fields)."""

    id: int
    type: int
    time_s: float                   # when the pedestrian is there (middle of it)
    position: tuple[float, float, float]   # route point (floor level), ENU [m]
    yaw_before: float               # [rad]
    yaw_after: float
    floor: int
    revisit_of: int | None          # id of an earlier landmark at the same place, if any


@dataclass(frozen=True)
class Period:
    """A span of one activity (Step activity constants), for evaluation."""

    activity: int
    start_s: float
    end_s: float


def _first_ramp(phase: np.ndarray) -> np.ndarray:
    """Fraction of a stride covered at ``phase`` by a cycle starting from rest."""
    return 2 * phase**2 - phase**3


def _last_ramp(phase: np.ndarray) -> np.ndarray:
    """... by a cycle ending at rest."""
    return phase + phase**2 - phase**3


def _only_ramp(phase: np.ndarray) -> np.ndarray:
    """... by a bout of one cycle."""
    return 3 * phase**2 - 2 * phase**3


class _Knots:
    """Knot times and per-cycle structure shared by all channels."""

    def __init__(self, plan: GaitPlan) -> None:
        c = plan.cycles
        self.plan = plan
        self.cycle_t = c.start[:, None] + KNOT_PHASES[None, :] * c.duration[:, None]
        ends = c.start + c.duration
        last = np.flatnonzero(c.last_of_bout)
        self.settle_t = ends[last, None] + np.array([0.0, 0.5, 1.0]) * \
            SETTLE_FRACTION * c.duration[last, None]
        self.last = last
        rest_t, rest_pitch, rest_index = [], [], []
        for i, rest in enumerate(plan.rests):
            times, pitch = _rest_knots(rest.start, rest.duration, rest.pitch)
            rest_t.append(times)
            rest_pitch.append(pitch)
            rest_index.append(np.full(len(times), i))
        self.rest_t = np.concatenate(rest_t) if rest_t else np.empty(0)
        self.rest_pitch = np.concatenate(rest_pitch) if rest_pitch else np.empty(0)
        self.rest_index = np.concatenate(rest_index) if rest_index else np.empty(0, int)
        times = np.concatenate([self.cycle_t.ravel(), self.settle_t.ravel(), self.rest_t])
        # a rest's first knot coincides with the previous settle's last; keep one
        self.times, self.order = np.unique(times, return_index=True)
        if self.times[-1] < plan.end_time:
            self.order = np.append(self.order, len(times))
            self.times = np.append(self.times, plan.end_time)
            self.tail = True
        else:
            self.tail = False

    def assemble(self, cycle_values: np.ndarray, settle_values: np.ndarray,
                 rest_values: np.ndarray, end_value: np.ndarray) -> np.ndarray:
        """Channel values (K,) or (K, d) in knot order from their three sources."""
        values = np.concatenate([cycle_values.reshape(-1, *cycle_values.shape[2:]),
                                 settle_values.reshape(-1, *settle_values.shape[2:]),
                                 rest_values])
        if self.tail:
            values = np.concatenate([values, end_value[None]])
        return values[self.order]


def _rest_knots(start: float, duration: float, pitch: float) -> tuple[np.ndarray, np.ndarray]:
    """Knot times and thigh pitch of a rest: held, with the sit-down and stand-up ramps."""
    if pitch == 0.0:
        times = start + np.arange(0.0, duration, REST_KNOT_S)
        return times, np.zeros(len(times))
    inner = start + SIT_TRANSITION_S + np.arange(0.0, duration - 2 * SIT_TRANSITION_S + 1e-9,
                                                REST_KNOT_S)
    times = np.concatenate([[start], inner])
    values = np.concatenate([[0.0], np.full(len(inner), pitch)])
    return times, values


def _pitch_knots(plan: GaitPlan, knots: _Knots, pmax: np.ndarray,
                 pmin: np.ndarray) -> np.ndarray:
    """Pitch at every knot from per-cycle knot extremes (the knot values, not yet the
    spline's extremes)."""
    c = plan.cycles
    shape = np.array([PITCH_SHAPES[a] for a in c.activity]).reshape(-1, len(KNOT_PHASES))
    cycle = pmin[:, None] + shape * (pmax - pmin)[:, None]
    # A heel strike ends one cycle and starts the next: both shapes must agree on it.
    # It takes the lower of the two shapes' values, and the knots on either side of it
    # (the previous cycle's last, this cycle's second) keep their offsets from it, the
    # second at least halfway down to the next knot, so a change of activity (stairs to
    # level and back) stays as smooth as a level walk.
    going = np.flatnonzero(~c.first_of_bout.astype(bool))
    heel = np.minimum(cycle[going, 0], cycle[going - 1, 0])
    cycle[going, 1] = np.maximum(cycle[going, 1] + heel - cycle[going, 0],
                                 (heel + cycle[going, 2]) / 2)
    cycle[going - 1, -1] += heel - cycle[going - 1, 0]
    cycle[going, 0] = heel
    starting = np.flatnonzero(c.first_of_bout)
    ramp = KNOT_PHASES < MIN_PHASE
    cycle[np.ix_(starting, ramp)] = (KNOT_PHASES[ramp] / MIN_PHASE)[None, :] * \
        pmin[starting, None]
    heel = shape[knots.last, 0] * (pmax - pmin)[knots.last] + pmin[knots.last]
    settle = heel[:, None] * np.array([1.0, 0.5, 0.0])[None, :]
    return knots.assemble(cycle, settle, knots.rest_pitch, np.zeros(()))


def _cycle_extremes(spline: CubicSpline, start: np.ndarray,
                    end: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Exact max and min of a spline over each [start, end]: the endpoints and the roots
    of its derivative."""
    if len(start) == 0:
        return np.empty(0), np.empty(0)
    roots = spline.derivative().roots(extrapolate=False)
    roots = roots[np.isfinite(roots)]
    which = np.searchsorted(start, roots, side="right") - 1
    inside = (which >= 0) & (roots <= end[np.clip(which, 0, None)])
    roots, which = roots[inside], which[inside]
    at_roots = spline(roots)
    pmax = np.maximum(spline(start), spline(end))
    pmin = np.minimum(spline(start), spline(end))
    np.maximum.at(pmax, which, at_roots)
    np.minimum.at(pmin, which, at_roots)
    return pmax, pmin


@dataclass(frozen=True)
class ThighTrajectory:
    """Trajectory model of an IMU in the trouser pocket walking a pocket scenario."""

    scenario: PocketScenario

    @cached_property
    def plan(self) -> GaitPlan:
        return plan_gait(self.scenario)

    @property
    def duration_s(self) -> float:
        return self.plan.end_time

    @cached_property
    def _knots(self) -> _Knots:
        return _Knots(self.plan)

    @cached_property
    def pitch_extremes(self) -> tuple[np.ndarray, np.ndarray]:
        """Knot extremes per cycle that make the spline's extremes the planned ones, and
        those exact extremes: (knot max, knot min, max, min) [rad]."""
        c, knots = self.plan.cycles, self._knots
        end = c.start + c.duration
        kmax, kmin = c.pitch_max.astype(float), c.pitch_min.astype(float)
        for _ in range(PITCH_ITERATIONS):
            spline = CubicSpline(knots.times, _pitch_knots(self.plan, knots, kmax, kmin),
                                 bc_type="clamped")
            pmax, pmin = _cycle_extremes(spline, c.start, end)
            kmax = kmax + (c.pitch_max - pmax)
            kmin = kmin + (c.pitch_min - pmin)
        spline = CubicSpline(knots.times, _pitch_knots(self.plan, knots, kmax, kmin),
                             bc_type="clamped")
        pmax, pmin = _cycle_extremes(spline, c.start, end)
        return kmax, kmin, pmax, pmin

    @cached_property
    def route(self) -> dict[str, np.ndarray]:
        """Per cycle: stride [m], start point (K, 3) of the route (floor level), start
        heading and chord heading [rad]."""
        p, c = self.scenario.person, self.plan.cycles
        _, _, pmax, pmin = self.pitch_extremes
        level = np.isnan(c.stair_stride_m)
        stride = np.where(level, p.a_h_m_per_deg * np.degrees(pmax - pmin) + p.b_h_m
                          + c.scatter_m, c.stair_stride_m)
        heading = c.heading.astype(float)
        chord = heading + c.turn / 2
        step = np.stack([stride * np.cos(chord), stride * np.sin(chord),
                         c.risers * c.riser_m], axis=1)
        start = np.asarray(self.scenario.initial.position_m) + \
            np.concatenate([np.zeros((1, 3)), np.cumsum(step, axis=0)[:-1]])
        return {"stride": stride, "start": start, "step": step, "heading": heading,
                "chord": chord}

    @cached_property
    def spline(self) -> CubicSpline:
        """All channels (x, y, z of the pelvis, route heading, θ, sway) as one spline."""
        p, c, knots = self.scenario.person, self.plan.cycles, self._knots
        route = self.route
        kmax, kmin, _, _ = self.pitch_extremes
        phase = KNOT_PHASES[None, :].repeat(len(c.start), 0)
        progress = phase.copy()
        first, last = c.first_of_bout.astype(bool), c.last_of_bout.astype(bool)
        progress[first & ~last] = _first_ramp(phase[first & ~last])
        progress[last & ~first] = _last_ramp(phase[last & ~first])
        progress[first & last] = _only_ramp(phase[first & last])
        pelvis = route["start"][:, None, :] + progress[..., None] * route["step"][:, None, :]
        pelvis[..., 2] += p.hip_height_m - p.hip_bob_m * np.cos(4 * np.pi * phase)
        heading = route["heading"][:, None] + progress * c.turn[:, None]
        side = 1.0 if p.leg == "right" else -1.0
        sway_env = np.where(first[:, None], np.minimum(1.0, phase / MIN_PHASE), 1.0)
        sway = side * np.radians(p.hip_sway_deg) / 2 * np.cos(2 * np.pi * phase) * sway_env
        cycle = np.concatenate([pelvis, heading[..., None], np.zeros_like(heading)[..., None],
                                sway[..., None]], axis=2)
        end_point = route["start"][knots.last] + route["step"][knots.last]
        end_point[:, 2] += p.hip_height_m
        settle = np.repeat(np.concatenate([end_point, (route["heading"] + c.turn)[knots.last,
                                                                                  None],
                                           np.zeros((len(knots.last), 2))], axis=1)[:, None],
                           3, axis=1)
        settle[:, 0, 2] -= p.hip_bob_m
        settle[:, :, SWAY] = side * np.radians(p.hip_sway_deg) / 2 * np.array([1.0, 0.5, 0.0])
        rest = self._rest_values(knots)
        values = knots.assemble(cycle, settle, rest,
                                self._end_values(rest) if len(rest) else settle[-1, -1])
        values[:, PITCH] = _pitch_knots(self.plan, knots, kmax, kmin)
        return CubicSpline(knots.times, values, bc_type="clamped")

    @cached_property
    def pitch(self) -> PPoly:
        """The thigh pitch θ(t) [rad] alone (the spline's pitch channel)."""
        return PPoly(self.spline.c[:, :, PITCH], self.spline.x)

    def _rest_values(self, knots: _Knots) -> np.ndarray:
        """Pose at the rest knots: where the previous bout ended (or the start), the
        heading turning by a smoothstep through a turn in place."""
        p, c, route = self.scenario.person, self.plan.cycles, self.route
        values = np.zeros((len(knots.rest_t), 6))
        ends = c.start + c.duration
        before = np.searchsorted(ends, knots.rest_t, side="right") - 1
        where = np.tile(np.asarray(self.scenario.initial.position_m, float),
                        (len(knots.rest_t), 1))
        done = before >= 0
        if len(c.start):
            where[done] = (route["start"] + route["step"])[before[done]]
        rests = self.plan.rests
        start, duration, heading, turn = (np.array([getattr(r, f) for r in rests])[
            knots.rest_index] for f in ("start", "duration", "heading", "turn"))
        u = (knots.rest_t - start) / duration if len(rests) else np.empty(0)
        values[:, :3] = where
        values[:, Z] += p.hip_height_m
        values[:, HEADING] = heading + turn * (3 * u**2 - 2 * u**3)
        values[:, PITCH] = knots.rest_pitch
        return values

    def _end_values(self, rest_values: np.ndarray) -> np.ndarray:
        """The pose at the end of a plan that ends resting (its last turn completed)."""
        end = rest_values[-1].copy()
        last = self.plan.rests[-1]
        end[HEADING] = last.heading + last.turn
        return end

    # --- the trajectory -------------------------------------------------------------
    def sample(self, rate_hz: float) -> Trajectory:
        from pdr_sim.foot_trajectory import sample_times

        return self.at(sample_times(self.duration_s, rate_hz))

    @cached_property
    def body(self) -> ThighBody:
        """The body dimensions and mounting the compiled kernel needs."""
        p, carry = self.scenario.person, CARRIED[self.scenario.carried]
        side = -1.0 if p.leg == "right" else 1.0
        hip = (0.0, side * p.hip_half_width_m, 0.0) if carry.hip_offset_m is None \
            else carry.hip_offset_m
        lever = p.lever_arm_m if carry.lever_arm_m is None else carry.lever_arm_m
        mounting = np.ascontiguousarray(self.scenario.mounting_matrix, dtype=float)
        return ThighBody(np.asarray(hip, float), np.asarray(lever, float), mounting,
                         Rotation.from_matrix(mounting).as_quat(), carry.pitch_coupling)

    def at(self, t: np.ndarray) -> Trajectory:
        """The sensor's trajectory at times ``t`` [s] (0 ≤ t ≤ duration), by
        :func:`pdr_sim.compiled_thigh.thigh_kinematics`."""
        motion = SensorMotion.empty(len(t))
        spline = ThighSpline(self.spline.x, np.ascontiguousarray(self.spline.c))
        thigh_kinematics(np.ascontiguousarray(t, dtype=float), spline, self.body, motion)
        attitude, rate = Rotation.from_quat(motion.quaternion), motion.body_rate
        if self.scenario.remounts:
            attitude, rate = self._remounted(t, attitude, rate)
        if self.plan.rides:
            for out, ride in zip((motion.position, motion.velocity, motion.acceleration),
                                 rides_motion(self.plan.rides, t), strict=True):
                out[:, 2] += ride
        return Trajectory(t, motion.position, motion.velocity, motion.acceleration, attitude,
                          rate)

    def _remounted(self, t: np.ndarray, attitude: Rotation,
                   rate: np.ndarray) -> tuple[Rotation, np.ndarray]:
        """The attitude and body rate with the scenario's remounts: each turns the sensor
        by E = C_beforeᵀ·C_after (sensor frame) as exp(s(u)·φ), φ = log E, s = 3u² − 2u³
        over its duration, so C_s^n = C_s0^n·P·exp(s·φ) (P: the remounts completed) and
        ω_s = exp(s·φ)ᵀ·Pᵀ·ω_s0 + ṡ·φ."""
        extra = Rotation.identity(len(t))
        spin = np.zeros_like(rate)
        before = self.scenario.mounting_matrix
        for start, duration, after in self.scenario.remount_matrices:
            phi = Rotation.from_matrix(before.T @ after).as_rotvec()
            u = np.clip((t - start) / duration, 0.0, 1.0)
            turning = (u > 0.0) & (u < 1.0)
            extra = extra * Rotation.from_rotvec(np.outer(3 * u**2 - 2 * u**3, phi))
            spin[turning] = np.outer(6 * u[turning] * (1 - u[turning]) / duration, phi)
            before = after
        return attitude * extra, extra.inv().apply(rate) + spin

    # --- the truth ------------------------------------------------------------------
    @cached_property
    def true_steps(self) -> TrueSteps:
        c, route = self.plan.cycles, self.route
        _, _, pmax, pmin = self.pitch_extremes
        return TrueSteps(c.start + c.duration, route["stride"], c.risers * c.riser_m,
                         wrap_angle(route["chord"]), pmax, pmin, c.duration.astype(float),
                         c.activity.astype(np.uint8))

    @cached_property
    def landmarks(self) -> tuple[TrueLandmark, ...]:
        """The route's corners and flights, with the earlier visit each one revisits: the
        nearest first visit of the same type and floor within :data:`REVISIT_RADIUS_M`,
        at least :data:`REVISIT_MIN_S` earlier (Muñoz Díaz 2016, Section 5.3). A lift ride
        is none: it has no shape in the heading a drift estimator could recognise; the
        landmarks after it are on the floor it went to, as high as it went."""
        c, route = self.plan.cycles, self.route
        ends = c.start + c.duration
        out: list[TrueLandmark] = []
        for i, mark in enumerate(self.plan.landmarks):
            a, b = mark.first_cycle, mark.last_cycle
            if mark.rest is not None:
                pivot = self.plan.rests[mark.rest]
                position = (route["start"][b] + route["step"][b]) if b >= 0 else \
                    np.asarray(self.scenario.initial.position_m, float)
                before, after = (float(wrap_angle(pivot.heading)),
                                 float(wrap_angle(pivot.heading + pivot.turn)))
                time_s = pivot.start + pivot.duration / 2
            elif mark.type == LandmarkType.STAIRS:
                finish = route["start"][b] + route["step"][b]
                position = (route["start"][a] + finish) / 2
                before = after = float(wrap_angle(route["chord"][a]))
                time_s = float((c.start[a] + ends[b]) / 2)
            else:
                middle = (a + b + 1) / 2
                k = int(middle)
                position = route["start"][k] + (middle - k) * route["step"][k]
                before = float(wrap_angle(route["heading"][a]))
                after = float(wrap_angle(route["heading"][b] + c.turn[b]))
                time_s = float((c.start[a] + ends[b]) / 2)
            if self.plan.rides:
                position = position + (0.0, 0.0, rides_motion(self.plan.rides, [time_s])[0][0])
            candidates = [(np.hypot(*(np.asarray(e.position[:2]) - position[:2])), e.id)
                          for e in out if e.type == mark.type and e.floor == mark.floor
                          and e.revisit_of is None and time_s - e.time_s >= REVISIT_MIN_S]
            near = min((c for c in candidates if c[0] <= REVISIT_RADIUS_M), default=None)
            revisit = None if near is None else near[1]
            out.append(TrueLandmark(i, mark.type, time_s, tuple(map(float, position)), before,
                                    after, mark.floor, revisit))
        return tuple(out)

    @cached_property
    def periods(self) -> tuple[Period, ...]:
        """Standing, sitting and the walking bouts (activity WALKING for a whole bout)."""
        c = self.plan.cycles
        spans = [Period(r.activity, r.start, r.start + r.duration) for r in self.plan.rests]
        starts = c.start[c.first_of_bout.astype(bool)]
        ends = (c.start + c.duration)[c.last_of_bout.astype(bool)]
        spans += [Period(Activity.WALKING, float(a), float(b))
                  for a, b in zip(starts, ends, strict=True)]
        return tuple(sorted(spans, key=lambda s: s.start_s))
