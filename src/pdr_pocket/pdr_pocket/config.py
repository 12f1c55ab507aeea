"""Configuration of the pocket navigator: typed dataclasses from YAML, units in the names.

    orientation:                        # OrientationConfig: the filter of chapter 3
      gyro_arw_deg_per_sqrt_h: 0.6      # σ_ν, the gyroscope's white noise
      bias_instability_deg_per_h: 10.0  # β, the Allan deviation's minimum ...
      bias_instability_time_s: 200.0    # ... at t_β (AR(1): Eqs. (3.10)-(3.11))
      updates: {absolute_gravity: true, differential_magnetic: true, zaru: true}
      ...
    base: other.yaml                    # optional: read that file first

Every key is checked and named when wrong (pdr_core.config_files); the dataclass defaults
are the shipped ``config/pocket_pdr.yaml`` (tested). The orientation section is
pdr_pocket.orientation_config's.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from pdr_core.config_files import (
    check_keys,
    check_positive,
    dataclass_from_mapping,
    read_config_file,
    shipped_config_dir,
)
from pdr_core.vocabulary import FLOOR_HEIGHT_M
from pdr_core.walking.stair_geometry import (
    FLIGHT_MAX_RISERS,
    FLIGHT_MIN_RISERS,
    RISER_MAX_M,
    RISER_MIN_M,
)
from pdr_pocket.orientation_config import OrientationConfig, orientation_config
from pdr_pocket.step_length import StepLengthConfig


@dataclass(frozen=True)
class MountingConfig:
    """The thigh's frame in the sensor's (pdr_pocket.compiled_mounting). ``rpy_deg`` set: the
    phone's mounting C_s^t is known (ZYX roll, pitch, yaw of the sensor in the thigh frame
    x forward, y left, z up) and nothing is estimated."""

    rpy_deg: tuple[float, float, float] | None = None
    rest_rate_deg_per_s: float = 6.0
    rest_acc_mps2: float = 0.4
    rest_min_s: float = 1.0
    standing_max_angle_deg: float = 25.0
    moved_min_angle_deg: float = 30.0
    moving_rate_deg_per_s: float = 30.0
    flexion_time_constant_s: float = 4.0
    flexion_min_s: float = 1.5
    turned_min_angle_deg: float = 25.0  # walking about an axis this far from the flexion
    turned_min_s: float = 1.5           # axis this long: the phone turned in the pocket
    turned_time_constant_s: float = 2.0
    turned_angle_deg: float = 25.0      # turned this far outside the thigh's axes, at once
    turned_pitch_angle_deg: float = 35.0  # the mean walking pitch moved this far
    walking_pitch_deg: float = 5.0      # level walking's mean pitch: u placed from it when
                                        # the walking pitch says the first rest was seated
    replay_s: float = 3.0               # samples kept while the axes are learned
    # without a gyroscope (imu/data's angular_velocity_covariance[0] = -1, REP-145)
    gravity_cutoff_hz: float = 1.5      # the gravity direction: low-pass of the specific force
    accel_motion_mps2: float = 1.0      # ‖α − gravity‖ that counts as walking motion

    def __post_init__(self) -> None:
        check_positive(self, ("rest_rate_deg_per_s", "rest_acc_mps2", "rest_min_s",
                         "standing_max_angle_deg", "moved_min_angle_deg",
                         "moving_rate_deg_per_s", "flexion_time_constant_s", "flexion_min_s",
                         "turned_min_angle_deg", "turned_min_s", "turned_time_constant_s",
                         "turned_angle_deg", "turned_pitch_angle_deg",
                         "replay_s", "gravity_cutoff_hz", "accel_motion_mps2"))
        if self.rpy_deg is not None and len(self.rpy_deg) != 3:
            raise ValueError(f"rpy_deg must be [roll, pitch, yaw], got {self.rpy_deg}")


@dataclass(frozen=True)
class StepsConfig:
    """The pitch-maximum step detector (Muñoz Díaz 2016, Section 4.1; compiled_peaks)."""

    drop_min_deg: float = 5.0
    drop_fraction: float = 0.2
    rise_min_deg: float = 5.0
    rise_fraction: float = 0.3
    min_amplitude_deg: float = 8.0
    max_amplitude_deg: float = 110.0   # no thigh swings further (Δθ_U ≈ 53°, sitting 90°)
    max_rise_s: float = 1.5
    max_hold_s: float = 1.0
    min_step_period_s: float = 0.6     # a shorter gait cycle is running (compiled_peaks)
    # without a gyroscope, footfalls in the specific force's norm (steps.FootfallDetector):
    footfall_cutoff_hz: float = 3.0     # the norm low-passed here (fourth-order) ...
    footfall_prominence_mps2: float = 1.5   # ... a footfall stands this far over its troughs
    footfall_min_interval_s: float = 0.3    # ... and this long after the last one
    max_step_period_s: float = 2.5     # longer gaps start a new walking bout
    nominal_step_period_s: float = 1.1  # the first step's duration (frequency model)

    def __post_init__(self) -> None:
        check_positive(self, ("drop_min_deg", "rise_min_deg", "min_amplitude_deg",
                         "footfall_cutoff_hz", "footfall_prominence_mps2",
                         "footfall_min_interval_s",
                         "max_amplitude_deg", "max_rise_s",
                         "max_hold_s", "min_step_period_s", "max_step_period_s",
                         "nominal_step_period_s"))


@dataclass(frozen=True)
class ActivityConfig:
    """The activity of each step (pdr_pocket.activity): ``model`` thesis (Muñoz Díaz 2016,
    Section 4.1.3: θ_min, θ_max and Δθ against the running means of the last
    ``level_history_steps`` level steps) or level_prior (beyond the thesis: a hidden
    Markov model of level, up and down with the level floor as the strong prior). Angles
    in degrees."""

    model: str = "level_prior"
    level_history_steps: int = 6             # both: the person's last level steps
    # thesis
    up_amplitude_margin_deg: float = 8.0     # Δθ ≫ mean Δθ_H: Δθ above it by this
    up_max_margin_deg: float = 10.0          # θ_max ≫ mean θ_Hmax
    up_min_tolerance_deg: float = 2.0        # and θ_min not below mean θ_Hmin by more
    down_min_margin_deg: float = 5.0         # θ_min ≫ mean θ_Hmin
    down_amplitude_ratio: float = 1.1        # Δθ ≪ mean Δθ_H: below this times it
    # level_prior: the chain ...
    enter_stairs_probability: float = 0.01   # a level step followed by a step up (or down)
    stay_on_stairs_probability: float = 0.85  # a stairs step followed by one more
    # ... the population's level gait, weighing this many steps of the person's ...
    level_max_deg: float = 24.0
    level_min_deg: float = -8.0
    prior_weight_steps: float = 3.0
    # ... each state's evidence against the level gait at the step's amplitude: the mid
    # pitch (θ_max + θ_min)/2 above it, ln(Δθ/Δθ_H), θ_min above it, with their spreads
    # (up: 7.9 and 8.8 on the simulated UP/DW, 9.4–11.7 on the real thigh board) ...
    level_mid_sigma_deg: float = 4.0
    level_log_amplitude_sigma: float = 0.3
    level_min_sigma_deg: float = 4.0
    level_outlier_probability: float = 0.05  # heavy tails: this much of a wider level
    level_outlier_sigma_factor: float = 4.0  # ... spread
    up_mid_excess_deg: float = 8.0
    up_amplitude_ratio: float = 1.7
    up_min_excess_deg: float = 8.0
    down_mid_excess_deg: float = 12.0
    down_amplitude_ratio_mean: float = 0.95
    down_min_deg: float = 5.0                # θ_min of a step down (absolute: θ_Dmin > 0)
    stairs_mid_sigma_deg: float = 6.0
    stairs_log_amplitude_sigma: float = 0.2
    stairs_min_sigma_deg: float = 5.0
    stairs_cycle_min_s: float = 1.1          # stairs are walked: a shorter cycle counts
    stairs_cycle_sigma_s: float = 0.15       # ... against them by this Gaussian tail
    # ... a step turning more than this carries no evidence, and the level gait is
    # learned from steps at least this probably level
    turn_max_deg: float = 60.0
    turn_sigma_factor: float = 1.5
    learn_min_probability: float = 0.9
    learn_max_tilt_sigma_deg: float = 3.0   # ... and whose tilt σ is at most this
    # at rest
    sitting_min_pitch_deg: float = 30.0      # at rest: sitting above, standing below
    rest_after_s: float = 2.5                # no step for this long: standing or sitting

    def __post_init__(self) -> None:
        if self.model not in ACTIVITY_MODELS:
            raise ValueError(f"model must be one of {', '.join(ACTIVITY_MODELS)}, "
                             f"got {self.model!r}")
        check_positive(self, ("level_history_steps", "up_amplitude_margin_deg", "up_max_margin_deg",
                         "up_min_tolerance_deg", "down_min_margin_deg", "down_amplitude_ratio",
                         "prior_weight_steps", "level_mid_sigma_deg",
                         "level_log_amplitude_sigma", "level_min_sigma_deg",
                         "up_amplitude_ratio", "down_amplitude_ratio_mean",
                         "stairs_mid_sigma_deg", "stairs_log_amplitude_sigma",
                         "stairs_min_sigma_deg", "turn_max_deg", "turn_sigma_factor",
                         "level_outlier_sigma_factor", "stairs_cycle_min_s",
                         "stairs_cycle_sigma_s", "learn_max_tilt_sigma_deg",
                         "sitting_min_pitch_deg", "rest_after_s"))
        for name in ("enter_stairs_probability", "stay_on_stairs_probability",
                     "learn_min_probability", "level_outlier_probability"):
            if not 0 < getattr(self, name) < 1:
                raise ValueError(f"{name} must be within (0, 1), got {getattr(self, name)}")
        if not self.enter_stairs_probability < 0.5:
            raise ValueError("enter_stairs_probability must be below 0.5")
        if not self.level_max_deg > self.level_min_deg:
            raise ValueError("level_max_deg must be above level_min_deg")


@dataclass(frozen=True)
class StairsConfig:
    """Vertical displacement per step (Muñoz Díaz 2016, Eqs. (4.4)-(4.5)), v in cm and Δθ
    in degrees as there, and floors; and what makes a run of stairs steps a staircase
    (pdr_pocket.stairs.FlightCheck, beyond the thesis): its mean riser [m] within the
    building codes' span (pdr_core.walking.stair_geometry), each step a whole number of its risers
    (one or two) within ``riser_count_tolerance`` (relative), at most ``flight_max_risers``
    risers without a landing."""

    a_u_cm_per_deg: float = 0.8
    b_u_cm: float = -8.456
    a_d_cm_per_deg: float = 2.0
    b_d_cm: float = -19.24
    floor_height_m: float = FLOOR_HEIGHT_M
    vertical_sigma_m: float = 0.02      # 1σ of one step's v
    check_flights: bool = True          # false: every stairs step of the pitch climbs
    riser_min_m: float = RISER_MIN_M
    riser_max_m: float = RISER_MAX_M
    riser_count_tolerance: float = 0.5  # ±50 % of the whole number
    flight_max_risers: int = FLIGHT_MAX_RISERS

    def __post_init__(self) -> None:
        check_positive(self, ("a_u_cm_per_deg", "a_d_cm_per_deg", "floor_height_m",
                         "vertical_sigma_m", "riser_min_m", "riser_count_tolerance"))
        if not self.riser_max_m > self.riser_min_m:
            raise ValueError(f"riser_max_m must be above riser_min_m, got {self.riser_max_m} "
                             f"and {self.riser_min_m}")
        if not self.riser_count_tolerance < 1.0:
            raise ValueError(f"riser_count_tolerance must be below 1 (a step of no riser is "
                             f"no stairs step), got {self.riser_count_tolerance}")
        if not self.flight_max_risers >= FLIGHT_MIN_RISERS:
            raise ValueError(f"flight_max_risers must be at least {FLIGHT_MIN_RISERS} (a "
                             f"flight, DIN 18065), got {self.flight_max_risers}")


@dataclass(frozen=True)
class PositionConfig:
    """The position filter (Muñoz Díaz 2016, chapter 6; pdr_pocket.position)."""

    heading_sigma_per_step_deg: float = 1.0   # the sway left in one step's mean heading
    heading_drift_sigma_deg_per_s: float = 0.01   # the heading error rate left (drift ε)
    heading_drift_correction_deg_per_s: float = 0.0   # ε₀ taken off the step headings
    # a level step's climb is 0 ± this grade (rise/run, 1σ) times its stride: a walking
    # surface is within a running slope of 1:20 and a cross slope of 1:48 (ADA 2010
    # Standards, 403.3; steeper is a ramp, 405), 2 % at 2σ
    level_grade_sigma: float = 0.01
    # the offset b of the person's own stride line from the one configured (1σ, the same
    # in every level stride), in the covariance published for a fusion node only
    # (pdr_pocket.position): the population's line (step_length.calibrated false), from
    # which people's lines lie up to 14 cm (Muñoz Díaz 2016, Section 4.2.3, taken as 2σ);
    # a line pdr-pocket calibrate-step fitted (fit_offset: b = (D − a_H·ΣΔθ)/N) from
    # its least N = 20 strides (MIN_CALIBRATION_STEPS) of σ_s 0.03 m over a distance D
    # measured with a tape or a laser rangefinder (σ_D 0.05 m over about 30 m):
    # √(σ_D² + N·σ_s²)/N = √(0.05² + 20·0.03²)/20 ≈ 0.007 m (0.016 m for a distance known
    # to 1 % only, a map's or a pacing's)
    stride_offset_sigma_m: float = 0.07
    calibrated_stride_offset_sigma_m: float = 0.007
    initial_position_sigma_m: float = 0.0
    correction_gate_probability: float = 0.999

    def __post_init__(self) -> None:
        check_positive(self, ("heading_sigma_per_step_deg", "heading_drift_sigma_deg_per_s",
                         "level_grade_sigma", "correction_gate_probability"))
        if min(self.stride_offset_sigma_m, self.calibrated_stride_offset_sigma_m) < 0:
            raise ValueError("stride_offset_sigma_m and calibrated_stride_offset_sigma_m "
                             "must be >= 0")
        if not np.isfinite(self.heading_drift_correction_deg_per_s):
            raise ValueError("heading_drift_correction_deg_per_s must be finite")
        if self.initial_position_sigma_m < 0:
            raise ValueError("initial_position_sigma_m must be >= 0")


@dataclass(frozen=True)
class PersonConfig:
    """Who carries the phone. ``height_m`` scales an uncalibrated stride line by geometric
    similarity (pdr_pocket.step_length); null: the population's adult."""

    height_m: float | None = None

    def __post_init__(self) -> None:
        if self.height_m is not None and not 1.0 <= self.height_m <= 2.3:
            raise ValueError(f"height_m must be within 1.0-2.3 m, got {self.height_m}")


@dataclass(frozen=True)
class BarometerConfig:
    """The height filter (pdr_pocket.height_filter): each step's v fused with the
    barometric height, the barometer's offset b and its weather drift as states, and the
    lift and escalator rides told from the barometer's own offsets. Pressures in hPa at
    this edge, as phones and weather reports give them (1 hPa ≈ 8.3 m near the ground);
    SI inside. The figures: a phone's barometer (pdr_core.sensors.imu_profiles, PHONE_BAROMETER),
    the weather's drift of up to about 1 hPa/h (Parviainen et al. 2008), offsets of
    0.2-0.4 hPa by a stairwell's or lift lobby's ventilation."""

    enabled: bool = True                    # false: imu/pressure is ignored
    # the barometer: one reading's white noise and its step, and what an epoch's mean
    # keeps of the noise (its slow part)
    pressure_noise_hpa: float = 0.03
    pressure_resolution_hpa: float = 0.01
    correlated_noise_hpa: float = 0.005
    epoch_s: float = 0.5                    # readings are averaged over epochs this long
    # the offset b: the weather's drift rate ḃ (σ, Gauss-Markov with its time), a slow
    # random walk, and sudden jumps behind a χ² gate (1 dof) on the innovation
    weather_drift_hpa_per_h: float = 1.0
    weather_drift_time_s: float = 3600.0
    offset_walk_hpa_per_sqrt_h: float = 0.05
    offset_jump_gate_probability: float = 0.9999
    offset_jump_sigma_hpa: float = 0.5
    # the steps: a step's v is good to this fraction of itself (1σ) at least
    step_vertical_sigma_fraction: float = 0.2
    # changes of the barometric height: moving while the height changes this fast over
    # the window, measured between the levels held this long before and after
    motion_speed_mps: float = 0.15
    motion_window_s: float = 2.0
    settle_s: float = 2.0
    max_change_s: float = 120.0             # a change still moving after this: unresolved
    ride_min_height_m: float = 2.0          # a ride climbs at least this far
    # a lift: still (f_up's σ in an epoch below the first) for most of the ride, the
    # vertical force's peak speed and its double integral within a factor of the height
    still_force_sigma_mps2: float = 0.5
    lift_min_still_fraction: float = 0.75
    lift_min_speed_mps: float = 0.3
    lift_height_ratio_max: float = 2.0
    # an escalator: no pulses, but at least this long (10-90 %) and never this fast
    escalators: bool = True
    escalator_min_s: float = 8.0
    escalator_max_speed_mps: float = 1.0

    def __post_init__(self) -> None:
        check_positive(self, ("pressure_noise_hpa", "epoch_s", "weather_drift_hpa_per_h",
                         "weather_drift_time_s", "offset_jump_sigma_hpa",
                         "step_vertical_sigma_fraction", "motion_speed_mps",
                         "motion_window_s", "settle_s", "max_change_s", "ride_min_height_m",
                         "still_force_sigma_mps2", "lift_min_speed_mps", "escalator_min_s",
                         "escalator_max_speed_mps"))
        for name in ("pressure_resolution_hpa", "correlated_noise_hpa",
                     "offset_walk_hpa_per_sqrt_h"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        for name in ("offset_jump_gate_probability", "lift_min_still_fraction"):
            if not 0 < getattr(self, name) < 1:
                raise ValueError(f"{name} must be within (0, 1), got {getattr(self, name)}")
        if not self.lift_height_ratio_max > 1:
            raise ValueError(f"lift_height_ratio_max must be above 1, got "
                             f"{self.lift_height_ratio_max}")
        if not self.motion_window_s >= self.epoch_s or not self.settle_s >= self.epoch_s:
            raise ValueError(f"motion_window_s and settle_s must span an epoch_s "
                             f"({self.epoch_s}) at least, got {self.motion_window_s} and "
                             f"{self.settle_s}")
        if not self.escalator_max_speed_mps > self.motion_speed_mps:
            raise ValueError(f"escalator_max_speed_mps must be above motion_speed_mps, got "
                             f"{self.escalator_max_speed_mps} and {self.motion_speed_mps}")


@dataclass(frozen=True)
class PocketConfig:
    """The whole navigator."""

    orientation: OrientationConfig = field(default_factory=OrientationConfig)
    mounting: MountingConfig = field(default_factory=MountingConfig)
    steps: StepsConfig = field(default_factory=StepsConfig)
    activity: ActivityConfig = field(default_factory=ActivityConfig)
    step_length: StepLengthConfig = field(default_factory=StepLengthConfig)
    stairs: StairsConfig = field(default_factory=StairsConfig)
    position: PositionConfig = field(default_factory=PositionConfig)
    person: PersonConfig = field(default_factory=PersonConfig)
    barometer: BarometerConfig = field(default_factory=BarometerConfig)
    magnetometer_calibration: str | None = None   # YAML of pdr-pocket calibrate-mag
    step_calibration: str | None = None   # YAML of pdr-pocket calibrate-step --foot
                                          # (pdr_pocket.saved_lines: the person's lines)


ACTIVITY_MODELS = ("thesis", "level_prior")
CALIBRATION_FILES = ("magnetometer_calibration", "step_calibration")
SECTIONS = {"mounting": MountingConfig, "steps": StepsConfig, "activity": ActivityConfig,
            "step_length": StepLengthConfig, "stairs": StairsConfig,
            "position": PositionConfig, "person": PersonConfig,
            "barometer": BarometerConfig}


def pocket_config(data: dict | None, where: str = "config") -> PocketConfig:
    """A PocketConfig from a mapping; InputError names bad keys."""
    values = check_keys(data or {}, PocketConfig, where)
    out: dict[str, Any] = {}
    if "orientation" in values:
        out["orientation"] = orientation_config(values["orientation"], f"{where}.orientation")
    for name, kind in SECTIONS.items():
        if values.get(name) is not None:
            out[name] = dataclass_from_mapping(kind, values[name], f"{where}.{name}")
    for name in CALIBRATION_FILES:
        if values.get(name) is not None:
            out[name] = str(values[name])
    return PocketConfig(**out)


def default_config_path() -> Path:
    """The installed ``config/pocket_pdr.yaml``."""
    return shipped_config_dir("pdr_pocket") / "pocket_pdr.yaml"


def load_pocket_config(path: str | Path | None = None) -> PocketConfig:
    """The configuration of a YAML file (default :func:`default_config_path`); a relative
    ``magnetometer_calibration`` or ``step_calibration`` is taken relative to the file."""
    path = Path(path) if path else default_config_path()
    config = pocket_config(read_config_file(path), str(path))
    for name in CALIBRATION_FILES:
        calibration = getattr(config, name)
        if calibration is not None and not Path(calibration).is_absolute():
            config = replace(config, **{name: str(path.parent / calibration)})
    return config


