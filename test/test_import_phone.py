"""``pdr-sim import-phone`` on the two shared Sensor Logger exports (issue 54, acceptance
1): one command from the app's folder (or its zip) to a bag, whose magnetometer and
barometer keep their own stamps; then ``pdr-pocket run`` says the phones were held in the
hand, not carried in a trouser pocket, and invents no path.

What holds, measured on the exports (docs/phone.md):

- the Android (Samsung SM-N960F): accelerometer and gravity at 100 Hz, the gyroscope at
  500 Hz starting 0.25 s later, so 25 accelerometer samples have no gyroscope reading and
  are dropped; 5 gyroscope readings a sample; the magnetometer's 1749 readings and the
  barometer's 177 (10 Hz) at their own stamps; median |f| 9.76 m/s²;
- the iPhone: every vector sensor at one stamp (1742 samples), its accelerometer and
  gravity in Core Motion's sign, turned (the phone's own attitude and its gravity file
  disagree in sign: −1.000 cosine); its barometer at 1 Hz (16 readings); median |f|
  9.53 m/s² (the phone swung in the hand).
"""
from __future__ import annotations

import csv
import json
import shlex
import shutil

import numpy as np
import pytest

from pdr_core import topics
from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.io.bag import BagReader
from pdr_core.walking.walk_plausibility import EXIT_REFUSED
from wstest import OXFORD, OXFORD_ARGS, SENSOR_LOGGER_EXPORTS, THIGH, cli, needs_shared

NORM_THIGH = THIGH / "norm_thigh_1" / "imu.csv"
NORM_THIGH_ARGS = ["--time-col", "time", "--acc-cols", "accel_x,accel_y,accel_z",
                   "--gyro-cols", "gyro_x,gyro_y,gyro_z", "--mag-cols", "mag_x,mag_y,mag_z",
                   "--mag-unit", "ut"]
pytestmark = needs_shared(*SENSOR_LOGGER_EXPORTS.values(), OXFORD, NORM_THIGH)

FORCE_MEDIAN_TOLERANCE_MPS2 = 0.5      # a phone swung in the hand: |f| about g
IMU_SAMPLES = {"android": 1741, "ios": 1742}


def time_column(path) -> np.ndarray:
    return np.loadtxt(path, delimiter=",", skiprows=1, usecols=0, dtype=np.int64, ndmin=1)


@pytest.fixture(scope="module")
def imported(tmp_path_factory):
    """Each export imported from its folder, its bag and the importer's output."""
    out = {}
    for platform, folder in SENSOR_LOGGER_EXPORTS.items():
        bag = tmp_path_factory.mktemp(platform) / "bag"
        done = cli("pdr-sim", "import-phone", folder, "--out", bag)
        assert done.returncode == 0, done.stderr
        out[platform] = (bag, done.stdout)
    return out


@pytest.mark.parametrize("platform", ["android", "ios"])
def test_one_command_writes_every_sensor_at_its_own_stamps(imported, platform):
    bag, stdout = imported[platform]
    folder = SENSOR_LOGGER_EXPORTS[platform]
    batches = BagReader(bag).read_batches([topics.IMU_DATA, topics.IMU_PRESSURE])
    imu, pressure = batches[topics.IMU_DATA], batches[topics.IMU_PRESSURE]
    assert len(imu) == IMU_SAMPLES[platform]
    assert set(imu.stamp_ns) <= set(time_column(folder / "Accelerometer.csv"))
    force = np.median(np.linalg.norm(imu["linear_acceleration"], axis=1))
    assert abs(force - STANDARD_GRAVITY_MPS2) < FORCE_MEDIAN_TOLERANCE_MPS2
    np.testing.assert_array_equal(pressure.stamp_ns, time_column(folder / "Barometer.csv"))
    for line in ("imu/data:", "imu/mag:", "imu/pressure:"):
        assert line in stdout
    if platform == "android":
        mag = BagReader(bag).read(topics.IMU_MAG)
        np.testing.assert_array_equal(mag.stamp_ns, time_column(folder / "Magnetometer.csv"))
        assert "500 Hz" in stdout and "(5 a sample)" in stdout
    else:
        assert topics.IMU_MAG not in BagReader(bag).topics
        assert "iOS's convention" in stdout and "at 1.03 Hz" in stdout


def test_the_zip_the_app_shares_imports_the_same(imported, tmp_path):
    folder = SENSOR_LOGGER_EXPORTS["ios"]
    archive = shutil.make_archive(str(tmp_path / "export"), "zip", folder.parent, folder.name)
    done = cli("pdr-sim", "import-phone", archive, "--out", tmp_path / "bag")
    assert done.returncode == 0, done.stderr
    direct = BagReader(imported["ios"][0]).read(topics.IMU_DATA)
    zipped = BagReader(tmp_path / "bag").read(topics.IMU_DATA)
    np.testing.assert_array_equal(zipped.stamp_ns, direct.stamp_ns)
    np.testing.assert_array_equal(zipped["linear_acceleration"], direct["linear_acceleration"])


@pytest.mark.parametrize("platform", ["android", "ios"])
def test_a_phone_held_in_the_hand_is_not_walked_as_a_pocket(imported, platform, tmp_path):
    bag, _ = imported[platform]
    done = cli("pdr-pocket", "run", bag, "--out", tmp_path / "run")
    report = json.loads((tmp_path / "run" / "report.json").read_text())
    assert report["placement"]["placement"] == "not in a pocket"
    assert report["steps"] == 0 and report["step_distance_m"] == 0.0
    assert done.returncode == EXIT_REFUSED
    assert "not in a pocket" in done.stderr.splitlines()[0]


def test_pdr_eval_runs_the_exports_as_they_are_beside_pocket_walks(tmp_path):
    """Acceptance 3: ``pdr-eval`` on the two exports' folders (imported with import-phone,
    the walkers' own footfall counts in the manifest) and on two shared pocket walks, the
    navigator chosen by ``auto``: summary.md gives each one's steps, footfalls, distance,
    floor, placement, barometer and warnings; the exports are no pocket walks, unscored."""
    manifest = tmp_path / "manifest.csv"
    with manifest.open("w", newline="") as stream:
        out = csv.writer(stream)
        out.writerow(["recording", "dataset", "import_options", "true_footfalls"])
        out.writerow([SENSOR_LOGGER_EXPORTS["android"], "phone", "", 27])
        out.writerow([SENSOR_LOGGER_EXPORTS["ios"], "phone", "", 28])
        out.writerow([OXFORD, "pocket", shlex.join(OXFORD_ARGS), ""])
        out.writerow([NORM_THIGH, "pocket", shlex.join(NORM_THIGH_ARGS), ""])
    done = cli("pdr-eval", "--manifest", manifest, "--out", tmp_path / "out")
    assert done.returncode == 0, done.stderr
    with (tmp_path / "out" / "summary.csv").open(newline="") as stream:
        rows = {r["recording"]: r for r in csv.DictReader(stream) if r["recording"]}
    for name in ("inhand-27-steps-Matan", "inhand-28-steps-Ido"):
        row = rows[name]
        assert (row["navigator"], row["status"], row["placement"]) == \
            ("pocket", "not a pocket walk", "not in a pocket")
        assert row["steps"] == "0" and row["footfall_error"] == ""
    assert rows["inhand-27-steps-Matan"]["barometer"] == "fused"
    for name in (OXFORD.stem, "imu"):
        row = rows[name]
        assert (row["navigator"], row["status"]) == ("pocket", "done")
        assert int(row["steps"]) > 20 and float(row["distance_m"]) > 20.0
        assert row["placement"] in ("front pocket", "back pocket", "unknown")
    text = (tmp_path / "out" / "summary.md").read_text()
    assert "| placement | barometer | steps | footfalls | distance_m | final_floor |" in text
    assert "## Not pocket walks" in text and "not in a pocket: the accelerometer heard" in text


def test_the_users_wrong_path_is_named_at_every_step(tmp_path):
    """Issue 54's first report: the Android's gravity-removed Accelerometer.csv alone, read
    in g as the old hint said. Import refuses it as gravity-removed (never a unit); forced
    in, the pocket navigator's first lines say gravity is missing and the pitch swings
    13 times a thigh's (the user's 13.4), and --strict refuses the run (acceptance 2)."""
    accelerometer = SENSOR_LOGGER_EXPORTS["android"] / "Accelerometer.csv"
    args = ["import-csv", accelerometer, "--out", tmp_path / "bag", "--time-col", "time",
            "--time-unit", "ns", "--acc-cols", "x,y,z", "--acc-unit", "g"]
    refused = cli("pdr-sim", *args)
    assert refused.returncode == 2 and "looks gravity-removed" in refused.stderr
    assert "--acc-unit" not in refused.stderr
    assert cli("pdr-sim", *args, "--force").returncode == 0
    run = cli("pdr-pocket", "run", tmp_path / "bag", "--out", tmp_path / "run")
    first = run.stderr.splitlines()
    assert run.returncode == 0 and "gravity is missing" in first[0]
    assert "the pitch swings 13." in first[1]
    strict = cli("pdr-pocket", "run", tmp_path / "bag", "--out", tmp_path / "strict", "--strict")
    assert strict.returncode == 2 and "gravity is missing" in strict.stderr
