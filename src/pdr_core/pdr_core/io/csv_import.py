"""Turning a CSV IMU log into ``sensor_msgs/Imu`` and ``geometry_msgs/PoseStamped`` batches.

The importer is driven entirely by a :class:`CsvImuFormat` (column mapping, units, axis
remap), so any log with one row per sample is imported without code of its own. Output
is SI and REP-145: specific force in m/s², angular rate in rad/s, stamps in ns.
``orientation_covariance[0] = -1`` (no orientation); without gyroscope columns,
``angular_velocity_covariance[0] = -1`` too (rates unknown).

An empty cell is a missing value, NaN (:func:`read_table`); a cell that is not a number
is refused naming its row (the file's line, the header line 1) and its column. A log
holds up to four sensors, each written at the stamps of its own rows (loggers that write
a row whenever any sensor fires leave the others' cells empty): the IMU (accelerometer
and gyroscope columns together, one ``sensor_msgs/Imu``), the magnetometer, the
barometer, and the truth (positions and quaternion). A row where all of one sensor's
cells are empty (or NaN) holds no reading of it. Invalid rows (:func:`sensor_rows`): a
sensor's cells partly empty (a sensor not yet started) or Inf, no time, no reading of
any sensor, a truth quaternion not of unit norm, a stamp not later than the same
sensor's previous reading. They are errors naming the file, the row and the column by
its header name, unless ``drop_invalid`` is set, in which case they are dropped and
counted. Rows that repeat the previous row exactly (same time, same cells) are refused
unless ``drop_duplicates`` is set; dropping them loses no information. The checks below
judge each sensor on its own rows (the sample interval is the IMU's).

Data that no walk or rest gives in the units they were read in (a median |f| far from g,
a sample rate beyond 5-10000 Hz, a 99th percentile of |ω| above 50 rad/s, a median |B|
beyond 1-1000 µT: pdr_core.sensors.imu_checks) are refused naming the file, the columns, the
value in the unit read and the unit option that fixes them (:func:`implausible_columns`),
unless ``accept_implausible`` is set (``--force``): then each is an InputWarning. An
accelerometer whose gravity was removed (a phone app's linear acceleration: the slow part
of the vector near zero against its median |f|, in whatever unit it is read,
pdr_core.sensors.imu_checks.gravity_removed) is refused as such, naming the gravity as the remedy
and never a unit (:func:`gravity_removed_problem`).

An accelerometer column that holds one value in every kept row, over at least
:data:`MIN_ROWS_CONSTANT_AXIS` rows, is refused whatever ``accept_implausible`` says
(:func:`constant_columns`): it is another column (a sensor's accuracy, a status), never
an axis of an accelerometer.

A barometer column (``pressure_col``, in hPa or Pa, :data:`PRESSURE_UNITS_PA`) becomes
``sensor_msgs/FluidPressure`` [Pa], one message per kept row with a reading. A median
beyond :data:`PRESSURE_RANGE` (30-110 kPa: from the height of Everest to above the
highest sea-level pressure ever measured) in the unit read is refused like the other
units (hPa read as Pa is 1 kPa); a pressure column that
holds one value over at least :data:`MIN_ROWS_CONSTANT_AXIS` rows is imported with an
InputWarning (:func:`warn_constant_pressure`): a coarse barometer at rest may hold one
reading, but more often it is another column.

A truth attitude (``quat_cols``, four columns in ``quat_order`` xyzw or wxyz) is the
tracked body's attitude C_world_body in the truth's world frame (z up); the sensor's
attitude written as ``pose.orientation`` of ``ground_truth/pose`` is
C_world_sensor = M · C_world_body · C_body_sensor (:func:`sensor_attitude`), with M the
``pos_axes`` remap and C_body_sensor the sensor frame's orientation in the body frame
(``sensor_in_body_rpy_deg``, ZYX roll, pitch, yaw as pdr_core.maths.rotations builds them). A
remap that mirrors the frame (determinant −1, ``-x,y,z``) is refused with quaternions: M
times a rotation is no rotation. A quaternion needs positions beside it (``pos_cols``):
``ground_truth/pose`` always carries a position, and the trajectory metrics would score
a navigator against zeros. A row whose quaternion's norm is not 1 within
:data:`QUATERNION_NORM_TOLERANCE` (a tracker that lost the body writes zeros) is an
invalid row like a NaN (:func:`valid_rows`); the others are normalised.

The pieces serve other importers too (pdr_core.io.oxiod, pdr_core.io.phone_import):
:func:`read_table`, :func:`valid_rows`, :func:`gravity_removed_problem`,
:func:`sensor_attitude` and the batch builders :func:`imu_batch`, :func:`pose_batch` and
:func:`mag_batch`.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError, InputWarning
from pdr_core.frames import MAP_FRAME, SENSOR_FRAME
from pdr_core.io.batch import MessageBatch, stamp_ns_from_seconds
from pdr_core.io.csv_rows import (
    SensorColumns,
    duplicate_rows,
    refuse_constant_axis,
    refuse_rows,
    sensor_rows,
    warn_constant_pressure,
)
from pdr_core.io.csv_table import column_index, column_label, read_table, select_columns
from pdr_core.io.msgtypes import FLUID_PRESSURE, IMU, MAGNETIC_FIELD, POSE_STAMPED
from pdr_core.maths.rotations import quaternion_xyzw, rotation_from_euler
from pdr_core.sensors.atmosphere import SEA_LEVEL_PRESSURE_PA
from pdr_core.sensors.barometry import PA_PER_HPA, PRESSURE_MAX_PA, PRESSURE_MIN_PA
from pdr_core.sensors.imu_checks import (
    ANGULAR_RATE_RANGE,
    FIELD_RANGE,
    SAMPLE_INTERVAL_RANGE,
    SLOW_PART_WINDOW_S,
    SPECIFIC_FORCE_RANGE,
    PlausibleRange,
    angular_rate_p99_radps,
    gravity_removed,
    median_field_t,
    median_interval_s,
    median_specific_force_mps2,
    slow_part_median_norm,
)
from pdr_core.topics import GROUND_TRUTH_POSE, IMU_DATA, IMU_MAG, IMU_PRESSURE
from pdr_core.units import (
    ACC_UNITS_MPS2,
    GYRO_UNITS_RADPS,
    MAG_UNITS_T,
    POS_UNITS_M,
    TIME_UNITS_S,
    UNIT_SYMBOLS,
)

# A barometer's units (name -> Pa) and their symbols; the ambient pressure anywhere a
# person walks is 30-110 kPa (Everest's summit about 34 kPa, the highest sea-level pressure
# measured 108.4 kPa)
PRESSURE_UNITS_PA = {"pa": 1.0, "hpa": PA_PER_HPA}
_SYMBOLS = {**UNIT_SYMBOLS, "pa": "Pa", "hpa": "hPa"}
PRESSURE_RANGE = PlausibleRange("median pressure", "Pa", PRESSURE_MIN_PA, PRESSURE_MAX_PA,
                                SEA_LEVEL_PRESSURE_PA, "300-1100 hPa, 30-110 kPa")

# The orders a truth's quaternion columns may come in: name -> the indices, among the
# columns as read, of x, y, z and w
QUATERNION_ORDERS = {"xyzw": (0, 1, 2, 3), "wxyz": (1, 2, 3, 0)}


@dataclass(frozen=True)
class CsvImuFormat:
    """How to read one CSV log. Columns are header names or 0-based indices (as str).

    Attributes:
        time_col: time column; ``time_unit`` one of s, ms, us, ns.
        acc_cols: three accelerometer columns (x, y, z); ``acc_unit`` mps2 or g.
        gyro_cols: three gyroscope columns, or () when the log has none; ``gyro_unit``
            radps or degps.
        pos_cols: three ground-truth position columns, or (); ``pos_unit`` m, cm or mm.
        mag_cols: three magnetometer columns, or (); ``mag_unit`` t, ut, nt or gauss;
            they take the accelerometer's axis remap unless ``mag_axes`` is given.
        pressure_col: the barometer column, or None; ``pressure_unit`` hpa or pa.
        axes: sensor-axis remap applied to acc and gyro, e.g. ("-y", "x", "z") means
            out_x = -in_y, out_y = in_x, out_z = in_z.
        acc_axes, gyro_axes: a remap for one sensor only, replacing ``axes`` for it (for
            logs whose accelerometer and gyroscope triads differ in sign or order).
        pos_axes: remap of the ground-truth positions into a right-handed, z-up map frame
            (a motion-capture frame may be left-handed: ``-x,y,z`` mirrors it); with
            ``quat_cols`` it turns the attitude too, and must not mirror.
        quat_cols: four columns of the truth's attitude quaternion, or () (needs
            ``pos_cols``); ``quat_order`` xyzw or wxyz. The tracked body's attitude in the
            truth's world frame, C_world_body.
        sensor_in_body_rpy_deg: the sensor frame's orientation in the tracked body's frame,
            C_body_sensor, as ZYX roll, pitch, yaw [deg]; the truth written is
            C_world_sensor = C_world_body · C_body_sensor.
        header: whether the first row holds column names.
        time_offset_s: added to every stamp.
        drop_invalid: drop NaN/Inf rows and non-increasing stamps instead of failing.
        drop_duplicates: drop rows that repeat the previous row exactly instead of failing.
        accept_implausible: import data that fail a plausibility check of their units
            (``--force``), each with an InputWarning, instead of failing; an accelerometer
            column constant over the whole recording is refused even so.
    """

    time_col: str
    acc_cols: tuple[str, str, str]
    time_unit: str = "s"
    acc_unit: str = "mps2"
    gyro_cols: tuple[str, ...] = ()
    gyro_unit: str = "radps"
    pos_cols: tuple[str, ...] = ()
    pos_unit: str = "m"
    mag_cols: tuple[str, ...] = ()
    mag_unit: str = "ut"
    mag_axes: tuple[str, str, str] | None = None
    pressure_col: str | None = None
    pressure_unit: str = "hpa"
    axes: tuple[str, str, str] = ("x", "y", "z")
    acc_axes: tuple[str, str, str] | None = None
    gyro_axes: tuple[str, str, str] | None = None
    pos_axes: tuple[str, str, str] = ("x", "y", "z")
    quat_cols: tuple[str, ...] = ()
    quat_order: str = "xyzw"
    sensor_in_body_rpy_deg: tuple[float, float, float] = (0.0, 0.0, 0.0)
    header: bool = True
    time_offset_s: float = 0.0
    drop_invalid: bool = False
    drop_duplicates: bool = False
    accept_implausible: bool = False
    imu_frame: str = SENSOR_FRAME
    map_frame: str = MAP_FRAME


@dataclass
class CsvImport:
    """Result of an import: ``imu`` and optional ``pose``, ``mag`` and ``pressure``
    batches, and the dropped rows (exact duplicates, and invalid rows dropped on
    request)."""

    imu: MessageBatch
    pose: MessageBatch | None
    rows_read: int
    rows_duplicate: int
    rows_invalid: int
    mag: MessageBatch | None = None
    pressure: MessageBatch | None = None


def unit_factor(value: str, choices: dict, what: str) -> float:
    """The SI factor of the unit ``value`` among ``choices`` (name -> factor), or an
    InputError naming the option ``what`` and the units it takes."""
    if value not in choices:
        raise InputError(what, f"unknown unit '{value}' (choose from {', '.join(choices)})")
    return choices[value]


def axis_matrix(axes: tuple[str, str, str]) -> np.ndarray:
    """3x3 signed permutation M with out = M @ in, from e.g. ("-y", "x", "z")."""
    matrix = np.zeros((3, 3))
    for row, spec in enumerate(axes):
        sign = -1.0 if spec.startswith("-") else 1.0
        name = spec.lstrip("+-")
        if name not in ("x", "y", "z"):
            raise InputError("--axes", f"'{spec}' is not one of [+-]x, [+-]y, [+-]z")
        matrix[row, "xyz".index(name)] = sign
    if not np.allclose(np.abs(matrix).sum(axis=0), 1.0):
        raise InputError("--axes", f"{','.join(axes)} does not use each axis exactly once")
    return matrix


@dataclass(frozen=True)
class Implausible:
    """Columns whose data no walk or rest gives in the unit they were read in: ``what``
    names the columns, the value in the unit read (and in SI) and the range expected;
    ``fix`` the unit option that makes them plausible."""

    what: str
    fix: str


def implausible_columns(fmt: CsvImuFormat, t_s: np.ndarray, acc: np.ndarray,
                        gyro: np.ndarray | None, mag: np.ndarray | None,
                        pressure: np.ndarray | None = None) -> list[Implausible]:
    """What no walk or rest gives in the units the columns were read in (the ranges of
    pdr_core.sensors.imu_checks and :data:`PRESSURE_RANGE`), one per sensor. Arguments in SI, of
    the rows kept: stamps [s] (N,), specific force [m/s²], angular rate [rad/s] or None,
    magnetic field [T] or None, each (N, 3), and pressure [Pa] (N,) or None."""
    problems = []
    if len(t_s) >= 2:
        interval = median_interval_s(t_s)
        problems.append(implausible(fmt.time_col, SAMPLE_INTERVAL_RANGE, interval,
                                    fmt.time_unit, TIME_UNITS_S, "--time-unit",
                                    f" ({1.0 / interval:.3g} Hz)" if interval > 0 else ""))
    if len(acc):
        acc_cols = ",".join(fmt.acc_cols)
        problems.append(gravity_removed_problem(acc_cols, t_s, acc) or implausible(
            acc_cols, SPECIFIC_FORCE_RANGE, median_specific_force_mps2(acc), fmt.acc_unit,
            ACC_UNITS_MPS2, "--acc-unit"))
    if gyro is not None and len(gyro):
        problems.append(implausible(",".join(fmt.gyro_cols), ANGULAR_RATE_RANGE,
                                    angular_rate_p99_radps(gyro), fmt.gyro_unit,
                                    GYRO_UNITS_RADPS, "--gyro-unit"))
    if mag is not None and len(mag):
        problems.append(implausible(",".join(fmt.mag_cols), FIELD_RANGE, median_field_t(mag),
                                    fmt.mag_unit, MAG_UNITS_T, "--mag-unit"))
    if pressure is not None and len(pressure):
        problems.append(implausible(str(fmt.pressure_col), PRESSURE_RANGE,
                                    float(np.median(pressure)), fmt.pressure_unit,
                                    PRESSURE_UNITS_PA, "--pressure-unit"))
    return [problem for problem in problems if problem is not None]


def gravity_removed_problem(columns: str, t_s: np.ndarray,
                            acc_mps2: np.ndarray) -> Implausible | None:
    """What is wrong with an accelerometer whose gravity was taken out, or None: the
    specific forces ``acc_mps2`` (N, 3) [m/s², in the unit given] of ``columns``
    (comma-separated) at the stamps ``t_s`` [s] (N,) look gravity-removed
    (pdr_core.sensors.imu_checks.gravity_removed, a ratio that holds in any unit: read in g, as a
    user told "the data look like g" did, a phone's linear acceleration is a plausible
    2-4 g). The problem names the median |f| and the median norm of the slow part; the fix
    the gravity, never a unit."""
    median = median_specific_force_mps2(acc_mps2)
    if not gravity_removed(t_s, acc_mps2):
        return None
    slow = slow_part_median_norm(t_s, acc_mps2)
    what = "column" if "," not in columns else "columns"
    return Implausible(
        f"{what} {columns}: median |f| {median:.3g} m/s² ({median / STANDARD_GRAVITY_MPS2:.2g} "
        f"g), and the median norm of its slow part ({SLOW_PART_WINDOW_S:g} s moving mean) "
        f"{slow:.3g} m/s², {slow / median:.2f} times the median |f| (data with gravity give "
        "about 1, in any unit): the accelerometer looks gravity-removed (a phone app's "
        "linear or user acceleration)",
        "import the raw accelerometer (gravity included) instead, or add the gravity part to "
        "it (Sensor Logger's Gravity.csv: pdr-sim import-phone DIR); a unit option cannot fix "
        "it (--force accepts it as read)")


def implausible(columns: str, plausible_range: PlausibleRange, value_si: float, unit: str,
                units: dict[str, float], flag: str, note: str = "") -> Implausible | None:
    """None when the statistic ``value_si`` (SI) of ``columns`` (comma-separated), read in
    ``unit`` of ``units`` (name -> SI factor; the option ``flag``), lies in
    ``plausible_range``; else what is wrong (``note`` follows the value) and the fix."""
    if not plausible_range.excludes(value_si):
        return None
    factor = units[unit]
    value = f"{value_si / factor:.4g} {_SYMBOLS[unit]}"
    if _SYMBOLS[unit] != plausible_range.si_unit:
        value += f" = {value_si:.4g} {plausible_range.si_unit}"
    what = "column" if "," not in columns else "columns"
    problem = (f"{what} {columns}: {plausible_range.statistic} {value}{note}, read in "
               f"{_SYMBOLS[unit]} ({flag} {unit}); expected {plausible_range.expected}")
    fix = plausible_range.unit_fix(value_si, units, read_in=factor)
    if fix is None:
        return Implausible(problem, f"no unit of {flag} makes them plausible; check {what} "
                                    f"{columns} (or pass --force to accept them as read)")
    return Implausible(problem, f"the data look like {_SYMBOLS[fix]}: pass {flag} {fix} "
                                "(or --force to accept them as read)")


def refuse_implausible(path: Path, problems: list[Implausible | None], accept: bool) -> None:
    """Refuse ``path`` for the first of ``problems`` (an InputError naming the fix), or with
    ``accept`` (``--force``) say what is used as read: an InputWarning each."""
    for problem in problems:
        if problem is None:
            continue
        if not accept:
            raise InputError(path, f"{problem.what}: {problem.fix}")
        warnings.warn(InputWarning(path, f"{problem.what}: accepted as read (--force)"),
                      stacklevel=3)


def turning_remap(world_axes: tuple[str, str, str]) -> np.ndarray:
    """The remap M of a truth's world frame (``--pos-axes``, :func:`axis_matrix`) that an
    attitude is turned by; one that mirrors the frame (determinant −1) is refused: M·C
    would be no rotation."""
    remap = axis_matrix(world_axes)
    if np.linalg.det(remap) < 0:
        raise InputError("--pos-axes", f"{','.join(world_axes)} mirrors the truth's frame, "
                                       "which turns an attitude (--quat-cols) into no "
                                       "rotation at all: give a remap that only turns it "
                                       "(an even number of minus signs and swaps), or "
                                       "import the positions without --quat-cols")
    return remap


def sensor_attitude(body_xyzw: np.ndarray,
                    sensor_in_body_rpy_deg: tuple[float, float, float] = (0.0, 0.0, 0.0),
                    world_axes: tuple[str, str, str] = ("x", "y", "z")) -> np.ndarray:
    """The sensor's attitude C_world_sensor = M · C_world_body · C_body_sensor, (N, 4) unit
    quaternions (x, y, z, w; w >= 0), from the tracked body's attitude ``body_xyzw`` (N, 4)
    (x, y, z, w; normalised here), the sensor frame's orientation in the body frame
    ``sensor_in_body_rpy_deg`` (ZYX roll, pitch, yaw [deg]: C_body_sensor =
    Rz(yaw)·Ry(pitch)·Rx(roll)) and the remap M of the world frame ``world_axes``
    (:func:`turning_remap`)."""
    remap = Rotation.from_matrix(turning_remap(world_axes))
    sensor_in_body = rotation_from_euler(*np.radians(np.asarray(sensor_in_body_rpy_deg, float)))
    return quaternion_xyzw(remap * Rotation.from_quat(body_xyzw) * sensor_in_body).reshape(-1, 4)


def imu_batch(stamp_ns: np.ndarray, frame: str, acc: np.ndarray,
              gyro: np.ndarray | None) -> MessageBatch:
    """sensor_msgs/Imu of specific force [m/s²] and angular rate [rad/s] (None: the log
    has no gyroscope, rates unknown: ``angular_velocity_covariance[0] = -1``), (N, 3) each,
    stamped ``stamp_ns`` (N,) in ``frame``; no orientation (``orientation_covariance[0] =
    -1``), covariances unknown (0)."""
    n = len(stamp_ns)
    no_estimate = np.zeros((n, 9))
    no_estimate[:, 0] = -1.0
    return MessageBatch(IMU, stamp_ns, frame, {
        "orientation": np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)),
        "orientation_covariance": no_estimate,
        "angular_velocity": np.zeros((n, 3)) if gyro is None else gyro,
        "angular_velocity_covariance": no_estimate.copy() if gyro is None else np.zeros((n, 9)),
        "linear_acceleration": acc,
        "linear_acceleration_covariance": np.zeros((n, 9)),
    })


def pose_batch(stamp_ns: np.ndarray, frame: str, position: np.ndarray,
               orientation_xyzw: np.ndarray | None = None) -> MessageBatch:
    """geometry_msgs/PoseStamped of the truth in ``frame``: position [m] (N, 3) and
    orientation (N, 4, x y z w; None: identity, a truth of positions only)."""
    if orientation_xyzw is None:
        orientation_xyzw = np.tile([0.0, 0.0, 0.0, 1.0], (len(stamp_ns), 1))
    return MessageBatch(POSE_STAMPED, stamp_ns, frame, {
        "pose.position": position, "pose.orientation": orientation_xyzw})


def mag_batch(stamp_ns: np.ndarray, frame: str, field_t: np.ndarray) -> MessageBatch:
    """sensor_msgs/MagneticField [T] (N, 3) in ``frame``, covariance unknown (0)."""
    return MessageBatch(MAGNETIC_FIELD, stamp_ns, frame, {
        "magnetic_field": field_t, "magnetic_field_covariance": np.zeros((len(stamp_ns), 9))})


def _check_truth_attitude(fmt: CsvImuFormat) -> None:
    """Refuse quaternion options that cannot make a truth (module docstring)."""
    if len(fmt.sensor_in_body_rpy_deg) != 3:
        raise InputError("--sensor-in-body-rpy-deg", "needs 3 angles (roll,pitch,yaw), got "
                                                     f"{len(fmt.sensor_in_body_rpy_deg)}")
    if not fmt.quat_cols:
        if any(fmt.sensor_in_body_rpy_deg):
            raise InputError("--sensor-in-body-rpy-deg", "turns a truth attitude: give its "
                                                         "--quat-cols too")
        return
    if len(fmt.quat_cols) != 4:
        raise InputError("--quat-cols", f"needs 4 columns (in --quat-order {fmt.quat_order}), "
                                        f"got {len(fmt.quat_cols)}")
    if fmt.quat_order not in QUATERNION_ORDERS:
        raise InputError("--quat-order", f"unknown order '{fmt.quat_order}' (choose from "
                                         f"{', '.join(QUATERNION_ORDERS)})")
    if not fmt.pos_cols:
        raise InputError("--quat-cols", "needs --pos-cols too: ground_truth/pose always "
                                        "carries a position, and a navigator's errors would "
                                        "be measured against a truth that never moves")
    turning_remap(fmt.pos_axes)


def import_csv(path: str | Path, fmt: CsvImuFormat) -> CsvImport:
    """Read a CSV IMU log into batches (see :class:`CsvImuFormat`), each sensor's topic at
    the stamps of its own rows (module docstring)."""
    path = Path(path)
    time_scale = unit_factor(fmt.time_unit, TIME_UNITS_S, "--time-unit")
    acc_scale = unit_factor(fmt.acc_unit, ACC_UNITS_MPS2, "--acc-unit")
    gyro_scale = unit_factor(fmt.gyro_unit, GYRO_UNITS_RADPS, "--gyro-unit")
    pos_scale = unit_factor(fmt.pos_unit, POS_UNITS_M, "--pos-unit")
    mag_scale = unit_factor(fmt.mag_unit, MAG_UNITS_T, "--mag-unit")
    pressure_scale = unit_factor(fmt.pressure_unit, PRESSURE_UNITS_PA, "--pressure-unit")
    for option, cols in (("--acc-cols", fmt.acc_cols), ("--gyro-cols", fmt.gyro_cols),
                         ("--pos-cols", fmt.pos_cols), ("--mag-cols", fmt.mag_cols)):
        if cols and len(cols) != 3:
            raise InputError(option, f"needs 3 columns (x,y,z), got {len(cols)}")
    _check_truth_attitude(fmt)
    acc_remap = axis_matrix(fmt.acc_axes or fmt.axes)
    gyro_remap = axis_matrix(fmt.gyro_axes or fmt.axes)
    names, table = read_table(path, fmt.header)

    def columns(cols: tuple[str, ...]) -> np.ndarray:
        return select_columns(path, names, table, cols)

    def sensor(name: str, cols: tuple[str, ...]) -> SensorColumns:
        labels = [column_label(names, column_index(path, names, c)) for c in cols]
        return SensorColumns(name, labels, columns(cols))

    t_s = columns((fmt.time_col,))[:, 0] * time_scale + fmt.time_offset_s
    sensors = {IMU_DATA: sensor("the IMU", fmt.acc_cols + fmt.gyro_cols)}
    if fmt.mag_cols:
        sensors[IMU_MAG] = sensor("the magnetometer", fmt.mag_cols)
    if fmt.pressure_col:
        sensors[IMU_PRESSURE] = sensor("the barometer", (fmt.pressure_col,))
    if fmt.pos_cols:
        sensors[GROUND_TRUTH_POSE] = sensor("the truth", fmt.pos_cols + fmt.quat_cols)
    acc_read = sensors[IMU_DATA].cells[:, :3]
    quat = columns(fmt.quat_cols)[:, QUATERNION_ORDERS[fmt.quat_order]] if fmt.quat_cols \
        else None
    first_row = 2 if fmt.header else 1
    duplicate = duplicate_rows(t_s, np.hstack([s.cells for s in sensors.values()]))
    if duplicate.any() and not fmt.drop_duplicates:
        refuse_rows(path, duplicate, first_row, "exact duplicate of the previous row",
                "--drop-duplicates")
    keep = sensor_rows(path, t_s, column_label(names, column_index(path, names, fmt.time_col)),
                       list(sensors.values()), first_row, fmt.drop_invalid, quat, ~duplicate)
    rows = {topic: keep & s.reading for topic, s in sensors.items()}
    for topic, s in sensors.items():
        if not rows[topic].any():
            raise InputError(path, f"no valid row with a reading of {s.name} "
                                   f"({','.join(s.labels)})")
    imu_rows = rows[IMU_DATA]
    acc = acc_read[imu_rows] * acc_scale @ acc_remap.T
    gyro = (sensors[IMU_DATA].cells[imu_rows, 3:] * gyro_scale @ gyro_remap.T
            if fmt.gyro_cols else None)
    mag = None if IMU_MAG not in rows else sensors[IMU_MAG].cells[rows[IMU_MAG]] * mag_scale \
        @ axis_matrix(fmt.mag_axes or fmt.acc_axes or fmt.axes).T
    pressure_read = None if IMU_PRESSURE not in rows else \
        sensors[IMU_PRESSURE].cells[rows[IMU_PRESSURE], 0]
    pressure = None if pressure_read is None else pressure_read * pressure_scale
    refuse_constant_axis(path, names, fmt.acc_cols, acc_read[imu_rows])
    if pressure_read is not None:
        warn_constant_pressure(path, str(fmt.pressure_col), pressure_read)
    refuse_implausible(path, implausible_columns(fmt, t_s[imu_rows], acc, gyro, mag, pressure),
                       accept=fmt.accept_implausible)

    stamp_ns = {topic: stamp_ns_from_seconds(t_s[r]) for topic, r in rows.items()}
    pose = None
    if GROUND_TRUTH_POSE in rows:
        truth = rows[GROUND_TRUTH_POSE]
        orientation = None if quat is None else sensor_attitude(
            quat[truth], fmt.sensor_in_body_rpy_deg, fmt.pos_axes)
        pose = pose_batch(stamp_ns[GROUND_TRUTH_POSE], fmt.map_frame, columns(fmt.pos_cols)[
            truth] * pos_scale @ axis_matrix(fmt.pos_axes).T, orientation)
    pressure_batch = None if pressure is None else MessageBatch(
        FLUID_PRESSURE, stamp_ns[IMU_PRESSURE], fmt.imu_frame,
        {"fluid_pressure": pressure, "variance": np.zeros(len(pressure))})
    return CsvImport(imu_batch(stamp_ns[IMU_DATA], fmt.imu_frame, acc, gyro), pose,
                     rows_read=len(t_s), rows_duplicate=int(duplicate.sum()),
                     rows_invalid=int((~keep & ~duplicate).sum()),
                     mag=None if mag is None else mag_batch(stamp_ns[IMU_MAG], fmt.imu_frame,
                                                            mag),
                     pressure=pressure_batch)
