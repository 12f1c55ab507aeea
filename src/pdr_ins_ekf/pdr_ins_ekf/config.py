"""Configuration of the foot navigator, one YAML file (typed dataclasses, units in names).

    detector:                       # one of the detectors of pdr_ins_ekf.zero_velocity
      type: retarded                # original | limited | retarded | shoe |
                                    # moving_variance | magnitude | angular_rate_energy
      <its parameters>              # e.g. w1: 15 (see the detector's class)
    filter:                         # pdr_ins_ekf.zupt_ekf.FilterConfig fields
      acc_noise: 0.002
    smoother:                       # pdr_ins_ekf.zupt_ekf.SmootherConfig fields
      mode: none                    # none | segmented | full
    alignment_min_s: 0.5            # shortest stationary period to align on [s]
    initial_yaw_deg: 0.0            # heading is unobservable: the start heading
    max_gap_s: 0.1                  # longer gaps between samples are warned about

Unknown keys are refused with their path; defaults are those of the dataclasses.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import yaml

from pdr_core.errors import InputError
from pdr_ins_ekf.zero_velocity import (
    AdaptiveShoeDetector,
    AngularRateEnergyDetector,
    MagnitudeDetector,
    MovingVarianceDetector,
    Paper000Detector,
    ShoeDetector,
    StanceDetector,
)
from pdr_ins_ekf.zupt_ekf import FilterConfig, SmootherConfig

DETECTORS = {"original": Paper000Detector, "limited": Paper000Detector,
             "retarded": Paper000Detector, "shoe": ShoeDetector,
             "adaptive_shoe": AdaptiveShoeDetector,
             "moving_variance": MovingVarianceDetector, "magnitude": MagnitudeDetector,
             "angular_rate_energy": AngularRateEnergyDetector}


@dataclass(frozen=True)
class RunConfig:
    detector: StanceDetector = field(default_factory=lambda: Paper000Detector(variant="retarded"))
    filter: FilterConfig = field(default_factory=FilterConfig)
    smoother: SmootherConfig = field(default_factory=SmootherConfig)
    alignment_min_s: float = 0.5
    initial_yaw_deg: float = 0.0
    max_gap_s: float = 0.1


def _typed(value: Any, kind: str, where: str) -> Any:
    """``value`` as the field's type; numbers written like 1.0e6, which YAML 1.1 reads
    as strings, are accepted."""
    if kind in ("float", "int"):
        if isinstance(value, str):
            try:
                value = float(value)
            except ValueError:
                raise InputError(where, f"expected a number, got {value!r}") from None
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise InputError(where, f"expected a number, got {value!r}")
        if kind == "int":
            if value != int(value):
                raise InputError(where, f"expected an integer, got {value!r}")
            return int(value)
        return float(value)
    if kind == "bool" and not isinstance(value, bool):
        raise InputError(where, f"expected true or false, got {value!r}")
    if kind == "str" and not isinstance(value, str):
        raise InputError(where, f"expected a string, got {value!r}")
    return value


def _build(cls: type, values: dict, where: str) -> Any:
    kinds = {f.name: str(f.type) for f in fields(cls)}
    for key in values:
        if key not in kinds:
            raise InputError(f"{where}.{key}", f"unknown key (known: {', '.join(sorted(kinds))})")
    typed = {k: _typed(v, kinds[k], f"{where}.{k}") for k, v in values.items()}
    try:
        return cls(**typed)
    except (TypeError, ValueError) as exc:
        raise InputError(where, str(exc)) from exc


def run_config(data: dict | None, where: str = "config") -> RunConfig:
    """A RunConfig from a mapping; InputError names bad keys."""
    data = dict(data or {})
    top = {f.name for f in fields(RunConfig)}
    for key in data:
        if key not in top:
            raise InputError(f"{where}.{key}", f"unknown key (known: {', '.join(sorted(top))})")
    out: dict[str, Any] = {k: _typed(v, "float", f"{where}.{k}") for k, v in data.items()
                           if k in ("alignment_min_s", "initial_yaw_deg", "max_gap_s")}
    if "detector" in data:
        detector = dict(data["detector"] or {})
        kind = detector.pop("type", "retarded")
        if kind not in DETECTORS:
            raise InputError(f"{where}.detector.type", f"unknown detector '{kind}' "
                                                       f"(known: {', '.join(DETECTORS)})")
        if DETECTORS[kind] is Paper000Detector:
            detector["variant"] = kind
        out["detector"] = _build(DETECTORS[kind], detector, f"{where}.detector")
    if "filter" in data:
        out["filter"] = _build(FilterConfig, dict(data["filter"] or {}), f"{where}.filter")
    if "smoother" in data:
        out["smoother"] = _build(SmootherConfig, dict(data["smoother"] or {}),
                                 f"{where}.smoother")
    return RunConfig(**out)


def default_config_path() -> Path:
    """The installed ``config/foot_ekf.yaml``: the documented default of the node and the
    CLI (the dataclass defaults are plain, paper-like values for simulated data)."""
    from ament_index_python.packages import get_package_share_directory

    return Path(get_package_share_directory("pdr_ins_ekf")) / "config" / "foot_ekf.yaml"


def load_run_config(path: str | Path | None) -> RunConfig:
    """The configuration of a YAML file, or of :func:`default_config_path`."""
    path = Path(path) if path else default_config_path()
    if not path.is_file():
        raise InputError(path, "no such configuration file")
    try:
        return run_config(yaml.safe_load(path.read_text()), str(path))
    except yaml.YAMLError as exc:
        raise InputError(path, f"invalid YAML ({exc})") from exc
