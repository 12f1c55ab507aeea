"""``pdr-sim import-csv`` on the real recordings of ../shared/data (issue 2, acceptance 3).

The command lines here are the ones the README documents: no dataset-specific code.
"""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core.io.bag import BagReader
from wstest import OXFORD, OXFORD_ARGS, PYSHOE, PYSHOE_ARGS, XIO, XIO_ARGS, needs_shared


def csv_rows(path) -> np.ndarray:
    has_header = not path.read_text().split("\n", 1)[0][0].isdigit()
    return np.loadtxt(path, delimiter=",", skiprows=int(has_header), ndmin=2)


def rest_specific_force(acc: np.ndarray, gyro: np.ndarray | None, rate_hz: float,
                        acc_std_max: float = 0.1) -> float:
    """Mean |f| over 0.5 s windows where the sensor is still: every axis of the
    accelerometer varies by < acc_std_max m/s² (std) and, with a gyroscope, |ω| < 0.1 rad/s."""
    w = int(rate_hz / 2)
    n = len(acc) // w
    windows = acc[: n * w].reshape(n, w, 3)
    still = windows.std(axis=1).max(axis=1) < acc_std_max
    if gyro is not None:
        still &= np.linalg.norm(gyro[: n * w].reshape(n, w, 3), axis=2).max(axis=1) < 0.1
    assert still.any(), "the recording has a rest period"
    return float(np.linalg.norm(windows[still], axis=2).mean())


def import_bag(procs, tmp_path, csv, args):
    out = tmp_path / "bag"
    result = procs.run("pdr-sim", "import-csv", str(csv), "--out", str(out), *args)
    assert result.returncode == 0, result.stderr
    return BagReader(out), result.stdout


@pytest.mark.parametrize("csv", [pytest.param(p, id=p.stem, marks=needs_shared(p))
                                 for p in PYSHOE])
def test_pyshoe_vicon(procs, tmp_path, csv):
    reader, _ = import_bag(procs, tmp_path, csv, PYSHOE_ARGS)
    table = csv_rows(csv)
    imu, pose = reader.read("/imu/data"), reader.read("/ground_truth/pose")
    assert len(imu) == len(pose) == len(table)
    np.testing.assert_array_equal(imu["linear_acceleration"], table[:, 1:4])
    np.testing.assert_array_equal(pose["pose.position"], table[:, 7:10])
    assert abs(rest_specific_force(imu["linear_acceleration"], imu["angular_velocity"], 200)
               - 9.81) <= 0.2


@needs_shared(XIO)
def test_xio_gait_tracking(procs, tmp_path):
    reader, stdout = import_bag(procs, tmp_path, XIO, XIO_ARGS)
    table = csv_rows(XIO)
    duplicates = int(((np.diff(table, axis=0) == 0).all(axis=1)).sum())
    assert "205 exact duplicates" in stdout and duplicates == 205
    imu = reader.read("/imu/data")
    assert len(imu) == len(table) - duplicates
    assert np.abs(imu["angular_velocity"]).max() < 35.0, "deg/s converted to rad/s"
    assert abs(rest_specific_force(imu["linear_acceleration"], imu["angular_velocity"], 400)
               - 9.81) <= 0.2, "g converted to m/s²"


@needs_shared(OXFORD)
def test_oxford_pocket_accelerometer_only(procs, tmp_path):
    reader, _ = import_bag(procs, tmp_path, OXFORD, OXFORD_ARGS)
    table = csv_rows(OXFORD)
    imu = reader.read("/imu/data")
    assert len(imu) == len(table)
    np.testing.assert_array_equal(imu.stamp_ns, table[:, 0].astype(np.int64))
    assert (imu["angular_velocity_covariance"][:, 0] == -1).all(), "no gyroscope: marked unknown"
    # A phone in the pocket of a walking person is never quite still: its quietest 0.5 s
    # windows (standing before and after the walk) have a std of 0.4 to 1 m/s².
    assert abs(rest_specific_force(imu["linear_acceleration"], None, 100, acc_std_max=1.0)
               - 9.81) <= 0.2


@needs_shared(XIO)
def test_xio_without_drop_duplicates_names_the_row(procs, tmp_path):
    result = procs.run("pdr-sim", "import-csv", str(XIO), "--out", str(tmp_path / "bag"),
                       *[arg for arg in XIO_ARGS if arg != "--drop-duplicates"])
    assert result.returncode == 2
    assert result.stderr.strip().splitlines()[-1] == (
        f"pdr-sim: error: {XIO}: row 4: exact duplicate of the previous row "
        "(205 such rows; --drop-duplicates drops them)")
    assert not (tmp_path / "bag").exists()
