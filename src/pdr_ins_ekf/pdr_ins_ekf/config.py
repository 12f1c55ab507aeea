"""Configuration of the foot navigator, one YAML file (typed dataclasses, units in names).

    detector:                       # one of the detectors of pdr_ins_ekf.zero_velocity
      type: retarded                # original | limited | retarded | shoe |
                                    # moving_variance | magnitude | angular_rate_energy
      <its parameters>              # e.g. w1_samples: 15 (see the detector's class)
    filter:                         # pdr_ins_ekf.zupt_ekf.FilterConfig fields
      acc_noise_mps2_per_sqrt_hz: 0.02
    smoother:                       # pdr_ins_ekf.zupt_ekf.SmootherConfig fields
      mode: none                    # none | segmented | full
    alignment_min_s: 0.3            # shortest stationary period to align on [s]
    initial_yaw_deg: 0.0            # heading is unobservable: the start heading
    max_gap_s: 0.1                  # longer gaps between samples are warned about
    base: other.yaml                # optional: read that file first, override its keys

Unknown keys are refused with their path (a key renamed to carry its unit, with its new
name: :data:`RENAMED_KEYS`); a key not given keeps RunConfig's default, the shipped
``foot_ekf.yaml``'s (tested, test/test_config_defaults.py). That file is the default of
the node and the CLI; ``foot_ekf_<profile>.yaml`` adapt it to the IMU profiles
of :mod:`pdr_core.sensors.imu_profiles` (``--imu-profile``).
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from pdr_core.config_files import (
    check_keys,
    dataclass_from_mapping,
    key_path,
    read_config_file,
    shipped_config_dir,
    typed_value,
)
from pdr_core.errors import InputError
from pdr_ins_ekf.zero_velocity import (
    AdaptiveShoeDetector,
    AngularRateEnergyDetector,
    ConditionVoteDetector,
    MagnitudeDetector,
    MovingVarianceDetector,
    ShoeDetector,
    StanceDetector,
)
from pdr_ins_ekf.zupt_ekf import FilterConfig, SmootherConfig

DETECTORS = {"original": ConditionVoteDetector, "limited": ConditionVoteDetector,
             "retarded": ConditionVoteDetector, "shoe": ShoeDetector,
             "adaptive_shoe": AdaptiveShoeDetector,
             "moving_variance": MovingVarianceDetector, "magnitude": MagnitudeDetector,
             "angular_rate_energy": AngularRateEnergyDetector}

# keys renamed to carry their unit: an old key is refused, naming its new name
RENAMED_KEYS = {
    "acc_noise": "acc_noise_mps2_per_sqrt_hz", "gyro_noise": "gyro_noise_radps_per_sqrt_hz",
    "acc_bias_noise": "acc_bias_noise_mps2_per_sqrt_s",
    "gyro_bias_noise": "gyro_bias_noise_radps_per_sqrt_s",
    "init_acc_bias_sigma": "init_acc_bias_sigma_mps2",
    "init_gyro_bias_sigma": "init_gyro_bias_sigma_radps",
    "window": "window_samples", "w1": "w1_samples", "w2": "w2_samples"}


@dataclass(frozen=True)
class RunConfig:
    """The navigator as the shipped ``foot_ekf.yaml`` sets it (tested): adaptive SHOE, the
    filter's and smoother's noise tuned for real shoes, and the published covariance
    scaled by the touchdown innovations (FilterConfig's and SmootherConfig's own defaults
    are plain, paper-like values for simulated data, the filter's own covariance)."""

    detector: StanceDetector = field(default_factory=AdaptiveShoeDetector)
    filter: FilterConfig = field(
        default_factory=lambda: FilterConfig(acc_noise_mps2_per_sqrt_hz=0.02,
                                             gyro_noise_radps_per_sqrt_hz=0.002,
                                             covariance_scale="innovations"))
    smoother: SmootherConfig = field(
        default_factory=lambda: SmootherConfig(gamma_s_m2ps2=3.0e-4))
    alignment_min_s: float = 0.3
    initial_yaw_deg: float = 0.0
    max_gap_s: float = 0.1


def _section(cls: type, data: Any, where: str, defaults: Any = None) -> Any:
    """``dataclass_from_mapping`` of one section, an old key refused with its new name."""
    section = dict(data or {})
    known = {f.name for f in fields(cls)}
    for key in section:
        if RENAMED_KEYS.get(key) in known:
            raise InputError(key_path(where, key), f"unknown key (renamed to "
                                                   f"{RENAMED_KEYS[key]})")
    return dataclass_from_mapping(cls, section, where, defaults)


def run_config(data: dict | None, where: str = "config") -> RunConfig:
    """A RunConfig from a mapping; InputError names bad keys."""
    data = check_keys(data or {}, RunConfig, where)
    out: dict[str, Any] = {k: typed_value(v, "float", f"{where}.{k}") for k, v in data.items()
                           if k in ("alignment_min_s", "initial_yaw_deg", "max_gap_s")}
    if "detector" in data:
        detector = dict(data["detector"] or {})
        kind = detector.pop("type", "adaptive_shoe")
        if kind not in DETECTORS:
            raise InputError(f"{where}.detector.type", f"unknown detector '{kind}' "
                                                       f"(known: {', '.join(DETECTORS)})")
        if DETECTORS[kind] is ConditionVoteDetector:
            detector["variant"] = kind
        out["detector"] = _section(DETECTORS[kind], detector, f"{where}.detector")
    defaults = RunConfig()
    if "filter" in data:
        out["filter"] = _section(FilterConfig, data["filter"], f"{where}.filter",
                                 defaults.filter)
    if "smoother" in data:
        out["smoother"] = _section(SmootherConfig, data["smoother"], f"{where}.smoother",
                                   defaults.smoother)
    return RunConfig(**out)


def default_config_path() -> Path:
    """The installed ``config/foot_ekf.yaml``: the documented default of the node and the
    CLI."""
    return shipped_config_dir("pdr_ins_ekf") / "foot_ekf.yaml"


def imu_profiles() -> list[str]:
    """The IMU profiles with a shipped configuration ``config/foot_ekf_<profile>.yaml``."""
    return sorted(p.stem.removeprefix("foot_ekf_")
                  for p in shipped_config_dir("pdr_ins_ekf").glob("foot_ekf_*.yaml"))


def profile_config_path(profile: str) -> Path:
    """The shipped configuration for an IMU profile of :mod:`pdr_core.sensors.imu_profiles`."""
    known = imu_profiles()
    if profile not in known:
        raise InputError("imu_profile", f"no configuration for '{profile}' (known: "
                                        f"{', '.join(known)})")
    return shipped_config_dir("pdr_ins_ekf") / f"foot_ekf_{profile}.yaml"


def load_run_config(path: str | Path | None = None, imu_profile: str | None = None
                    ) -> RunConfig:
    """The configuration of a YAML file, of an IMU profile (:func:`profile_config_path`),
    or of :func:`default_config_path`."""
    if path and imu_profile:
        raise InputError("config", "give a configuration file or an IMU profile, not both")
    if imu_profile:
        path = profile_config_path(imu_profile)
    path = Path(path) if path else default_config_path()
    return run_config(read_config_file(path), str(path))
