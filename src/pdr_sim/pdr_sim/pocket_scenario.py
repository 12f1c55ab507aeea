"""Pocket (thigh) walking scenarios: who walks, where the phone sits, and the route.

A pocket scenario is a YAML mapping (built-in ones in ``pdr_sim/scenarios/pocket/``):

    name: h1_rectangle
    seed: 1                        # per-step scatter and speed variation
    person:                        # Muñoz Díaz 2016, chapter 4 (defaults: PersonSpec)
      a_h_m_per_deg: 0.025         # stride s = a_H·Δθ + b_H (Eq. (4.2)), Δθ in degrees
      b_h_m: 0.42
      a_u_cm_per_deg: 0.8          # stairs up: v = a_U·Δθ_U + b_U [cm] (Eq. (4.4))
      b_u_cm: -8.46
      a_d_cm_per_deg: 2.0          # stairs down: v = a_D·Δθ_D + b_D [cm] (Eq. (4.5))
      b_d_cm: -19.24
    mounting: phone_front_pocket   # or thigh_frame, or {rpy_deg: [roll, pitch, yaw]}
    remounts:                      # the phone turned in the pocket during the walk
      - {at_s: 60, duration_s: 1, mounting: {rpy_deg: [30, 0, 90]}}
    initial: {position_m: [0, 0, 0], yaw_deg: 0}
    environment: {...}             # as for the foot (pdr_sim.scenario): field, latitude
    segments:
      - {type: standing, duration_s: 5}
      - {type: walk, distance_m: 100, speed_kmh: 3.5}      # or steps: N
      - {type: turn, angle_deg: 90, steps: 2}               # walked; + = left
      - {type: turn, angle_deg: 180, duration_s: 2}         # in place, standing
      - {type: stairs, direction: up, flights: 2, risers: 10, riser_m: 0.17,
         tread_m: 0.28, landing_turn_deg: 180, landing_steps: 2, flights_per_floor: 2}
      - {type: platform, direction: up, riser_m: 0.17}     # one riser on level ground
      - {type: sitting, duration_s: 60, pitch_deg: 80}
      - {type: lift, direction: up, floors: 3}             # or height_m: 10.5; standing
      - {type: lift, direction: down, floors: 2, floor_height_m: 3.5, speed_mps: 1.6,
         acceleration_mps2: 0.8, jerk_mps3: 1.2, dwell_s: 4}
      - {type: repeat, times: 3, segments: [{type: walk, steps: 3},     # a lap, 3 times
                                            {type: turn, angle_deg: 90, steps: 1}]}

A *lift* ride (pdr_sim.lift) carries the standing person ``floors`` × ``floor_height_m``
(default pdr_core.vocabulary.FLOOR_HEIGHT_M, 3.5 m), or ``height_m``, up or down, the car
moving with the jerk-limited profile of a passenger lift (defaults: pdr_sim.lift.LiftMotion),
``dwell_s`` of standing in the car before it moves and after it stops. The floor index
follows the ride (``floors``, or the height in floors when only ``height_m`` is given).

A *repeat* walks its segments ``times`` times in place (a lap of a room or a block), as
in a foot scenario (:func:`pdr_sim.scenario.flattened_segments`); repeats may nest.

A *step* is one gait cycle of the sensor leg (two footfalls), as in the thesis. Walking
segments take ``speed_kmh`` (default: the previous walking speed, first 3.5); cadence
follows the person's line f = c₀ + c₁·v. Every key is checked and a value the body cannot
do is refused with the key named; nothing is clipped.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pdr_core.config_files import check_keys
from pdr_core.errors import InputError
from pdr_core.vocabulary import FLOOR_HEIGHT_M
from pdr_sim.lift import LiftMotion
from pdr_sim.scenario import (
    Environment,
    environment_from,
    flattened_segments,
    number,
    read_scenario_yaml,
    seed_from,
    vector,
)

# Built-in pocket scenarios (pdr_sim/scenarios/pocket/<name>.yaml), named after what they
# reproduce in Muñoz Díaz 2016 (corridor_grid: the street grid of its warning after
# Table 5.8, for the multi-hypothesis association; indoor_loops: the loops of the OxIOD
# recordings around a small room in its own field, issue 53).
POCKET_BUILTIN = ("h1_rectangle", "h2_rectangle_speeds", "h3_museum", "up_dw",
                  "sit_stand", "theresienhoehe", "building", "out_and_back_39min",
                  "block_two_laps", "corridor_grid", "building_lift", "indoor_loops",
                  "two_imu_walk", "two_imu_stairs")

SEGMENT_TYPES = ("standing", "sitting", "walk", "turn", "stairs", "platform", "lift")
# Human range checked on the scenario (beyond it the key is refused).
STRIDE_RANGE_M = (0.3, 2.2)          # one gait cycle (two footfalls)
SPEED_RANGE_KMH = (0.5, 7.0)         # walking; faster is running, out of the thesis' scope
RISER_RANGE_M = (0.05, 0.25)         # Muñoz Díaz 2016, Section 4.3.1: 15-25 cm tested
TREAD_RANGE_M = (0.20, 0.50)
SITTING_RANGE_DEG = (30.0, 100.0)
MAX_TURN_PER_STEP_DEG = 120.0
PITCH_AMPLITUDE_RANGE_DEG = (5.0, 100.0)   # Δθ a person's line may ask of the thigh
MIN_SITTING_S = 4.0                  # sitting down and standing up take 1.5 s each
# What a passenger lift does, beyond which a lift key is refused (pdr_sim.lift: comfort
# keeps its acceleration at or below about 1 m/s² and its jerk about 2 m/s³; the ranges
# leave room around them and up to the fastest lifts), and a floor's height
LIFT_SPEED_RANGE_MPS = (0.25, 10.0)
LIFT_ACCELERATION_RANGE_MPS2 = (0.1, 1.5)
LIFT_JERK_RANGE_MPS3 = (0.2, 3.0)
FLOOR_HEIGHT_RANGE_M = (2.4, 6.0)
LIFT_RISE_RANGE_M = (0.5, 500.0)
KMH = 1.0 / 3.6
DEFAULT_SPEED_KMH = 3.5
# Named phone mountings, C_s^t: sensor axes in the thigh frame (x forward, y left, z up
# along the thigh when standing).
MOUNTINGS = {
    # the thesis' sensor frame: x forward, y left, z up along the thigh
    "thigh_frame": np.eye(3),
    # a phone upright in a front pocket, screen facing out (forward): Android axes, x to
    # the screen's right (the person's left), y up, z out of the screen
    "phone_front_pocket": np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
    # upright in a back pocket, screen facing out (backward): x to the person's right
    "phone_back_pocket": np.array([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
    # held in front of the chest to read it: top forward and 30° up, screen up and back
    "phone_in_hand": np.array([[0.0, np.cos(np.pi / 6), -np.sin(np.pi / 6)],
                               [-1.0, 0.0, 0.0],
                               [0.0, np.sin(np.pi / 6), np.cos(np.pi / 6)]]),
}


@dataclass(frozen=True)
class Carry:
    """Where on the body the phone is carried: the share of the thigh's pitch its body
    follows, the hip joint's offset from the pelvis centre (m, pelvis frame; None: the
    person's), the sensor's lever arm (m, thigh frame; None: the person's) and the
    mounting it takes unless the scenario names one."""

    pitch_coupling: float
    hip_offset_m: tuple[float, float, float] | None
    lever_arm_m: tuple[float, float, float] | None
    mounting: str


# ``carried:`` of a pocket scenario (pdr-sim generate --placement pocket, back_pocket,
# hand). Brajdic and Harle (2013) recorded phones in front and back trouser pockets and in
# the hand (the Oxford step counter data), the cases a pocket navigator meets:
# - front_pocket: on the thigh, as the thesis' sensor (Muñoz Díaz 2016, Fig. 4.7);
# - back_pocket: on the buttock, behind and a little below the hip joint; the gluteal soft
#   tissue follows the thigh's flexion only in part, taken here as 40 % of its pitch (an
#   assumption, the share no study we know measured; it makes the pitch swing smaller than
#   a front pocket's, the case the step detector must fall back for);
# - hand: held in front of the chest to read it, moving with the trunk: the pelvis' bob
#   (twice per cycle, ``hip_bob_m``) and yaw sway, no thigh swing.
CARRIED = {
    "front_pocket": Carry(1.0, None, None, "phone_front_pocket"),
    "back_pocket": Carry(0.4, None, (-0.12, 0.0, -0.06), "phone_back_pocket"),
    "hand": Carry(0.0, (0.0, 0.0, 0.0), (0.35, -0.05, 0.45), "phone_in_hand"),
}


@dataclass(frozen=True)
class PersonSpec:
    """How one person walks: the lines of Muñoz Díaz 2016, chapter 4, and the body.

    The lines hold exactly in the simulated truth up to the scatter terms, so that the
    estimators can recover them. Defaults: Δθ_U = 53.07° and Δθ_D = 26.62° on 17 cm risers
    (Section 4.3.1); a_H, b_H give Δθ_H ≈ 32° (θ_Hmax ≈ 27°) at 3.5 km/h.
    """

    a_h_m_per_deg: float = 0.025
    b_h_m: float = 0.42
    a_u_cm_per_deg: float = 0.8
    b_u_cm: float = -8.456
    a_d_cm_per_deg: float = 2.0
    b_d_cm: float = -19.24
    cadence_hz_at_rest: float = 0.55        # gait cycles per second f = c₀ + c₁·v
    cadence_hz_per_mps: float = 0.25
    stair_cadence_hz: float = 0.8
    stride_scatter_m: float = 0.02          # σ of s about its line, per step
    centre_scatter: bool = True             # the scatter's mean 0 over each segment
    stair_pitch_scatter_deg: float = 0.3    # σ of Δθ about the stairs lines, per step
    speed_scatter: float = 0.03             # relative σ of each step's speed
    pitch_min_fraction: float = 0.15        # level: θ_Hmin = −fraction·Δθ_H up to the pace
                                            # of DEFAULT_SPEED_KMH
    faster_swing_back_fraction: float = 0.5  # ... and beyond it, this share of Δθ's growth
                                             # behind the vertical
    up_pitch_min_sigma_deg: float = 2.0     # upstairs: θ_Umin ~ N(0, σ)
    down_pitch_min_deg: float = 7.0         # downstairs: θ_Dmin (positive)
    hip_sway_deg: float = 20.0              # thigh yaw sway, peak to peak
    hip_bob_m: float = 0.025                # pelvis vertical bob, amplitude
    leg: str = "right"                      # the leg carrying the sensor
    hip_half_width_m: float = 0.09          # hip joint from the pelvis centre
    hip_height_m: float = 0.9               # hip joint above the floor, standing
    lever_arm_m: tuple[float, float, float] = (0.07, 0.0, -0.20)   # sensor from the hip
                                                                   # joint, thigh frame


@dataclass(frozen=True)
class InitialPlacement:
    position_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    yaw_deg: float = 0.0


@dataclass(frozen=True)
class PocketSegment:
    type: str
    duration_s: float = 0.0
    distance_m: float = 0.0
    steps: int = 0
    speed_kmh: float | None = None
    angle_deg: float = 0.0
    pitch_deg: float = 80.0
    direction: str = "up"
    flights: int = 1
    risers: int = 10
    riser_m: float = 0.0
    tread_m: float = 0.28
    landing_turn_deg: float = 180.0
    landing_steps: int = 2
    flights_per_floor: int = 2
    floors: int = 0                             # lift: floors ridden (0: from height_m)
    height_m: float = 0.0                       # lift: the rise (0: floors × floor height)
    floor_height_m: float = FLOOR_HEIGHT_M
    speed_mps: float = LiftMotion.speed_mps
    acceleration_mps2: float = LiftMotion.acceleration_mps2
    jerk_mps3: float = LiftMotion.jerk_mps3
    dwell_s: float = 4.0                        # lift: standing in the car before and after

    @property
    def rise_m(self) -> float:
        """A lift's rise [m], + up."""
        height = self.height_m or self.floors * self.floor_height_m
        return height if self.direction == "up" else -height


@dataclass(frozen=True)
class Remount:
    """The phone turned in the pocket from the mounting before to ``mounting``, over
    [at_s, at_s + duration_s] (the sensor stays where it is on the thigh)."""

    at_s: float
    mounting: Any
    duration_s: float = 1.0


@dataclass(frozen=True)
class PocketScenario:
    name: str
    segments: tuple[PocketSegment, ...]
    person: PersonSpec = field(default_factory=PersonSpec)
    mounting: Any = "phone_front_pocket"
    remounts: tuple[Remount, ...] = ()
    seed: int = 0
    initial: InitialPlacement = field(default_factory=InitialPlacement)
    environment: Environment = field(default_factory=Environment)
    placement: str = "pocket"
    carried: str = "front_pocket"

    @property
    def mounting_matrix(self) -> np.ndarray:
        """C_s^t, (3, 3): sensor axes in the thigh frame."""
        return mounting_matrix(self.mounting)

    @property
    def remount_matrices(self) -> list[tuple[float, float, np.ndarray]]:
        """(start [s], duration [s], C_s^t after) of each remount, in time order."""
        return [(r.at_s, r.duration_s, mounting_matrix(r.mounting)) for r in self.remounts]


def cadence_hz(person: PersonSpec, speed_mps: float) -> float:
    """Gait cycles per second at a walking speed: f = c₀ + c₁·v."""
    return person.cadence_hz_at_rest + person.cadence_hz_per_mps * speed_mps


def nominal_stride_m(person: PersonSpec, speed_kmh: float) -> float:
    """Stride (one gait cycle) at a steady speed: v / f(v)."""
    v = speed_kmh * KMH
    return v / cadence_hz(person, v)


def _check_gait(scenario: PocketScenario, where: str) -> None:
    """Refuse segments this person cannot walk: a stride beyond human range at the
    segment's speed, or a pitch amplitude their lines would have to go beyond."""
    p, speed = scenario.person, DEFAULT_SPEED_KMH
    for i, seg in enumerate(scenario.segments):
        at = f"{where}: segments[{i}]"
        if seg.type in ("walk", "turn"):
            speed = seg.speed_kmh or speed
            stride = nominal_stride_m(p, speed)
            _in_range(stride, STRIDE_RANGE_M, f"{at}.speed_kmh",
                      f"a human stride at {speed:g} km/h (m)")
            _in_range((stride - p.b_h_m) / p.a_h_m_per_deg, PITCH_AMPLITUDE_RANGE_DEG,
                      f"{at}.speed_kmh", f"the pitch amplitude (deg) of a {stride:.2f} m stride "
                      "by the person's line")
        if seg.type in ("stairs", "platform"):
            rise_cm = 100.0 * seg.riser_m * (1 if seg.type == "platform" else 2)
            a, b = ((p.a_u_cm_per_deg, p.b_u_cm) if seg.direction == "up"
                    else (p.a_d_cm_per_deg, p.b_d_cm))
            _in_range((rise_cm - b) / a, PITCH_AMPLITUDE_RANGE_DEG, f"{at}.riser_m",
                      f"the pitch amplitude (deg) of {seg.direction}stairs steps by the "
                      "person's line")
        if seg.type == "sitting" and seg.duration_s < MIN_SITTING_S:
            raise InputError(f"{at}.duration_s", f"sitting takes at least {MIN_SITTING_S:g} s "
                                                 "(sitting down and standing up)")


def mounting_matrix(mounting: Any) -> np.ndarray:
    """C_s^t of a named mounting or ``{rpy_deg: [roll, pitch, yaw]}`` (ZYX, applied to the
    thigh frame)."""
    from scipy.spatial.transform import Rotation

    if isinstance(mounting, str):
        return MOUNTINGS[mounting]
    return Rotation.from_euler("ZYX", np.radians(mounting["rpy_deg"][::-1])).as_matrix()


_NEEDS = {
    "standing": ("duration_s",), "sitting": ("duration_s",),
    "walk": (), "turn": ("angle_deg",), "stairs": ("direction", "riser_m"),
    "platform": ("direction", "riser_m"), "lift": ("direction",),
}
_ALLOWED = {
    "standing": ("duration_s",), "sitting": ("duration_s", "pitch_deg"),
    "walk": ("distance_m", "steps", "speed_kmh"),
    "turn": ("angle_deg", "steps", "speed_kmh", "duration_s"),
    "stairs": ("direction", "flights", "risers", "riser_m", "tread_m", "landing_turn_deg",
               "landing_steps", "flights_per_floor", "speed_kmh"),
    "platform": ("direction", "riser_m", "tread_m"),
    "lift": ("direction", "floors", "height_m", "floor_height_m", "speed_mps",
             "acceleration_mps2", "jerk_mps3", "dwell_s"),
}
_INTEGERS = ("steps", "flights", "risers", "landing_steps", "flights_per_floor", "floors")
_RANGES = {  # key -> (range, what it is beyond)
    "speed_kmh": (SPEED_RANGE_KMH, "walking speed"),
    "pitch_deg": (SITTING_RANGE_DEG, "a sitting pitch"),
    "riser_m": (RISER_RANGE_M, "a human-range riser"),
    "tread_m": (TREAD_RANGE_M, "a human-range tread"),
    "speed_mps": (LIFT_SPEED_RANGE_MPS, "a passenger lift's speed"),
    "acceleration_mps2": (LIFT_ACCELERATION_RANGE_MPS2, "a passenger lift's acceleration"),
    "jerk_mps3": (LIFT_JERK_RANGE_MPS3, "a passenger lift's jerk"),
    "floor_height_m": (FLOOR_HEIGHT_RANGE_M, "a floor's height"),
    "height_m": (LIFT_RISE_RANGE_M, "a lift ride's rise"),
}


def _in_range(value: float, bounds: tuple[float, float], where: str, what: str) -> float:
    if not bounds[0] <= value <= bounds[1]:
        raise InputError(where, f"{value:.3g} is beyond {what} ({bounds[0]:g}-{bounds[1]:g})")
    return value


def _segment(data: Any, where: str) -> PocketSegment:
    values = check_keys(data, PocketSegment, where, required=("type",))
    kind = values.pop("type")
    if kind not in _NEEDS:
        raise InputError(f"{where}.type", f"unknown segment type '{kind}' "
                                          f"(known: {', '.join(SEGMENT_TYPES)}, repeat)")
    for key in values:
        if key not in _ALLOWED[kind]:
            raise InputError(f"{where}.{key}", f"not a key of a '{kind}' segment (keys: "
                                               f"{', '.join(sorted(_ALLOWED[kind]))})")
    for key in _NEEDS[kind]:
        if key not in values:
            raise InputError(f"{where}.{key}", f"required for a '{kind}' segment")
    out: dict[str, Any] = {"type": kind}
    for key, value in values.items():
        at = f"{where}.{key}"
        if key in _INTEGERS:
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise InputError(at, f"must be a positive integer, got {value!r}")
            out[key] = value
        elif key == "direction":
            if value not in ("up", "down"):
                raise InputError(at, f"must be up or down, got {value!r}")
            out[key] = value
        elif key in ("angle_deg", "landing_turn_deg"):
            out[key] = number(value, at)
        else:
            out[key] = number(value, at, 0.0, strict=True)
    if kind == "walk" and ("distance_m" in out) == ("steps" in out):
        raise InputError(f"{where}.distance_m", "give either distance_m or steps")
    if kind == "lift" and "floors" not in out and "height_m" not in out:
        raise InputError(f"{where}.floors", "give floors or height_m")
    for key, (bounds, what) in _RANGES.items():
        if key in out:
            _in_range(out[key], bounds, f"{where}.{key}", what)
    if kind == "lift" and "floors" not in out:
        out["floors"] = round(out["height_m"] / out.get("floor_height_m", FLOOR_HEIGHT_M))
    if kind == "turn" and "duration_s" in out and "steps" in out:
        raise InputError(f"{where}.duration_s", "a turn is walked (steps) or in place "
                                                "(duration_s), not both")
    if kind == "turn" and "duration_s" not in out:
        steps = out.get("steps", 2)
        per_step = abs(out["angle_deg"]) / steps
        if per_step > MAX_TURN_PER_STEP_DEG:
            raise InputError(f"{where}.angle_deg",
                             f"{out['angle_deg']:g}° in {steps} step(s) is {per_step:g}° per "
                             f"step, sharper than a step allows ({MAX_TURN_PER_STEP_DEG:g}°)")
    if kind == "stairs" and out.get("landing_steps", 2) > 0:
        per_step = abs(out.get("landing_turn_deg", 180.0)) / out.get("landing_steps", 2)
        if per_step > MAX_TURN_PER_STEP_DEG:
            raise InputError(f"{where}.landing_turn_deg",
                             f"{per_step:g}° per landing step is sharper than a step allows "
                             f"({MAX_TURN_PER_STEP_DEG:g}°)")
    return PocketSegment(**out)


SWING_SHARES = ("pitch_min_fraction", "faster_swing_back_fraction")   # of Δθ, in [0, 1]


def _person(data: Any, where: str) -> PersonSpec:
    values = check_keys(data, PersonSpec, where)
    out: dict[str, Any] = {}
    for key, value in values.items():
        at = f"{where}.{key}"
        if key == "leg":
            if value not in ("left", "right"):
                raise InputError(at, f"must be left or right, got {value!r}")
            out[key] = value
        elif key == "centre_scatter":
            if not isinstance(value, bool):
                raise InputError(at, f"must be true or false, got {value!r}")
            out[key] = value
        elif key == "lever_arm_m":
            out[key] = vector(value, at)
        elif key in ("b_h_m", "b_u_cm", "b_d_cm", "cadence_hz_at_rest"):
            out[key] = number(value, at)
        elif key in ("a_h_m_per_deg", "a_u_cm_per_deg", "a_d_cm_per_deg", "stair_cadence_hz"):
            out[key] = number(value, at, 0.0, strict=True)
        elif key in SWING_SHARES:
            out[key] = number(value, at, 0.0)
            if out[key] > 1.0:
                raise InputError(at, f"a share of the swing, at most 1, got {value}")
        else:
            out[key] = number(value, at, 0.0)
    return PersonSpec(**out)


def _mounting(value: Any, where: str) -> Any:
    if isinstance(value, str):
        if value not in MOUNTINGS:
            raise InputError(where, f"unknown mounting '{value}' (known: {', '.join(MOUNTINGS)},"
                                    " or {rpy_deg: [roll, pitch, yaw]})")
        return value
    if not isinstance(value, dict) or set(value) != {"rpy_deg"}:
        raise InputError(where, f"a mounting name or {{rpy_deg: [r, p, y]}}, got {value!r}")
    return {"rpy_deg": list(vector(value["rpy_deg"], f"{where}.rpy_deg"))}


def _remounts(value: Any, where: str) -> tuple[Remount, ...]:
    """Remounts in time order, none overlapping the one before."""
    if not isinstance(value, list):
        raise InputError(where, f"expected a list of {{at_s, mounting, duration_s}}, got {value!r}")
    out, free_from = [], 0.0
    for i, item in enumerate(value):
        at = f"{where}[{i}]"
        values = check_keys(item, Remount, at, required=("at_s", "mounting"))
        remount = Remount(at_s=number(values["at_s"], f"{at}.at_s", 0.0),
                          mounting=_mounting(values["mounting"], f"{at}.mounting"),
                          duration_s=number(values.get("duration_s", 1.0), f"{at}.duration_s",
                                            0.0, strict=True))
        if remount.at_s < free_from:
            raise InputError(f"{at}.at_s", f"{remount.at_s:g} s starts before the remount "
                                           f"before it has ended ({free_from:g} s)")
        free_from = remount.at_s + remount.duration_s
        out.append(remount)
    return tuple(out)


def pocket_scenario_from_dict(data: Any, where: str) -> PocketScenario:
    """Validate a pocket scenario mapping; InputError names the key as WHERE: key.path."""
    values = check_keys(data, PocketScenario, f"{where}:", required=("segments",))
    if values.get("placement", "pocket") != "pocket":
        raise InputError(f"{where}: placement", f"a pocket scenario, got {values['placement']!r}")
    carried = values.get("carried", "front_pocket")
    if carried not in CARRIED:
        raise InputError(f"{where}: carried", f"one of {', '.join(CARRIED)}, got {carried!r}")
    segments = flattened_segments(values["segments"], f"{where}: segments")
    initial = check_keys(values.get("initial", {}), InitialPlacement, f"{where}: initial")
    placement = InitialPlacement(
        position_m=vector(initial.get("position_m", [0, 0, 0]), f"{where}: initial.position_m"),
        yaw_deg=number(initial.get("yaw_deg", 0.0), f"{where}: initial.yaw_deg"))
    scenario = PocketScenario(
        name=str(values.get("name", where)),
        segments=tuple(_segment(s, at) for s, at in segments),
        person=_person(values.get("person", {}), f"{where}: person"),
        mounting=_mounting(values.get("mounting", CARRIED[carried].mounting),
                           f"{where}: mounting"),
        carried=carried,
        remounts=_remounts(values.get("remounts", []), f"{where}: remounts"),
        seed=seed_from(values.get("seed", 0), f"{where}: seed"),
        initial=placement,
        environment=environment_from(values.get("environment", {}), f"{where}: environment"))
    _check_gait(scenario, where)
    return scenario


def load_pocket_scenario(name_or_path: str) -> tuple[PocketScenario, dict]:
    """A built-in pocket scenario by name, or a YAML file; returns it and its raw mapping."""
    data, where = read_scenario_yaml(name_or_path, POCKET_BUILTIN, "scenarios/pocket")
    return pocket_scenario_from_dict(data, where), data
