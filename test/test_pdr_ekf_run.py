"""``pdr-ekf run`` on bags: outputs, report, and bad input (issue 4, offline part)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pdr_core.io.bag import BagReader, write_batches
from pdr_core.io.nav_path import last_path
from wstest import ROOT, XIO, XIO_COLUMNS, needs_shared

REPORT_KEYS = {"duration_s", "distance_m", "final_error_m", "final_error_pct",
               "mean_error_3d_m", "armse_3d_m", "armse_2d_m"}



def test_sample_bag_outputs_and_report(procs, tmp_path):
    result = procs.run("pdr-ekf", "run", str(ROOT / "bags" / "foot_walk"), "--out",
                       str(tmp_path / "out"), "--plot")
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert report.keys() >= REPORT_KEYS
    assert report["armse_3d_m"] < 0.05 and report["final_error_pct"] < 0.5
    assert report["warnings"] == [] and result.stderr == ""    # a walk's median |f|
    reader = BagReader(tmp_path / "out")
    assert set(reader.topics) == {"/pdr/foot/pose", "/pdr/foot/velocity", "/pdr/foot/stance",
                                  "/pdr/foot/path", "/pdr/foot/odometry", "/tf", "/tf_static",
                                  "/pdr/foot/step", "/pdr/foot/step_pose"}
    pose = reader.read("/pdr/foot/pose")
    assert len(pose) == report["samples"] == 6095
    cov = pose["pose.covariance"].reshape(-1, 6, 6)[:, :3, :3]
    assert (np.linalg.eigvalsh(cov) > 0).all(), "position covariance filled in"
    # the NEES once a second of the 61 s walk, position and (a simulated truth) attitude
    for figures in report["consistency"].values():
        low, high = figures["band_per_dof"]
        assert figures["samples"] == int(report["duration_s"])
        assert figures["inside"] == (low <= figures["nees_per_dof"] <= high)
    assert report["consistency"].keys() == {"position_3d", "position_2d", "attitude"}
    stance = reader.read("/pdr/foot/stance")
    assert 0.3 < stance["stationary"].mean() < 0.7
    # a stride per footfall of the simulated 1.3 m strides (bags/foot_walk.yaml), level
    steps, step_poses = reader.read("/pdr/foot/step"), reader.read("/pdr/foot/step_pose")
    np.testing.assert_array_equal(steps.stamp_ns, step_poses.stamp_ns)
    np.testing.assert_array_equal(steps["index"], np.arange(len(steps)))
    assert len(steps) == len(last_path(reader, "/pdr/foot/path")) >= 30
    assert np.median(steps["length"]) == pytest.approx(1.3, abs=0.05)
    assert (steps["activity"] == 1).all() and np.abs(steps["vertical_displacement"]).max() < 0.05
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


@needs_shared(XIO)
@pytest.mark.parametrize("units, message", [
    (["--acc-unit", "mps2", "--gyro-unit", "deg/s"], "the accelerometer looks like it is in g"),
    (["--acc-unit", "g", "--gyro-unit", "radps"], "the gyroscope looks like it is in deg/s")])
def test_wrong_units_are_refused(procs, tmp_path, units, message):
    imported = procs.run("pdr-sim", "import-csv", str(XIO), "--out", str(tmp_path / "bag"),
                         *XIO_COLUMNS, *units)
    assert imported.returncode == 2 and "--force" in imported.stderr, "refused at import"
    imported = procs.run("pdr-sim", "import-csv", str(XIO), "--out", str(tmp_path / "bag"),
                         *XIO_COLUMNS, *units, "--force")
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
    assert "gyro_bias ins: 50/50 runs" in result.stderr
    lines = (tmp_path / "mc" / "fits.csv").read_text().splitlines()
    assert lines[0] == "source,estimator,quantity,coefficient,exponent"
    exponents = {line.split(",")[2]: float(line.split(",")[4]) for line in lines[1:]}
    assert exponents["sigma_p"] == pytest.approx(3.0, abs=0.15)
    assert exponents["sigma_yaw"] == pytest.approx(1.0, abs=0.15)
    assert (tmp_path / "mc" / "growth.png").stat().st_size > 10_000
    assert len((tmp_path / "mc" / "sigma.csv").read_text().splitlines()) > 100


def test_montecarlo_ekf_writes_paper_tables_and_consistency(procs, tmp_path):
    result = procs.run("pdr-ekf", "montecarlo", "--source", "acc_noise", "--estimator",
                       "ekf_original,ekf_limited", "--profile", "xsens_mti", "--runs", "4",
                       "--steps", "10", "--out", str(tmp_path / "mc"))
    assert result.returncode == 0, result.stderr
    assert "acc_noise ekf_limited: 4/4 runs" in result.stderr
    rows = [line.split(",") for line in
            (tmp_path / "mc" / "fits.csv").read_text().splitlines()[1:]]
    assert {(r[0], r[1], r[2]) for r in rows} == {
        ("acc_noise", e, q) for e in ("ekf_original", "ekf_limited")
        for q in ("sigma_p", "sigma_yaw")}
    assert "| acc_noise | ekf_limited | sigma_p |" in result.stdout and "6e-4·t" in result.stdout
    consistency = (tmp_path / "mc" / "consistency.csv").read_text().splitlines()
    assert consistency[0].endswith("nees_position") and len(consistency) > 20


def test_analytic_prints_the_papers_quantities_as_json(procs):
    result = procs.run("pdr-ekf", "analytic", "--json", "--times", "10,100")
    assert result.returncode == 0, result.stderr
    out = json.loads(result.stdout)
    assert out.keys() >= {"sigma_v_mps", "sigma_theta_rad", "sigma_gN_radps", "sigma_par_m",
                          "sigma_perp_m", "sigma_yaw_rad"}
    assert len(out["sigma_perp_m"]) == 2 and out["sigma_perp_m"][1] > out["sigma_perp_m"][0]
    assert out["sigma_v_mps"] == pytest.approx(vn200_sigma_v_mps(), rel=1e-6)  # 1.5195 mm/s


def vn200_sigma_v_mps() -> float:
    """σ_v of the defaults (VN-200 at 800 Hz, r = 0.02 m/s, 0.2 s of stance in a 0.536 s
    stride, a_c = 0.84) from Eq. (43) with P12 of Eq. (45), solved for σ_v² by bisection
    (not through Eq. (44)'s quartic, as the model does): x²/K − VRW² = −2g·P12."""
    g = 9.80665
    arw, vrw = math.radians(0.21) / 60, 0.14e-3 * g          # rad/√s, m/s²/√Hz
    rrw = math.radians(0.048) / 60                            # rad/s/√s
    k = 0.02**2 * 0.536 / (800 * 0.2)                         # Eq. (53)

    def balance(x):
        return x**2 / k - vrw**2 - 2 * g * math.sqrt(arw**2 * k + 2 * 0.84 * rrw * x
                                                     * math.sqrt(k) / g)

    return math.sqrt(brentq(balance, math.sqrt(k) * vrw, 1.0, xtol=1e-300, rtol=1e-15))


@pytest.mark.parametrize("args, message", [
    (["montecarlo", "--acc-noise", "-0.1", "--source", "acc_noise"],
     "--acc-noise: acc_noise_mps2_per_sqrt_hz must be a finite value >= 0"),
    (["montecarlo", "--runs", "1"], "--runs: need at least 2 runs"),
    (["montecarlo", "--estimator", "ekf_limited", "--rest-s", "0"],
     "--rest-s: the EKF aligns on the standing period"),
    (["analytic", "--t-stance-s", "0.6", "--t-stride-s", "0.5"],
     "t_stance_s must be in (0, t_stride_s"),
    (["analytic", "--vrw-mg-per-sqrt-hz", "-0.1"],
     "--vrw-mg-per-sqrt-hz: a noise density must be"),
    (["analytic", "--zupt-sigma-mps", "0"], "zupt_sigma_mps (r) must be > 0"),
    (["analytic", "--times", "-5"], "times must be finite and >= 0 s"),
    (["study", "sweep", "--runs", "1"], "need points >= 2, steps >= 3 and runs 0 or >= 2")])
def test_analyses_refuse_impossible_parameters(procs, args, message):
    result = procs.run("pdr-ekf", *args)
    assert result.returncode == 2
    assert message in result.stderr


def test_sweep_writes_table_csv_and_figure(procs, tmp_path):
    result = procs.run("pdr-ekf", "study", "sweep", "--points", "2", "--runs", "2",
                       "--steps", "10", "--out", str(tmp_path / "sweep"))
    assert result.returncode == 0, result.stderr
    lines = (tmp_path / "sweep" / "sweep.csv").read_text().splitlines()
    assert lines[0].startswith("parameter,value,quantity,analytic,simulated_mean")
    assert len(lines) == 1 + 3 * 2 * 4
    assert (tmp_path / "sweep" / "sweep.png").stat().st_size > 30_000


def test_imu_profile_selects_the_shipped_configuration(procs, tmp_path):
    result = procs.run("pdr-ekf", "run", str(ROOT / "bags" / "foot_walk"), "--out",
                       str(tmp_path / "out"), "--imu-profile", "xsens_mtw")
    assert result.returncode == 0, result.stderr
    assert json.loads((tmp_path / "out" / "report.json").read_text())["armse_3d_m"] < 0.05
    result = procs.run("pdr-ekf", "run", str(ROOT / "bags" / "foot_walk"), "--out",
                       str(tmp_path / "other"), "--imu-profile", "bno055")
    assert result.returncode == 2
    assert "imu_profile: no configuration for 'bno055' (known: consumer_phone" in result.stderr
