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

import json
import shutil

import numpy as np
import pytest

from pdr_core import topics
from pdr_core.bag import BagReader
from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.walk_plausibility import EXIT_REFUSED
from wstest import SENSOR_LOGGER_EXPORTS, cli, needs_shared

pytestmark = needs_shared(*SENSOR_LOGGER_EXPORTS.values())

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
