"""Walking scenarios: segments of standing, straight walking, curves and turns in place.

A scenario is a YAML mapping (see ``pdr_sim/scenarios/*.yaml`` for the built-in ones):

    name: square_loop
    step:                    # defaults for every stride (Zampella et al. 2011, Fig. 4)
      length_m: 1.3          # SL, stride length
      height_m: 0.14         # SH
      swing_s: 0.8           # t_u
      stance_s: 0.4          # t_0
      pitch_max_rad: 0.55    # θ_max
    variation:               # per-stride standard deviations, drawn with ``seed``
      length_m: 0.05
    seed: 1
    initial: {position_m: [0, 0, 0], roll_deg: 0, pitch_deg: 0, yaw_deg: 0}
    pattern: basic           # or fitted, with fitted_pattern: FILE.yaml (pdr-sim fit-steps),
                             # a path relative to the scenario file
    timing: smooth           # or: linear, the paper's exact Eqs. (1)-(2) (see step_pattern)
    environment:
      latitude_deg: 48.15    # adds Earth rotation to the gyroscope (omit: none)
      magnetic_field:
        preset: munich       # north_pole | equator | munich, or vector_ut: [e, n, u]
        cylinders: [{east_m: 3, north_m: 1, radius_m: 0.3, permeability: 200}]
        distortion: table_3_3   # or {xi: .., offset: [..], M: [[..], [..], [..]]}
        indoor: {azimuth_sigma_deg: 7, norm_sigma_ut: 2.4, dip_sigma_deg: 3.5,
                 correlation_length_m: 1.6, seed: 0}   # a building's own disturbance
    segments:
      - {type: standing, duration_s: 2}
      - {type: straight, steps: 5}
      - {type: curve, steps: 4, radius_m: 3, direction: left}
      - {type: turn, angle_deg: 90, duration_s: 1.5}     # in place; positive = left
      - {type: stairs, direction: up, steps: 8, gait: {riser_m: 0.18}}
      - {type: run, steps: 20}
      - {type: repeat, times: 3, segments: [{type: straight, steps: 4},
                                            {type: turn, angle_deg: 90, duration_s: 1.2}]}

Gait segments (:mod:`pdr_sim.foot_gaits`, a stance that is not a still foot): ``walk``,
``run``, ``stairs`` (direction up or down), ``in_place``, ``side_steps`` (direction left
or right), ``back_steps`` and ``crawl``, each with ``steps`` (strides) and an optional
``gait:`` mapping over the gait's defaults (the keys of ``GaitSpec``); they take no
``step:`` and no per-stride ``variation`` beyond their own stride-time scatter.

``indoor`` adds a building's own field to the Earth's, spatially correlated
(:class:`pdr_core.sensors.magnetic_field.IndoorDisturbance`, whose defaults, from the room of the
OxIOD recordings, are the values above; ``indoor: {}`` takes them all, ``seed`` picks
another building).

A segment may carry its own ``step:`` mapping, overriding the defaults. Every key is
checked: unknown keys, negative durations and impossible steps are refused with the key
named; nothing is silently defaulted beyond the documented defaults above.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from importlib import resources
from pathlib import Path
from typing import Any

from pdr_core.config_files import check_keys, parse_yaml
from pdr_core.errors import InputError
from pdr_core.sensors.magnetic_field import Cylinder, IndoorDisturbance
from pdr_sim.foot_gaits import GAIT_TYPES, GaitSpec, gait_defaults, gait_keys, with_overrides
from pdr_sim.step_pattern import TIMINGS

GAIT_SCENARIOS = ("stairs_up_down", "stairs_slow", "running", "stepping_in_place",
                  "side_and_back_steps", "crawling", "level_walk_matched")
BUILTIN = ("straight", "square_loop", "figure_eight", "long_mixed_walk", "block_laps",
           *GAIT_SCENARIOS)
SEGMENT_TYPES = ("standing", "straight", "curve", "turn", *GAIT_TYPES)
DIRECTIONS = {"curve": ("left", "right"), "side_steps": ("left", "right"),
              "stairs": ("up", "down")}


@dataclass(frozen=True)
class StepSpec:
    """Stride parameters (Zampella et al. 2011, Eqs. (1)–(2)); defaults of its Fig. 4."""

    length_m: float = 1.3
    height_m: float = 0.14
    swing_s: float = 0.8
    stance_s: float = 0.4
    pitch_max_rad: float = 0.55


@dataclass(frozen=True)
class InitialPose:
    position_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    roll_deg: float = 0.0
    pitch_deg: float = 0.0
    yaw_deg: float = 0.0


@dataclass(frozen=True)
class MagneticFieldSpec:
    preset: str | None = "munich"
    vector_ut: tuple[float, float, float] | None = None
    cylinders: tuple[Cylinder, ...] = ()
    distortion: Any = None
    indoor: IndoorDisturbance | None = None


@dataclass(frozen=True)
class Environment:
    latitude_deg: float | None = None
    magnetic_field: MagneticFieldSpec = field(default_factory=MagneticFieldSpec)


@dataclass(frozen=True)
class Segment:
    type: str
    steps: int = 0
    duration_s: float = 0.0
    radius_m: float = 0.0
    direction: str = "left"
    angle_deg: float = 0.0
    step: StepSpec | None = None
    gait: GaitSpec | None = None


@dataclass(frozen=True)
class Scenario:
    name: str
    segments: tuple[Segment, ...]
    step: StepSpec = field(default_factory=StepSpec)
    variation: StepSpec = field(default_factory=lambda: StepSpec(0.0, 0.0, 0.0, 0.0, 0.0))
    seed: int = 0
    initial: InitialPose = field(default_factory=InitialPose)
    pattern: str = "basic"
    fitted_pattern: str | None = None
    timing: str = "smooth"
    environment: Environment = field(default_factory=Environment)


def number(value: Any, where: str, minimum: float | None = None, strict: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(where, f"expected a number, got {value!r}")
    if minimum is not None and (value <= minimum if strict else value < minimum):
        raise InputError(where, f"must be {'>' if strict else '>='} {minimum}, got {value}")
    return float(value)


def vector(value: Any, where: str) -> tuple[float, float, float]:
    if not isinstance(value, list | tuple) or len(value) != 3:
        raise InputError(where, f"expected a list of 3 numbers, got {value!r}")
    return tuple(number(v, where) for v in value)


def _step(data: Any, where: str, base: StepSpec, variation: bool = False) -> StepSpec:
    values = check_keys(data, StepSpec, where)
    positive = () if variation else ("length_m", "swing_s")
    out = {}
    for key, value in values.items():
        strict = key in positive
        out[key] = number(value, f"{where}.{key}", minimum=0.0, strict=strict)
    return replace(base, **out)


def _gait(data: Any, where: str, kind: str, direction: str) -> GaitSpec:
    """A gait segment's stride: its defaults (pdr_sim.foot_gaits.GAITS) with the keys of
    its ``gait:`` mapping, each checked."""
    allowed = gait_keys(kind)
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise InputError(where, f"expected a mapping, got {data!r}")
    values = {}
    for key, value in data.items():
        if key not in allowed:
            raise InputError(f"{where}.{key}", f"not a key of a '{kind}' gait "
                                               f"(keys: {', '.join(allowed)})")
        signed = key.endswith("_deg")
        strict = key in ("cycle_s", "stance_fraction", "loading_s", "impact_hz", "impact_s",
                         "tread_m")
        values[key] = number(value, f"{where}.{key}", None if signed else 0.0, strict=strict)
    spec = with_overrides(gait_defaults(kind, direction), values)
    stance = spec.stance_fraction * spec.cycle_s
    checks = (("stance_fraction", spec.stance_fraction < 1, "must be < 1"),
              ("loading_s", spec.loading_s + spec.flat_s < stance,
               f"with flat_s must be shorter than the stance ({stance:g} s)"),
              ("impact_s", spec.impact_s < stance, f"must be shorter than the stance "
                                                   f"({stance:g} s)"),
              ("settle_s", spec.settle_s > 0 or spec.stance_pitch_deg == 0,
               "must be > 0 with a stance_pitch_deg other than 0"),
              ("cycle_variation", spec.cycle_variation < 0.2 * (1 - spec.stance_fraction),
               "must be < 0.2 of the swing's share of the cycle"))
    for key, ok, message in checks:
        if not ok:
            raise InputError(f"{where}.{key}", message)
    return spec


def _segment(data: Any, where: str, step: StepSpec) -> Segment:
    values = check_keys(data, Segment, where, required=("type",))
    kind = values["type"]
    needs = {"standing": ("duration_s",), "straight": ("steps",),
             "curve": ("steps", "radius_m", "direction"), "turn": ("angle_deg", "duration_s"),
             **{gait: ("steps",) for gait in GAIT_TYPES},
             "stairs": ("steps", "direction"), "side_steps": ("steps", "direction")}
    if kind not in needs:
        raise InputError(f"{where}.type", f"unknown segment type '{kind}' "
                                          f"(known: {', '.join(SEGMENT_TYPES)}, repeat)")
    optional = ("gait",) if kind in GAIT_TYPES else ("step",)
    allowed = {"type", *optional, *needs[kind]}
    for key in values:
        if key not in allowed:
            raise InputError(f"{where}.{key}", f"not a key of a '{kind}' segment "
                                               f"(keys: {', '.join(sorted(allowed))})")
    for key in needs[kind]:
        if key not in values:
            raise InputError(f"{where}.{key}", f"required for a '{kind}' segment")
    out: dict[str, Any] = {"type": kind}
    if "steps" in values:
        steps = values["steps"]
        if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
            raise InputError(f"{where}.steps", f"must be a positive integer, got {steps!r}")
        out["steps"] = steps
    if "duration_s" in values:
        out["duration_s"] = number(values["duration_s"], f"{where}.duration_s", 0.0, strict=True)
    if "radius_m" in values:
        out["radius_m"] = number(values["radius_m"], f"{where}.radius_m", 0.0, strict=True)
    if "direction" in values:
        if values["direction"] not in DIRECTIONS[kind]:
            raise InputError(f"{where}.direction", f"must be {' or '.join(DIRECTIONS[kind])}, "
                                                   f"got {values['direction']!r}")
        out["direction"] = values["direction"]
    if "angle_deg" in values:
        out["angle_deg"] = number(values["angle_deg"], f"{where}.angle_deg")
    if "step" in values:
        out["step"] = _step(values["step"], f"{where}.step", step)
    if kind in GAIT_TYPES:
        out["gait"] = _gait(values.get("gait"), f"{where}.gait", kind,
                            out.get("direction", ""))
    return Segment(**out)


def _magnetic_field(data: Any, where: str) -> MagneticFieldSpec:
    values = check_keys(data, MagneticFieldSpec, where)
    out: dict[str, Any] = {}
    if "vector_ut" in values:
        out["vector_ut"] = vector(values["vector_ut"], f"{where}.vector_ut")
        out["preset"] = None
    if "preset" in values:
        if "vector_ut" in values:
            raise InputError(f"{where}.preset", "give either preset or vector_ut, not both")
        out["preset"] = values["preset"]
    cylinders = []
    for i, cyl in enumerate(values.get("cylinders") or []):
        c = check_keys(cyl, Cylinder, f"{where}.cylinders[{i}]",
                        required=("east_m", "north_m", "radius_m"))
        cylinders.append(Cylinder(
            number(c["east_m"], f"{where}.cylinders[{i}].east_m"),
            number(c["north_m"], f"{where}.cylinders[{i}].north_m"),
            number(c["radius_m"], f"{where}.cylinders[{i}].radius_m", 0.0, strict=True),
            number(c.get("permeability", 200.0), f"{where}.cylinders[{i}].permeability", 1.0)))
    out["cylinders"] = tuple(cylinders)
    if "distortion" in values:
        out["distortion"] = values["distortion"]
    if values.get("indoor") is not None:
        out["indoor"] = _indoor(values["indoor"], f"{where}.indoor")
    return MagneticFieldSpec(**out)


def _indoor(data: Any, where: str) -> IndoorDisturbance:
    """An ``indoor:`` mapping: the keys of IndoorDisturbance, each checked."""
    values = check_keys(data, IndoorDisturbance, where)
    out: dict[str, Any] = {}
    for key, value in values.items():
        at = f"{where}.{key}"
        if key == "seed":
            out[key] = seed_from(value, at)
        elif key.endswith("_deg"):
            out[key] = number(value, at, 0.0)
            if out[key] >= 45.0:
                raise InputError(at, f"must be below 45 degrees, got {value}")
        else:
            out[key] = number(value, at, 0.0, strict=key == "correlation_length_m")
    return IndoorDisturbance(**out)


def environment_from(data: Any, where: str) -> Environment:
    """The ``environment:`` mapping of a scenario (any placement)."""
    env = check_keys(data, Environment, where)
    return Environment(
        latitude_deg=(number(env["latitude_deg"], f"{where}.latitude_deg")
                      if env.get("latitude_deg") is not None else None),
        magnetic_field=_magnetic_field(env.get("magnetic_field", {}), f"{where}.magnetic_field"))


def seed_from(value: Any, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise InputError(where, f"must be a non-negative integer, got {value!r}")
    return value


def flattened_segments(segments: Any, where: str) -> list[tuple[Any, str]]:
    """The segments with every ``repeat`` expanded in place, each with the name errors
    should cite: ``{type: repeat, times: N, segments: [...]}`` walks its segments N times
    (a lap of a block, say), and may hold repeats itself."""
    if not isinstance(segments, list) or not segments:
        raise InputError(where, "expected a non-empty list")
    out = []
    for i, item in enumerate(segments):
        at = f"{where}[{i}]"
        if not (isinstance(item, dict) and item.get("type") == "repeat"):
            out.append((item, at))
            continue
        unknown = sorted(set(item) - {"type", "times", "segments"})
        if unknown:
            raise InputError(f"{at}.{unknown[0]}", "not a key of a 'repeat' segment (keys: "
                                                   "segments, times, type)")
        times = item.get("times")
        if isinstance(times, bool) or not isinstance(times, int) or times < 1:
            raise InputError(f"{at}.times", f"must be a positive integer, got {times!r}")
        out += flattened_segments(item.get("segments"), f"{at}.segments") * times
    return out


def scenario_from_dict(data: Any, where: str) -> Scenario:
    """Validate a scenario mapping; InputError names the offending key as WHERE: key.path."""
    values = check_keys(data, Scenario, f"{where}:", required=("segments",))
    step = _step(values.get("step", {}), f"{where}: step", StepSpec())
    variation = _step(values.get("variation", {}), f"{where}: variation",
                      StepSpec(0.0, 0.0, 0.0, 0.0, 0.0), variation=True)
    segments = flattened_segments(values["segments"], f"{where}: segments")
    initial = check_keys(values.get("initial", {}), InitialPose, f"{where}: initial")
    pose = InitialPose(
        position_m=vector(initial.get("position_m", [0, 0, 0]), f"{where}: initial.position_m"),
        **{k: number(initial[k], f"{where}: initial.{k}") for k in
           ("roll_deg", "pitch_deg", "yaw_deg") if k in initial})
    pattern = values.get("pattern", "basic")
    if pattern not in ("basic", "fitted"):
        raise InputError(f"{where}: pattern", f"must be basic or fitted, got {pattern!r}")
    if pattern == "fitted" and not values.get("fitted_pattern"):
        raise InputError(f"{where}: fitted_pattern", "required with pattern: fitted")
    timing = values.get("timing", "smooth")
    if timing not in TIMINGS:
        raise InputError(f"{where}: timing", f"must be one of {', '.join(TIMINGS)}, got {timing!r}")
    environment = environment_from(values.get("environment", {}), f"{where}: environment")
    seed = seed_from(values.get("seed", 0), f"{where}: seed")
    return Scenario(
        name=str(values.get("name", where)),
        segments=tuple(_segment(s, at, step) for s, at in segments),
        step=step, variation=variation, seed=seed, initial=pose, pattern=pattern,
        fitted_pattern=values.get("fitted_pattern"), timing=timing, environment=environment)


def read_scenario_yaml(name_or_path: str, builtin: tuple[str, ...],
                       folder: str) -> tuple[Any, str]:
    """The raw mapping of a built-in scenario (``pdr_sim/<folder>/<name>.yaml``) or of a YAML
    file, and the name errors should cite."""
    if name_or_path in builtin:
        text = resources.files("pdr_sim").joinpath(f"{folder}/{name_or_path}.yaml").read_text()
        where = name_or_path
    else:
        path = Path(name_or_path)
        if not path.is_file():
            raise InputError(path, f"no such scenario file (built-in: {', '.join(builtin)})")
        text, where = path.read_text(), str(path)
    return parse_yaml(text, where), where


def load_scenario(name_or_path: str) -> tuple[Scenario, dict]:
    """A built-in scenario by name, or a YAML file; returns it and its raw mapping."""
    data, where = read_scenario_yaml(name_or_path, BUILTIN, "scenarios")
    scenario = scenario_from_dict(data, where)
    if scenario.fitted_pattern and name_or_path not in BUILTIN:
        resolved = Path(name_or_path).parent / scenario.fitted_pattern
        scenario = replace(scenario, fitted_pattern=str(resolved))
    return scenario, data
