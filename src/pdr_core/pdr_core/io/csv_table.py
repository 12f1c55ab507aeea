"""A CSV table read as numbers, for pdr_core.io.csv_import: the header's column names, the
cells as float64 (a cell that is no number refused naming its row and column, blank lines
skipped), a column found by name or 0-based index, the columns chosen.
"""
from __future__ import annotations

import csv
import warnings
from pathlib import Path

import numpy as np

from pdr_core.errors import InputError


def column_index(path: Path, names: list[str] | None, col: str) -> int:
    """The 0-based index of column ``col`` (a header name of ``names``, or an index) of
    ``path``; InputError naming the columns there are."""
    if names is not None and col in names:
        return names.index(col)
    if col.isdigit():
        return int(col)
    known = f" (columns: {', '.join(names)})" if names else ""
    raise InputError(path, f"no column '{col}'{known}")


def read_table(path: Path, header: bool) -> tuple[list[str] | None, np.ndarray]:
    """The column names (None without a header) and the numbers (N, M) of a CSV file.

    An empty cell is a missing value: NaN. Row i of the table is line i + 2 of the file
    with a header (the header is line 1), i + 1 without: the rows the importers' messages
    name. InputError names the file and what is wrong with it: none, empty, no data rows,
    a row of another length than the first (its line), a cell that is not a number (its
    line, and its column by header name, by 0-based index without a header)."""
    if not path.is_file():
        raise InputError(path, "no such file")
    with path.open(newline="") as stream:
        first = next(csv.reader(stream), None)
    if first is None:
        raise InputError(path, "empty file")
    names = [c.strip() for c in first] if header else None
    lines = path.read_bytes().rstrip().count(b"\n") + 1 - int(header)
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", "loadtxt: input contained no data")
            table = np.loadtxt(path, delimiter=",", skiprows=1 if header else 0, ndmin=2,
                               dtype=np.float64)
    except ValueError:
        table = None
    if table is None or (len(table) and len(table) != lines):
        table = _cells_as_numbers(path, names, header)
    if table.shape[0] == 0:
        raise InputError(path, "no data rows")
    return names, table


def _cells_as_numbers(path: Path, names: list[str] | None, header: bool) -> np.ndarray:
    """:func:`read_table`'s slow path, for what np.loadtxt refuses or skips (empty cells,
    blank or comment lines, rows of other lengths, words): every line up to the last
    non-blank one is a row, a blank line a row of empty cells."""
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))[int(header):]
    while rows and not any(cell.strip() for cell in rows[-1]):
        rows.pop()
    if not rows:
        return np.empty((0, 0))
    blank = [not any(cell.strip() for cell in row) for row in rows]
    width = next((len(row) for row, empty in zip(rows, blank, strict=True) if not empty), 0)
    for i, row in enumerate(rows):
        if blank[i]:
            rows[i] = [""] * width
        elif len(row) != width:
            raise InputError(path, f"row {i + 1 + int(header)}: {len(row)} cells, but the first "
                                   f"data row has {width}")
    cells = np.char.strip(np.array(rows, dtype=str).reshape(len(rows), width))
    cells[cells == ""] = "nan"
    try:
        return cells.astype(np.float64)
    except ValueError:
        i, j = next((i, j) for (i, j), cell in np.ndenumerate(cells) if not _is_number(cell))
        raise InputError(path, f"row {i + 1 + int(header)}, column {column_label(names, j)}: "
                               f"'{cells[i, j]}' is not a number") from None


def _is_number(cell: str) -> bool:
    try:
        np.float64(cell)
    except ValueError:
        return False
    return True


def column_label(names: list[str] | None, index: int) -> str:
    """How messages name column ``index``: its header name, or its 0-based index."""
    return names[index] if names is not None and index < len(names) else str(index)


def select_columns(path: Path, names: list[str] | None, table: np.ndarray,
                   cols: tuple[str, ...]) -> np.ndarray:
    """The columns ``cols`` (header names or 0-based indices) of ``table`` (N, M) read from
    ``path`` with the header ``names``; InputError naming a column that is not there."""
    idx = [column_index(path, names, c) for c in cols]
    if max(idx) >= table.shape[1]:
        raise InputError(path, f"column index {max(idx)} out of range "
                               f"({table.shape[1]} columns)")
    return table[:, idx]


def read_columns(path: str | Path, columns: tuple[str, ...], header: bool = True) -> np.ndarray:
    """The named (or 0-based numbered) columns of a CSV file of numbers, (N, len(columns));
    InputError names the file and what is wrong with it."""
    path = Path(path)
    names, table = read_table(path, header)
    return select_columns(path, names, table, tuple(columns))
