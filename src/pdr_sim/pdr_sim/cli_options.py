"""The options ``pdr-sim``'s commands share: a bag to write (``--out``, ``--overwrite``,
``--compress``) and a CSV's format (its time, accelerometer, gyroscope columns, units and
axes), read into :class:`pdr_core.io.csv_import.CsvImuFormat`.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.io.csv_import import (
    ACC_UNITS_MPS2,
    GYRO_UNITS_RADPS,
    TIME_UNITS_S,
    CsvImuFormat,
)


def columns(text: str) -> tuple[str, ...]:
    return tuple(c.strip() for c in text.split(",")) if text else ()


def add_bag_output(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, required=True, help="output bag directory")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output")
    p.add_argument("--compress", action="store_true", help="zstd-compress the MCAP chunks")


def add_csv_format(p: argparse.ArgumentParser, required: bool = True) -> None:
    p.add_argument("--no-header", dest="header", action="store_false",
                   help="the first row is data, not column names")
    p.add_argument("--time-col", default="0", help="time column (default: first column)")
    p.add_argument("--time-unit", default="s", choices=sorted(TIME_UNITS_S),
                   help="unit of the time column: s, ms, us (µs) or ns")
    p.add_argument("--time-offset-s", type=float, default=0.0,
                   help="added to every stamp [s]")
    p.add_argument("--acc-cols", type=columns, required=required, help="accelerometer x,y,z")
    p.add_argument("--acc-unit", default="mps2", choices=sorted(ACC_UNITS_MPS2),
                   help="unit of the accelerometer columns: mps2, m/s2 or m/s^2 (m/s²), or "
                        f"g ({STANDARD_GRAVITY_MPS2} m/s²)")
    p.add_argument("--gyro-cols", type=columns, default=(),
                   help="gyroscope x,y,z (omit when the log has none)")
    p.add_argument("--gyro-unit", default="radps", choices=sorted(GYRO_UNITS_RADPS),
                   help="unit of the gyroscope columns: radps or rad/s, degps or deg/s")
    p.add_argument("--axes", type=columns, default=("x", "y", "z"),
                   help="sensor axis remap, e.g. --axes=-y,x,z means out_x=-in_y, out_y=in_x")
    p.add_argument("--acc-axes", type=columns, default=None,
                   help="remap of the accelerometer only (replaces --axes for it)")
    p.add_argument("--gyro-axes", type=columns, default=None,
                   help="remap of the gyroscope only (replaces --axes for it)")
    p.add_argument("--drop-invalid", action="store_true",
                   help="drop NaN/Inf rows and non-increasing stamps instead of failing")
    p.add_argument("--drop-duplicates", action="store_true",
                   help="drop rows that repeat the previous row exactly (time and values)")
    p.add_argument("--force", action="store_true",
                   help="import data that fail a plausibility check of their units (a "
                        "median |f| beyond 0.5-5 g, a rate beyond 5-10000 Hz, a 99th "
                        "percentile of |ω| above 50 rad/s, a median |B| beyond 1-1000 µT, a "
                        "median pressure beyond 300-1100 hPa), "
                        "each with a warning, instead of refusing them (an accelerometer "
                        "column constant over the whole recording is refused even so)")


def angles_deg(text: tuple[str, ...], option: str) -> tuple[float, ...]:
    try:
        return tuple(float(angle) for angle in text)
    except ValueError:
        raise InputError(option, f"'{','.join(text)}' is not a list of angles in degrees "
                                 "(e.g. 0,0,180)") from None


def csv_format(args: argparse.Namespace) -> CsvImuFormat:
    for option, axes in (("--axes", args.axes), ("--acc-axes", args.acc_axes),
                         ("--gyro-axes", args.gyro_axes)):
        if axes is not None and len(axes) != 3:
            raise InputError(option, f"needs 3 entries, got {','.join(axes)}")
    return CsvImuFormat(
        time_col=args.time_col, time_unit=args.time_unit, acc_cols=args.acc_cols,
        acc_unit=args.acc_unit, gyro_cols=args.gyro_cols, gyro_unit=args.gyro_unit,
        pos_cols=getattr(args, "pos_cols", ()), pos_unit=getattr(args, "pos_unit", "m"),
        pos_axes=getattr(args, "pos_axes", ("x", "y", "z")),
        quat_cols=getattr(args, "quat_cols", ()),
        quat_order=getattr(args, "quat_order", "xyzw"),
        sensor_in_body_rpy_deg=angles_deg(getattr(args, "sensor_in_body_rpy_deg", ()) or
                                           ("0", "0", "0"), "--sensor-in-body-rpy-deg"),
        mag_cols=getattr(args, "mag_cols", ()), mag_unit=getattr(args, "mag_unit", "ut"),
        mag_axes=getattr(args, "mag_axes", None),
        pressure_col=getattr(args, "pressure_col", None),
        pressure_unit=getattr(args, "pressure_unit", "hpa"),
        axes=args.axes, acc_axes=args.acc_axes, gyro_axes=args.gyro_axes,
        header=args.header, time_offset_s=args.time_offset_s,
        drop_invalid=args.drop_invalid, drop_duplicates=args.drop_duplicates,
        accept_implausible=args.force)
