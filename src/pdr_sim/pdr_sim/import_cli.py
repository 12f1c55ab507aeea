"""``pdr-sim``'s import commands: ``import-csv`` (a CSV log, pdr_core.io.csv_import),
``import-oxiod`` (an OxIOD sequence, pdr_core.io.oxiod) and ``import-phone`` (a phone app's
export folder, pdr_core.io.phone_import), each writing a bag of what it read and printing
what it wrote.

:func:`import_recording` is the same commands in Python (``pdr-eval``'s import of a CSV
log or a phone's export): the command's options in, the bag written, the lines the
command prints returned; it prints nothing, and options the command refuses raise
:class:`OptionsError` with argparse's message instead of exiting.
"""
from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import NoReturn

import numpy as np

from pdr_core import topics
from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import CliParser, InputError
from pdr_core.io.bag import write_batches
from pdr_core.io.batch import MessageBatch
from pdr_core.io.csv_import import (
    ACC_UNITS_MPS2,
    GYRO_UNITS_RADPS,
    MAG_UNITS_T,
    POS_UNITS_M,
    PRESSURE_RANGE,
    PRESSURE_UNITS_PA,
    QUATERNION_ORDERS,
    TIME_UNITS_S,
    import_csv,
)
from pdr_core.io.csv_rows import QUATERNION_NORM_TOLERANCE
from pdr_core.io.odometry import truth_tf
from pdr_core.io.oxiod import GLITCH_STEP_RAD, import_oxiod
from pdr_core.io.phone_import import CONVENTION_SIGNS, import_phone
from pdr_sim.cli_options import add_bag_output, add_csv_format, columns, csv_format
from pdr_sim.phone_layouts import phone_layout


def add_import_csv(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "import-csv", help="turn a CSV IMU log into a bag",
        description="Turn a CSV IMU log (one row per sample) into a rosbag2 MCAP bag with "
                    "imu/data (sensor_msgs/Imu, SI units) and, when their columns are given, "
                    "imu/mag (sensor_msgs/MagneticField, tesla), imu/pressure "
                    "(sensor_msgs/FluidPressure, pascal) and ground_truth/pose (positions, "
                    "and the sensor's attitude from a quaternion with --quat-cols). "
                    "Columns are header names or 0-based indices. Data implausible in the "
                    "units given (a median |f| far from g, a time column in ms read as s, "
                    "a magnetometer in T read as µT) are refused, naming the unit option "
                    "that fixes them; --force imports them as read.")
    p.add_argument("csv", type=Path, help="input CSV file")
    add_bag_output(p)
    add_csv_format(p)
    p.add_argument("--pos-cols", type=columns, default=(),
                   help="ground-truth position x,y,z (map frame, z up)")
    p.add_argument("--pos-unit", default="m", choices=sorted(POS_UNITS_M),
                   help="unit of the position columns: m, cm or mm")
    p.add_argument("--pos-axes", type=columns, default=("x", "y", "z"),
                   help="remap of the positions into a right-handed z-up frame, "
                        "e.g. --pos-axes=-x,y,z; with --quat-cols it turns the attitude "
                        "too, and one that mirrors the frame (an odd number of minus signs "
                        "and swaps, as -x,y,z) is refused then")
    p.add_argument("--quat-cols", type=columns, default=(),
                   help="the truth's attitude: 4 quaternion columns, in --quat-order, of the "
                        "tracked body in the truth's world frame (C_world_body, z up); "
                        "needs --pos-cols. Written normalised as pose.orientation of "
                        "ground_truth/pose: the sensor's attitude C_world_sensor = "
                        "C_world_body · C_body_sensor (--sensor-in-body-rpy-deg). A row whose "
                        f"quaternion's norm is not 1 within {QUATERNION_NORM_TOLERANCE:g} is "
                        "an invalid row (refused, or dropped with --drop-invalid)")
    p.add_argument("--quat-order", default="xyzw", choices=sorted(QUATERNION_ORDERS),
                   help="order of the --quat-cols: xyzw (ROS, scipy, OxIOD's Vicon files) "
                        "or wxyz (scalar first)")
    p.add_argument("--sensor-in-body-rpy-deg", type=columns, default=("0", "0", "0"),
                   metavar="R,P,Y",
                   help="the IMU's frame in the tracked body's frame, C_body_sensor = "
                        "Rz(Y)·Ry(P)·Rx(R): ZYX roll, pitch, yaw [deg], e.g. 0,0,180 for "
                        "OxIOD's phone in its Vicon object (write the = when the first is "
                        "negative: --sensor-in-body-rpy-deg=-90,0,0)")
    p.add_argument("--mag-cols", type=columns, default=(),
                   help="magnetometer x,y,z (written to imu/mag)")
    p.add_argument("--mag-unit", default="ut", choices=sorted(MAG_UNITS_T),
                   help="unit of the magnetometer columns: ut (µT), nt (nT), t (T) or "
                        "gauss (G)")
    p.add_argument("--mag-axes", type=columns, default=None,
                   help="remap of the magnetometer only (default: the accelerometer's)")
    p.add_argument("--pressure-col", default=None, metavar="NAME",
                   help="barometer column (written to imu/pressure, one message per row "
                        "with a reading; an empty cell is no reading at that row)")
    p.add_argument("--pressure-unit", default="hpa", choices=sorted(PRESSURE_UNITS_PA),
                   help="unit of the pressure column: hpa (hPa, as Android reports it, = "
                        f"mbar) or pa (Pa); a median beyond {PRESSURE_RANGE.expected} in "
                        "the unit given is refused")
    p.set_defaults(func=_print_lines, lines=import_csv_lines)


def import_csv_lines(args: argparse.Namespace) -> list[str]:
    """``import-csv``: the bag of a CSV log; what it wrote, in a line."""
    fmt = csv_format(args)
    result = import_csv(args.csv, fmt)
    _write_recording(args, args.csv, result.imu, pose=result.pose, mag=result.mag,
                     pressure=result.pressure)
    written = [f"{len(result.imu)} imu/data messages"]
    written += [f"{len(batch)} {topics.graph_name(topic)}" for topic, batch in (
        (topics.IMU_MAG, result.mag), (topics.IMU_PRESSURE, result.pressure),
        (topics.GROUND_TRUTH_POSE, result.pose)) if batch is not None]
    if fmt.quat_cols:
        written[-1] += " with attitude"
    return [f"{args.out}: {', '.join(written)}; {_span(result.imu)}; "
            f"{result.rows_read} rows read, {result.rows_duplicate} exact duplicates and "
            f"{result.rows_invalid} invalid rows dropped"]


def _write_recording(args: argparse.Namespace, source: Path, imu: MessageBatch,
                     pose: MessageBatch | None = None, mag: MessageBatch | None = None,
                     pressure: MessageBatch | None = None) -> None:
    """Write an imported recording to ``args.out``: its topics, the truth's /tf, and the
    source and command line in the bag's custom_data."""
    batches = {topics.IMU_DATA: imu}
    if pose is not None:
        batches[topics.GROUND_TRUTH_POSE] = pose
        batches |= truth_tf(pose)
    if mag is not None:
        batches[topics.IMU_MAG] = mag
    if pressure is not None:
        batches[topics.IMU_PRESSURE] = pressure
    command = " ".join([Path(sys.argv[0]).name, *sys.argv[1:]])
    write_batches(args.out, batches, overwrite=args.overwrite, compress=args.compress,
                  custom_data={"pdr.source": str(source), "pdr.command": command})


def _span(imu: MessageBatch) -> str:
    """What an import summary says of its IMU samples: duration, mean rate, median |f|."""
    t = imu.t_s
    rate = (len(t) - 1) / (t[-1] - t[0]) if len(t) > 1 else float("nan")
    acc_norm = np.linalg.norm(imu["linear_acceleration"], axis=1)
    return (f"{t[-1] - t[0]:.3f} s at {rate:.1f} Hz mean; "
            f"median |f| {np.median(acc_norm):.3f} m/s^2")


def add_import_oxiod(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "import-oxiod", help="turn an OxIOD sequence into a bag",
        description="Turn one sequence of the Oxford Inertial Odometry Dataset (OxIOD: "
                    "imuK.csv and viK.csv, synchronised, no header) into a bag as "
                    "import-csv writes it: imu/data (specific force -(gravity + user "
                    f"acceleration) x {STANDARD_GRAVITY_MPS2} m/s², rotation rate as is), "
                    "imu/mag (µT -> T) and ground_truth/pose (the Vicon translation, and "
                    "the phone's attitude C_world_phone = C_world_object · Rz(180°): the "
                    "Vicon object frame is the phone's turned 180° about z), with the "
                    "truth's /tf. The time columns are too coarse to use: row k is stamped "
                    "--start-s + k × 10 ms. The Vicon glitches (marker swaps: attitude "
                    f"jumps of more than {GLITCH_STEP_RAD:g} rad between consecutive rows) "
                    "are kept and counted in the summary.")
    p.add_argument("sequence", type=Path,
                   help="the sequence's directory, holding one pair imuK.csv/viK.csv (or "
                        "one of the two files, where a directory holds several pairs)")
    add_bag_output(p)
    p.add_argument("--start-s", type=float, default=0.0,
                   help="stamp of the first row [s]; row k is 10 ms × k later")
    p.add_argument("--drop-invalid", action="store_true",
                   help="drop the rows with a NaN or Inf in either file, or a rotation that "
                        "is not a unit quaternion, from both, instead of failing")
    p.set_defaults(func=_print_lines, lines=import_oxiod_lines)


def import_oxiod_lines(args: argparse.Namespace) -> list[str]:
    """``import-oxiod``: the bag of an OxIOD sequence; what it wrote, in a line."""
    result = import_oxiod(args.sequence, start_s=args.start_s, drop_invalid=args.drop_invalid)
    _write_recording(args, result.sequence.imu_csv.parent, result.imu, pose=result.pose,
                     mag=result.mag)
    sequence = result.sequence
    magnetometer = "yes" if result.mag is not None else "none (constant columns)"
    return [f"{args.out}: OxIOD {sequence.imu_csv.parent.name} ({sequence.imu_csv.name} + "
            f"{sequence.vicon_csv.name}): {len(result.imu)} samples from "
            f"{result.imu.t_s[0]:.3f} s, {_span(result.imu)}; magnetometer: {magnetometer}; "
            f"truth: attitude and position ({len(result.pose)} ground_truth/pose); "
            f"{result.glitches} truth glitches (attitude jumps > {GLITCH_STEP_RAD:g} rad "
            f"between rows, kept); {result.repeated_frames} rows repeat the previous Vicon "
            f"frame; {result.rows_read} rows read, {result.rows_invalid} invalid rows "
            "dropped"]


def add_import_phone(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "import-phone", help="turn a phone's own export (one CSV per sensor) into a bag",
        description="Turn a phone's recording, one CSV file per sensor at its own rate, into "
                    "a bag: imu/data (the accelerometer and the gyroscope paired at the "
                    "slower one's stamps, the faster one averaged over each sample's "
                    "interval: nothing interpolated), imu/mag and imu/pressure (each reading "
                    "at its own stamp). A Sensor Logger export (its folder, or the zip it "
                    "shares) is read as it is: a gravity-removed Accelerometer.csv is added "
                    "to Gravity.csv, iOS's sign is turned to the specific force's, units are "
                    "the app's. Any other layout: name each file with --acc FILE:TIME:X,Y,Z "
                    "(and --gravity, --gyro, --mag the same way, --pressure FILE:TIME:COL), "
                    "FILE relative to DIR, columns by header name or 0-based index. See "
                    "docs/phone.md.")
    p.add_argument("folder", type=Path, help="the export's folder (or a Sensor Logger .zip)")
    add_bag_output(p)
    for name, what in (("acc", "accelerometer (gravity included, or removed with --gravity)"),
                       ("gravity", "gravity part of a gravity-removed accelerometer"),
                       ("gyro", "gyroscope"), ("mag", "magnetometer")):
        p.add_argument(f"--{name}", metavar="FILE:TIME:X,Y,Z", help=f"the {what} file")
    p.add_argument("--pressure", metavar="FILE:TIME:COL", help="the barometer file")
    p.add_argument("--convention", choices=sorted(CONVENTION_SIGNS),
                   help="the accelerometer's sign: android (a phone lying face up reads "
                        "+9.8 m/s² on z, the specific force) or ios (−9.8, Core Motion's); "
                        "default for Sensor Logger: from the phone's own attitude, else its "
                        "Metadata.csv; for named files: android")
    p.add_argument("--time-unit", default=None, choices=sorted(TIME_UNITS_S),
                   help="unit of every time column (default: ns, Sensor Logger's)")
    p.add_argument("--acc-unit", default="mps2", choices=sorted(ACC_UNITS_MPS2),
                   help="unit of the accelerometer and gravity columns")
    p.add_argument("--gyro-unit", default="radps", choices=sorted(GYRO_UNITS_RADPS),
                   help="unit of the gyroscope columns")
    p.add_argument("--mag-unit", default="ut", choices=sorted(MAG_UNITS_T),
                   help="unit of the magnetometer columns")
    p.add_argument("--pressure-unit", default="hpa", choices=sorted(PRESSURE_UNITS_PA),
                   help="unit of the pressure column")
    p.add_argument("--drop-invalid", action="store_true",
                   help="drop rows with an empty, NaN or Inf cell and stamps that do not "
                        "increase, instead of failing")
    p.add_argument("--force", action="store_true",
                   help="import data that fail a plausibility check of their units, each "
                        "with a warning")
    p.set_defaults(func=_print_lines, lines=import_phone_lines)


def import_phone_lines(args: argparse.Namespace) -> list[str]:
    """``import-phone``: the bag of a phone's own export; what it wrote, a line each."""
    with phone_layout(args) as layout:
        result = import_phone(layout)
        _write_recording(args, args.folder, result.imu, mag=result.mag,
                         pressure=result.pressure)
    return [f"{args.out}: {_span(result.imu)}", *(f"  {line}" for line in result.lines),
            *(f"  {topic.lstrip('/')}: none (the export has no such sensor)"
              for topic, batch in ((topics.IMU_MAG, result.mag),
                                   (topics.IMU_PRESSURE, result.pressure)) if batch is None)]


def _print_lines(args: argparse.Namespace) -> int:
    """The import command's ``func``: its ``lines`` printed."""
    print("\n".join(args.lines(args)))
    return 0


class OptionsError(InputError):
    """Options an import command refuses: ``source`` the command (``pdr-sim import-csv``,
    or ``pdr-sim`` for arguments it does not know), ``problem`` argparse's message."""


class _RefusingParser(CliParser):
    """A parser whose errors raise :class:`OptionsError`, where argparse prints the usage
    and exits."""

    def error(self, message: str) -> NoReturn:
        raise OptionsError(self.prog, message)


# each import command's parser
IMPORTERS = {"import-csv": add_import_csv, "import-oxiod": add_import_oxiod,
             "import-phone": add_import_phone}


def import_recording(importer: str, source: Path, options: Sequence[str], out: Path
                     ) -> list[str]:
    """``pdr-sim IMPORTER SOURCE OPTIONS --out OUT --overwrite`` in Python (module
    docstring): the lines it prints, printed by none. OptionsError for ``options`` it
    refuses, InputError for input it cannot use, InputWarning for input used in part."""
    top = _RefusingParser(prog="pdr-sim")
    IMPORTERS[importer](top.add_subparsers(dest="command", required=True))
    args = top.parse_args([importer, str(source), *options, "--out", str(out), "--overwrite"])
    return args.lines(args)
