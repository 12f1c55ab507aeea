"""The foot of the pocket's leg on the same walk: a second IMU for one pedestrian.

Muñoz Díaz 2016, Section 7.3: a pedestrian who wears a foot IMU and a phone in the
trouser pocket moves both by the same strides, so the foot INS can calibrate the pocket's
lines (issue 57, ``pdr_pocket.line_calibration``). This module builds that foot from a
pocket scenario's gait plan and route (:class:`~pdr_sim.thigh_trajectory.ThighTrajectory`),
so that the two sensors share every stride, turn, flight of stairs and rest:

- gait cycle k of the sensor leg runs from its heel strike to the next (Section 4.1.1);
  the foot of that leg stands still for ``STANCE_FRACTION`` of it (0.60 of the cycle
  walking, Perry 1992; stairs 0.60–0.66, McFadyen & Winter 1988, as
  :data:`pdr_sim.foot_gaits.GAITS`) and swings over the rest, landing as the cycle ends;
- the swing is Zampella et al. 2011's pattern (Eqs. (1)–(2), :mod:`pdr_sim.step_pattern`)
  of the cycle's true stride, the pelvis's chord (``ThighTrajectory.route``), so the foot
  lands where the route's next cycle starts: straight, or on a turn an arc from the
  cycle's start heading through its turn φ, of length s·(φ/2)/sin(φ/2) so that its chord
  is the stride s;
- on stairs the swing also climbs the cycle's risers, in proportion to its progress;
- a rest stands still, a turn in place turns the foot about its vertical.

The foot's stride is then the thigh's to the last bit, and both lines of the person
(``PersonSpec``) hold in it as they do in the pocket's truth; what the foot INS gives
back carries its own sensor's errors. Lift rides are not modelled for the foot (an
:class:`InputError`).

Units: time [s], lengths [m], angles [rad].
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.io.batch import MessageBatch
from pdr_sim.foot_pieces import Impacts, Pieces
from pdr_sim.foot_trajectory import CURVE, REST, STRAIGHT, TURN, FootTrajectory, Phases
from pdr_sim.scenario import InitialPose, Scenario
from pdr_sim.simulation import Simulation, SimulationConfig, simulate
from pdr_sim.thigh_trajectory import ThighTrajectory

STANCE_FRACTION = 0.6


def foot_scenario(thigh: ThighTrajectory) -> Scenario:
    """The foot scenario beside a pocket one: its name, seed, start and environment, the
    basic swing pattern on a linear timing (its segments are the pocket's plan,
    :func:`paired_phases`): a swing of 40 % of a cycle peaks at π/2 times its mean speed,
    5 m/s for a stride of 1.4 m in 0.44 s, where the smooth timing would give 9."""
    pocket = thigh.scenario
    return Scenario(name=f"{pocket.name}, the foot of the pocket's leg", segments=(),
                    seed=pocket.seed,
                    initial=InitialPose(position_m=pocket.initial.position_m,
                                        yaw_deg=pocket.initial.yaw_deg),
                    timing="linear", environment=pocket.environment)


def _arc(stride: float, turn: float) -> tuple[float, float]:
    """The swing's length along its arc [m] and its signed curvature [1/m]: the arc
    through ``turn`` whose chord is ``stride``."""
    if turn == 0.0:
        return stride, 0.0
    length = stride * (turn / 2) / np.sin(turn / 2)
    return length, turn / length


def paired_phases(thigh: ThighTrajectory, step_height_m: float, pitch_max_rad: float) -> Phases:
    """The foot's phase table (:class:`~pdr_sim.foot_trajectory.Phases`) from the pocket's
    plan (a loop over cycles and rests, not samples)."""
    plan = thigh.plan
    if plan.rides:
        raise InputError(thigh.scenario.name, "the foot of a walk with lift rides is not "
                                              "simulated (take the rides out)")
    c, route = plan.cycles, thigh.route
    rows: list[tuple] = []
    events = sorted([(float(c.start[k]), 0, k) for k in range(len(c))]
                    + [(r.start, 1, i) for i, r in enumerate(plan.rests)])
    position = np.asarray(thigh.scenario.initial.position_m, float)
    yaw = float(np.radians(thigh.scenario.initial.yaw_deg))
    t = 0.0
    for start, is_rest, index in events:
        if start > t:
            rows.append((t, start - t, REST, position, yaw, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
        if is_rest:
            rest = plan.rests[index]
            kind = TURN if rest.turn else REST
            rows.append((start, rest.duration, kind, position, yaw, 0.0, 0.0, 0.0, 0.0,
                         rest.turn, 0.0))
            t, yaw = start + rest.duration, yaw + rest.turn
            continue
        period = float(c.duration[index])
        stance = STANCE_FRACTION * period
        position, yaw = route["start"][index], float(c.heading[index])
        rows.append((start, stance, REST, position, yaw, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
        length, curvature = _arc(float(route["stride"][index]), float(c.turn[index]))
        rows.append((start + stance, period - stance, CURVE if curvature else STRAIGHT,
                     position, yaw, length, step_height_m, pitch_max_rad, curvature, 0.0,
                     float(route["step"][index, 2])))
        position = route["start"][index] + route["step"][index]
        t, yaw = start + period, yaw + float(c.turn[index])
    if plan.end_time > t:
        rows.append((t, plan.end_time - t, REST, position, yaw, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    cols = list(zip(*rows, strict=True))
    return Phases(*(np.asarray(col, float) for col in cols[:2]), np.asarray(cols[2], int),
                  np.stack(cols[3]), *(np.asarray(col, float) for col in cols[4:10]),
                  end_time=float(plan.end_time), end_position=position, end_yaw=yaw,
                  pieces=Pieces.empty(len(rows)), impacts=Impacts.from_rows([]),
                  climb=np.asarray(cols[10], float))


@dataclass(frozen=True)
class PairedFoot(FootTrajectory):
    """The foot of the pocket's leg walking ``thigh``'s plan (module docstring); its
    ``scenario`` is :func:`foot_scenario`'s, its swing the scenario's default stride's
    height and pitch (Zampella et al. 2011, Fig. 4)."""

    thigh: ThighTrajectory | None = None

    @cached_property
    def phases(self) -> Phases:
        step = self.scenario.step
        return paired_phases(self.thigh, step.height_m, step.pitch_max_rad)


def paired_foot(thigh: ThighTrajectory) -> PairedFoot:
    """The foot beside a pocket walk."""
    return PairedFoot(foot_scenario(thigh), thigh=thigh)


FOOT_STREAM = 57
"""The foot's sensor errors draw from this child of the run's seed, so that they are
independent of the pocket's (which draw from the seed itself)."""


def foot_seed(seed: int) -> int:
    """The seed of the foot's sensor errors beside a pocket run of ``seed``."""
    return int(np.random.SeedSequence([seed, FOOT_STREAM]).generate_state(1)[0])


def foot_simulation(pocket: Simulation, imu: str, imu_overrides: dict | None = None
                    ) -> Simulation:
    """The foot IMU of a pocket run's walk (its sample times, gravity and environment),
    with the profile ``imu`` and its own errors (:func:`foot_seed`)."""
    config = pocket.config
    foot = paired_foot(pocket.model)
    foot_config = SimulationConfig(
        foot.scenario, {"paired_with": config.scenario.name}, imu, dict(imu_overrides or {}),
        config.rate_hz, foot_seed(config.seed), config.gravity_mps2, "foot")
    return simulate(foot_config, model=foot)


def namespaced(batches: dict[str, MessageBatch], namespace: str = topics.FOOT_NAMESPACE
               ) -> dict[str, MessageBatch]:
    """The foot's topics under ``namespace``: ``/imu/data`` -> ``/foot/imu/data``."""
    return {namespace + name: batch for name, batch in batches.items()}
