"""The orientation filter on the real thigh recordings of ../shared/data (issue 16,
acceptance 8). They are samples: nothing here is tuned to them."""
from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.signal import find_peaks

from pdr_core.bag import BagReader
from pdr_pocket.attitude_offline import pocket_inputs
from pdr_pocket.config import OrientationConfig
from pdr_pocket.mounting import flexion_axis, signed_flexion_axis, thigh_pitch, up_axis
from pdr_pocket.orientation import OrientationFilter
from wstest import OXFORD, OXFORD_ARGS, THIGH, needs_shared

IMPORT = ["--time-col", "time", "--acc-cols", "accel_x,accel_y,accel_z",
          "--gyro-cols", "gyro_x,gyro_y,gyro_z", "--mag-cols", "mag_x,mag_y,mag_z",
          "--mag-unit", "ut"]
RECORDINGS = {"norm_thigh_1": 89, "s_both_thigh_1": 51}     # footfalls (both legs)
pytestmark = [pytest.mark.ros, needs_shared(OXFORD, *(THIGH / name for name in RECORDINGS))]


@pytest.fixture(scope="module")
def imported(tmp_path_factory):
    from wstest import Processes
    folder = tmp_path_factory.mktemp("thigh")
    procs = Processes(0, folder)
    for name in RECORDINGS:
        result = procs.run("pdr-sim", "import-csv", str(THIGH / name / "imu.csv"), "--out",
                           str(folder / name), *IMPORT)
        assert result.returncode == 0, result.stderr
    return folder, procs


@pytest.mark.parametrize("name", list(RECORDINGS))
def test_filter_runs_through_without_nans_and_flags_saturation(imported, name):
    folder, procs = imported
    result = procs.run("pdr-pocket", "attitude", str(folder / name), "--out",
                       str(folder / f"{name}_att"))
    assert result.returncode == 0, result.stderr
    report = json.loads((folder / f"{name}_att" / "report.json").read_text())
    attitude = BagReader(folder / f"{name}_att").read("/pdr/pocket/attitude")
    assert np.isfinite(attitude["orientation"]).all()
    assert np.isfinite(attitude["orientation_covariance"]).all()
    data = np.genfromtxt(THIGH / name / "imu.csv", delimiter=",", names=True)
    gyro = np.column_stack([data["gyro_x"], data["gyro_y"], data["gyro_z"]])
    flat_tops = ((gyro[1:] == gyro[:-1]) & (np.abs(gyro[1:]) > 4.0)).any(axis=1).sum()
    assert report["saturated_fraction"] * report["samples"] == flat_tops
    assert (flat_tops > 0) == (name == "s_both_thigh_1")


@pytest.mark.parametrize("name", list(RECORDINGS))
def test_pitch_swings_once_per_gait_cycle(imported, name):
    """The thigh pitch from the filter's attitude (the mounting estimated from the data)
    has one swing, a peak of at least 10°, per gait cycle: two footfalls."""
    folder, _ = imported
    batches = BagReader(folder / name).read_batches(["/imu/data", "/imu/mag"])
    inputs = pocket_inputs(batches["/imu/data"], batches["/imu/mag"])
    estimate = OrientationFilter(OrientationConfig()).run(inputs.t, inputs.gyro, inputs.accel,
                                                          inputs.mag)
    up = up_axis(inputs.accel[:50])          # both recordings start standing
    flexion = signed_flexion_axis(estimate.attitude, up, flexion_axis(inputs.gyro, up))
    pitch = np.degrees(thigh_pitch(estimate.attitude, up, flexion))
    peaks, _ = find_peaks(pitch, prominence=10.0, distance=40)   # 0.4 s at 100 Hz
    assert abs(len(peaks) - RECORDINGS[name] / 2) <= 2


def test_calibrate_mag_reports_the_coverage_of_a_walk(imported):
    folder, procs = imported
    refused = procs.run("pdr-pocket", "calibrate-mag", str(folder / "norm_thigh_1"), "--out",
                        str(folder / "mag.yaml"))
    assert refused.returncode == 2 and "% of the sphere of directions" in refused.stderr
    forced = procs.run("pdr-pocket", "calibrate-mag", str(folder / "norm_thigh_1"), "--out",
                       str(folder / "mag.yaml"), "--min-coverage", "0")
    assert forced.returncode == 0, forced.stderr
    assert "% of the sphere" in forced.stdout


@pytest.mark.parametrize(("name", "tolerance"), [("norm_thigh_1", 0.03),
                                               ("s_both_thigh_1", 0.05)])
def test_navigator_counts_the_footfalls(imported, tmp_path, name, tolerance):
    """Issue 17, acceptance 7: footfalls within 3 % of the 89 true on the level walk and 5 %
    of the 51 on the stairs."""
    folder, procs = imported
    result = procs.run("pdr-pocket", "run", str(folder / name), "--out", str(tmp_path / "run"))
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "run" / "report.json").read_text())
    assert abs(report["footfalls"] - RECORDINGS[name]) <= tolerance * RECORDINGS[name]


def test_accelerometer_only_pocket_counts_the_footfalls(tmp_path):
    """Issue 17, acceptance 7: the Oxford front-pocket phone (no gyroscope), the pitch from
    the gravity direction alone: footfalls within 3 % of the 327 counted by the foot
    switch."""
    from wstest import Processes
    procs = Processes(0, tmp_path)
    imported = procs.run("pdr-sim", "import-csv", str(OXFORD), "--out", str(tmp_path / "bag"),
                         *OXFORD_ARGS)
    assert imported.returncode == 0, imported.stderr
    result = procs.run("pdr-pocket", "run", str(tmp_path / "bag"), "--out", str(tmp_path / "run"))
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "run" / "report.json").read_text())
    assert abs(report["footfalls"] - 327) <= 0.03 * 327
    assert report["activities"]["walking"] >= 0.95 * report["steps"]
