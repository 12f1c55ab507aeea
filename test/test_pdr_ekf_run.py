"""``pdr-ekf run`` on bags: outputs, report, and bad input (issue 4, offline part)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from pdr_core.bag import BagReader, write_batches
from wstest import ROOT, XIO, XIO_COLUMNS

REPORT_KEYS = {"duration_s", "distance_m", "final_error_m", "final_error_pct",
               "mean_error_3d_m", "armse_3d_m", "armse_2d_m"}



def test_sample_bag_outputs_and_report(procs, tmp_path):
    result = procs.run("pdr-ekf", "run", str(ROOT / "bags" / "foot_walk"), "--out",
                       str(tmp_path / "out"), "--plot")
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert report.keys() >= REPORT_KEYS
    assert report["armse_3d_m"] < 0.05 and report["final_error_pct"] < 0.5
    reader = BagReader(tmp_path / "out")
    assert set(reader.topics) == {"/pdr/foot/pose", "/pdr/foot/velocity", "/pdr/foot/stance",
                                  "/pdr/foot/path"}
    pose = reader.read("/pdr/foot/pose")
    assert len(pose) == report["samples"] == 6095
    cov = pose["pose.covariance"].reshape(-1, 6, 6)[:, :3, :3]
    assert (np.linalg.eigvalsh(cov) > 0).all(), "position covariance filled in"
    stance = reader.read("/pdr/foot/stance")
    assert 0.3 < stance["stationary"].mean() < 0.7
    assert (tmp_path / "out" / "path.png").stat().st_size > 10_000


def test_non_finite_samples_are_dropped_and_counted(procs, tmp_path):
    imu = BagReader(ROOT / "bags" / "foot_walk").read("/imu/data")
    imu["linear_acceleration"][[1000, 2000, 3000], 1] = np.nan
    imu["angular_velocity"][4000, 2] = np.inf
    write_batches(tmp_path / "bad", {"/imu/data": imu})
    result = procs.run("pdr-ekf", "run", str(tmp_path / "bad"), "--out", str(tmp_path / "out"))
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert report["dropped"]["non_finite"] == 4 and report["samples"] == 6091
    assert "loop_gap_m" in report, "no ground truth in this bag"


@pytest.mark.parametrize("units, message", [
    (["--acc-unit", "mps2", "--gyro-unit", "deg/s"], "the accelerometer looks like it is in g"),
    (["--acc-unit", "g", "--gyro-unit", "radps"], "the gyroscope looks like it is in deg/s")])
def test_wrong_units_are_refused(procs, tmp_path, units, message):
    imported = procs.run("pdr-sim", "import-csv", str(XIO), "--out", str(tmp_path / "bag"),
                         *XIO_COLUMNS, *units)
    assert imported.returncode == 0, imported.stderr
    result = procs.run("pdr-ekf", "run", str(tmp_path / "bag"), "--out", str(tmp_path / "out"))
    assert result.returncode == 2
    [line] = result.stderr.strip().splitlines()
    assert message in line and not (tmp_path / "out").exists()


def test_unknown_configuration_key_is_named(procs, tmp_path):
    config = tmp_path / "ekf.yaml"
    config.write_text("detector: {type: retarded, w3: 4}\n")
    result = procs.run("pdr-ekf", "run", str(ROOT / "bags" / "foot_walk"), "--out",
                       str(tmp_path / "out"), "--config", str(config))
    assert result.returncode == 2
    assert f"{config}.detector.w3: unknown key" in result.stderr


def test_evaluate_reproduces_the_run_report(procs, tmp_path):
    bag = ROOT / "bags" / "foot_walk"
    assert procs.run("pdr-ekf", "run", str(bag), "--out", str(tmp_path / "out")).returncode == 0
    result = procs.run("pdr-ekf", "evaluate", str(tmp_path / "out"), "--truth", str(bag),
                       "--plot", str(tmp_path / "e.png"))
    assert result.returncode == 0, result.stderr
    evaluated = json.loads(result.stdout.split("plot:")[0])
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    for key in REPORT_KEYS:
        assert evaluated[key] == pytest.approx(report[key], rel=1e-12)


def test_smoother_adds_the_smoothed_path_and_report(procs, tmp_path):
    bag = ROOT / "bags" / "foot_walk"
    result = procs.run("pdr-ekf", "run", str(bag), "--out", str(tmp_path / "out"),
                       "--smoother", "segmented", "--plot")
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert report["smoothed"].keys() >= REPORT_KEYS | {"segments"}
    paths = BagReader(tmp_path / "out").read_messages("/pdr/foot/smoothed_path")
    assert len(paths) == report["smoothed"]["segments"] > 30
    assert sum(len(path.poses) for _, path in paths) == report["samples"]
    assert (tmp_path / "out" / "smoothing.png").stat().st_size > 10_000


def test_montecarlo_writes_fits_table_series_and_plot(procs, tmp_path):
    result = procs.run("pdr-ekf", "montecarlo", "--source", "gyro_bias", "--runs", "50",
                       "--steps", "10", "--out", str(tmp_path / "mc"))
    assert result.returncode == 0, result.stderr
    assert "gyro_bias: 50/50 runs" in result.stderr
    lines = (tmp_path / "mc" / "fits.csv").read_text().splitlines()
    assert lines[0] == "source,estimator,quantity,coefficient,exponent"
    exponents = {line.split(",")[2]: float(line.split(",")[4]) for line in lines[1:]}
    assert exponents["sigma_p"] == pytest.approx(3.0, abs=0.15)
    assert exponents["sigma_yaw"] == pytest.approx(1.0, abs=0.15)
    assert (tmp_path / "mc" / "growth.png").stat().st_size > 10_000
    assert len((tmp_path / "mc" / "sigma.csv").read_text().splitlines()) > 100


@pytest.mark.parametrize("args, message", [
    (["--acc-noise", "-0.1", "--source", "acc_noise"],
     "--acc-noise: acc_noise_mps2_per_sqrt_hz must be a finite value >= 0"),
    (["--runs", "1"], "--runs: need at least 2 runs")])
def test_montecarlo_refuses_impossible_parameters(procs, args, message):
    result = procs.run("pdr-ekf", "montecarlo", *args)
    assert result.returncode == 2
    assert message in result.stderr
