"""Reading a sequence of the Oxford Inertial Odometry Dataset (OxIOD; Chen et al. 2018) into
the batches ``pdr-sim import-csv`` writes: ``imu/data``, ``imu/mag`` and
``ground_truth/pose`` with the phone's attitude and the Vicon position.

A sequence is a pair of synchronised files without a header, ``imuK.csv`` and ``viK.csv``
for one K (the dataset's ``syn/`` folders hold several pairs: name one file then):

- ``imuK.csv``, 16 columns: time, attitude roll/pitch/yaw (Core Motion's own estimate,
  not read), rotation rate x/y/z [rad/s], gravity x/y/z [g], user acceleration x/y/z [g],
  magnetic field x/y/z [µT], in Core Motion's axes (x right, y up the screen, z out of it);
- ``viK.csv``, 9 columns: time, the Vicon frame counter, translation x/y/z [m] and rotation
  x/y/z/w of the Vicon object, in the Vicon world frame (z up).

The time columns hold 5 significant digits, useless as stamps: row k of both files is
the instant ``start_s`` + k × 10 ms (a uniform 100 Hz grid). Specific force is
−(gravity + user acceleration) × g₀ (Core Motion's total acceleration reads (0, 0, −1) g
lying face up); the magnetometer µT becomes T. The Vicon object frame is the phone's
turned 180° about its z axis, so the truth is C_world_phone = C_world_object · Rz(180°)
(pdr_core.io.csv_import.sensor_attitude with :data:`PHONE_IN_OBJECT_RPY_DEG`) and the
position is the translation.

Rows with NaN or Inf in either file, or a rotation quaternion whose norm is not 1, are
refused naming the file and the row, or dropped from both files with ``drop_invalid``
(the kept rows keep their stamps). The Vicon truth has glitches: marker swaps, where its
attitude jumps by up to 180° for a few to a few dozen rows and back. They are kept, and
counted (:func:`attitude_jumps`: more than :data:`GLITCH_STEP_RAD` between consecutive
rows, which no hand turns in 10 ms), as are the rows that repeat the previous Vicon
frame (its counter does not advance).

- :func:`find_sequence`: the pair of files of a directory (or beside a file);
- :func:`import_oxiod`: the batches and what went in (:class:`OxiodImport`);
- :func:`attitude_jumps`: the truth's glitches.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.frames import MAP_FRAME, SENSOR_FRAME
from pdr_core.io.batch import MessageBatch, stamp_ns_from_seconds
from pdr_core.io.csv_import import imu_batch, mag_batch, pose_batch, sensor_attitude
from pdr_core.io.csv_rows import valid_rows
from pdr_core.io.csv_table import read_table
from pdr_core.units import MAG_UNITS_T

RATE_HZ = 100.0
ROW_INTERVAL_NS = 10_000_000              # row k is k × 10 ms after the first
IMU_COLUMNS = ("time, attitude roll/pitch/yaw, rotation rate x/y/z, gravity x/y/z, "
               "user acceleration x/y/z, magnetic field x/y/z")
VICON_COLUMNS = "time, frame counter, translation x/y/z, rotation x/y/z/w"
# Column indices of imuK.csv
GYRO, GRAVITY, USER_ACC, MAG = slice(4, 7), slice(7, 10), slice(10, 13), slice(13, 16)
# Column indices of viK.csv
FRAME, TRANSLATION, ROTATION_XYZW = 1, slice(2, 5), slice(5, 9)
# The phone's frame in the Vicon object's: turned 180° about z (ZYX roll, pitch, yaw [deg])
PHONE_IN_OBJECT_RPY_DEG = (0.0, 0.0, 180.0)
# A truth glitch: the attitude moves more than this between consecutive rows (50 rad/s;
# a phone in the hand turns at a few rad/s at most)
GLITCH_STEP_RAD = 0.5

_PAIR_FILE = re.compile(r"(imu|vi)(\d+)\.csv")


@dataclass(frozen=True)
class OxiodSequence:
    """The two files of one sequence."""

    imu_csv: Path
    vicon_csv: Path


@dataclass
class OxiodImport:
    """An imported sequence: ``imu``, ``mag`` (None when the magnetometer columns hold
    one value throughout: no magnetometer) and ``pose`` batches; the rows read and those
    dropped as invalid; the truth's glitches (:func:`attitude_jumps` of the kept rows)
    and the rows that repeat the previous Vicon frame."""

    sequence: OxiodSequence
    imu: MessageBatch
    mag: MessageBatch | None
    pose: MessageBatch
    rows_read: int
    rows_invalid: int
    glitches: int
    repeated_frames: int


def find_sequence(path: str | Path) -> OxiodSequence:
    """The pair ``imuK.csv``/``viK.csv`` of the directory ``path``, which must hold one
    pair; or, when ``path`` is one of the two files, it and its partner beside it."""
    path = Path(path)
    if path.is_file():
        match = _PAIR_FILE.fullmatch(path.name)
        if match is None:
            raise InputError(path, "not an OxIOD file (imuK.csv or viK.csv)")
        files = [path.with_name(f"{kind}{match[2]}.csv") for kind in ("imu", "vi")]
        for partner in files:
            if not partner.is_file():
                raise InputError(partner, f"no such file (the partner of {path.name})")
        return OxiodSequence(*files)
    if not path.is_dir():
        raise InputError(path, "no such directory")
    found: dict[str, dict[int, Path]] = {"imu": {}, "vi": {}}
    for entry in path.iterdir():
        match = _PAIR_FILE.fullmatch(entry.name)
        if match and entry.is_file():
            found[match[1]][int(match[2])] = entry
    pairs = sorted(set(found["imu"]) & set(found["vi"]))
    if len(pairs) == 1:
        return OxiodSequence(found["imu"][pairs[0]], found["vi"][pairs[0]])
    if pairs:
        names = ", ".join(f"imu{k}.csv/vi{k}.csv" for k in pairs)
        raise InputError(path, f"{len(pairs)} OxIOD pairs ({names}): name one of the files, "
                               f"e.g. {path / f'imu{pairs[0]}.csv'}")
    seen = sorted(p.name for files in found.values() for p in files.values())
    hint = "; the synchronised files are in its syn/ folder" if (path / "syn").is_dir() else ""
    raise InputError(path, "no OxIOD pair imuK.csv + viK.csv of the same K (found "
                           f"{', '.join(seen) if seen else 'no imu*.csv or vi*.csv'}){hint}")


def _table(path: Path, columns: int, described: str) -> np.ndarray:
    table = read_table(path, header=False)[1]
    if table.shape[1] != columns:
        raise InputError(path, f"{table.shape[1]} columns, expected {columns} ({described})")
    return table


def attitude_jumps(orientation_xyzw: np.ndarray, max_step_rad: float = GLITCH_STEP_RAD
                   ) -> np.ndarray:
    """(N,) bool: the rows whose attitude (quaternions (N, 4), x y z w) is more than
    ``max_step_rad`` from the previous row's; never the first."""
    attitude = Rotation.from_quat(orientation_xyzw)
    if len(attitude) < 2:
        return np.zeros(len(attitude), bool)
    step = (attitude[:-1].inv() * attitude[1:]).magnitude()
    return np.concatenate(([False], step > max_step_rad))


def import_oxiod(path: str | Path, start_s: float = 0.0, drop_invalid: bool = False,
                 imu_frame: str = SENSOR_FRAME, map_frame: str = MAP_FRAME) -> OxiodImport:
    """Read the sequence of ``path`` (:func:`find_sequence`): row k stamped ``start_s`` [s]
    + k × 10 ms; invalid rows refused, or dropped with ``drop_invalid`` (module
    docstring). InputError names the file and the problem."""
    sequence = find_sequence(path)
    imu = _table(sequence.imu_csv, 16, IMU_COLUMNS)
    vicon = _table(sequence.vicon_csv, 9, VICON_COLUMNS)
    if len(vicon) != len(imu):
        raise InputError(sequence.vicon_csv, f"{len(vicon)} rows, but {sequence.imu_csv.name} "
                                             f"has {len(imu)}: row k of both must be one instant "
                                             "(OxIOD's syn/ files, not raw/)")
    keep = valid_rows(sequence.imu_csv, imu, 1, drop_invalid) \
        & valid_rows(sequence.vicon_csv, vicon, 1, drop_invalid, vicon[:, ROTATION_XYZW])
    if not keep.any():
        raise InputError(sequence.imu_csv, f"no valid rows (all {len(imu)} hold a NaN, an Inf "
                                           f"or a rotation that is not a unit quaternion)")
    imu, vicon = imu[keep], vicon[keep]
    stamp_ns = (int(stamp_ns_from_seconds(start_s)) + np.flatnonzero(keep).astype(np.int64)
                * ROW_INTERVAL_NS)
    force = -(imu[:, GRAVITY] + imu[:, USER_ACC]) * STANDARD_GRAVITY_MPS2
    field_t = imu[:, MAG] * MAG_UNITS_T["ut"]
    has_mag = bool(np.ptp(field_t, axis=0).any())
    orientation = sensor_attitude(vicon[:, ROTATION_XYZW], PHONE_IN_OBJECT_RPY_DEG)
    return OxiodImport(
        sequence=sequence,
        imu=imu_batch(stamp_ns, imu_frame, force, imu[:, GYRO]),
        mag=mag_batch(stamp_ns, imu_frame, field_t) if has_mag else None,
        pose=pose_batch(stamp_ns, map_frame, vicon[:, TRANSLATION], orientation),
        rows_read=len(keep), rows_invalid=int((~keep).sum()),
        glitches=int(attitude_jumps(orientation).sum()),
        repeated_frames=int((np.diff(vicon[:, FRAME]) == 0).sum()))
