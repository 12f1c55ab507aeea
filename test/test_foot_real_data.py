"""The foot navigator on the real recordings of ../shared/data, with the shipped
configuration (config/foot_ekf.yaml) and nothing tuned per trial (issue 4, acceptance 2–3).

Every trial goes through the documented commands: ``pdr-sim import-csv`` then
``pdr-ekf run``; the figures are read from the ``report.json`` it writes.
"""
from __future__ import annotations

import json
import math

import numpy as np

from wstest import (
    PYSHOE,
    PYSHOE_CLIMB,
    PYSHOE_NAV_ARGS,
    ROOT,
    XIO,
    XIO_ARGS,
    imported,
    needs_shared,
)

# ARMSE 3D per VICON trial, docs/foot_ins.md (measured 0.0948, 0.1256, 0.0833, 0.1159,
# 0.1227, 0.2043, 0.0469 m; mean 0.1134 m)
PYSHOE_ARMSE_M = {"2017-11-22-11-22-03": 0.095, "2017-11-22-11-30-14": 0.126,
                  "2017-11-22-11-49-03": 0.083, "2017-11-27-11-13-10": 0.116,
                  "2017-11-27-11-24-07": 0.123, "2017-12-15-18-03-05": 0.204,
                  "2018-02-22-10-10-29": 0.047}


def run_report(procs, tmp_path, csv, import_args, *run_args) -> dict:
    """``pdr-ekf run`` on the recording imported by ``pdr-sim import-csv`` (once per
    session, wstest.imported): its report."""
    bag, out = imported(csv, import_args), tmp_path / f"{csv.stem}_out"
    result = procs.run("pdr-ekf", "run", str(bag), "--out", str(out), *run_args)
    assert result.returncode == 0, result.stderr
    return json.loads((out / "report.json").read_text())


@needs_shared(*PYSHOE)
def test_pyshoe_vicon_one_configuration_for_all_trials(procs, tmp_path):
    """Target: mean ARMSE <= 0.12 m, no trial above 0.30 m (issue 4); held to the documented
    per-trial figures (PYSHOE_ARMSE_M) and mean 0.113 m. The pyshoe EKF with one SHOE
    threshold: mean 1.97 m; with the threshold tuned per trial (an oracle): 0.115 m.

    Smoothed too (issue 5, acceptance 2). Its mean ARMSE is 0.117 m against the filter's
    0.113 m: ARMSE over a trial is mostly heading drift, which smoothing cannot see. Within
    the steps, each step's heading removed, it is 39 % closer to the truth (mean 0.050 m
    against 0.082 m)."""
    reports = {csv.stem: run_report(procs, tmp_path, csv, PYSHOE_NAV_ARGS,
                                    "--smoother", "segmented") for csv in PYSHOE}
    vicon_armse = {k: r["armse_3d_m"] for k, r in reports.items()}
    print("armse_3d_m:", {k: round(v, 4) for k, v in vicon_armse.items()})
    assert vicon_armse.keys() == PYSHOE_ARMSE_M.keys()
    for trial, documented in PYSHOE_ARMSE_M.items():   # documented + 5 %
        assert vicon_armse[trial] <= 1.05 * documented, trial
    # README / docs/foot_ins.md: mean 0.113 m (+2 %); 0.1134 m measured
    assert np.mean(list(vicon_armse.values())) <= 0.116
    within = np.mean([r["within_step_rmse_m"] for r in reports.values()])
    smoothed = np.mean([r["smoothed"]["within_step_rmse_m"] for r in reports.values()])
    smoothed_armse = np.mean([r["smoothed"]["armse_3d_m"] for r in reports.values()])
    print(f"within-step RMSE: filter {within:.4f} m, smoothed {smoothed:.4f} m; smoothed "
          f"ARMSE {smoothed_armse:.4f} m")
    # README / docs/smoothing.md: 0.050 m against 0.082 m filtered (39 % closer, ratio
    # 0.61), each + 3-5 %; measured 0.0505 against 0.0835 m (ratio 0.605)
    assert within <= 0.085
    assert smoothed <= 0.0525
    assert smoothed <= 0.63 * within
    # docs/smoothing.md: smoothed mean ARMSE 0.117 m (+5 %); 0.1174 m measured
    assert smoothed_armse <= 0.124


@needs_shared(PYSHOE_CLIMB)
def test_the_trial_that_climbs(procs, tmp_path):
    """Issue 45, acceptance 1: the foot lifted 0.7 m in swings of 2.3 s, longer than the
    detector's adaptive span; without the valley-depth rule (``depth_min``) adaptive SHOE
    took each swing's slowest moment for stance, a ZUPT on a foot still coming down, and
    ended 0.871 m ARMSE (docs/foot_ins.md, "The foot on real stairs"). Target 0.15 m;
    held to the documented 0.035 m + 5 % (0.0346 m measured)."""
    report = run_report(procs, tmp_path, PYSHOE_CLIMB, PYSHOE_NAV_ARGS)
    assert report["armse_3d_m"] <= 0.0365


@needs_shared(XIO)
def test_xio_loop_gap(procs, tmp_path):
    """The walk ends where it started: the start-end gap is the error. Issue 4's target is
    0.08 m (the vendor's method: 82 mm); we end 0.36 m away, almost all of it height
    (+0.38 m over 16 strides of about 1.4 m, 2.4 cm per stride). The foot keeps turning
    in stance, which leaves the SHOE detector 3-16 samples of stance per stride, and the
    heel strike leaves ~0.09 m/s of forward velocity that the ZUPT turns into lift. The
    vendor's own figure moves by 4 cm of height per ms of gyro-accelerometer timing;
    ours stays at 0.35-0.44 m (README, "Real data"). Until that is solved, this guards
    the present figures against regressions."""
    report = run_report(procs, tmp_path, XIO, XIO_ARGS)
    assert 20 < report["distance_m"] < 30
    assert report["loop_gap_m"] <= 0.40


@needs_shared(PYSHOE[0])
def test_zeroed_heading_position_covariance_smooths_real_walks(procs, tmp_path):
    """smoother.zero_heading_position (Simón Colomar et al. 2012, section IV) on a VICON
    trial where the zeroed covariance turns indefinite: Eq. (9) with the covariance solves it
    by LU and stays finite (it gave NaN before; the states alone need no inverse)."""
    config = tmp_path / "zeroed.yaml"
    config.write_text(f"base: {ROOT / 'src/pdr_ins_ekf/config/foot_ekf.yaml'}\n"
                      "smoother:\n  zero_heading_position: true\n  covariance: true\n")
    csv = PYSHOE[0]                         # 2017-11-22-11-22-03
    report = run_report(procs, tmp_path, csv, PYSHOE_NAV_ARGS, "--smoother", "segmented",
                        "--config", str(config))
    assert math.isfinite(report["smoothed"]["armse_3d_m"])
    assert report["smoothed"]["armse_3d_m"] < 0.15


@needs_shared(*PYSHOE, XIO)
def test_the_drift_loop_changes_no_real_trial():
    """Issue 44, acceptance 3: the trials last 1-2 minutes, less than a revisit needs
    (min_revisit_s, 120 s), so with config/foot_drift.yaml the online loop associates no
    landmark and its path is the run's without it, sample for sample (docs/foot_ins.md,
    "Drift corrections")."""
    from pdr_core.io.bag import BagReader
    from pdr_drift.config import load_drift_config
    from pdr_ins_ekf.config import load_run_config
    from pdr_ins_ekf.drift_loop import navigate_online
    from pdr_ins_ekf.offline import navigate

    config = load_run_config(ROOT / "src" / "pdr_ins_ekf" / "config" / "foot_drift.yaml")
    drift = load_drift_config(ROOT / "src" / "pdr_drift" / "config" /
                              "landmark_drift_foot.yaml")
    for csv, args in [*((trial, PYSHOE_NAV_ARGS) for trial in PYSHOE), (XIO, XIO_ARGS)]:
        imu = BagReader(imported(csv, args)).read("/imu/data")
        plain = navigate(imu, config)
        corrected, log = navigate_online(imu, config, drift)
        assert log.drifts == [] and log.corrections == [], csv.stem
        np.testing.assert_array_equal(corrected.stamp_ns, plain.stamp_ns)
        np.testing.assert_array_equal(corrected.output.position, plain.output.position)
