"""Foot-mounted IMU trajectory of a scenario (Zampella et al. 2011, section II).

The walk is a sequence of *phases*: rest (standing or stance, the foot still), swing along
a straight line or an arc, and turns in place. Every sample is evaluated in one
vectorised pass: the phase of each sample is found with ``searchsorted`` and its pattern
evaluated with per-sample parameters.

- Straight swing: p = p₀ + s(τ)·u(ψ) + z(τ)·e_up, the pattern of Eqs. (1)–(2) (or the
  fitted one of Eqs. (3)–(4)), on the scenario's swing timing (see
  :mod:`pdr_sim.step_pattern`).
- Curved swing: the along-track displacement s becomes the angle ϑ = s/r on a circle of
  radius r (section II-B): p = c + r·(cos α, sin α), α = α₀ ± s/r, and the heading turns
  with it, ψ = ψ₀ ± s/r. Velocity r·α̇·(−sin α, cos α), acceleration
  r·α̈·(−sin α, cos α) − r·α̇²·(cos α, sin α).
- Turn in place: ψ = ψ₀ + Δψ·(1 − cos(πτ/T))/2, position fixed.
- Gaits beyond level walking (running, stairs, stepping in place, side and back steps,
  crawling, and a walk with a realistic stance): phases of kind ``PIECE``, the rolls and
  swings of :mod:`pdr_sim.foot_gaits` evaluated by :mod:`pdr_sim.foot_pieces`, with the
  landing impacts added on top.

Per-stride parameters are drawn once from the scenario's variation (normal, clipped to
at least 20 % of the mean so that no stride is impossible) with its seed.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from pdr_core.errors import InputError
from pdr_sim.foot_gaits import GAIT_TYPES, GAITS, gait_segment, stride_vector
from pdr_sim.foot_pieces import SWING, Impacts, Pieces, evaluate
from pdr_sim.scenario import Scenario, StepSpec, scenario_from_dict
from pdr_sim.step_pattern import FittedPattern, basic_swing, swing_phase
from pdr_sim.trajectory import Trajectory

REST, STRAIGHT, CURVE, TURN, PIECE = 0, 1, 2, 3, 4
_STEP_KEYS = ("length_m", "height_m", "swing_s", "stance_s", "pitch_max_rad")


@dataclass(frozen=True)
class Phases:
    """Phase table, arrays of length P: start time [s], duration [s], kind, start position
    (P, 3), start yaw [rad], and per-phase parameters (stride length, height, pitch max,
    signed curvature 1/r [1/m] (+ left), turn angle [rad]); the pieces of the gait
    phases (rows of the other phases unused) and the landing impacts; optionally the
    height a swing climbs (:mod:`pdr_sim.paired_foot`'s stairs), in proportion to its
    along-track progress s(τ)/L."""

    start: np.ndarray
    duration: np.ndarray
    kind: np.ndarray
    position: np.ndarray
    yaw: np.ndarray
    length: np.ndarray
    height: np.ndarray
    pitch_max: np.ndarray
    curvature: np.ndarray
    turn: np.ndarray
    end_time: float
    end_position: np.ndarray
    end_yaw: float
    pieces: Pieces
    impacts: Impacts
    climb: np.ndarray | None = None     # height gained over a swing [m] (+ up), or none

    @property
    def path_length_m(self) -> float:
        """Horizontal distance travelled by the foot [m] (a gait's swings count their
        stride, not the rolls about the contacts)."""
        return float(self.length[self.kind != REST].sum())

    @property
    def heading_change_rad(self) -> float:
        """Total change of heading [rad], counter-clockwise positive."""
        return float((self.length * self.curvature).sum() + self.turn.sum())


def draw_strides(scenario: Scenario) -> list[StepSpec]:
    """The parameters of every stride, in order, with the scenario's seeded variation."""
    rng = np.random.default_rng(scenario.seed)
    strides = []
    for segment in scenario.segments:
        base = segment.step or scenario.step
        for _ in range(segment.steps if segment.type in ("straight", "curve") else 0):
            noise = rng.standard_normal(len(_STEP_KEYS))
            values = {k: max(getattr(base, k) + getattr(scenario.variation, k) * e,
                             0.2 * getattr(base, k)) for k, e in zip(_STEP_KEYS, noise,
                                                                      strict=True)}
            strides.append(StepSpec(**values))
    return strides


def build_phases(scenario: Scenario) -> Phases:
    """The phase table of a scenario (a short Python loop over strides, not samples)."""
    rows: list[tuple] = []
    piece_rows: dict[int, object] = {}
    impacts: list[tuple] = []
    t = 0.0
    position = np.asarray(scenario.initial.position_m, float)
    yaw = np.radians(scenario.initial.yaw_deg)
    strides = iter(draw_strides(scenario))
    for number, segment in enumerate(scenario.segments):
        if segment.type == "standing":
            rows.append((t, segment.duration_s, REST, position, yaw, 0, 0, 0, 0, 0))
            t += segment.duration_s
        elif segment.type == "turn":
            turn = np.radians(segment.angle_deg)
            rows.append((t, segment.duration_s, TURN, position, yaw, 0, 0, 0, 0, turn))
            t += segment.duration_s
            yaw += turn
        elif segment.type in GAIT_TYPES:
            built = gait_segment(segment.type, segment.direction, segment.steps, segment.gait,
                                 t, position, yaw, np.radians(scenario.initial.roll_deg),
                                 np.radians(scenario.initial.pitch_deg),
                                 np.random.default_rng([scenario.seed, number]))
            stride = stride_vector(segment.type, segment.direction, segment.gait, yaw)
            for piece in built.pieces:
                piece_rows[len(rows)] = piece
                start = piece.state(0.0).position.f[0]
                length = float(np.hypot(*stride[:2])) if piece.kind == SWING else 0.0
                rows.append((piece.start, piece.duration, PIECE, start, yaw, length, 0, 0, 0,
                             0))
            impacts += built.impacts
            t, position = built.end_time, built.end_position
        else:
            curvature = 0.0
            if segment.type == "curve":
                curvature = (1 if segment.direction == "left" else -1) / segment.radius_m
            for _ in range(segment.steps):
                stride = next(strides)
                rows.append((t, stride.stance_s, REST, position, yaw, 0, 0, 0, 0, 0))
                t += stride.stance_s
                kind = CURVE if curvature else STRAIGHT
                rows.append((t, stride.swing_s, kind, position, yaw, stride.length_m,
                             stride.height_m, stride.pitch_max_rad, curvature, 0))
                t += stride.swing_s
                position, yaw = _swing_end(position, yaw, stride.length_m, curvature)
    cols = list(zip(*rows, strict=True))
    pieces = Pieces.empty(len(rows))
    for row, piece in piece_rows.items():
        pieces.kind[row], pieces.euler[row] = piece.kind, piece.euler
        pieces.position[row], pieces.lever[row] = piece.position, piece.lever
    return Phases(*(np.asarray(c, float) for c in cols[:2]), np.asarray(cols[2], int),
                  np.stack(cols[3]), *(np.asarray(c, float) for c in cols[4:]),
                  end_time=t, end_position=position, end_yaw=float(yaw), pieces=pieces,
                  impacts=Impacts.from_rows(impacts))


def _swing_end(position: np.ndarray, yaw: float, length: float, curvature: float):
    if curvature == 0:
        return position + length * np.array([np.cos(yaw), np.sin(yaw), 0.0]), yaw
    r = 1.0 / curvature
    centre = position[:2] + r * np.array([-np.sin(yaw), np.cos(yaw)])
    angle = np.arctan2(*(position[:2] - centre)[::-1]) + length * curvature
    end = centre + abs(r) * np.array([np.cos(angle), np.sin(angle)])
    return np.array([end[0], end[1], position[2]]), yaw + length * curvature


def sample_times(duration_s: float, rate_hz: float) -> np.ndarray:
    """Times [s] of the samples from 0 to ``duration_s`` at ``rate_hz``."""
    return np.arange(int(np.floor(duration_s * rate_hz + 1e-9)) + 1) / rate_hz


@dataclass(frozen=True)
class FootTrajectory:
    """Trajectory model of a foot-mounted IMU walking a scenario."""

    scenario: Scenario
    fitted: FittedPattern | None = None

    @cached_property
    def phases(self) -> Phases:
        return build_phases(self.scenario)

    @property
    def duration_s(self) -> float:
        return self.phases.end_time

    def sample(self, rate_hz: float) -> Trajectory:
        """All samples from t = 0 to the end of the last phase, at ``rate_hz``."""
        return self.at(sample_times(self.duration_s, rate_hz))

    def at(self, t: np.ndarray) -> Trajectory:
        """The trajectory at times ``t`` [s] (0 ≤ t ≤ duration).

        Rest samples keep their phase's pose; swing and turn samples are evaluated on
        their own index subsets, so no work is spent on samples that do not move.
        """
        phases = self.phases
        n = len(t)
        idx = np.clip(np.searchsorted(phases.start, t, side="right") - 1, 0, None)
        kind = phases.kind[idx]
        pos = phases.position[idx]
        vel, acc, rate = np.zeros((3, n, 3))
        euler = np.empty((n, 3))
        euler[:, 0] = np.radians(self.scenario.initial.roll_deg)
        euler[:, 1] = np.radians(self.scenario.initial.pitch_deg)
        euler[:, 2] = phases.yaw[idx]
        swinging = np.flatnonzero((kind == STRAIGHT) | (kind == CURVE))
        self._add_swing(t, swinging, idx[swinging], kind[swinging], pos, vel, acc, euler, rate)
        turning = np.flatnonzero(kind == TURN)
        phase_of = idx[turning]
        duration = phases.duration[phase_of]
        angle = phases.turn[phase_of]
        x = np.pi * np.minimum(t[turning] - phases.start[phase_of], duration) / duration
        euler[turning, 2] += angle * (1 - np.cos(x)) / 2
        rate[turning, 2] = angle * np.pi / (2 * duration) * np.sin(x)
        gait = np.flatnonzero(kind == PIECE)
        if gait.size:
            self._add_pieces(t, gait, idx[gait], pos, vel, acc, euler, rate)
        return Trajectory.from_euler(t, pos, vel, acc, euler, rate)

    def _add_pieces(self, t, rows, phase_of, pos, vel, acc, euler, rate) -> None:
        """Set the samples ``rows`` of gait phases from their pieces, and add the landing
        impacts (in place)."""
        phases = self.phases
        duration = phases.duration[phase_of]
        tau = np.minimum(t[rows] - phases.start[phase_of], duration)
        state = evaluate(phases.pieces, phase_of, tau, duration)
        pos[rows], vel[rows], acc[rows] = state.position.f, state.position.d1, state.position.d2
        euler[rows], rate[rows] = state.euler.f, state.euler.d1
        hit, shift, turn = phases.impacts.at(t[rows])
        hit = rows[hit]
        pos[hit] += shift.f
        vel[hit] += shift.d1
        acc[hit] += shift.d2
        euler[hit] += turn.f
        rate[hit] += turn.d1

    def _add_swing(self, t, rows, phase_of, kind, pos, vel, acc, euler, rate) -> None:
        """Add the swing pattern to the samples ``rows`` (in place)."""
        phases = self.phases
        tau = np.minimum(t[rows] - phases.start[phase_of], phases.duration[phase_of])
        phase = swing_phase(tau, phases.duration[phase_of], self.scenario.timing)
        length = phases.length[phase_of]
        if self.fitted is None:
            swing = basic_swing(phase, length, phases.height[phase_of],
                                phases.pitch_max[phase_of])
        else:
            swing = self.fitted.swing(phase, length)
        pos[rows, 2] += swing.z.f
        vel[rows, 2], acc[rows, 2] = swing.z.d1, swing.z.d2
        if phases.climb is not None:
            grade = phases.climb[phase_of] / length
            pos[rows, 2] += grade * swing.s.f
            vel[rows, 2] += grade * swing.s.d1
            acc[rows, 2] += grade * swing.s.d2
        euler[rows, 0] += swing.roll.f
        euler[rows, 1] += swing.pitch.f
        rate[rows, 0], rate[rows, 1] = swing.roll.d1, swing.pitch.d1
        yaw0 = phases.yaw[phase_of]

        straight = kind == STRAIGHT
        r_st = rows[straight]
        u = np.stack([np.cos(yaw0[straight]), np.sin(yaw0[straight])], axis=1)
        pos[r_st, :2] += swing.s.f[straight, None] * u
        vel[r_st, :2] = swing.s.d1[straight, None] * u
        acc[r_st, :2] = swing.s.d2[straight, None] * u

        curve = ~straight
        r_cu = rows[curve]
        k = phases.curvature[phase_of[curve]]
        r = 1.0 / k
        yc = yaw0[curve]
        centre = pos[r_cu, :2] + r[:, None] * np.stack([-np.sin(yc), np.cos(yc)], axis=1)
        alpha = yc - np.sign(k) * np.pi / 2 + swing.s.f[curve] * k
        alpha_d, alpha_dd = swing.s.d1[curve] * k, swing.s.d2[curve] * k
        radial = np.stack([np.cos(alpha), np.sin(alpha)], axis=1)
        tangent = np.stack([-np.sin(alpha), np.cos(alpha)], axis=1)
        radius = np.abs(r)[:, None]
        pos[r_cu, :2] = centre + radius * radial
        vel[r_cu, :2] = radius * alpha_d[:, None] * tangent
        acc[r_cu, :2] = radius * (alpha_dd[:, None] * tangent - alpha_d[:, None] ** 2 * radial)
        euler[r_cu, 2] += swing.s.f[curve] * k
        rate[r_cu, 2] = alpha_d


def level_walk_like(scenario: Scenario, data: dict) -> dict:
    """The scenario mapping of a level walk as long as ``scenario``, to compare a gait
    against: its first and last standing (5 s if it starts or ends otherwise), and between
    them ``walk`` strides (pdr_sim.foot_gaits) out, a 180° turn in place of 2 s, and back,
    the last standing stretched to the same duration. Seed, initial pose and environment
    are the scenario's."""
    segments = scenario.segments
    first = segments[0].duration_s if segments[0].type == "standing" else 5.0
    last = segments[-1].duration_s if segments[-1].type == "standing" else 5.0
    duration = FootTrajectory(scenario).duration_s
    strides = int((duration - first - last - 2.0) // GAITS["walk"].cycle_s)
    if strides < 2:
        raise InputError("--level-walk", f"scenario '{scenario.name}' is too short "
                                         f"({duration:.1f} s) for a level walk")
    walk = {key: value for key, value in data.items() if key != "segments"}
    walk["name"] = f"level walk like {scenario.name}"
    walk["segments"] = [{"type": "standing", "duration_s": first},
                        {"type": "walk", "steps": strides // 2},
                        {"type": "turn", "angle_deg": 180, "duration_s": 2.0},
                        {"type": "walk", "steps": strides - strides // 2},
                        {"type": "standing", "duration_s": last}]
    short = FootTrajectory(scenario_from_dict(walk, walk["name"])).duration_s
    walk["segments"][-1]["duration_s"] = round(float(last + duration - short), 6)
    return walk
