"""``pdr-sim import-phone``'s options turned into a pdr_core.io.phone_import.PhoneLayout.

- :func:`sensor_file`: ``FILE:TIME:X,Y,Z`` (or ``FILE:TIME:COL``) -> SensorFile, FILE
  relative to the export's folder;
- :func:`phone_layout`: the layout of the command line, as a context manager: a Sensor
  Logger zip is unpacked into a temporary folder that lives while the files are read.
"""
from __future__ import annotations

import argparse
import tempfile
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from pdr_core.errors import InputError
from pdr_core.io.phone_import import (
    CONVENTION_SIGNS,
    PhoneLayout,
    SensorFile,
    sensor_logger_layout,
)

NAMED_SENSORS = ("acc", "gravity", "gyro", "mag", "pressure")
DEFAULT_TIME_UNIT = "ns"


def sensor_file(folder: Path, option: str, spec: str, values: int) -> SensorFile:
    """The file of ``--option FILE:TIME:COLS`` (``values`` comma-separated columns), FILE
    relative to ``folder``; InputError naming the option and what is wrong."""
    parts = spec.rsplit(":", 2)
    if len(parts) != 3 or not all(parts):
        raise InputError(f"--{option}", f"'{spec}' is not FILE:TIME:"
                                        f"{'X,Y,Z' if values == 3 else 'COL'}")
    name, time_col, columns = parts
    value_cols = tuple(c.strip() for c in columns.split(","))
    if len(value_cols) != values:
        raise InputError(f"--{option}", f"'{spec}' names {len(value_cols)} value columns, "
                                        f"needs {values}")
    path = folder / name
    if not path.is_file():
        raise InputError(f"--{option}", f"no file {path}")
    return SensorFile(path, time_col.strip(), value_cols)


def named_layout(folder: Path, args: argparse.Namespace) -> PhoneLayout:
    """The layout of files named on the command line (``--acc`` needed)."""
    if not args.acc:
        raise InputError("--acc", "the other files are named, the accelerometer is not: "
                                  "give --acc FILE:TIME:X,Y,Z")
    files = {name: None if getattr(args, name) is None else
             sensor_file(folder, name, getattr(args, name), 1 if name == "pressure" else 3)
             for name in NAMED_SENSORS}
    convention = args.convention or "android"
    return PhoneLayout(
        accelerometer=files["acc"], gravity=files["gravity"], gyroscope=files["gyro"],
        magnetometer=files["mag"], barometer=files["pressure"],
        time_unit=args.time_unit or DEFAULT_TIME_UNIT, acc_unit=args.acc_unit,
        gyro_unit=args.gyro_unit, mag_unit=args.mag_unit, pressure_unit=args.pressure_unit,
        acc_sign=CONVENTION_SIGNS[convention],
        sign_source=f"{convention}'s convention"
                    f"{' (--convention)' if args.convention else ' (the default)'}",
        drop_invalid=args.drop_invalid, accept_implausible=args.force)


def _refuse_unit_options(args: argparse.Namespace) -> None:
    """A Sensor Logger export has its units: an option that would change them is a
    mistake, refused rather than ignored."""
    given = [f"--{name.replace('_', '-')}" for name, default in
             (("time_unit", None), ("acc_unit", "mps2"), ("gyro_unit", "radps"),
              ("mag_unit", "ut"), ("pressure_unit", "hpa"))
             if getattr(args, name) != default]
    if given:
        raise InputError(", ".join(given), "a Sensor Logger export's units are the app's "
                                           "(ns, m/s², rad/s, µT, hPa); name the files with "
                                           "--acc ... to read another layout")


@contextmanager
def phone_layout(args: argparse.Namespace) -> Iterator[PhoneLayout]:
    """The layout of ``args`` (named files, or a Sensor Logger folder or zip), valid while
    the context lasts."""
    folder = Path(args.folder)
    with tempfile.TemporaryDirectory(prefix="pdr-phone-") as scratch:
        if folder.is_file() and zipfile.is_zipfile(folder):
            folder = _unpacked(folder, Path(scratch))
        elif not folder.is_dir():
            raise InputError(folder, "no such folder (or not a zip file)")
        if any(getattr(args, name) for name in NAMED_SENSORS):
            yield named_layout(folder, args)
            return
        _refuse_unit_options(args)
        yield sensor_logger_layout(folder, args.convention, args.drop_invalid, args.force)


def _unpacked(archive: Path, scratch: Path) -> Path:
    """The folder of ``archive``'s CSV files once unpacked into ``scratch`` (the app puts
    them at the top, or in one folder)."""
    try:
        with zipfile.ZipFile(archive) as zipped:
            zipped.extractall(scratch)
    except (zipfile.BadZipFile, OSError) as exc:
        raise InputError(archive, f"cannot unpack ({exc})") from exc
    folders = {p.parent for p in scratch.rglob("*.csv")}
    if len(folders) != 1:
        raise InputError(archive, f"expected the CSV files of one recording, found them in "
                                  f"{len(folders)} folders")
    return folders.pop()
