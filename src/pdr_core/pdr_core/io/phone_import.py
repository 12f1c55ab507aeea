"""A phone's own recording, one CSV per sensor, into the project's topics (issue 54).

Phone logging apps write each sensor to its own file, with its own time column and rate:
Sensor Logger (iOS and Android, the ``Accelerometer.csv``, ``Gyroscope.csv``, ... of the
folder it exports) and many others. :class:`PhoneLayout` says which file holds which
sensor and in which columns (:class:`SensorFile`); :func:`sensor_logger_layout` builds it
for a Sensor Logger folder, and a user names the files of any other layout
(``pdr-sim import-phone DIR --acc FILE:TIME:X,Y,Z ...``). :func:`import_phone` reads them:

- ``imu/data`` (sensor_msgs/Imu): the accelerometer and the gyroscope paired at the slower
  one's stamps, the faster one's readings averaged over each sample's interval
  (pdr_core.sensors.sample_pairing: nothing interpolated or held; a sample whose interval holds no
  reading of the other sensor is dropped and counted);
- ``imu/mag`` (sensor_msgs/MagneticField, T) and ``imu/pressure``
  (sensor_msgs/FluidPressure, Pa): each reading at its own stamp, at its own rate.

**Gravity-removed accelerometers.** A phone's "accelerometer" file may hold the motion
only, gravity removed (Sensor Logger's ``Accelerometer.csv``: Android's linear
acceleration, iOS's user acceleration), with the gravity part in a file of its own
(``Gravity.csv``). The specific force is then their sum, ``f = s · (a + g)``, paired
sample by sample. Given alone, such a file is refused (|f| far below 1 g while the phone
moves: pdr_core.io.csv_import's check), naming the gravity file as the remedy.

**Signs.** Android gives the specific force as REP-145 does (a phone lying face up reads
+9.81 m/s² on z): ``s = +1``. iOS's Core Motion gives the opposite, the inertial force
(face up: gravity −9.81 m/s² on z): ``s = −1``. The gyroscope (rad/s) and the
magnetometer (µT) follow the same right-handed device axes on both (x to the right of the
screen, y to its top, z out of it). Sensor Logger's "Standardise Units & Frames" setting
turns an iPhone's export to Android's convention, so the platform alone does not say which
holds: when the folder has the phone's own attitude (``Orientation.csv``, a quaternion
of the device in an x-north, z-up world), the vertical it gives in device axes is
compared with the gravity file's direction (:func:`gravity_sign_from_attitude`): +1 or −1
within :data:`SIGN_AGREEMENT`, else the platform of ``Metadata.csv`` decides; a folder with
neither is refused, naming ``--convention``.

A Sensor Logger folder may also hold ``TotalAcceleration.csv`` (Android: the accelerometer
as measured, gravity included): it is the specific force itself and is preferred to the
sum. Its uncalibrated files are left out (calibrated readings are the app's advice), and
so are its fused ``Orientation.csv`` (not a truth) and ``relativeAltitude``.
"""
from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.frames import SENSOR_FRAME
from pdr_core.io.batch import MessageBatch
from pdr_core.io.csv_import import (
    PRESSURE_RANGE,
    PRESSURE_UNITS_PA,
    Implausible,
    gravity_removed_problem,
    implausible,
    imu_batch,
    mag_batch,
    refuse_implausible,
    unit_factor,
)
from pdr_core.io.csv_rows import not_later, refuse_rows, valid_rows
from pdr_core.io.csv_table import column_index, read_table, select_columns
from pdr_core.io.msgtypes import FLUID_PRESSURE
from pdr_core.sensors.imu_checks import (
    ANGULAR_RATE_RANGE,
    FIELD_RANGE,
    SAMPLE_INTERVAL_RANGE,
    SPECIFIC_FORCE_RANGE,
    angular_rate_p99_radps,
    median_field_t,
    median_interval_s,
    median_specific_force_mps2,
)
from pdr_core.sensors.sample_pairing import interval_means
from pdr_core.units import ACC_UNITS_MPS2, GYRO_UNITS_RADPS, MAG_UNITS_T, TIME_UNITS_S

# The sign s of f = s · (a + g) per platform (module docstring): Android's accelerometer
# reads the specific force, iOS's the inertial force
CONVENTION_SIGNS = {"android": 1.0, "ios": -1.0}
# The median cosine between the phone's own vertical and its gravity file's direction
# beyond which their agreement (+1) or opposition (−1) decides the sign: the two come from
# one fusion, so they agree to the digit (measured: 1.000000 on an Android, −1.000000 on an
# iPhone export); 0.9 leaves room for a fusion that lags by a few degrees
SIGN_AGREEMENT = 0.9

# Sensor Logger's files (its docs' UNITS.md): time in ns since the epoch, vectors x, y, z
# in m/s², rad/s and µT, pressure in hPa (mbar)
SENSOR_LOGGER_TIME = "time"
SENSOR_LOGGER_VECTOR = ("x", "y", "z")
SENSOR_LOGGER_FILES = {
    "total": "TotalAcceleration.csv", "accelerometer": "Accelerometer.csv",
    "gravity": "Gravity.csv", "gyroscope": "Gyroscope.csv",
    "magnetometer": "Magnetometer.csv", "barometer": "Barometer.csv",
    "orientation": "Orientation.csv", "metadata": "Metadata.csv"}
SENSOR_LOGGER_PRESSURE = "pressure"
SENSOR_LOGGER_QUATERNION = ("qx", "qy", "qz", "qw")


@dataclass(frozen=True)
class SensorFile:
    """One sensor's CSV file: its path, its time column and its value columns (x, y, z
    of the output's axes; one column for a barometer), header names or 0-based indices."""

    path: Path
    time_col: str
    value_cols: tuple[str, ...]

    def describe(self) -> str:
        return f"{self.path.name} ({self.time_col}; {','.join(self.value_cols)})"


@dataclass(frozen=True)
class PhoneLayout:
    """Which file holds which sensor, in which units, and the accelerometer's sign.

    Attributes:
        accelerometer: the accelerometer (gravity included, or removed when ``gravity``
            is given).
        gravity: the gravity part of a gravity-removed accelerometer, or None.
        gyroscope, magnetometer, barometer: their files, or None.
        time_unit: the unit of every time column (s, ms, us, ns).
        acc_unit, gyro_unit, mag_unit, pressure_unit: units of the values (the
            accelerometer's applies to the gravity file too).
        acc_sign: s of f = s · (a + g): +1 Android's convention, −1 iOS's.
        sign_source: how the sign was decided, in words (for the summary).
        drop_invalid: drop NaN/Inf rows and non-increasing stamps instead of failing.
        accept_implausible: import data that fail a plausibility check of their units.
    """

    accelerometer: SensorFile
    gravity: SensorFile | None = None
    gyroscope: SensorFile | None = None
    magnetometer: SensorFile | None = None
    barometer: SensorFile | None = None
    time_unit: str = "ns"
    acc_unit: str = "mps2"
    gyro_unit: str = "radps"
    mag_unit: str = "ut"
    pressure_unit: str = "hpa"
    acc_sign: float = 1.0
    sign_source: str = "Android's convention (given)"
    drop_invalid: bool = False
    accept_implausible: bool = False


@dataclass
class PhoneImport:
    """What :func:`import_phone` read: the batches (``mag`` and ``pressure`` None when the
    layout has no such file) and one line per topic saying what went in."""

    imu: MessageBatch
    mag: MessageBatch | None
    pressure: MessageBatch | None
    lines: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class _Readings:
    """One file's kept rows: stamps [ns] (N,), values in SI (N, M), rows read, dropped."""

    stamp_ns: np.ndarray
    values: np.ndarray
    rows_read: int
    rows_dropped: int

    def rate_hz(self) -> float:
        if len(self.stamp_ns) < 2:
            return float("nan")
        return (len(self.stamp_ns) - 1) / ((self.stamp_ns[-1] - self.stamp_ns[0]) * 1e-9)


def read_sensor(sensor: SensorFile, time_unit: str, scale: float, drop_invalid: bool,
                check_rate: bool = True) -> _Readings:
    """The kept rows of ``sensor``'s file: stamps [ns], values × ``scale`` (SI). Rows with
    a NaN or Inf (an empty cell) or a stamp not later than every row before are refused
    naming the file and the row, or dropped with ``drop_invalid``; a file without a valid
    row is refused, and with ``check_rate`` one whose median interval lies beyond 5-10000
    Hz in ``time_unit`` (a barometer, at 1-25 Hz on phones, is not checked)."""
    names, table = read_table(sensor.path, header=True)
    columns = (sensor.time_col, *sensor.value_cols)
    picked = select_columns(sensor.path, names, table, columns)
    keep = valid_rows(sensor.path, picked, first_row=2, drop_invalid=drop_invalid,
                      labels=list(columns))
    t_s = picked[:, 0] * unit_factor(time_unit, TIME_UNITS_S, "--time-unit")
    late = not_later(t_s, keep)
    if late.any() and not drop_invalid:
        refuse_rows(sensor.path, late, 2, f"time {picked[np.flatnonzero(late)[0], 0]:.9g} "
                                          "does not increase", "--drop-invalid", sensor.time_col)
    keep &= ~late
    if not keep.any():
        raise InputError(sensor.path, "no valid row")
    if check_rate:
        refuse_implausible(sensor.path, [implausible(
            sensor.time_col, SAMPLE_INTERVAL_RANGE, median_interval_s(t_s[keep]), time_unit,
            TIME_UNITS_S, "--time-unit")], accept=False)
    exact_ns = None if time_unit != "ns" else _integer_stamps(
        sensor.path, column_index(sensor.path, names, sensor.time_col))
    stamp_ns = exact_ns[keep] if exact_ns is not None else np.rint(t_s[keep] * 1e9).astype(
        np.int64)
    return _Readings(stamp_ns, picked[keep, 1:] * scale, len(picked), int((~keep).sum()))


def _integer_stamps(path: Path, column: int) -> np.ndarray | None:
    """The time column ``column`` of ``path`` as int64 ns when every cell is an integer
    (a float64 holds an epoch stamp in ns to 256 ns only), else None."""
    try:
        return np.loadtxt(path, delimiter=",", skiprows=1, usecols=column, dtype=np.int64,
                          ndmin=1)
    except ValueError:
        return None


def _refuse_gravity_removed(layout: PhoneLayout, acc: _Readings) -> None:
    """Refuse an accelerometer given without its gravity file that looks gravity-removed
    (pdr_core.io.csv_import.gravity_removed_problem), naming ``--gravity`` as the remedy."""
    problem = gravity_removed_problem(",".join(layout.accelerometer.value_cols),
                                      acc.stamp_ns * 1e-9, acc.values)
    if problem is not None:
        problem = Implausible(problem.what, "name its gravity file with --gravity "
                                            "FILE:TIME:X,Y,Z (Sensor Logger's Gravity.csv), "
                                            "or import the raw accelerometer instead (--force "
                                            "accepts it as read)")
    refuse_implausible(layout.accelerometer.path, [problem], accept=layout.accept_implausible)


def paired_specific_force(layout: PhoneLayout, scale: float
                          ) -> tuple[_Readings, str]:
    """The specific force [m/s²] f = s · (a + g) at the accelerometer's stamps (module
    docstring), and what went in, in words; accelerometer samples without a gravity
    reading in their interval are dropped."""
    acc = read_sensor(layout.accelerometer, layout.time_unit, scale, layout.drop_invalid)
    sign = "" if layout.acc_sign > 0 else "−"
    if layout.gravity is None:
        _refuse_gravity_removed(layout, acc)
        return (_Readings(acc.stamp_ns, layout.acc_sign * acc.values, acc.rows_read,
                          acc.rows_dropped), f"= {sign}{layout.accelerometer.path.name}")
    gravity = read_sensor(layout.gravity, layout.time_unit, scale, layout.drop_invalid)
    paired, count = interval_means(acc.stamp_ns, gravity.stamp_ns, gravity.values)
    has = count > 0
    force = layout.acc_sign * (acc.values[has] + paired[has])
    return (_Readings(acc.stamp_ns[has], force, acc.rows_read,
                      acc.rows_dropped + int((~has).sum())),
            f"= {sign}({layout.accelerometer.path.name} + {layout.gravity.path.name})")


def paired_imu(force: _Readings, gyro: _Readings) -> tuple[_Readings, np.ndarray, str]:
    """The IMU samples: their specific force [m/s²] (stamps, values and counts) and angular
    rate [rad/s], at the slower sensor's stamps, the faster one's readings averaged over
    each sample's interval (pdr_core.sensors.sample_pairing); a sample without a reading of the
    other is dropped and counted. Also how they were paired, in words."""
    if force.rate_hz() <= gyro.rate_hz() or np.isnan(gyro.rate_hz()):
        base, other, base_name, other_name = force, gyro, "accelerometer", "gyroscope"
    else:
        base, other, base_name, other_name = gyro, force, "gyroscope", "accelerometer"
    means, count = interval_means(base.stamp_ns, other.stamp_ns, other.values)
    has = count > 0
    per_sample = float(np.mean(count[has])) if has.any() else 0.0
    how = (f"at the {base_name}'s stamps, the {other_name}'s mean over each sample's "
           f"interval ({per_sample:.2g} a sample)")
    if (~has).any():
        how += f"; {int((~has).sum())} {base_name} samples without one dropped"
    dropped = force.rows_dropped + int((~has).sum()) if base is force else force.rows_dropped
    stamps = base.stamp_ns[has]
    if base is force:
        return _Readings(stamps, base.values[has], force.rows_read, dropped), means[has], how
    return _Readings(stamps, means[has], force.rows_read, dropped), base.values[has], how


def _line(topic: str, readings: _Readings, what: str, source: str) -> str:
    """What went into ``topic``, for the import's summary."""
    dropped = f", {readings.rows_dropped} dropped" if readings.rows_dropped else ""
    return (f"{topic.lstrip('/')}: {len(readings.stamp_ns)} messages at "
            f"{readings.rate_hz():.3g} Hz, {what}; from {source} ({readings.rows_read} rows "
            f"read{dropped})")


def _magnetometer(layout: PhoneLayout) -> tuple[MessageBatch, str]:
    sensor = layout.magnetometer
    scale = unit_factor(layout.mag_unit, MAG_UNITS_T, "--mag-unit")
    readings = read_sensor(sensor, layout.time_unit, scale, layout.drop_invalid)
    refuse_implausible(sensor.path, [implausible(",".join(sensor.value_cols), FIELD_RANGE,
                                                 median_field_t(readings.values),
                                                 layout.mag_unit, MAG_UNITS_T, "--mag-unit")],
                       accept=layout.accept_implausible)
    line = _line(topics.IMU_MAG, readings,
                        f"median |B| {median_field_t(readings.values) * 1e6:.1f} µT",
                        sensor.describe())
    return mag_batch(readings.stamp_ns, SENSOR_FRAME, readings.values), line


def _barometer(layout: PhoneLayout) -> tuple[MessageBatch, str]:
    sensor = layout.barometer
    if len(sensor.value_cols) != 1:
        raise InputError("--pressure", f"needs 1 value column, got {len(sensor.value_cols)}")
    scale = unit_factor(layout.pressure_unit, PRESSURE_UNITS_PA, "--pressure-unit")
    readings = read_sensor(sensor, layout.time_unit, scale, layout.drop_invalid,
                           check_rate=False)
    pressure = readings.values[:, 0]
    refuse_implausible(sensor.path, [implausible(sensor.value_cols[0], PRESSURE_RANGE,
                                                 float(np.median(pressure)),
                                                 layout.pressure_unit, PRESSURE_UNITS_PA,
                                                 "--pressure-unit")],
                       accept=layout.accept_implausible)
    line = _line(topics.IMU_PRESSURE, readings,
                        f"median {np.median(pressure) / 100.0:.2f} hPa", sensor.describe())
    batch = MessageBatch(FLUID_PRESSURE, readings.stamp_ns, SENSOR_FRAME, {
        "fluid_pressure": pressure, "variance": np.zeros(len(pressure))})
    return batch, line


def import_phone(layout: PhoneLayout) -> PhoneImport:
    """Read the files of ``layout`` into ``imu/data``, ``imu/mag`` and ``imu/pressure``
    batches (module docstring). Units are checked as import-csv checks them (a refusal
    names the file, the columns and the unit option that fixes them)."""
    acc_scale = unit_factor(layout.acc_unit, ACC_UNITS_MPS2, "--acc-unit")
    force, source = paired_specific_force(layout, acc_scale)
    rate = None
    source = f"{source} ({layout.sign_source})"
    if layout.gyroscope is None:
        source += "; no gyroscope: rates unknown"
    else:
        gyro = read_sensor(layout.gyroscope, layout.time_unit,
                           unit_factor(layout.gyro_unit, GYRO_UNITS_RADPS, "--gyro-unit"),
                           layout.drop_invalid)
        refuse_implausible(layout.gyroscope.path, [implausible(
            ",".join(layout.gyroscope.value_cols), ANGULAR_RATE_RANGE,
            angular_rate_p99_radps(gyro.values), layout.gyro_unit, GYRO_UNITS_RADPS,
            "--gyro-unit")], accept=layout.accept_implausible)
        force, rate, how = paired_imu(force, gyro)
        source += f"; {layout.gyroscope.path.name} at {gyro.rate_hz():.3g} Hz, {how}"
    refuse_implausible(layout.accelerometer.path, [implausible(
        ",".join(layout.accelerometer.value_cols), SPECIFIC_FORCE_RANGE,
        median_specific_force_mps2(force.values), layout.acc_unit, ACC_UNITS_MPS2,
        "--acc-unit")], accept=layout.accept_implausible)
    imu = imu_batch(force.stamp_ns, SENSOR_FRAME, force.values, rate)
    lines = [_line(topics.IMU_DATA, force,
                   f"median |f| {median_specific_force_mps2(force.values):.3f} m/s²",
                   f"specific force {source}")]
    mag = pressure = None
    if layout.magnetometer is not None:
        mag, line = _magnetometer(layout)
        lines.append(line)
    if layout.barometer is not None:
        pressure, line = _barometer(layout)
        lines.append(line)
    return PhoneImport(imu, mag, pressure, lines)


def metadata_platform(path: Path) -> str | None:
    """The ``platform`` of a Sensor Logger ``Metadata.csv`` in lower case (ios, android),
    or None without one."""
    if not path.is_file():
        return None
    with path.open(newline="") as stream:
        rows = list(csv.DictReader(stream))
    platform = (rows[0].get("platform") or "").strip().lower() if rows else ""
    return platform or None


def gravity_sign_from_attitude(orientation: Path, gravity: Path, time_unit: str
                               ) -> float | None:
    """+1 when the gravity file's direction agrees with the vertical of the phone's own
    attitude (the quaternion of ``orientation``, device to an x-north z-up world, at the
    same stamps), −1 when it is opposite, None when neither holds within
    :data:`SIGN_AGREEMENT` or the files do not share stamps."""
    quaternion = read_sensor(SensorFile(orientation, SENSOR_LOGGER_TIME,
                                        SENSOR_LOGGER_QUATERNION), time_unit, 1.0, True)
    down = read_sensor(SensorFile(gravity, SENSOR_LOGGER_TIME, SENSOR_LOGGER_VECTOR),
                       time_unit, 1.0, True)
    common, qi, gi = np.intersect1d(quaternion.stamp_ns, down.stamp_ns, return_indices=True)
    if not len(common):
        return None
    up = Rotation.from_quat(quaternion.values[qi]).inv().apply([0.0, 0.0, 1.0])
    direction = down.values[gi] / np.linalg.norm(down.values[gi], axis=1)[:, None]
    cosine = float(np.median(np.sum(up * direction, axis=1)))
    if abs(cosine) < SIGN_AGREEMENT:
        return None
    return float(np.sign(cosine))


def _sign(folder: Path, gravity: Path | None, convention: str | None) -> tuple[float, str]:
    """The accelerometer's sign and why (module docstring): ``convention`` when given,
    else the phone's own attitude, else Metadata.csv's platform."""
    if convention is not None:
        unit_factor(convention, CONVENTION_SIGNS, "--convention")
        return CONVENTION_SIGNS[convention], f"{convention}'s convention (--convention)"
    orientation = folder / SENSOR_LOGGER_FILES["orientation"]
    if gravity is not None and orientation.is_file():
        sign = gravity_sign_from_attitude(orientation, gravity, "ns")
        if sign is not None:
            name = "Android's" if sign > 0 else "iOS's"
            return sign, f"{name} convention: {gravity.name} against {orientation.name}"
    platform = metadata_platform(folder / SENSOR_LOGGER_FILES["metadata"])
    if platform in CONVENTION_SIGNS:
        return CONVENTION_SIGNS[platform], f"{platform}'s convention (Metadata.csv)"
    raise InputError(folder, "cannot tell the accelerometer's sign: no Orientation.csv that "
                             "agrees with the gravity file, no platform in Metadata.csv; pass "
                             "--convention android (a phone face up reads +9.8 m/s² on z) or "
                             "--convention ios (−9.8)")


def sensor_logger_layout(folder: Path, convention: str | None = None,
                         drop_invalid: bool = False, accept_implausible: bool = False
                         ) -> PhoneLayout:
    """The layout of a Sensor Logger export ``folder`` (module docstring), or an
    InputError naming the folder and the files it lacks."""
    def present(key: str) -> Path | None:
        path = folder / SENSOR_LOGGER_FILES[key]
        return path if path.is_file() else None

    def vector(key: str) -> SensorFile | None:
        path = present(key)
        return None if path is None else SensorFile(path, SENSOR_LOGGER_TIME,
                                                    SENSOR_LOGGER_VECTOR)

    total, accelerometer, gravity = present("total"), present("accelerometer"), present("gravity")
    if total is None and (accelerometer is None or gravity is None):
        found = ", ".join(sorted(p.name for p in folder.glob("*.csv"))) or "no CSV file"
        raise InputError(folder, "not a Sensor Logger export with an accelerometer: it needs "
                                 "TotalAcceleration.csv, or Accelerometer.csv with "
                                 f"Gravity.csv (found: {found}); name the files of another "
                                 "layout with --acc FILE:TIME:X,Y,Z (--gravity, --gyro, "
                                 "--mag, --pressure)")
    sign, source = _sign(folder, gravity, convention)
    barometer = present("barometer")
    return PhoneLayout(
        accelerometer=vector("total") or vector("accelerometer"),
        gravity=None if total is not None else vector("gravity"),
        gyroscope=vector("gyroscope"), magnetometer=vector("magnetometer"),
        barometer=None if barometer is None else SensorFile(
            barometer, SENSOR_LOGGER_TIME, (SENSOR_LOGGER_PRESSURE,)),
        time_unit="ns", acc_sign=sign, sign_source=source, drop_invalid=drop_invalid,
        accept_implausible=accept_implausible)
