"""The orientation filter's configuration (``orientation:`` of the pocket navigator's YAML;
pdr_pocket.config holds the rest): the filter and its bias model, the sensor's noise from
its named profile (pdr_core.sensors.imu_profiles) or given, the updates that run
(:class:`Updates`), the default filter's own settings (:class:`EkfConfig`), and the
kernels' parameters in SI units built from them (:meth:`OrientationConfig.ekf_params`,
:meth:`OrientationConfig.thesis_params`). :func:`orientation_from_allan` makes the section
straight from ``pdr-sim allan``'s CSV.
"""
from __future__ import annotations

import csv
from dataclasses import dataclass, field, fields, replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from pdr_core import units
from pdr_core.config_files import (
    check_positive,
    dataclass_from_mapping,
)
from pdr_core.constants import EARTH_FIELD_RANGE_UT, STANDARD_GRAVITY_MPS2, earth_rate_enu
from pdr_core.errors import InputError
from pdr_core.maths.chi2 import chi2_quantile
from pdr_core.sensors.allan import (
    allan_deviation_model,
    first_minimum,
    gm_sigma_for_bias_instability,
)
from pdr_core.sensors.imu_profiles import PROFILES
from pdr_pocket.compiled_attitude_data import AttitudeParams
from pdr_pocket.compiled_gait_window import WindowParams
from pdr_pocket.compiled_orientation_data import FilterParams


@dataclass(frozen=True)
class Updates:
    """Which updates of Muñoz Díaz 2016, Section 3.3 run (each behind its detector)."""

    absolute_gravity: bool = True       # Eqs. (3.12)-(3.14), zero acceleration
    differential_gravity: bool = False  # Eqs. (3.15)-(3.16), zero acceleration
    absolute_magnetic: bool = True      # Eq. (3.17), quasi-constant field
    differential_magnetic: bool = True  # Eqs. (3.18)-(3.19), quasi-constant field
    compass: bool = False               # Eqs. (3.20)-(3.21), quasi-constant field
    zaru: bool = True                   # Eq. (3.22), zero angular rate
    mean_gravity: bool = True           # beyond the thesis: see compiled_orientation

    @property
    def magnetic(self) -> bool:
        """Whether any update reads the magnetometer (beyond the first heading)."""
        return self.absolute_magnetic or self.differential_magnetic or self.compass

    def mask(self) -> np.ndarray:
        """The flags in the order of pdr_pocket.compiled_orientation's update kinds."""
        return np.array([getattr(self, f.name) for f in fields(self)], dtype=bool)


@dataclass(frozen=True)
class EkfConfig:
    """The phone's attitude filter (``filter: ekf``, pdr_pocket.compiled_attitude, whose
    docstring gives the equations; why it departs from the thesis: docs/pocket.md,
    "Heading on real phones"). Angles in degrees, fields in µT at this edge.

    - ``tilt``: the tilt from the specific force in the navigation frame, low-passed by two
      first-order stages of ``tilt_time_constant_s``; ``tilt_sigma_deg`` is the error of
      its direction that the walk's change of speed leaves (1 m/s over 4τ is 0.7°).
    - ``cycles``: while walking, the tilt from windows of whole gait cycles (a thigh's
      swing markers), where the periodic accelerations cancel: the summed force is
      vertical up to the velocity change, ``cycle_velocity_sigma_mps`` from stride to
      stride plus ``walking_speed_mps`` times the turn over the window (and the markers'
      timing); a window that turned beyond ``cycle_turn_max_deg`` is left out, and so is
      one whose direction fails a χ² gate of ``cycle_gate_probability`` (1, the default,
      gates nothing: at 0.99 the gate refused the windows of a jog's changing speed on
      jog_thigh_1, the tilt's spread grew, and the activity took 2 of its 75 level steps
      for stairs). Without a window for ``cycle_timeout_s`` the low-pass takes
      over.
    - ``rest``: the rate and the specific force each within ``rest_rate_deg_per_s`` and
      ``rest_accel_mps2`` of its own low-pass (``rest_time_constant_s``) for ``rest_min_s``
      (a hand holding a phone still turns it by 0.5–2 °/s for a second or so: shorter rests
      would teach the bias that turn); then z = ω, whose sway ``rest_sway_deg_per_s``
      (correlated over the time constant) and the gyroscope's white noise make R, behind
      the χ² gate of ``zaru_gate_probability``.
    - ``field``: the magnetometer, a vector update of the heading, the magnetometer's
      offset (initial σ ``mag_offset_sigma_ut``, drifting by ``mag_offset_change_ut_per_
      sqrt_s``) and the field's magnitudes (drifting by ``field_change_ut_per_sqrt_s`` as
      the walker moves), never the tilt or the gyro biases. ``field_sigma_ut`` is the local
      field's spread about its model (2–3 µT in the OxIOD Vicon room once the phone's
      offset is known), correlated over ``field_time_constant_s``; a reading beyond the χ²
      gate of ``field_gate_probability`` is a disturbance and is left out, and after
      ``field_reset_s`` of them the field's magnitudes are taken anew.
    - the accelerometer's bias (initial σ ``accel_bias_sigma_mg``, drifting by
      ``accel_bias_change_mg_per_sqrt_s``), seen through the tilt updates as the attitude
      turns."""

    tilt: bool = True
    cycles: bool = True
    rest: bool = True
    field: bool = True
    cycle_timeout_s: float = 2.5
    cycle_velocity_sigma_mps: float = 0.25
    walking_speed_mps: float = 1.4
    cycle_turn_max_deg: float = 10.0
    cycle_gate_probability: float = 1.0
    tilt_time_constant_s: float = 2.0
    tilt_sigma_deg: float = 1.5
    rest_time_constant_s: float = 0.5
    rest_rate_deg_per_s: float = 2.0
    rest_accel_mps2: float = 0.4
    rest_min_s: float = 1.5
    rest_sway_deg_per_s: float = 0.03
    rest_tilt_sigma_deg: float = 0.2
    field_sigma_ut: float = 3.0
    field_time_constant_s: float = 4.0
    field_gate_probability: float = 0.999
    field_reset_s: float = 30.0
    field_norm_time_constant_s: float = 10.0
    field_change_ut_per_sqrt_s: float = 0.1
    mag_offset_sigma_ut: float = 5.0
    mag_offset_change_ut_per_sqrt_s: float = 0.01
    mag_offset_reset_sigma_ut: float = 20.0
    accel_bias_sigma_mg: float = 40.0
    accel_bias_change_mg_per_sqrt_s: float = 0.01

    def __post_init__(self) -> None:
        check_positive(self, ("cycle_timeout_s", "cycle_velocity_sigma_mps", "walking_speed_mps",
                         "cycle_turn_max_deg",
                         "tilt_time_constant_s",
                         "tilt_sigma_deg",
                         "rest_time_constant_s", "rest_rate_deg_per_s", "rest_accel_mps2",
                         "rest_min_s", "rest_sway_deg_per_s", "rest_tilt_sigma_deg",
                         "field_sigma_ut", "field_time_constant_s", "field_reset_s",
                         "field_norm_time_constant_s",
                         "mag_offset_sigma_ut", "accel_bias_sigma_mg"))
        for name in ("field_change_ut_per_sqrt_s", "mag_offset_change_ut_per_sqrt_s",
                     "accel_bias_change_mg_per_sqrt_s", "mag_offset_reset_sigma_ut"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if not 0 < self.field_gate_probability < 1:
            raise ValueError("field_gate_probability must be within (0, 1), got "
                             f"{self.field_gate_probability}")
        if not 0 < self.cycle_gate_probability <= 1:
            raise ValueError("cycle_gate_probability must be within (0, 1] (1: no gate), got "
                             f"{self.cycle_gate_probability}")


BIAS_MODELS = ("allan", "thesis")       # OrientationConfig.bias_model


FILTERS = ("ekf", "thesis")             # OrientationConfig.filter


# OrientationConfig's sensor noise keys that its imu_profile fills when they are not given
PROFILE_KEYS = ("gyro_arw_deg_per_sqrt_h", "bias_instability_deg_per_h",
                "bias_instability_time_s", "initial_bias_sigma_deg_per_s")


# The filter's initial gyro bias σ [°/s] for the profiles of pdr_core.sensors.imu_profiles it knows:
# calibrated_phone's, what a phone's own calibration leaves (the gyroscope a phone's OS
# hands to apps: iOS Core Motion's rotation rate and Android's calibrated TYPE_GYROSCOPE;
# the OxIOD iPhones drift by up to 0.7 °/s against their Vicon truth, docs/pocket.md);
# consumer_phone's turn-on σ, for a raw MEMS gyroscope; and for xsens_mtw twice the
# 0.1 °/s biases of Muñoz Díaz 2016, Table 3.2 (the value shipped before the profiles).
PROFILE_INITIAL_BIAS_SIGMA_DEG_PER_S = {"calibrated_phone": 0.25, "consumer_phone": 1.0,
                                        "xsens_mtw": 0.2}


def profile_noise(name: str) -> dict[str, float]:
    """The :data:`PROFILE_KEYS` of an IMU profile: the gyroscope's white noise, bias
    instability β and correlation time as pdr_core.sensors.imu_profiles gives them to the simulator
    (the correlation time is the t_β of Eq. (3.10); a profile that gives the Gauss-Markov
    σ instead has the β of its modelled Allan deviation's first minimum, so that the allan
    bias model gives that σ back), and the initial bias σ."""
    gyro = PROFILES[name]["gyro"]
    arw = float(gyro["arw_deg_per_sqrt_h"])
    tau = float(gyro["bias_correlation_time_s"])
    if "bias_instability_deg_per_h" in gyro:
        beta = float(gyro["bias_instability_deg_per_h"])
    else:
        beta = allan_minimum_deg_per_h(arw, float(gyro["gauss_markov_sigma_deg_per_s"]), tau)
    return {"gyro_arw_deg_per_sqrt_h": arw, "bias_instability_deg_per_h": beta,
            "bias_instability_time_s": tau,
            "initial_bias_sigma_deg_per_s": PROFILE_INITIAL_BIAS_SIGMA_DEG_PER_S[name]}


@lru_cache(maxsize=16)
def allan_minimum_deg_per_h(arw_deg_per_sqrt_h: float, gm_sigma_deg_per_s: float,
                            tau_s: float) -> float:
    """β [°/h]: the first minimum of the modelled Allan deviation of white noise and a
    Gauss-Markov bias (pdr_core.sensors.allan.allan_deviation_model)."""
    curve = allan_deviation_model(np.logspace(-3, 5, 1600), units.arw_to_si(arw_deg_per_sqrt_h),
                                  np.radians(gm_sigma_deg_per_s), tau_s)
    return float(curve[first_minimum(curve)] / units.deg_per_h_to_si(1))


@lru_cache(maxsize=64)
def allan_bias_sigma(beta_radps: float, t_beta_s: float, arw_rad_per_sqrt_s: float) -> float:
    """σ [rad/s] of the AR(1) gyro bias of correlation time t_β [s] whose modelled Allan
    deviation with the white noise σ_ν [rad/√s] has its minimum β [rad/s]
    (pdr_core.sensors.allan.gm_sigma_for_bias_instability); ValueError naming the keys when β
    leaves no such minimum."""
    try:
        return gm_sigma_for_bias_instability(beta_radps, t_beta_s, arw_rad_per_sqrt_s)
    except ValueError as exc:
        raise ValueError(
            f"bias_instability_deg_per_h {beta_radps / units.deg_per_h_to_si(1):g} is no "
            f"Allan minimum over the white noise gyro_arw_deg_per_sqrt_h "
            f"{arw_rad_per_sqrt_s / units.arw_to_si(1):g} with bias_instability_time_s "
            f"{t_beta_s:g} (bias_model allan: {exc})") from exc


@dataclass(frozen=True)
class OrientationConfig:
    """The orientation filter. Angles in degrees, rates in °/s or °/h at this edge, as the
    names say; SI inside (:meth:`params`).

    The filter. ``filter: ekf``, the default, is the phone's error-state filter
    (:class:`EkfConfig`, its own keys under ``ekf``): a continuous tilt reference, a rest
    update, and a magnetometer update of the heading and the phone's magnetometer offset
    behind a χ² gate. ``filter: thesis`` is the unscented filter of Muñoz Díaz 2016,
    chapter 3 (pdr_pocket.compiled_orientation), with its detectors and updates
    (``updates``, the zero-acceleration, zero-rate, mean gravity and magnetic keys below),
    kept by name so that its tables stay reproducible (config/pocket_pdr_thesis.yaml). The
    keys above ``updates`` serve both.

    The sensor noise. ``imu_profile`` names the gyroscope: its white noise, bias
    instability β and correlation time t_β are those pdr_core.sensors.imu_profiles gives the
    simulator, and its initial bias σ is in :data:`PROFILE_INITIAL_BIAS_SIGMA_DEG_PER_S`;
    each of the four keys given (not None) overrides the profile's. The default,
    calibrated_phone, is a phone's gyroscope as its OS hands it to apps, its turn-on bias
    already removed (initial σ 0.25 °/s); consumer_phone is a raw MEMS gyroscope of unknown
    make: 0.42 °/√h, β = 30 °/h at t_β = 100 s (σ_bias = 220 °/h with the allan model)
    and an initial bias σ of 1 °/s; xsens_mtw is the thesis' sensor (0.6 °/√h, 10 °/h at
    200 s, 0.2 °/s: the values shipped before).

    The bias model. Eq. (3.8), b̂^k = c·b^{k−1} + n, pulls the estimate toward zero with
    the time constant t_β, and its stationary spread σ_bias = β/√τ (Eq. (3.11)) is about
    10⁻⁴ °/s for a MEMS gyroscope: a turn-on bias of 0.1 °/s is then a thousand-σ outlier
    the filter cannot hold, and the thesis' own Figs. 3.14-3.17 (biases of ±0.1 °/s found
    over 10-30 min) could not come out of it. So the bias is carried as a random constant
    (initial σ ``initial_bias_sigma_deg_per_s``) whose variation follows the AR(1) of Eqs.
    (3.8)-(3.10): its process noise σ_n² = σ_bias²(1 − e^{−2/τ}) (Eq. (3.9), τ = t_β·f_s
    samples, Eq. (3.10)) is added at every sample. ``bias_mean_decays: true`` applies
    Eq. (3.8) to the estimate as written. ``bias_model`` sets σ_bias:

    - allan (default): the σ of the Gauss-Markov bias whose modelled Allan deviation (white
      noise σ_ν and the AR(1), pdr_core.sensors.allan.allan_deviation_model) has its minimum β
      (pdr_core.sensors.allan.gm_sigma_for_bias_instability): what ``pdr-sim allan`` fits and the
      simulator draws; 25 °/h for β = 10 °/h, t_β = 200 s, σ_ν = 0.6 °/√h;
    - thesis: σ_bias = β/√τ, Eq. (3.11) as written (0.07 °/h for the same sensor at
      100 Hz: the filter holds the bias for constant); the reproductions of the thesis'
      figures use it."""

    filter: str = "ekf"                 # ekf | thesis (see the class doc)
    # sensor noise, as pdr-sim allan reads it (Eqs. (3.7)-(3.11)); None: imu_profile's
    imu_profile: str = "calibrated_phone"   # a profile of PROFILE_INITIAL_BIAS_SIGMA_DEG_PER_S
    gyro_arw_deg_per_sqrt_h: float | None = None
    gyro_scale_sigma: float = 0.03      # sensitivity and cross-axis errors, a fraction
    bias_instability_deg_per_h: float | None = None
    bias_instability_time_s: float | None = None
    bias_model: str = "allan"           # allan | thesis: σ_bias (see the class doc)
    nominal_rate_hz: float = 100.0      # the f_s of Eq. (3.10): τ = t_β·f_s samples
    bias_mean_decays: bool = False      # True: Eq. (3.8) as written (see the class doc)
    # initial state
    initial_bias_sigma_deg_per_s: float | None = None
    initial_tilt_sigma_deg: float = 2.0
    initial_yaw_sigma_deg: float = 5.0
    initial_yaw_deg: float | None = None    # None: from the compass (magnetometer), else 0
    # environment
    latitude_deg: float | None = None   # Earth-rate compensation (Eqs. (3.23)-(3.24)); None: off
    declination_deg: float = 0.0        # magnetic declination, east positive (Eq. (3.20))
    gravity_mps2: float = STANDARD_GRAVITY_MPS2
    zaru_gate_probability: float = 0.999     # χ² gate of the rest update's innovation (3 dof)
    gyro_range_deg_per_s: float | None = None   # saturation limit; None: flat tops only
    max_gap_s: float = 0.1
    # filter: ekf
    ekf: EkfConfig = field(default_factory=EkfConfig)
    # filter: thesis, its updates and their measurement noise
    updates: Updates = field(default_factory=Updates)
    gravity_angle_sigma_deg: float = 2.0        # φ̄, θ̄ of the absolute gravity update
    differential_gravity_sigma_mps2: float = 0.03
    magnetic_sigma_ut: float = 0.5              # absolute and differential field updates
    compass_sigma_deg: float = 5.0
    zaru_sigma_deg_per_s: float = 0.05
    mean_gravity_window_s: float = 10.0
    mean_gravity_velocity_sigma_mps: float = 1.0
    mean_gravity_cycle_min_s: float = 1.0       # a window of whole gait cycles: this long
    mean_gravity_cycle_velocity_sigma_mps: float = 0.15  # ... and its velocity change
    swing_time_constant_s: float = 4.0          # the thigh's swing axis, for the cycles
    swing_rate_threshold_deg_per_s: float = 60.0
    # detectors (trailing windows, so the live node gives the offline result)
    zero_acc_window_s: float = 0.1
    zero_acc_threshold_mps2: float = 0.4
    zero_acc_max_rate_deg_per_s: float = 20.0   # beyond the thesis: see compiled_orientation
    zero_rate_window_s: float = 0.5
    zero_rate_threshold_deg_per_s: float = 3.0  # every ω this close to the window's mean
    mag_window_s: float = 0.5
    mag_norm_threshold_ut: float = 1.0
    mag_direction_threshold_deg: float = 3.0
    mag_reference_max_tilt_sigma_deg: float = 5.0   # the field reference needs this tilt

    def __post_init__(self) -> None:
        if self.imu_profile not in PROFILE_INITIAL_BIAS_SIGMA_DEG_PER_S:
            raise ValueError(f"imu_profile must be one of "
                             f"{', '.join(PROFILE_INITIAL_BIAS_SIGMA_DEG_PER_S)}, "
                             f"got {self.imu_profile!r}")
        if self.filter not in FILTERS:
            raise ValueError(f"filter must be one of {', '.join(FILTERS)}, got {self.filter!r}")
        if self.bias_model not in BIAS_MODELS:
            raise ValueError(f"bias_model must be one of {', '.join(BIAS_MODELS)}, "
                             f"got {self.bias_model!r}")
        check_positive(self, tuple(name for name in PROFILE_KEYS
                                   if getattr(self, name) is not None))
        positive = ("nominal_rate_hz", "initial_tilt_sigma_deg", "initial_yaw_sigma_deg",
                    "gravity_mps2", "gravity_angle_sigma_deg", "differential_gravity_sigma_mps2",
                    "magnetic_sigma_ut", "compass_sigma_deg", "zaru_sigma_deg_per_s",
                    "mean_gravity_window_s", "mean_gravity_velocity_sigma_mps",
                    "mean_gravity_cycle_min_s", "mean_gravity_cycle_velocity_sigma_mps",
                    "swing_time_constant_s", "swing_rate_threshold_deg_per_s",
                    "zero_acc_window_s", "zero_acc_threshold_mps2", "zero_acc_max_rate_deg_per_s",
                    "zero_rate_window_s",
                    "zero_rate_threshold_deg_per_s", "mag_window_s", "mag_norm_threshold_ut",
                    "mag_direction_threshold_deg", "mag_reference_max_tilt_sigma_deg",
                    "max_gap_s")
        check_positive(self, positive)
        if not 0 < self.zaru_gate_probability < 1:
            raise ValueError(f"zaru_gate_probability must be within (0, 1), got "
                             f"{self.zaru_gate_probability}")
        if not self.gyro_scale_sigma >= 0:
            raise ValueError(f"gyro_scale_sigma must be >= 0, got {self.gyro_scale_sigma}")
        if self.latitude_deg is not None and not -90 <= self.latitude_deg <= 90:
            raise ValueError(f"latitude_deg must be within ±90, got {self.latitude_deg}")
        _ = self.bias_sigma_radps   # allan: β must be a dip over σ_ν at t_β (named if not)

    @property
    def magnetic(self) -> bool:
        """Whether the configured filter updates from the magnetometer beyond its first
        heading: ``ekf.field`` for ``filter: ekf``, any magnetic update for ``thesis``."""
        return self.ekf.field if self.filter == "ekf" else self.updates.magnetic

    def noise(self, name: str) -> float:
        """A sensor noise key of :data:`PROFILE_KEYS` as given, else ``imu_profile``'s."""
        value = getattr(self, name)
        return profile_noise(self.imu_profile)[name] if value is None else value

    @property
    def bias_tau_samples(self) -> float:
        """τ = t_β·f_s (Eq. (3.10))."""
        return self.noise("bias_instability_time_s") * self.nominal_rate_hz

    @property
    def bias_sigma_radps(self) -> float:
        """σ_bias [rad/s] of the AR(1) bias: ``bias_model`` allan, the σ of the Gauss-Markov
        bias (correlation time t_β) whose Allan deviation with the white noise σ_ν has its
        minimum β (pdr_core.sensors.allan.gm_sigma_for_bias_instability); thesis, β/√τ
        (Eq. (3.11), τ of Eq. (3.10))."""
        beta = units.deg_per_h_to_si(self.noise("bias_instability_deg_per_h"))
        if self.bias_model == "thesis":
            return beta / np.sqrt(self.bias_tau_samples)
        return allan_bias_sigma(beta, self.noise("bias_instability_time_s"),
                                units.arw_to_si(self.noise("gyro_arw_deg_per_sqrt_h")))

    def params(self) -> AttitudeParams | FilterParams:
        """The compiled filter's parameters, SI units: :class:`AttitudeParams` for
        ``filter: ekf``, :class:`FilterParams` for ``filter: thesis``."""
        return self.ekf_params() if self.filter == "ekf" else self.thesis_params()

    @property
    def _earth_rate(self) -> np.ndarray:
        return np.zeros(3) if self.latitude_deg is None else earth_rate_enu(self.latitude_deg)

    def ekf_params(self) -> AttitudeParams:
        """pdr_pocket.compiled_attitude's parameters, SI units."""
        e = self.ekf
        arw = units.arw_to_si(self.noise("gyro_arw_deg_per_sqrt_h"))       # rad/√s
        return AttitudeParams(
            gyro_noise_var=arw**2 * self.nominal_rate_hz, gyro_noise_density2=arw**2,
            gyro_scale_var=self.gyro_scale_sigma**2,
            bias_tau_s=self.noise("bias_instability_time_s"), bias_sigma=self.bias_sigma_radps,
            bias_mean_decays=self.bias_mean_decays, earth_rate_n=self._earth_rate,
            gravity=self.gravity_mps2, max_gap_s=self.max_gap_s,
            use_tilt=e.tilt, use_cycles=e.cycles, window=self.window_params(),
            cycle_velocity_var=e.cycle_velocity_sigma_mps**2,
            walking_speed=e.walking_speed_mps, cycle_timeout_s=e.cycle_timeout_s,
            cycle_turn_max=np.radians(e.cycle_turn_max_deg),
            cycle_gate_nis=chi2_quantile(e.cycle_gate_probability, 2),
            tilt_tau_s=e.tilt_time_constant_s,
            tilt_var=np.radians(e.tilt_sigma_deg) ** 2,
            use_rest=e.rest, rest_tau_s=e.rest_time_constant_s,
            rest_gyro_threshold2=np.radians(e.rest_rate_deg_per_s) ** 2,
            rest_accel_threshold2=e.rest_accel_mps2**2, rest_min_s=e.rest_min_s,
            rest_sway_var=np.radians(e.rest_sway_deg_per_s) ** 2,
            rest_gate_nis=chi2_quantile(self.zaru_gate_probability, 3),
            rest_tilt_var=np.radians(e.rest_tilt_sigma_deg) ** 2,
            use_field=e.field, heading_from_field=self.initial_yaw_deg is None,
            field_azimuth=np.pi / 2 - np.radians(self.declination_deg),
            field_var=(e.field_sigma_ut * 1e-6) ** 2, field_tau_s=e.field_time_constant_s,
            field_gate_nis=chi2_quantile(e.field_gate_probability, 3),
            field_reset_s=e.field_reset_s, field_start_var=(e.field_sigma_ut * 1e-6) ** 2,
            field_norm_min=EARTH_FIELD_RANGE_UT[0] * 1e-6,
            field_norm_max=EARTH_FIELD_RANGE_UT[1] * 1e-6,
            field_norm_tau_s=e.field_norm_time_constant_s,
            field_change_var_per_s=(e.field_change_ut_per_sqrt_s * 1e-6) ** 2,
            offset_change_var_per_s=(e.mag_offset_change_ut_per_sqrt_s * 1e-6) ** 2,
            offset_reset_var=(e.mag_offset_reset_sigma_ut * 1e-6) ** 2,
            accel_bias_change_var_per_s=units.mg_to_si(e.accel_bias_change_mg_per_sqrt_s) ** 2,
            heading_start_var=np.radians(self.initial_yaw_sigma_deg) ** 2)

    def window_params(self) -> WindowParams:
        """pdr_pocket.compiled_gait_window's parameters, SI units."""
        return WindowParams(self.mean_gravity_window_s, self.mean_gravity_cycle_min_s,
                            self.swing_time_constant_s,
                            np.radians(self.swing_rate_threshold_deg_per_s), self.gravity_mps2)

    def thesis_params(self) -> FilterParams:
        """pdr_pocket.compiled_orientation's parameters, SI units."""
        arw = units.arw_to_si(self.noise("gyro_arw_deg_per_sqrt_h"))       # rad/√s
        earth = self._earth_rate
        return FilterParams(
            gyro_noise_var=arw**2 * self.nominal_rate_hz,        # σ_ν² per sample
            bias_tau_s=self.noise("bias_instability_time_s"), bias_sigma=self.bias_sigma_radps,
            bias_mean_decays=self.bias_mean_decays,
            earth_rate_n=earth, gravity=self.gravity_mps2, use=self.updates.mask(),
            gravity_angle_var=np.radians(self.gravity_angle_sigma_deg) ** 2,
            diff_gravity_var=self.differential_gravity_sigma_mps2**2,
            mag_var=(self.magnetic_sigma_ut * 1e-6) ** 2,
            compass_var=np.radians(self.compass_sigma_deg) ** 2,
            zaru_var=np.radians(self.zaru_sigma_deg_per_s) ** 2,
            zaru_gate_nis=chi2_quantile(self.zaru_gate_probability, 3),
            window=self.window_params(),
            mean_gravity_velocity_var=self.mean_gravity_velocity_sigma_mps**2,
            cycle_velocity_var=self.mean_gravity_cycle_velocity_sigma_mps**2,
            field_azimuth=np.pi / 2 - np.radians(self.declination_deg),
            zero_acc_window_s=self.zero_acc_window_s,
            zero_acc_threshold=self.zero_acc_threshold_mps2,
            zero_acc_max_rate=np.radians(self.zero_acc_max_rate_deg_per_s),
            zero_rate_window_s=self.zero_rate_window_s,
            zero_rate_threshold=np.radians(self.zero_rate_threshold_deg_per_s),
            mag_window_s=self.mag_window_s, mag_norm_threshold=self.mag_norm_threshold_ut * 1e-6,
            mag_direction_threshold=np.radians(self.mag_direction_threshold_deg),
            max_gap_s=self.max_gap_s,
            gyro_scale_var=self.gyro_scale_sigma**2,
            mag_reference_max_var=np.radians(self.mag_reference_max_tilt_sigma_deg) ** 2)


ORIENTATION_SECTIONS = {"ekf": EkfConfig, "updates": Updates}


def orientation_config(data: dict | None, where: str) -> OrientationConfig:
    values = dict(data or {})
    sections = {name: values.pop(name, None) for name in ORIENTATION_SECTIONS}
    config = dataclass_from_mapping(OrientationConfig, values, where)
    for name, kind in ORIENTATION_SECTIONS.items():
        section = sections[name]
        if section is None:
            continue
        if not isinstance(section, dict):
            raise InputError(f"{where}.{name}", f"expected a mapping, got {section!r}")
        config = replace(config, **{name: dataclass_from_mapping(kind, section,
                                                                  f"{where}.{name}")})
    return config


def orientation_from_allan(csv_path: str | Path,
                           base: OrientationConfig | None = None) -> OrientationConfig:
    """The orientation section with the gyroscope's noise read by ``pdr-sim allan``
    (its allan.csv): the mean over the axes of ARW, β and t_β (the minimum's τ, taken as
    the AR(1)'s time constant as Eq. (3.10) takes it). With ``bias_model: allan`` a t_β
    too short for a Gauss-Markov bias to dip to β over that white noise (t_β below
    2.2·(σ_ν/β)²) is refused by name: the curve's minimum lies at about the same τ for any
    correlation time from t_β to 100·t_β, so it cannot tell the correlation time; give
    ``bias_instability_time_s`` (the sensor's correlation time) after it, or
    ``bias_model: thesis``."""
    path = Path(csv_path)
    try:
        with path.open() as stream:
            rows = [r for r in csv.DictReader(stream) if r.get("axis", "").startswith("gyro")]
        values = {key: float(np.mean([float(r[key]) for r in rows])) for key in
                  ("arw_deg_per_sqrt_h", "bias_instability_deg_per_h", "t_beta_s")}
    except (OSError, KeyError, ValueError) as exc:
        raise InputError(path, f"not an allan.csv of pdr-sim allan ({exc})") from exc
    if not rows:
        raise InputError(path, "no gyroscope rows (axis gyro_x, ...)")
    try:
        return replace(base or OrientationConfig(),
                       gyro_arw_deg_per_sqrt_h=values["arw_deg_per_sqrt_h"],
                       bias_instability_deg_per_h=values["bias_instability_deg_per_h"],
                       bias_instability_time_s=values["t_beta_s"])
    except ValueError as exc:
        raise InputError(path, str(exc)) from exc
