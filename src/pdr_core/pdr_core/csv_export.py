"""A bag's ``imu/data`` as a phone-style CSV log (``pdr-sim export-csv``), the way
pdr_core.csv_import reads one back: one row per ``imu/data`` message, in the bag's order,
with the unit in each column's name.

- ``t_s``: the message's stamp [s] from the first ``imu/data`` message's;
- ``acc_x_mps2``, ``acc_y_mps2``, ``acc_z_mps2``: specific force [m/s²];
- ``gyr_x_radps``, ``gyr_y_radps``, ``gyr_z_radps``: angular rate [rad/s], left out when
  the bag has no gyroscope (``angular_velocity_covariance[0] = -1`` in every message,
  REP-145, as import-csv marks a log without one);
- with ``imu/mag``: ``mag_x_ut``, ``mag_y_ut``, ``mag_z_ut`` [µT], the reading paired with
  the row as the pocket navigator pairs them (pdr_core.magnetometer_pairing: the latest
  at most 0.05 s old), empty cells when there is none;
- with ``ground_truth/pose``: ``gt_x_m``, ``gt_y_m``, ``gt_z_m`` [m], the true position
  interpolated at the row's stamp (pdr_core.metrics.truth_at).

Numbers are written with the fewest digits that read back to the same float64, so the
log imports to the same values (the magnetometer within a rounding of µT to T).

- :func:`log_table`: the column names and the values of a bag's batches;
- :func:`import_arguments`: the ``pdr-sim import-csv`` options that read such a log back;
- :func:`step_times`: ``ground_truth/step`` stamps [s] on the log's time axis;
- :func:`write_csv`: a table to a file, refusing to replace one unless asked;
- :func:`export_bag`: all of it for one bag (the CLI's work).
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdr_core import topics
from pdr_core.batch import MessageBatch
from pdr_core.errors import InputError
from pdr_core.magnetometer_pairing import paired_mag
from pdr_core.metrics import truth_at

TIME_COLUMN = "t_s"
ACC_COLUMNS = ("acc_x_mps2", "acc_y_mps2", "acc_z_mps2")
GYRO_COLUMNS = ("gyr_x_radps", "gyr_y_radps", "gyr_z_radps")
MAG_COLUMNS = ("mag_x_ut", "mag_y_ut", "mag_z_ut")
TRUTH_COLUMNS = ("gt_x_m", "gt_y_m", "gt_z_m")
T_TO_UT = 1e6


@dataclass
class LogTable:
    """The log: ``columns`` (k,) names and ``values`` (N, k); NaN in a magnetometer
    column is an empty cell (no reading)."""

    columns: list[str]
    values: np.ndarray

    def has(self, names: tuple[str, ...]) -> bool:
        return names[0] in self.columns


def has_gyroscope(imu: MessageBatch) -> bool:
    """False when every message says its rates are unknown (REP-145)."""
    return not bool(np.all(imu["angular_velocity_covariance"][:, 0] == -1))


def log_table(imu: MessageBatch, mag: MessageBatch | None = None,
              pose: MessageBatch | None = None) -> LogTable:
    """The log of ``imu`` (module docstring), with ``mag`` and the truth ``pose`` when
    given."""
    columns = [TIME_COLUMN, *ACC_COLUMNS]
    parts = [((imu.stamp_ns - imu.stamp_ns[0]) * 1e-9)[:, None], imu["linear_acceleration"]]
    if has_gyroscope(imu):
        columns += GYRO_COLUMNS
        parts.append(imu["angular_velocity"])
    if mag is not None:
        columns += MAG_COLUMNS
        parts.append(paired_mag(imu.stamp_ns, mag)[0] * T_TO_UT)
    if pose is not None:
        columns += TRUTH_COLUMNS
        parts.append(truth_at(pose, imu.stamp_ns))
    return LogTable(columns, np.hstack(parts))


def import_arguments(table: LogTable) -> list[str]:
    """The ``pdr-sim import-csv`` options that read the log back, units spelled out."""
    args = ["--time-col", TIME_COLUMN, "--time-unit", "s",
            "--acc-cols", ",".join(ACC_COLUMNS), "--acc-unit", "mps2"]
    if table.has(GYRO_COLUMNS):
        args += ["--gyro-cols", ",".join(GYRO_COLUMNS), "--gyro-unit", "radps"]
    if table.has(MAG_COLUMNS):
        args += ["--mag-cols", ",".join(MAG_COLUMNS), "--mag-unit", "ut"]
    if table.has(TRUTH_COLUMNS):
        args += ["--pos-cols", ",".join(TRUTH_COLUMNS), "--pos-unit", "m"]
    return args


def step_times(steps: MessageBatch, start_ns: int) -> np.ndarray:
    """The stamps [s] of ``ground_truth/step`` (each true step's end) from ``start_ns``,
    the log's time origin."""
    return (steps.stamp_ns - start_ns) * 1e-9


def _cell(value: float, empty_if_nan: bool) -> str:
    return "" if empty_if_nan and value != value else repr(value)


def write_csv(path: Path, table: LogTable, *, overwrite: bool = False) -> None:
    """Write ``table`` with a header row; the file appears whole or not at all. An
    existing ``path`` is an InputError unless ``overwrite``."""
    refuse_existing(path, overwrite)
    empty = [name in MAG_COLUMNS for name in table.columns]
    lines = [",".join(table.columns)]
    lines += [",".join(_cell(v, e) for v, e in zip(row, empty, strict=True))
              for row in table.values.tolist()]
    path.parent.mkdir(parents=True, exist_ok=True)
    staging = path.with_name(f".{path.name}.partial")
    staging.write_text("\n".join(lines) + "\n")
    os.replace(staging, path)


def refuse_existing(path: Path, overwrite: bool) -> None:
    """InputError when ``path`` exists and ``overwrite`` is not set."""
    if path.exists() and not overwrite:
        raise InputError(path, "output exists already (remove it or pass --overwrite)")


@dataclass
class Export:
    """What :func:`export_bag` wrote: the log, and the count of true steps (or None)."""

    table: LogTable
    steps: int | None


def export_bag(bag: Path, out: Path, steps_out: Path | None = None, *,
               overwrite: bool = False, strict: bool = False) -> Export:
    """``bag``'s log to ``out`` and, with ``steps_out``, its true step times (one column
    ``t_s``, on the log's time axis). Nothing is written when an input or an output is
    refused."""
    from pdr_core.bag import BagReader

    reader = BagReader(bag, strict=strict)
    reader.require_topics([topics.IMU_DATA] + ([topics.GROUND_TRUTH_STEP] if steps_out
                                                else []))
    for path in (out, steps_out):
        if path is not None:
            refuse_existing(path, overwrite)
    wanted = [t for t in (topics.IMU_DATA, topics.IMU_MAG, topics.GROUND_TRUTH_POSE,
                          topics.GROUND_TRUTH_STEP) if t in reader.topics]
    batches = reader.read_batches(wanted)
    imu = batches[topics.IMU_DATA]
    if len(imu) == 0:
        raise InputError(topics.IMU_DATA, f"{bag}: no messages to export")
    table = log_table(imu, batches.get(topics.IMU_MAG), batches.get(topics.GROUND_TRUTH_POSE))
    steps = None
    if steps_out is not None:
        times = step_times(batches[topics.GROUND_TRUTH_STEP], int(imu.stamp_ns[0]))
        write_csv(steps_out, LogTable([TIME_COLUMN], times[:, None]), overwrite=overwrite)
        steps = len(times)
    write_csv(out, table, overwrite=overwrite)
    return Export(table, steps)
