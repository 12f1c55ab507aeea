"""The rows of a CSV import checked, for pdr_core.io.csv_import: an accelerometer axis that
never moves refused, a barometer that never changes warned about; rows with a value that
cannot be used refused naming row and column, or dropped with ``--drop-invalid``; a truth's
quaternions of unit norm; a sparse sensor's own rows (its cells filled where it read);
stamps that do not increase and duplicated rows found.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdr_core.errors import InputError, InputWarning
from pdr_core.io.csv_table import column_index

# A real accelerometer axis is never exactly constant over this many rows (10 s at
# 100 Hz): its noise, walking or at rest, spans more than one step of its resolution. A
# coarse one (8-10 bits, tens of mg a step) may hold one value while it rests for a few
# seconds, and a short synthetic file may be constant: fewer rows are left alone.
MIN_ROWS_CONSTANT_AXIS = 1000

# How far from 1 a quaternion's norm may be before its row is invalid: a quaternion
# printed with 3 significant digits is within 0.002 of unit norm; a tracker that lost the
# body writes zeros, and a column mapped wrongly is far off
QUATERNION_NORM_TOLERANCE = 0.01


def constant_columns(values: np.ndarray) -> np.ndarray:
    """The indices of the columns of the (N, M) ``values`` that hold one value in all N
    rows (peak-to-peak 0), when N >= :data:`MIN_ROWS_CONSTANT_AXIS`; else none."""
    if len(values) < MIN_ROWS_CONSTANT_AXIS:
        return np.array([], dtype=int)
    return np.flatnonzero(np.ptp(values, axis=0) == 0)


def refuse_constant_axis(path: Path, names: list[str] | None, acc_cols: tuple[str, ...],
                          acc_read: np.ndarray) -> None:
    """Refuse ``path`` when one of the accelerometer columns ``acc_cols`` is constant
    (:func:`constant_columns` of ``acc_read``, the kept rows as read, (N, 3)), naming it by
    its header name (by its index without a header); ``--force`` does not accept it."""
    constant = constant_columns(acc_read)
    if not len(constant):
        return
    i = int(constant[0])
    index = column_index(path, names, acc_cols[i])
    raise InputError(path, f"column {names[index] if names else index}, the "
                           f"{('first', 'second', 'third')[i]} of --acc-cols, is "
                           f"{acc_read[0, i]:g} in all {len(acc_read)} rows: constant over "
                           "the whole recording, so it cannot be an accelerometer axis (a "
                           "sensor's accuracy or status column?); check --acc-cols (--force "
                           "does not accept a constant axis)")


def warn_constant_pressure(path: Path, column: str, pressure_read: np.ndarray) -> None:
    """An InputWarning naming ``column`` when the barometer readings ``pressure_read`` (the
    kept rows as read, (N,)) hold one value over at least :data:`MIN_ROWS_CONSTANT_AXIS`
    rows: a barometer's noise moves its last digit, so this is most likely another column
    (it is imported all the same: a coarse barometer at rest may hold one reading)."""
    if not len(constant_columns(pressure_read[:, None])):
        return
    warnings.warn(InputWarning(path, f"column {column} (--pressure-col) is "
                                     f"{pressure_read[0]:g} in all {len(pressure_read)} rows: "
                                     "constant over the whole recording, which a barometer's "
                                     "noise rarely is; check --pressure-col"), stacklevel=3)


def refuse_rows(path: Path, bad: np.ndarray, first_row: int, what: str, flag: str,
                column: str | None = None) -> None:
    """Refuse ``path`` for the first of the ``bad`` (N,) rows: an InputError naming it
    (numbered from ``first_row``), its ``column`` if given, ``what`` is wrong, how many
    such rows there are and the ``flag`` that drops them."""
    row = int(np.flatnonzero(bad)[0])
    where = f"row {row + first_row}" + ("" if column is None else f", column {column}")
    raise InputError(path, f"{where}: {what} ({int(bad.sum())} such rows; {flag} drops them)")


def _refuse_cells(path: Path, bad: np.ndarray, first_row: int, labels: list[str],
                  values: np.ndarray, nan_note: str = "") -> None:
    """Refuse ``path`` for the first row of ``bad`` (N, M) cells, naming it (numbered from
    ``first_row``), the first such cell's column (``labels``, M) and its value in
    ``values`` (N, M): Inf, or empty or NaN followed by ``nan_note``."""
    rows = bad.any(axis=1)
    row = int(np.flatnonzero(rows)[0])
    col = int(np.flatnonzero(bad[row])[0])
    value = values[row, col]
    what = "empty or NaN" + nan_note if np.isnan(value) else f"{value:g}"
    refuse_rows(path, rows, first_row, what, "--drop-invalid", labels[col])


def valid_rows(path: Path, values: np.ndarray, first_row: int, drop_invalid: bool,
               quaternion: np.ndarray | None = None,
               labels: list[str] | None = None) -> np.ndarray:
    """(N,) bool: the rows of ``values`` (N, M) that hold no NaN (an empty cell) or Inf
    and, with ``quaternion`` (N, 4), whose quaternion's norm is 1 within
    :data:`QUATERNION_NORM_TOLERANCE`. Unless ``drop_invalid``, any other row is refused:
    an InputError naming ``path``, the first such row (numbered from ``first_row``), its
    column (``labels``, M names; 0-based indices without) and ``--drop-invalid``."""
    finite = np.isfinite(values)
    if not drop_invalid and not finite.all():
        _refuse_cells(path, ~finite, first_row,
                      labels or [str(i) for i in range(values.shape[1])], values)
    keep = finite.all(axis=1)
    if quaternion is not None:
        keep &= unit_quaternions(path, quaternion, first_row, drop_invalid)
    return keep


def unit_quaternions(path: Path, quaternion: np.ndarray, first_row: int,
                      drop_invalid: bool) -> np.ndarray:
    """(N,) bool: False for the rows of ``quaternion`` (N, 4) whose norm is further than
    :data:`QUATERNION_NORM_TOLERANCE` from 1 (a NaN row is judged elsewhere), refused
    unless ``drop_invalid`` (:func:`valid_rows`)."""
    norm = np.linalg.norm(quaternion, axis=1)
    with np.errstate(invalid="ignore"):
        off = np.abs(norm - 1.0) > QUATERNION_NORM_TOLERANCE
    if off.any() and not drop_invalid:
        refuse_rows(path, off, first_row, f"quaternion norm {norm[np.flatnonzero(off)[0]]:.4g}, "
                                      f"not 1 (±{QUATERNION_NORM_TOLERANCE:g})", "--drop-invalid")
    return ~off


@dataclass(frozen=True)
class SensorColumns:
    """One sensor of a log: ``name`` (what messages call it), the ``labels`` of its
    columns (header names, or 0-based indices) and its ``cells`` (N, k) as read, NaN where
    empty. A row holds a reading of it when any of its cells is not empty."""

    name: str
    labels: list[str]
    cells: np.ndarray

    @property
    def reading(self) -> np.ndarray:
        return ~np.isnan(self.cells).all(axis=1)


def sensor_rows(path: Path, t_s: np.ndarray, time_label: str, sensors: list[SensorColumns],
                first_row: int, drop_invalid: bool, quaternion: np.ndarray | None = None,
                judged: np.ndarray | None = None) -> np.ndarray:
    """(N,) bool: the valid rows of a log of ``sensors`` stamped ``t_s`` [s] (N,) by the
    column ``time_label`` (module docstring: a sensor's cells all empty is no reading of
    it; partly empty, an Inf, no time, no reading of any sensor, a truth ``quaternion``
    (N, 4) not of unit norm, or a stamp not later than the sensor's previous reading make
    an invalid row). Unless ``drop_invalid``, an invalid row is refused: an InputError
    naming ``path``, the row (numbered from ``first_row``), the column and
    ``--drop-invalid``. Only the rows ``judged`` (N,) bool (default: all) can be valid
    (the others, e.g. exact duplicates, are left out)."""
    judged = np.ones(len(t_s), bool) if judged is None else judged
    no_time = judged & ~np.isfinite(t_s)
    if no_time.any() and not drop_invalid:
        _refuse_cells(path, no_time[:, None], first_row, [time_label], t_s[:, None],
                      " (no time)")
    valid = judged & ~no_time
    for sensor in sensors:
        partly = np.isnan(sensor.cells) & sensor.reading[:, None]
        bad = (partly | np.isinf(sensor.cells)) & judged[:, None]
        if bad.any() and not drop_invalid:
            _refuse_cells(path, bad, first_row, sensor.labels, sensor.cells,
                          f", while other columns of {sensor.name} ({','.join(sensor.labels)})"
                          " hold values (a sensor not yet started, or a value lost?)")
        valid &= ~bad.any(axis=1)
    silent = judged & ~np.any([sensor.reading for sensor in sensors], axis=0)
    if silent.any() and not drop_invalid:
        labels = ",".join(label for sensor in sensors for label in sensor.labels)
        refuse_rows(path, silent, first_row, f"no reading of any sensor (every cell of {labels} "
                                         "is empty)", "--drop-invalid")
    valid &= ~silent
    if quaternion is not None:
        valid &= unit_quaternions(path, np.where(judged[:, None], quaternion, np.nan),
                                   first_row, drop_invalid)
    for sensor in sensors:
        late = not_later(t_s, valid & sensor.reading)
        if late.any() and not drop_invalid:
            refuse_rows(path, late, first_row, f"time {t_s[np.flatnonzero(late)[0]]:.9f} does "
                                           f"not increase over {sensor.name}'s previous "
                                           "reading", "--drop-invalid", time_label)
        valid &= ~late
    return valid


def not_later(t_s: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """(N,) bool: the ``rows`` whose stamp ``t_s`` is not later than that of every one of
    the ``rows`` before."""
    kept_t = np.where(rows, t_s, -np.inf)
    earlier_max = np.concatenate(([-np.inf], np.maximum.accumulate(kept_t)[:-1]))
    return rows & ~(t_s > earlier_max)


def duplicate_rows(t_s: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """(N,) bool: the rows that repeat the previous row exactly, stamp ``t_s`` (N,) and
    every cell of ``cells`` (N, M) (an empty cell repeats an empty cell)."""
    values = np.column_stack([t_s, cells])
    same = (values[1:] == values[:-1]) | (np.isnan(values[1:]) & np.isnan(values[:-1]))
    return np.concatenate(([False], same.all(axis=1)))
