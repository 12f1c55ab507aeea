"""Unit mistakes in a CSV log (issue 29, defect 3): refused by ``pdr-sim import-csv`` in one
line naming the file, the columns, the value in the unit read and the option that fixes
it; ``--force`` imports them as read with a warning, and then the navigators refuse them
naming the topic, the value with its unit and the same fix."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.io.bag import BagReader
from wstest import SHARED_DATA, cli, needs_shared

COLUMNS = ["--time-col", "t", "--acc-cols", "ax,ay,az", "--gyro-cols", "gx,gy,gz",
           "--mag-cols", "mx,my,mz"]


def write_walk(path, *, t_scale=1.0, acc_scale=1.0, gyro_scale=1.0, mag_scale=1.0, n=500):
    """``n`` rows at 100 Hz: specific force about g [m/s²], rates of 1 rad/s RMS per axis,
    a 44.7 µT field, each column multiplied by its scale (a unit mistake)."""
    rng = np.random.default_rng(0)
    t = np.arange(n) * 0.01
    acc = rng.normal(0.0, 0.5, (n, 3)) + [0.0, 0.0, STANDARD_GRAVITY_MPS2]
    gyro = rng.normal(0.0, 1.0, (n, 3))
    mag = np.tile([20.0, 0.0, -40.0], (n, 1))       # µT
    np.savetxt(path, np.column_stack([t * t_scale, acc * acc_scale, gyro * gyro_scale,
                                      mag * mag_scale]),
               delimiter=",", header="t,ax,ay,az,gx,gy,gz,mx,my,mz", comments="")
    return path


# (scales of the file, unit options given, what the line must say: columns, value and
# unit read, the fix)
MISTAKES = {
    "acc_in_g_read_as_mps2": ({"acc_scale": 1 / STANDARD_GRAVITY_MPS2}, [],
                              ["columns ax,ay,az: median |f| 1.00", "read in m/s²",
                               "pass --acc-unit g"]),
    "time_in_ms_read_as_s": ({"t_scale": 1000.0}, [],
                             ["column t: median sample interval 10 s (0.1 Hz)", "read in s",
                              "pass --time-unit ms"]),
    "mag_in_t_read_as_ut": ({"mag_scale": 1e-6}, [],
                            ["columns mx,my,mz: median |B| 4.472e-05 µT = 4.472e-11 T",
                             "read in µT", "pass --mag-unit t"]),
    "mag_in_ut_read_as_t": ({}, ["--mag-unit", "t"],
                            ["columns mx,my,mz: median |B| 44.72 T", "read in T",
                             "pass --mag-unit ut"]),
    "gyro_in_degps_read_as_radps": ({"gyro_scale": 180 / np.pi}, [],
                                    ["columns gx,gy,gz: 99th percentile of |ω|",
                                     "rad/s, read in rad/s", "pass --gyro-unit degps"]),
}


def import_walk(tmp_path, mistake: str, *options: str, unit_options: bool = True):
    """The walk written with ``mistake`` and imported to TMP/bag with the mistake's unit
    options (unless not ``unit_options``) and ``options``: the CSV and the result."""
    scales, units, _ = MISTAKES[mistake]
    csv = write_walk(tmp_path / "walk.csv", **scales)
    return csv, cli("pdr-sim", "import-csv", str(csv), "--out", str(tmp_path / "bag"),
                    *COLUMNS, *(units if unit_options else ()), *options)


@pytest.mark.parametrize("mistake", MISTAKES)
def test_unit_mistake_is_refused_naming_the_file_column_and_fix(tmp_path, mistake):
    said = MISTAKES[mistake][2]
    csv, result = import_walk(tmp_path, mistake)
    assert result.returncode == 2, result.stdout
    [line] = result.stderr.splitlines()
    assert line.startswith(f"pdr-sim: error: {csv}: ")
    for words in said:
        assert words in line, (words, line)
    assert "--force" in line
    assert list(tmp_path.iterdir()) == [csv], "no output"


@pytest.mark.parametrize("mistake", MISTAKES)
def test_force_imports_the_mistake_as_read_and_says_so(tmp_path, mistake):
    said = MISTAKES[mistake][2]
    csv, result = import_walk(tmp_path, mistake, "--force")
    assert result.returncode == 0, result.stderr
    [line] = result.stderr.splitlines()
    assert line.startswith(f"pdr-sim: warning: {csv}: {said[0]}")
    assert line.endswith("accepted as read (--force)")
    assert len(BagReader(tmp_path / "bag").read("/imu/data")) == 500


@pytest.mark.parametrize("mistake", MISTAKES)
def test_the_named_fix_imports_the_file(tmp_path, mistake):
    fix = MISTAKES[mistake][2][-1].removeprefix("pass ").split()
    _, result = import_walk(tmp_path, mistake, *fix, unit_options=False)
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""
    imu = BagReader(tmp_path / "bag").read("/imu/data")
    assert np.median(np.diff(imu.t_s)) == pytest.approx(0.01)
    assert np.median(np.linalg.norm(imu["linear_acceleration"], axis=1)) == \
        pytest.approx(STANDARD_GRAVITY_MPS2, rel=0.05)


# A bag imported with --force, then navigated: (mistake, CLI, what its one line must say)
LATER = [
    ("acc_in_g_read_as_mps2", "pdr-pocket", ["imu/data: median |f| 1.00", "m/s²",
                                                 "the accelerometer looks like it is in g",
                                                 "re-import with pdr-sim import-csv "
                                                 "--acc-unit g"]),
    ("time_in_ms_read_as_s", "pdr-pocket", ["/imu/data: median sample interval 10 s",
                                                "re-import with pdr-sim import-csv "
                                                "--time-unit ms"]),
    ("mag_in_t_read_as_ut", "pdr-pocket", ["/imu/mag: median |B| 4.472e-11 T",
                                               "a column in T imported as µT",
                                               "re-import with pdr-sim import-csv "
                                               "--mag-unit t"]),
    ("mag_in_ut_read_as_t", "pdr-pocket", ["/imu/mag: median |B| 44.72 T",
                                               "the magnetometer looks like it is in µT",
                                               "re-import with pdr-sim import-csv "
                                               "--mag-unit ut"]),
    ("acc_in_g_read_as_mps2", "pdr-ekf", ["imu/data: median |f| 1.00", "m/s²",
                                                  "re-import with pdr-sim import-csv "
                                                  "--acc-unit g"]),
    ("gyro_in_degps_read_as_radps", "pdr-ekf", [
        "imu/data: 99th percentile of |ω|", "rad/s (expected at most 50 rad/s)",
        "the gyroscope looks like it is in deg/s",
        "re-import with pdr-sim import-csv --gyro-unit degps"]),
]


@pytest.mark.parametrize("mistake, prog, said", LATER, ids=[f"{m}-{c}" for m, c, _ in LATER])
def test_navigators_refuse_a_forced_mistake_naming_topic_value_unit_and_fix(
        tmp_path, mistake, prog, said):
    _, imported = import_walk(tmp_path, mistake, "--force")
    assert imported.returncode == 0, imported.stderr
    result = cli(prog, "run", str(tmp_path / "bag"), "--out", str(tmp_path / "out"))
    assert result.returncode == 2, result.stdout
    [line] = result.stderr.splitlines()
    assert line.startswith(f"{prog}: error: ")
    for words in said:
        assert words in line, (words, line)
    assert not (tmp_path / "out").exists()


def test_calibrate_mag_refuses_a_csv_in_t_read_as_ut_unless_forced(tmp_path):
    """The same check and the same --force on pdr-pocket calibrate-mag's CSV source."""
    rng = np.random.default_rng(1)
    directions = rng.normal(size=(2000, 3))
    field_t = 48e-6 * directions / np.linalg.norm(directions, axis=1, keepdims=True)
    csv = tmp_path / "cal.csv"
    np.savetxt(csv, field_t, delimiter=",", header="mag_x,mag_y,mag_z", comments="")
    out = str(tmp_path / "mag.yaml")
    result = cli("pdr-pocket", "calibrate-mag", str(csv), "--out", out)
    assert result.returncode == 2
    assert result.stderr == (f"pdr-pocket: error: {csv}: columns mag_x,mag_y,mag_z: median "
                             "|B| 4.8e-05 µT = 4.8e-11 T, read in µT (--mag-unit ut); "
                             "expected 1-1000 µT: the data look like T: pass --mag-unit t "
                             "(or --force to accept them as read)\n")
    forced = cli("pdr-pocket", "calibrate-mag", str(csv), "--out", out, "--force")
    assert forced.returncode == 0, forced.stderr
    assert forced.stderr.endswith("accepted as read (--force)\n")
    fixed = cli("pdr-pocket", "calibrate-mag", str(csv), "--out", out, "--mag-unit", "t")
    assert fixed.returncode == 0 and fixed.stderr == "", fixed.stderr
    assert "|H| 48.00 µT" in fixed.stdout


# Sensor Logger's Accelerometer.csv of a phone held in the hand (Android): gravity removed,
# in m/s², columns time,z,y,x, time in ns (../shared/data/README.md)
LINEAR_ACCELERATION = (SHARED_DATA / "phone" / "sensor_logger" / "inhand-27-steps-Matan"
                       / "Accelerometer.csv")


@needs_shared(LINEAR_ACCELERATION)
def test_a_phones_gravity_removed_accelerometer_is_named_so_never_g(tmp_path):
    """Issue 54, defect 1: import-csv told the user to pass --acc-unit g."""
    result = cli("pdr-sim", "import-csv", str(LINEAR_ACCELERATION), "--out",
                 str(tmp_path / "bag"), "--time-col", "time", "--time-unit", "ns",
                 "--acc-cols", "x,y,z")
    assert result.returncode == 2, result.stdout
    [line] = result.stderr.splitlines()
    assert line == (f"pdr-sim: error: {LINEAR_ACCELERATION}: columns x,y,z: median |f| 2.06 "
                    "m/s² (0.21 g), and the median norm of its slow part (1 s moving mean) "
                    "0.889 m/s², 0.43 times the median |f| (data with gravity give about 1, "
                    "in any unit): the accelerometer looks gravity-removed (a phone app's "
                    "linear or user acceleration): import the raw accelerometer (gravity "
                    "included) instead, or add the gravity part to it (Sensor Logger's "
                    "Gravity.csv: pdr-sim import-phone DIR); a unit option cannot fix it "
                    "(--force accepts it as read)")
    assert "--acc-unit g" not in line and not (tmp_path / "bag").exists()
