"""pdr-pocket attitude and calibrate-mag, and the pocket_pdr node against them (issue 16)."""
from __future__ import annotations

import json
import signal

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdr_core.bag import BagReader
from pdr_core.magnetic_field import TABLE_3_3, IronDistortion, homogeneous
from wstest import ROOT, log_text, wait_for_log

pytestmark = pytest.mark.ros
BAG = ROOT / "bags" / "pocket_walk"


def test_attitude_report_and_outputs_on_the_sample_bag(procs, tmp_path):
    result = procs.run("pdr-pocket", "attitude", str(BAG), "--out", str(tmp_path / "att"),
                       "--plot")
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "att" / "report.json").read_text())
    assert report["samples"] == 11538
    assert report["rmse_deg"]["roll"] < 1.0 and report["rmse_deg"]["pitch"] < 1.0
    assert max(abs(e) for e in report["final_bias_error_deg_per_s"]) < 0.02
    assert 0 < report["update_fraction"]["absolute_gravity"] < 1
    assert report["update_fraction"]["differential_magnetic"] > 0.9
    reader = BagReader(tmp_path / "att")
    attitude = reader.read("/pdr/pocket/attitude")
    assert len(attitude) == len(reader.read("/pdr/pocket/gyro_bias")) == 11538
    q = attitude["orientation"]
    assert np.isfinite(q).all() and np.allclose(np.linalg.norm(q, axis=1), 1.0)
    cov = attitude["orientation_covariance"].reshape(-1, 3, 3)
    assert (np.linalg.eigvalsh(cov) > 0).all()
    assert (tmp_path / "att" / "attitude.png").stat().st_size > 20_000


def test_attitude_refuses_data_in_g_with_one_line(procs, tmp_path):
    csv = tmp_path / "g.csv"
    t = np.arange(300) * 0.01
    np.savetxt(csv, np.column_stack([t, np.zeros(300), np.zeros(300), np.ones(300),
                                     np.zeros((300, 3))]), delimiter=",",
               header="t,ax,ay,az,gx,gy,gz", comments="")
    imported = procs.run("pdr-sim", "import-csv", str(csv), "--out", str(tmp_path / "bag"),
                         "--time-col", "t", "--acc-cols", "ax,ay,az", "--gyro-cols", "gx,gy,gz")
    assert imported.returncode == 0, imported.stderr
    result = procs.run("pdr-pocket", "attitude", str(tmp_path / "bag"), "--out",
                       str(tmp_path / "out"))
    assert result.returncode == 2
    [line] = result.stderr.strip().splitlines()
    assert "imu/data" in line and "in g" in line and not (tmp_path / "out").exists()


def calibration_csv(path, seed=0, n=3000):
    """A calibration motion simulated in Munich's field: the sensor turned through random
    directions, its magnetometer distorted as Table 3.3, 0.015 µT noise."""
    rng = np.random.default_rng(seed)
    field = homogeneous("munich")
    true = Rotation.random(n, random_state=seed).inv().apply(field)
    raw = IronDistortion(**TABLE_3_3).distort(true, float(np.linalg.norm(field)))
    raw += rng.normal(0.0, 0.015e-6, raw.shape)
    np.savetxt(path, raw * 1e6, delimiter=",", header="mag_x,mag_y,mag_z", comments="")


def test_calibrate_mag_recovers_table_3_3(procs, tmp_path):
    calibration_csv(tmp_path / "cal.csv")
    result = procs.run("pdr-pocket", "calibrate-mag", str(tmp_path / "cal.csv"), "--out",
                       str(tmp_path / "mag.yaml"), "--field-norm-ut", "48", "--plot",
                       str(tmp_path / "mag.png"))
    assert result.returncode == 0, result.stderr
    assert "residual RMS" in result.stdout and "% of the sphere" in result.stdout
    import yaml
    fitted = yaml.safe_load((tmp_path / "mag.yaml").read_text())
    assert fitted["xi"] == pytest.approx(TABLE_3_3["xi"], rel=0.01)
    np.testing.assert_allclose(fitted["offset"], TABLE_3_3["offset"], rtol=0.01)
    np.testing.assert_allclose(fitted["M"], TABLE_3_3["M"], rtol=0.01, atol=1e-4)
    assert (tmp_path / "mag.png").stat().st_size > 20_000


def test_calibrate_mag_refuses_a_walk_saying_how_much_it_covers(procs, tmp_path):
    result = procs.run("pdr-pocket", "calibrate-mag", str(BAG), "--out",
                       str(tmp_path / "mag.yaml"))
    assert result.returncode == 2
    assert "% of the sphere of directions" in result.stderr
    assert not (tmp_path / "mag.yaml").exists()


def test_live_node_equals_offline_run(procs, tmp_path):
    offline = procs.run("pdr-pocket", "attitude", str(BAG), "--out", str(tmp_path / "offline"))
    assert offline.returncode == 0, offline.stderr
    ref = BagReader(tmp_path / "offline").read("/pdr/pocket/attitude")
    expected = len(ref)     # the last sample goes out when its magnetometer reading comes
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={tmp_path / 'live'}", "-p",
                           "topics:=[pdr/pocket/attitude, pdr/pocket/gyro_bias]", "-p",
                           f"max_messages:={2 * expected}", name="record")
    node = procs.start("pocket_pdr", "--ros-args", "-p", "imu_durability:=transient_local",
                       name="pocket_pdr")
    wait_for_log(recorder, "recording /pdr/pocket/attitude", "recording /pdr/pocket/gyro_bias")
    played = procs.run("bag_play", "--ros-args", "-p", f"bag:={BAG}", "-p",
                       "topics:=[/imu/data, /imu/mag]", "-p", "rate:=0.0", "-p",
                       "wait_for_subscribers:=1")
    assert played.returncode == 0, played.stderr
    assert recorder.wait(timeout=120) == 0, log_text(recorder) + log_text(node)
    assert procs.stop(node, signal.SIGINT) == 0
    live = BagReader(tmp_path / "live").read("/pdr/pocket/attitude")
    assert len(live) == expected
    np.testing.assert_array_equal(live.stamp_ns, ref.stamp_ns[:expected])
    np.testing.assert_allclose(live["orientation"], ref["orientation"][:expected], rtol=0,
                               atol=1e-9)
    np.testing.assert_allclose(live["orientation_covariance"],
                               ref["orientation_covariance"][:expected], rtol=0, atol=1e-12)


def test_run_writes_steps_poses_path_and_report_on_the_sample_bag(procs, tmp_path):
    result = procs.run("pdr-pocket", "run", str(BAG), "--out", str(tmp_path / "run"), "--plot")
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "run" / "report.json").read_text())
    assert report["missed_steps"] == 0 and report["false_steps"] == 0
    assert abs(report["distance_error_pct"]) < 1.5
    assert report["activity_correct_pct"] > 98
    reader = BagReader(tmp_path / "run")
    steps = reader.read("/pdr/pocket/step")
    poses = reader.read("/pdr/pocket/pose")
    assert len(steps) == len(poses) == report["steps"] > 0
    cov = poses["pose.covariance"].reshape(-1, 6, 6)[:, :3, :3]
    assert np.isfinite(cov).all() and (np.linalg.eigvalsh(cov) >= -1e-12).all()
    [(_, path)] = reader.read_messages("/pdr/pocket/path")
    assert len(path.poses) == len(steps)
    assert (tmp_path / "run" / "path.png").stat().st_size > 30_000
