"""Named IMU error profiles and their configuration format (units in the key names).

A profile is a mapping with up to three sections for the triads, ``gyro``, ``accel`` and
``mag``, each value a scalar (all axes) or a list of three (x, y, z), and a ``baro``
section for the barometer beside them. :func:`imu_errors` turns it into an
:class:`~pdr_core.sensors.imu_errors.ImuErrors` in SI units; unknown keys and negative densities
are refused with the key named. Keys:

gyro:  arw_deg_per_sqrt_h, bias_deg_per_s, bias_sigma_deg_per_s,
       bias_instability_deg_per_h | gauss_markov_sigma_deg_per_s, bias_correlation_time_s,
       rrw_deg_per_s_per_sqrt_h, warmup_bias_deg_per_s, warmup_time_constant_s,
       scale_factor_ppm, misalignment_mrad, range_deg_per_s, resolution_deg_per_s
accel: vrw_ug_per_sqrt_hz | vrw_mps_per_sqrt_h, bias_mg, bias_sigma_mg,
       bias_instability_mg | gauss_markov_sigma_mg, bias_correlation_time_s,
       random_walk_mps2_per_sqrt_h, warmup_bias_mg, warmup_time_constant_s,
       scale_factor_ppm, misalignment_mrad, range_g, resolution_mg
mag:   noise_ut_per_sqrt_hz, bias_ut, bias_sigma_ut, scale_factor_ppm, misalignment_mrad,
       range_ut, resolution_ut
baro:  rate_hz, noise_hpa (std per reading), resolution_hpa, reference_hpa (the true
       pressure at the map's z = 0 at the start, default 1013.25), drift_hpa_per_h
       (signed), drift_sigma_hpa_per_h (std of a per-run drift), offsets (a list of
       {at_s, size_hpa, duration_s}), offsets_per_h (random offsets), offset_size_hpa
       ([least, largest]), offset_duration_s, warmup_hpa and warmup_time_constant_s (the
       settling after the start), lag_s (the phone's own low-pass), hold_share (readings
       that repeat the one before)

A profile without a ``baro`` section takes :data:`PHONE_BAROMETER` (``consumer_phone``'s):
the sources give no barometer figures for the others (``ideal`` has an ideal one).

The Gauss–Markov (AR(1)) bias of Muñoz Díaz 2016, Eqs. (3.8)–(3.9) is given
either directly, by its σ (``gauss_markov_sigma_*``) and correlation time τ, or by a bias
instability β: then σ is chosen so that the first minimum of the modelled Allan deviation
equals β (:func:`pdr_core.sensors.allan.gm_sigma_for_bias_instability`), so ``pdr-sim allan`` on
static data reads β back. β needs the white noise of its triad: without it the curve
rises from zero and has no first minimum, and the profile is refused.

Misalignment is given as the three small angles (about x, y, z) of a non-orthogonality
that couples the axes: M = [[0, −γz, γy], [γz, 0, −γx], [−γy, γx, 0]] plus its symmetric
part (each axis tilted towards the next), i.e. M_ij = γ for i ≠ j.
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

from pdr_core import units
from pdr_core.config_files import typed_value
from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.sensors.allan import gm_sigma_for_bias_instability
from pdr_core.sensors.imu_errors import BarometerErrors, ImuErrors, PressureOffset, TriadErrors

# The barometer of a phone (``baro``; pdr_core.sensors.imu_errors.BarometerErrors for the model):
# - rate_hz 25: the output rate a phone's barometer runs at for navigation. The Bosch
#   BMP280 datasheet (BST-BMP280-DS001, 2015) gives 26.3 Hz for its "indoor navigation"
#   setting (×16 pressure oversampling, IIR filter 16), ST's LPS25HB and LPS22HB
#   datasheets output rates of 1-25 Hz and 1-75 Hz; the Android Compatibility
#   Definition (section 7.3.5, Barometer) requires at least 5 Hz.
# - noise_hpa 0.03: white noise per reading. The LPS25HB datasheet gives 0.01 hPa RMS in
#   its high-resolution mode, the LPS22HB 0.0075 hPa RMS with its low-pass filter, the
#   BMP280 a resolution of 0.0016 hPa at ×16 oversampling and a relative accuracy of
#   ±0.12 hPa (as the Android Compatibility Definition asks: "0.12 hPa over 20 hPa"); a
#   phone's reading at 25 Hz is less filtered than those figures, so the upper end of
#   0.01-0.03 hPa is taken (0.25 m of height per reading).
# - resolution_hpa 0.01: the step of the readings (assumed: a sensor hub reporting hPa
#   with two decimals; the sensors' own steps are finer, 1/4096 hPa for the LPS22HB).
# - drift_sigma_hpa_per_h 0.3: the weather moves the ambient pressure by up to about
#   1 hPa/h (Parviainen et al. 2008; pdr_core.sensors.atmosphere), taken as three σ of a per-run
#   drift rate; drift_hpa_per_h sets one (e.g. 1 for the worst case).
# - offsets_per_h 0 (none unless asked for), offset_size_hpa 0.2-0.4, offset_duration_s
#   60: a pressurised stairwell or a lift lobby holds its own pressure against the floors
#   (IBC 2015 section 909.20.5 and NFPA 92: 0.10 inch of water, 25 Pa, at least, 87 Pa at
#   most), about a floor's worth of pressure for as long as the walk stays there: the hard
#   case of a barometric floor count. ``offsets`` places them.
PHONE_BAROMETER: dict[str, Any] = {
    "rate_hz": 25.0, "noise_hpa": 0.03, "resolution_hpa": 0.01,
    "drift_sigma_hpa_per_h": 0.3, "offsets_per_h": 0.0, "offset_size_hpa": [0.2, 0.4],
    "offset_duration_s": 60.0,
}

# An iPhone's barometer as the Sensor Logger app exports it (Barometer.csv of
# ../shared/data/phone/sensor_logger/inhand-28-steps-Ido, 16 readings of a level walk):
# - rate_hz 1: its readings come once a second (Core Motion's altimeter; the Android
#   phone of the same app gives 10 Hz);
# - noise_hpa 0.002: its level readings differ by 0.001-0.004 hPa (a filtered output; the
#   Android's 10 Hz ones by 0.009 hPa RMS), resolution_hpa 0: floats;
# - warmup_hpa 0.095, warmup_time_constant_s 3: its pressure rises 0.095 hPa (0.8 m down)
#   over the first 6 s of a level walk: 0.095·(1 − e^{−t/3 s}) through the lag below
#   fits it within 0.011 hPa (0.012 hPa without the lag);
# - lag_s 1: assumed (a file of 16 readings cannot tell it better), the phone's own
#   filtering smooths a climb over about a reading;
# - hold_share 0.25: 4 of its 15 readings repeat the one before exactly.
IPHONE_BAROMETER: dict[str, Any] = PHONE_BAROMETER | {
    "rate_hz": 1.0, "noise_hpa": 0.002, "resolution_hpa": 0.0, "warmup_hpa": 0.095,
    "warmup_time_constant_s": 3.0, "lag_s": 1.0, "hold_share": 0.25,
}

# A smartphone-class MEMS IMU (typical values of a Bosch BMI160-class datasheet): the
# gyroscope's white noise 0.007 °/s/√Hz (0.42 °/√h), 1° cross-axis, ±2000 °/s in 16 bits;
# the accelerometer's 180 µg/√Hz, turn-on bias σ 40 mg, 1 % scale factor, 1° cross-axis,
# ±8 g in 16 bits. The parts of consumer_phone that calibrated_phone shares.
PHONE_GYROSCOPE: dict[str, Any] = {
    "arw_deg_per_sqrt_h": 0.42, "misalignment_mrad": 17.0, "range_deg_per_s": 2000.0,
    "resolution_deg_per_s": 2000.0 / 32768,
}
PHONE_ACCELEROMETER: dict[str, Any] = {
    "vrw_ug_per_sqrt_hz": 180.0, "bias_sigma_mg": 40.0, "bias_instability_mg": 0.5,
    "bias_correlation_time_s": 100.0, "scale_factor_ppm": 10000.0, "misalignment_mrad": 17.0,
    "range_g": 8.0, "resolution_mg": 8000.0 / 32768,
}

# Sources are cited per profile; "assumed" marks values the cited source does not give.
PROFILES: dict[str, dict[str, dict[str, Any]]] = {
    "ideal": {"baro": {}},
    # Xsens MTi, Zampella et al. 2011, section IV-B: 3 °/√h ARW, 122 µg/√Hz VRW,
    # constant biases drawn per axis with σ 1.23 mg (accelerometer) and 0.5 °/s (gyro).
    "xsens_mti": {
        "gyro": {"arw_deg_per_sqrt_h": 3.0, "bias_sigma_deg_per_s": 0.5},
        "accel": {"vrw_ug_per_sqrt_hz": 122.0, "bias_sigma_mg": 1.23},
    },
    # Xsens MTw, Muñoz Díaz 2016, Table 3.2: gyro white noise 0.1 °/s per sample
    # at 100 Hz (= 0.01 °/s/√Hz = 0.6 °/√h), biases (−0.1, 0.1, −0.1) °/s, magnetometer
    # noise 0.015 µT per sample at 100 Hz; Table 6.1 uses the same noise. Assumed (not in
    # the thesis, MTw datasheet order): gyro bias instability 10 °/h, accelerometer
    # 200 µg/√Hz and 0.1 mg bias instability, correlation times 200 s and 100 s.
    "xsens_mtw": {
        "gyro": {"arw_deg_per_sqrt_h": 0.6, "bias_deg_per_s": [-0.1, 0.1, -0.1],
                 "bias_instability_deg_per_h": 10.0, "bias_correlation_time_s": 200.0,
                 "range_deg_per_s": 2000.0},
        "accel": {"vrw_ug_per_sqrt_hz": 200.0, "bias_instability_mg": 0.1,
                  "bias_correlation_time_s": 100.0, "range_g": 16.0},
        "mag": {"noise_ut_per_sqrt_hz": 0.0015},
    },
    # The error setups of Muñoz Díaz 2016 for its orientation filter, as published and
    # nothing more: Table 3.2, gyro white noise 0.1 °/s per sample at 100 Hz
    # (0.01 °/s/√Hz = 0.6 °/√h), constant biases (−0.1, 0.1, −0.1) °/s, magnetometer noise
    # 0.015 µT per sample at 100 Hz; Table 6.1, the same with a z bias of +0.05 °/s.
    "thesis_table_3_2": {
        "gyro": {"arw_deg_per_sqrt_h": 0.6, "bias_deg_per_s": [-0.1, 0.1, -0.1]},
        "mag": {"noise_ut_per_sqrt_hz": 0.0015},
    },
    "thesis_table_6_1": {
        "gyro": {"arw_deg_per_sqrt_h": 0.6, "bias_deg_per_s": [-0.1, 0.1, 0.05]},
        "mag": {"noise_ut_per_sqrt_hz": 0.0015},
    },
    # VectorNav VN-200, Wang et al. 2020, section IV: ARW 0.21 °/√h,
    # VRW 0.14 mg/√Hz, RRW 0.048 °/s/√h (from its Allan deviation, Fig. 7).
    "vn200": {
        "gyro": {"arw_deg_per_sqrt_h": 0.21, "rrw_deg_per_s_per_sqrt_h": 0.048},
        "accel": {"vrw_ug_per_sqrt_hz": 140.0},
    },
    # A smartphone-class MEMS IMU (typical values of a Bosch BMI160-class datasheet):
    # 0.007 °/s/√Hz (0.42 °/√h), turn-on bias σ 1 °/s, 180 µg/√Hz, bias σ 40 mg, 1 %
    # scale factor, 1° cross-axis, ±2000 °/s and ±8 g in 16 bits; magnetometer 0.3 µT RMS
    # at 100 Hz.
    "consumer_phone": {
        "gyro": {**PHONE_GYROSCOPE, "bias_sigma_deg_per_s": 1.0,
                 "bias_instability_deg_per_h": 30.0, "bias_correlation_time_s": 100.0,
                 "scale_factor_ppm": 10000.0},
        "accel": PHONE_ACCELEROMETER,
        "mag": {"noise_ut_per_sqrt_hz": 0.03, "bias_sigma_ut": 0.5},
        "baro": PHONE_BAROMETER,
    },
    # The same phone read through its OS's calibrated sensors (Android Sensor.TYPE_GYROSCOPE,
    # iOS CMDeviceMotion.rotationRate), as most phone recordings are (OxIOD's are):
    # - gyro: consumer_phone's noise and misalignment; no turn-on bias of a raw MEMS gyro
    #   but the residual the OS's online calibration leaves. Android's TYPE_GYROSCOPE is
    #   "gyro-drift compensated", TYPE_GYROSCOPE_UNCALIBRATED "no gyro-drift compensation ...
    #   Factory calibration and temperature compensation is still applied" (Android SDK,
    #   Sensor); Apple's rotationRate is gyroscope data "whose bias has been removed by Core
    #   Motion algorithms" (CMDeviceMotion). Neither says how well. The Android
    #   Compatibility Definition (7.3.4) strongly recommends a calibration error below
    #   0.01 rad/s (0.57 °/s) at rest at room temperature; AOSP's runtime calibration
    #   (device/google/contexthub, calibration/gyroscope/gyro_cal.c) takes the mean rate
    #   over 5-6 s of stillness as the bias. On OxIOD's three iPhones, integrating the
    #   gyroscope over 5 s windows against the Vicon attitude leaves 0.01-0.57 °/s per axis
    #   (RMS 0.24 °/s over the nine axis-sequences; the iPhone 7 Plus -0.34, -0.19,
    #   -0.57 °/s), moving by about 0.1 °/s (std) from one minute to the next: a residual
    #   drawn per run with σ 0.25 °/s, and a Gauss-Markov variation of σ 0.1 °/s with a
    #   correlation time of 100 s (assumed, consumer_phone's). Scale factor 0.3 %: the same
    #   fit gives -0.26 to +0.31 % (± 0.1-0.2 %) on the axis the phone turns about (an OS
    #   does not calibrate it), below consumer_phone's datasheet 1 %; assumed the same on
    #   all axes. The re-estimation at rests is not modelled (the residual is the same before
    #   and after a stop).
    # - mag: the OS's calibrated field is smoother than consumer_phone's raw 0.3 µT per
    #   sample: OxIOD's iPhones give a reading at 50-73 Hz (held on the 100 Hz grid) that
    #   moves by 0.1-0.16 µT (second differences, walking: an upper bound of the noise),
    #   and the norm of the field spreads by less than 1 µT over 68-88 % of their 0.5 s
    #   windows (median 0-0.85 µT); white noise of 0.01 µT/√Hz (0.1 µT per sample at
    #   100 Hz) gives 66-69 % and a median of 0.8 µT on indoor_loops, held or in the
    #   pocket (0.03 µT/√Hz: 0-26 %). A phone-fixed offset the OS's calibration leaves
    #   (hard iron of the phone's own parts, changed since it was last calibrated): on
    #   OxIOD, fitting a constant body-frame offset o with one room field for the three
    #   phones gives (-4.8, 2.1, -3.2), (-0.2, 1.5, 3.7), (-3.2, 1.9, -1.2) µT, stable over
    #   30 s windows to about 1 µT: RMS 2.8 µT per axis, drawn per run with σ 3 µT.
    # - accel: consumer_phone's (assumed: the OS does not re-estimate it while walking).
    "calibrated_phone": {
        "gyro": {**PHONE_GYROSCOPE, "bias_sigma_deg_per_s": 0.25,
                 "gauss_markov_sigma_deg_per_s": 0.1, "bias_correlation_time_s": 100.0,
                 "scale_factor_ppm": 3000.0},
        "accel": PHONE_ACCELEROMETER,
        "mag": {"noise_ut_per_sqrt_hz": 0.01, "bias_sigma_ut": 3.0},
        "baro": PHONE_BAROMETER,
    },
}

_SCALES = {
    "gyro": {"arw_deg_per_sqrt_h": units.arw_to_si(1), "bias_deg_per_s": units.DEG,
             "bias_sigma_deg_per_s": units.DEG,
             "bias_instability_deg_per_h": units.deg_per_h_to_si(1),
             "gauss_markov_sigma_deg_per_s": units.DEG,
             "rrw_deg_per_s_per_sqrt_h": units.rrw_to_si(1),
             "warmup_bias_deg_per_s": units.DEG,
             "range_deg_per_s": units.DEG, "resolution_deg_per_s": units.DEG},
    "accel": {"vrw_ug_per_sqrt_hz": units.ug_per_sqrt_hz_to_si(1),
              "vrw_mps_per_sqrt_h": units.vrw_to_si(1), "bias_mg": units.mg_to_si(1),
              "bias_sigma_mg": units.mg_to_si(1), "bias_instability_mg": units.mg_to_si(1),
              "gauss_markov_sigma_mg": units.mg_to_si(1),
              "random_walk_mps2_per_sqrt_h": 1 / units.SQRT_HOUR,
              "warmup_bias_mg": units.mg_to_si(1),
              "range_g": STANDARD_GRAVITY_MPS2, "resolution_mg": units.mg_to_si(1)},
    "mag": {"noise_ut_per_sqrt_hz": 1e-6, "bias_ut": 1e-6, "bias_sigma_ut": 1e-6,
            "range_ut": 1e-6, "resolution_ut": 1e-6},
}
_COMMON = {"scale_factor_ppm": 1e-6, "misalignment_mrad": 1e-3, "bias_correlation_time_s": 1.0,
           "warmup_time_constant_s": 1.0}
_FIELDS = {  # config key (after unit scaling) -> TriadErrors field
    "arw_deg_per_sqrt_h": "white_density", "vrw_ug_per_sqrt_hz": "white_density",
    "vrw_mps_per_sqrt_h": "white_density", "noise_ut_per_sqrt_hz": "white_density",
    "bias_deg_per_s": "bias", "bias_mg": "bias", "bias_ut": "bias",
    "bias_sigma_deg_per_s": "bias_sigma", "bias_sigma_mg": "bias_sigma",
    "bias_sigma_ut": "bias_sigma", "rrw_deg_per_s_per_sqrt_h": "random_walk_density",
    "random_walk_mps2_per_sqrt_h": "random_walk_density", "scale_factor_ppm": "scale_factor",
    "gauss_markov_sigma_deg_per_s": "gm_sigma", "gauss_markov_sigma_mg": "gm_sigma",
    "warmup_bias_deg_per_s": "warmup", "warmup_bias_mg": "warmup",
}
_SCALAR_KEYS = {"range_deg_per_s", "range_g", "range_ut", "resolution_deg_per_s",
                "resolution_mg", "resolution_ut"}


def _axes(value: Any, where: str) -> tuple[float, float, float]:
    if isinstance(value, int | float):
        return (float(value),) * 3
    if isinstance(value, list | tuple) and len(value) == 3 and all(
            isinstance(v, int | float) for v in value):
        return tuple(float(v) for v in value)
    raise InputError(where, f"expected a number or a list of 3 numbers, got {value!r}")


def _refuse_unknown_keys(config: Mapping[str, Any], known: Iterable[str], where: str) -> None:
    """Refuse the first key of ``config`` not in ``known``, naming it and the known ones."""
    unknown = sorted(set(config) - set(known))
    if unknown:
        raise InputError(f"{where}.{unknown[0]}",
                         f"unknown key (known: {', '.join(sorted(known))})")


def _triad(sensor: str, config: Mapping[str, Any], where: str) -> TriadErrors:
    scales = {**_SCALES[sensor], **_COMMON}
    _refuse_unknown_keys(config, scales, where)
    values: dict[str, Any] = {}
    for key, raw in config.items():
        if key in _SCALAR_KEYS:
            if not isinstance(raw, int | float) or raw <= 0:
                raise InputError(f"{where}.{key}", f"must be a positive number, got {raw!r}")
            continue
        axes = tuple(v * scales[key] for v in _axes(raw, f"{where}.{key}"))
        signed = key in ("bias_deg_per_s", "bias_mg", "bias_ut", "scale_factor_ppm",
                         "warmup_bias_deg_per_s", "warmup_bias_mg")
        if not signed and min(axes) < 0:
            raise InputError(f"{where}.{key}", f"must be >= 0, got {raw!r}")
        values[key] = axes
    fields: dict[str, Any] = {_FIELDS[k]: v for k, v in values.items() if k in _FIELDS}
    if "misalignment_mrad" in values:
        gx, gy, gz = values["misalignment_mrad"]
        fields["misalignment"] = ((0.0, gz, gy), (gz, 0.0, gx), (gy, gx, 0.0))
    instability = next((k for k in values if k.startswith("bias_instability")), None)
    direct = next((k for k in values if k.startswith("gauss_markov_sigma")), None)
    if instability and direct:
        raise InputError(f"{where}.{direct}", f"give either {instability} or {direct}")
    if direct:
        tau = values.get("bias_correlation_time_s")
        if tau is None:
            raise InputError(f"{where}.bias_correlation_time_s", f"required with {direct}")
        fields["gm_tau_s"] = tau
    if instability:
        tau = values.get("bias_correlation_time_s")
        if tau is None or min(tau) <= 0:
            raise InputError(f"{where}.bias_correlation_time_s",
                             "required (> 0) with a bias instability")
        white = fields.get("white_density", (0.0,) * 3)
        walk = fields.get("random_walk_density", (0.0,) * 3)
        try:
            fields["gm_sigma"] = tuple(gm_sigma_for_bias_instability(b, t, w, k) for b, t, w, k
                                       in zip(values[instability], tau, white, walk, strict=True))
        except ValueError as exc:
            raise InputError(f"{where}.{instability}", str(exc)) from exc
        fields["gm_tau_s"] = tau
    if "warmup_time_constant_s" in values:
        if min(values["warmup_time_constant_s"]) <= 0:
            raise InputError(f"{where}.warmup_time_constant_s", "must be > 0")
        fields["warmup_tau_s"] = values["warmup_time_constant_s"]
    for key in _SCALAR_KEYS & set(config):
        target = "saturation" if key.startswith("range") else "quantum"
        fields[target] = float(config[key]) * scales[key]
    return TriadErrors(**fields)


PA_PER_HPA = 100.0
_BARO_SCALES = {"rate_hz": 1.0, "noise_hpa": PA_PER_HPA, "resolution_hpa": PA_PER_HPA,
                "reference_hpa": PA_PER_HPA, "drift_hpa_per_h": PA_PER_HPA / 3600.0,
                "drift_sigma_hpa_per_h": PA_PER_HPA / 3600.0, "offsets_per_h": 1 / 3600.0,
                "offset_duration_s": 1.0, "warmup_hpa": PA_PER_HPA,
                "warmup_time_constant_s": 1.0, "lag_s": 1.0, "hold_share": 1.0}
_BARO_FIELDS = {"rate_hz": "rate_hz", "noise_hpa": "noise_pa", "resolution_hpa": "quantum_pa",
                "reference_hpa": "reference_pa", "drift_hpa_per_h": "drift_pa_per_s",
                "drift_sigma_hpa_per_h": "drift_sigma_pa_per_s",
                "offsets_per_h": "offsets_per_s", "offset_duration_s": "offset_duration_s",
                "warmup_hpa": "warmup_pa", "warmup_time_constant_s": "warmup_tau_s",
                "lag_s": "lag_s", "hold_share": "hold_share"}
_BARO_POSITIVE = {"rate_hz", "reference_hpa", "offset_duration_s", "warmup_time_constant_s"}
_OFFSET_KEYS = ("at_s", "size_hpa", "duration_s")


def _number(value: Any, where: str, low: float | None = None, strict: bool = False) -> float:
    number = typed_value(value, "float", where)
    if low is not None and (number <= low if strict else number < low):
        raise InputError(where, f"must be {'>' if strict else '>='} {low:g}, got {value!r}")
    return number


def _pressure_offset(item: Any, where: str) -> PressureOffset:
    if not isinstance(item, Mapping) or set(item) != set(_OFFSET_KEYS):
        raise InputError(where, f"expected {{{', '.join(_OFFSET_KEYS)}}}, got {item!r}")
    return PressureOffset(_number(item["at_s"], f"{where}.at_s", 0.0),
                          _number(item["duration_s"], f"{where}.duration_s", 0.0, strict=True),
                          _number(item["size_hpa"], f"{where}.size_hpa") * PA_PER_HPA)


def barometer_errors(config: Mapping[str, Any], where: str = "baro") -> BarometerErrors:
    """BarometerErrors from a ``baro`` section (module docstring); InputError names bad
    keys."""
    if not isinstance(config, Mapping):
        raise InputError(where, f"expected a mapping, got {config!r}")
    _refuse_unknown_keys(config, (*_BARO_SCALES, "offsets", "offset_size_hpa"), where)
    fields: dict[str, Any] = {}
    for key, scale in _BARO_SCALES.items():
        if key in config:
            low = None if key in ("drift_hpa_per_h", "warmup_hpa") else 0.0
            fields[_BARO_FIELDS[key]] = _number(config[key], f"{where}.{key}", low,
                                                strict=key in _BARO_POSITIVE) * scale
    if fields.get("hold_share", 0.0) >= 1:
        raise InputError(f"{where}.hold_share", f"must be < 1, got {config['hold_share']!r}")
    if "offset_size_hpa" in config:
        size = config["offset_size_hpa"]
        at = f"{where}.offset_size_hpa"
        if not isinstance(size, list | tuple) or len(size) != 2:
            raise InputError(at, f"expected [least, largest], got {size!r}")
        low, high = (_number(v, at, 0.0) * PA_PER_HPA for v in size)
        if low > high:
            raise InputError(at, f"the least is larger than the largest: {size!r}")
        fields["offset_size_pa"] = (low, high)
    offsets = config.get("offsets") or []
    if not isinstance(offsets, list):
        raise InputError(f"{where}.offsets", f"expected a list, got {offsets!r}")
    fields["offsets"] = tuple(_pressure_offset(item, f"{where}.offsets[{i}]")
                              for i, item in enumerate(offsets))
    return BarometerErrors(**fields)


def imu_errors(config: Mapping[str, Any], where: str = "imu") -> ImuErrors:
    """ImuErrors from a profile mapping (see module docstring); InputError names bad keys."""
    if not isinstance(config, Mapping):
        raise InputError(where, f"expected a mapping, got {config!r}")
    unknown = sorted(set(config) - {"gyro", "accel", "mag", "baro"})
    if unknown:
        raise InputError(f"{where}.{unknown[0]}",
                         "unknown sensor (known: gyro, accel, mag, baro)")
    sections = {s: _triad(s, config[s] or {}, f"{where}.{s}") for s in config if s != "baro"}
    if "baro" in config:
        sections["baro"] = barometer_errors(config["baro"] or {}, f"{where}.baro")
    return ImuErrors(**sections)


def profile(name: str, overrides: Mapping[str, Any] | None = None) -> ImuErrors:
    """The named profile, with ``overrides`` ({sensor: {key: value}}) merged in."""
    if name not in PROFILES:
        raise InputError("--imu", f"unknown profile '{name}' (known: {', '.join(PROFILES)})")
    merged = {"baro": dict(PHONE_BAROMETER)} | {s: dict(v) for s, v in PROFILES[name].items()}
    for sensor, values in (overrides or {}).items():
        merged.setdefault(sensor, {}).update(values or {})
    return imu_errors(merged, where=name)
