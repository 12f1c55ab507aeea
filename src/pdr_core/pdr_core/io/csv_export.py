"""A bag's sensors and truth as one phone-style CSV log (``pdr-sim export-csv``), the way
pdr_core.io.csv_import reads one back: one row per stamp at which any exported topic has a
message, its cells of the topics without a message at that stamp empty (the sparse log
import-csv reads, each topic at its own stamps), the unit in each column's name.

- ``t_s``: the row's stamp [s] from the log's origin, the earliest exported message's
  stamp: import-csv gives back every stamp to the ns, shifted by that constant (absolute
  stamps in float64 seconds would keep only about 0.2 µs);
- ``imu/data``: ``acc_x_mps2``, ``acc_y_mps2``, ``acc_z_mps2`` specific force [m/s²];
  ``gyr_x_radps``, ``gyr_y_radps``, ``gyr_z_radps`` angular rate [rad/s], left out when
  the bag has no gyroscope (``angular_velocity_covariance[0] = -1`` in every message,
  REP-145, as import-csv marks a log without one);
- ``imu/mag``: ``mag_x_t``, ``mag_y_t``, ``mag_z_t`` [T] (tesla, so that the values read
  back exactly);
- ``imu/pressure``: ``pressure_pa`` [Pa];
- ``ground_truth/pose``: ``gt_x_m``, ``gt_y_m``, ``gt_z_m`` [m] and its attitude
  ``gt_qx``, ``gt_qy``, ``gt_qz``, ``gt_qw`` (x y z w; import-csv normalises it and
  writes it with w >= 0, the same rotation).

Numbers are written with the fewest digits that read back to the same float64; a NaN is
an empty cell. Other topics are not written: :attr:`Export.unwritten` names them.

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
from pdr_core.errors import InputError
from pdr_core.io.batch import MessageBatch

TIME_COLUMN = "t_s"
ACC_COLUMNS = ("acc_x_mps2", "acc_y_mps2", "acc_z_mps2")
GYRO_COLUMNS = ("gyr_x_radps", "gyr_y_radps", "gyr_z_radps")
MAG_COLUMNS = ("mag_x_t", "mag_y_t", "mag_z_t")
PRESSURE_COLUMNS = ("pressure_pa",)
TRUTH_COLUMNS = ("gt_x_m", "gt_y_m", "gt_z_m")
TRUTH_QUATERNION_COLUMNS = ("gt_qx", "gt_qy", "gt_qz", "gt_qw")
# The topics a log holds, in its column order
EXPORTED_TOPICS = (topics.IMU_DATA, topics.IMU_MAG, topics.IMU_PRESSURE,
                   topics.GROUND_TRUTH_POSE)


@dataclass
class LogTable:
    """The log: ``columns`` (k,) names, ``values`` (N, k), NaN in an empty cell, and
    ``origin_ns``, the stamp [ns] of ``t_s`` = 0."""

    columns: list[str]
    values: np.ndarray
    origin_ns: int = 0

    def has(self, names: tuple[str, ...]) -> bool:
        return names[0] in self.columns


def has_gyroscope(imu: MessageBatch) -> bool:
    """False when every message says its rates are unknown (REP-145)."""
    return not bool(np.all(imu["angular_velocity_covariance"][:, 0] == -1))


def _topic_columns(imu: MessageBatch, mag: MessageBatch | None, pressure: MessageBatch | None,
                   pose: MessageBatch | None
                   ) -> list[tuple[MessageBatch, tuple[str, ...], np.ndarray]]:
    """Each given topic's batch, its columns and its values (N, k) in the log's units."""
    parts = [(imu, ACC_COLUMNS, imu["linear_acceleration"])]
    if has_gyroscope(imu):
        parts[0] = (imu, ACC_COLUMNS + GYRO_COLUMNS,
                    np.hstack([imu["linear_acceleration"], imu["angular_velocity"]]))
    if mag is not None:
        parts.append((mag, MAG_COLUMNS, mag["magnetic_field"]))
    if pressure is not None:
        parts.append((pressure, PRESSURE_COLUMNS, pressure["fluid_pressure"][:, None]))
    if pose is not None:
        parts.append((pose, TRUTH_COLUMNS + TRUTH_QUATERNION_COLUMNS,
                      np.hstack([pose["pose.position"], pose["pose.orientation"]])))
    return parts


def _row_keys(stamp_ns: np.ndarray) -> np.ndarray:
    """(N, 2) int64: each message's stamp and how many messages before it share that stamp
    (``stamp_ns`` sorted): messages of two topics with the same key share a row."""
    first = np.searchsorted(stamp_ns, stamp_ns, side="left")
    return np.column_stack([stamp_ns, np.arange(len(stamp_ns)) - first])


def log_table(imu: MessageBatch, mag: MessageBatch | None = None,
              pose: MessageBatch | None = None,
              pressure: MessageBatch | None = None) -> LogTable:
    """The log of ``imu`` and, when given, ``mag``, ``pressure`` and the truth ``pose``
    (module docstring): the union of their stamps, one row per stamp (a stamp repeated
    within a topic takes a row per message)."""
    parts = []
    for batch, names, values in _topic_columns(imu, mag, pressure, pose):
        order = np.argsort(batch.stamp_ns, kind="stable")
        parts.append((names, values[order], _row_keys(batch.stamp_ns[order])))
    keys, rows = np.unique(np.vstack([k for _, _, k in parts]), axis=0, return_inverse=True)
    columns = [TIME_COLUMN]
    origin_ns = int(keys[0, 0])
    table = [((keys[:, 0] - origin_ns) * 1e-9)[:, None]]
    start = 0
    for names, values, part_keys in parts:
        cells = np.full((len(keys), len(names)), np.nan)
        cells[rows.ravel()[start:start + len(part_keys)]] = values
        start += len(part_keys)
        columns += names
        table.append(cells)
    return LogTable(columns, np.hstack(table), origin_ns)


def import_arguments(table: LogTable) -> list[str]:
    """The ``pdr-sim import-csv`` options that read the log back, units spelled out."""
    args = ["--time-col", TIME_COLUMN, "--time-unit", "s",
            "--acc-cols", ",".join(ACC_COLUMNS), "--acc-unit", "mps2"]
    if table.has(GYRO_COLUMNS):
        args += ["--gyro-cols", ",".join(GYRO_COLUMNS), "--gyro-unit", "radps"]
    if table.has(MAG_COLUMNS):
        args += ["--mag-cols", ",".join(MAG_COLUMNS), "--mag-unit", "t"]
    if table.has(PRESSURE_COLUMNS):
        args += ["--pressure-col", PRESSURE_COLUMNS[0], "--pressure-unit", "pa"]
    if table.has(TRUTH_COLUMNS):
        args += ["--pos-cols", ",".join(TRUTH_COLUMNS), "--pos-unit", "m",
                 "--quat-cols", ",".join(TRUTH_QUATERNION_COLUMNS), "--quat-order", "xyzw"]
    return args


def step_times(steps: MessageBatch, start_ns: int) -> np.ndarray:
    """The stamps [s] of ``ground_truth/step`` (each true step's end) from ``start_ns``,
    the log's time origin."""
    return (steps.stamp_ns - start_ns) * 1e-9


def _cell(value: float) -> str:
    return "" if value != value else repr(value)


def write_csv(path: Path, table: LogTable, *, overwrite: bool = False) -> None:
    """Write ``table`` with a header row; the file appears whole or not at all. An
    existing ``path`` is an InputError unless ``overwrite``."""
    refuse_existing(path, overwrite)
    lines = [",".join(table.columns)]
    lines += [",".join(map(_cell, row)) for row in table.values.tolist()]
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
    """What :func:`export_bag` wrote: the log, the count of true steps (or None), and the
    bag's topics it did not write."""

    table: LogTable
    steps: int | None
    unwritten: list[str]


def export_bag(bag: Path, out: Path, steps_out: Path | None = None, *,
               overwrite: bool = False, strict: bool = False) -> Export:
    """``bag``'s log to ``out`` (its topics of :data:`EXPORTED_TOPICS`) and, with
    ``steps_out``, its true step times (one column ``t_s``, on the log's time axis).
    Nothing is written when an input or an output is refused."""
    from pdr_core.io.bag import BagReader

    reader = BagReader(bag, strict=strict)
    reader.require_topics([topics.IMU_DATA] + ([topics.GROUND_TRUTH_STEP] if steps_out
                                                else []))
    for path in (out, steps_out):
        if path is not None:
            refuse_existing(path, overwrite)
    steps_topic = [topics.GROUND_TRUTH_STEP] if steps_out is not None else []
    wanted = [t for t in EXPORTED_TOPICS if t in reader.topics] + steps_topic
    batches = reader.read_batches(wanted)
    imu = batches[topics.IMU_DATA]
    if len(imu) == 0:
        raise InputError(topics.IMU_DATA, f"{bag}: no messages to export")
    logged = {t: batches[t] for t in EXPORTED_TOPICS if t in batches and len(batches[t])}
    table = log_table(imu, logged.get(topics.IMU_MAG), logged.get(topics.GROUND_TRUTH_POSE),
                      logged.get(topics.IMU_PRESSURE))
    steps = None
    if steps_out is not None:
        times = step_times(batches[topics.GROUND_TRUTH_STEP], table.origin_ns)
        write_csv(steps_out, LogTable([TIME_COLUMN], times[:, None]), overwrite=overwrite)
        steps = len(times)
    write_csv(out, table, overwrite=overwrite)
    return Export(table, steps, sorted(set(reader.topics) - set(logged) - set(steps_topic)))
