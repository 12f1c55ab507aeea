"""``pdr-sim export-csv`` and ``pdr-pocket evaluate`` (issue 29, "Evaluate a pocket
recording"): a simulated pocket walk exported as a phone's CSV log and imported again is
navigated to the same steps; a run's output evaluated afterwards against the truth gives
the figures ``pdr-pocket run`` reports itself, against true step times the count, against
a known distance its error; and every refusal is one line with exit status 2."""
from __future__ import annotations

import json

import numpy as np
import pytest

from pdr_core import topics
from pdr_core.io.bag import BagReader, write_batches
from pdr_core.io.csv_export import import_arguments, log_table
from wstest import ROOT, Processes

pytestmark = pytest.mark.ros
POCKET_WALK = ROOT / "bags" / "pocket_walk"
FOOT_WALK = ROOT / "bags" / "foot_walk"
# What only pdr-pocket run can tell (the navigator's inputs and set-up), and what only
# evaluate says (where its truth came from): docs/reports.md
RUN_ONLY = {"samples", "dropped", "mounting_changes", "detection", "step_length", "placement",
            "stairs_refused", "warnings", "inputs", "refused"}
EVALUATE_ONLY = {"run", "truth_bag", "truth_time_offset_s", "warnings"}


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    """bags/pocket_walk navigated as it is, and exported, imported and navigated again."""
    folder = tmp_path_factory.mktemp("pocket_evaluate")
    procs = Processes(0, folder)
    exported = procs.run("pdr-sim", "export-csv", str(POCKET_WALK), "--out",
                         str(folder / "walk.csv"), "--steps-out", str(folder / "steps.csv"))
    assert exported.returncode == 0, exported.stderr
    reader = BagReader(POCKET_WALK)
    batches = reader.read_batches(["/imu/data", "/imu/mag", "/ground_truth/pose"])
    arguments = import_arguments(log_table(batches["/imu/data"], batches["/imu/mag"],
                                           batches["/ground_truth/pose"]))
    imported = procs.run("pdr-sim", "import-csv", str(folder / "walk.csv"), "--out",
                         str(folder / "imported"), *arguments)
    assert imported.returncode == 0, imported.stderr
    for bag, out in ((POCKET_WALK, "run"), (folder / "imported", "run_imported")):
        ran = procs.run("pdr-pocket", "run", str(bag), "--out", str(folder / out))
        assert ran.returncode == 0, ran.stderr
    return folder, exported.stdout


def report(folder, name="run"):
    return json.loads((folder / name / "report.json").read_text())


def evaluate(procs, *args):
    result = procs.run("pdr-pocket", "evaluate", *map(str, args))
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def test_export_writes_the_bags_samples_with_units_in_the_column_names(walk):
    folder, stdout = walk
    header, *rows = (folder / "walk.csv").read_text().splitlines()
    assert header.split(",") == ["t_s", "acc_x_mps2", "acc_y_mps2", "acc_z_mps2",
                                 "gyr_x_radps", "gyr_y_radps", "gyr_z_radps",
                                 "mag_x_t", "mag_y_t", "mag_z_t", "gt_x_m", "gt_y_m", "gt_z_m",
                                 "gt_qx", "gt_qy", "gt_qz", "gt_qw"]
    table = np.array([[float(v) for v in row.split(",")] for row in rows])
    data = BagReader(POCKET_WALK).read_batches(["/imu/data", "/imu/mag", "/ground_truth/pose"])
    imu = data["/imu/data"]
    # the three topics share their stamps: one row each
    assert len(table) == len(imu) == 11538
    assert np.array_equal(table[:, 0], (imu.stamp_ns - imu.stamp_ns[0]) * 1e-9)
    assert np.array_equal(table[:, 1:4], imu["linear_acceleration"])
    assert np.array_equal(table[:, 4:7], imu["angular_velocity"])
    assert np.array_equal(table[:, 7:10], data["/imu/mag"]["magnetic_field"])
    assert np.array_equal(table[:, 10:13], data["/ground_truth/pose"]["pose.position"])
    assert np.array_equal(table[:, 13:], data["/ground_truth/pose"]["pose.orientation"])
    steps = (folder / "steps.csv").read_text().split()
    true_ends = BagReader(POCKET_WALK).read("/ground_truth/step").stamp_ns
    assert steps[0] == "t_s" and np.array_equal(
        np.array(steps[1:], float), (true_ends - imu.stamp_ns[0]) * 1e-9)
    assert "--mag-unit t" in stdout and "--acc-unit mps2" in stdout
    assert "not written: /ground_truth/landmarks, /tf, /tf_static" in stdout


def test_the_exported_log_imported_again_navigates_to_the_same_steps(walk):
    folder, _ = walk
    original = BagReader(folder / "run").read(topics.POCKET_STEP)
    again = BagReader(folder / "run_imported").read(topics.POCKET_STEP)
    assert len(again) == len(original) == 122
    assert np.array_equal(again.stamp_ns - again.stamp_ns[0],
                          original.stamp_ns - original.stamp_ns[0])
    for name in ("index", "activity", "duration"):
        assert np.array_equal(again[name], original[name]), name
    for name in ("length", "heading", "vertical_displacement", "pitch_max", "pitch_min"):
        assert np.allclose(again[name], original[name], rtol=0, atol=1e-9), name
    assert report(folder, "run_imported")["steps"] == report(folder)["steps"] == 122


def test_evaluate_against_the_truth_gives_the_runs_own_figures(walk, procs):
    folder, _ = walk
    own = report(folder)
    assert own["true_steps"] == own["matched_steps"] == 122      # the run had the truth
    evaluated = evaluate(procs, folder / "run", "--truth", POCKET_WALK)
    assert evaluated.keys() - EVALUATE_ONLY == own.keys() - RUN_ONLY
    assert {k: v for k, v in evaluated.items() if k not in EVALUATE_ONLY} == \
        {k: v for k, v in own.items() if k not in RUN_ONLY}
    assert evaluated["truth_time_offset_s"] == 0.0 and evaluated["warnings"] == []


def test_evaluate_a_run_on_the_imported_log_against_the_simulated_truth(walk, procs):
    """The log's t = 0 is the simulated bag's first IMU message: the truth is moved onto
    the imported bag's clock, and the step figures are the original run's."""
    folder, _ = walk
    own = report(folder)
    assert "true_steps" not in report(folder, "run_imported")   # imported: no step truth
    evaluated = evaluate(procs, folder / "run_imported", "--truth", POCKET_WALK)
    assert evaluated["truth_time_offset_s"] == pytest.approx(1.7e9)
    for key in ("steps", "true_steps", "matched_steps", "missed_steps", "false_steps",
                "activity_confusion", "floor_error", "duration_s"):
        assert evaluated[key] == own[key], key
    for key in ("distance_error_pct", "final_error_m", "armse_2d_m", "step_distance_m"):
        assert evaluated[key] == pytest.approx(own[key], rel=1e-9), key
    # against its own import's ground_truth/pose (--pos-cols): the trajectory errors only
    own_import = evaluate(procs, folder / "run_imported", "--truth", folder / "imported")
    assert own_import["truth_time_offset_s"] == 0.0 and "true_steps" not in own_import
    assert own_import["armse_2d_m"] == pytest.approx(own["armse_2d_m"], rel=1e-9)


def test_truth_steps_count_footfalls_or_gait_cycles(walk, procs, tmp_path):
    folder, _ = walk
    own = report(folder)
    cycles = evaluate(procs, folder / "run_imported", "--truth-steps", folder / "steps.csv",
                      "--truth-steps-per", "cycle")
    assert cycles["truth_steps"] == {"file": str(folder / "steps.csv"), "per": "cycle",
                                     "rows": 122, "counted": 122, "error": 0,
                                     "error_pct": 0.0}
    # one row per footfall, no header, one footfall short: both feet, the other foot's
    # halfway through each cycle of the sensor leg
    ends = np.loadtxt(folder / "steps.csv", skiprows=1)
    durations = BagReader(POCKET_WALK).read("/ground_truth/step")["duration"]
    footfalls = np.sort(np.r_[ends, ends - durations / 2])[1:]
    np.savetxt(tmp_path / "footfalls.csv", footfalls)
    counted = evaluate(procs, folder / "run", "--truth-steps", tmp_path / "footfalls.csv")
    assert counted["truth_steps"] | {"file": None} == {
        "file": None, "per": "footfall", "rows": 243, "counted": own["footfalls"],
        "error": own["footfalls"] - 243, "error_pct": 100 * (own["footfalls"] - 243) / 243}
    assert counted["warnings"] == [] and "true_steps" not in counted
    # the same times in ms: counted all the same, and a warning
    np.savetxt(tmp_path / "ms.csv", footfalls * 1000, header="t_ms", comments="")
    result = procs.run("pdr-pocket", "evaluate", str(folder / "run"), "--truth-steps",
                       str(tmp_path / "ms.csv"))
    assert result.returncode == 0 and json.loads(result.stdout)["truth_steps"]["rows"] == 243
    [line] = result.stderr.splitlines()
    assert line.startswith(f"pdr-pocket: warning: {tmp_path / 'ms.csv'}: the step times span")
    assert "in another unit" in line


def test_distance_m_and_the_written_report(walk, procs, tmp_path):
    folder, _ = walk
    walked = report(folder)["step_distance_m"]
    out = tmp_path / "eval" / "report.json"
    printed = evaluate(procs, folder / "run", "--distance-m", "150", "--out", out)
    assert json.loads(out.read_text()) == printed
    assert printed["known_distance_m"] == 150.0
    assert printed["known_distance_error_m"] == pytest.approx(walked - 150)
    assert printed["known_distance_error_pct"] == pytest.approx(100 * (walked - 150) / 150)
    again = procs.run("pdr-pocket", "evaluate", str(folder / "run"), "--distance-m", "140",
                      "--out", str(out))
    assert again.returncode == 2 and json.loads(out.read_text()) == printed
    assert again.stderr == f"pdr-pocket: error: {out}: output exists already (remove it or " \
                           "pass --overwrite)\n"
    replaced = evaluate(procs, folder / "run", "--distance-m", "140", "--out", out,
                        "--overwrite")
    assert json.loads(out.read_text()) == replaced and replaced["known_distance_m"] == 140.0


def refusal(procs, *args) -> str:
    result = procs.run(*map(str, args))
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""
    [line] = result.stderr.splitlines()
    return line


def test_evaluate_refusals(walk, procs, tmp_path):
    folder, _ = walk
    run = folder / "run"
    assert refusal(procs, "pdr-pocket", "evaluate", run) == (
        f"pdr-pocket: error: {run}: nothing to evaluate against: give --truth BAG, "
        "--truth-steps CSV or --distance-m D")
    line = refusal(procs, "pdr-pocket", "evaluate", POCKET_WALK, "--distance-m", "10")
    assert line.startswith(f"pdr-pocket: error: {POCKET_WALK}: not a pdr-pocket run output: "
                           "no topic /pdr/pocket/step, /pdr/pocket/pose (the bag has: ")
    # steps and poses alone (a recording of pocket_pdr): no run record
    data = BagReader(run).read_batches([topics.POCKET_STEP, topics.POCKET_POSE])
    write_batches(tmp_path / "recorded", data)
    line = refusal(procs, "pdr-pocket", "evaluate", tmp_path / "recorded", "--distance-m", "10")
    assert line.startswith(f"pdr-pocket: error: {tmp_path / 'recorded'}: not a pdr-pocket run "
                           "output: its metadata.yaml has no pdr.pocket_run record")
    line = refusal(procs, "pdr-pocket", "evaluate", run, "--truth", run)
    assert line.startswith(f"pdr-pocket: error: {run}: no topic /ground_truth/step or "
                           "/ground_truth/pose to evaluate against (the bag has: ")
    assert refusal(procs, "pdr-pocket", "evaluate", run, "--truth-steps",
                   tmp_path / "none.csv") == f"pdr-pocket: error: {tmp_path / 'none.csv'}: no " \
                                             "such file"
    (tmp_path / "words.csv").write_text("t_s\n1.0\nlater\n")
    assert refusal(procs, "pdr-pocket", "evaluate", run, "--truth-steps",
                   tmp_path / "words.csv") == \
        f"pdr-pocket: error: {tmp_path / 'words.csv'}: row 3, column t_s: 'later' is not a number"
    assert refusal(procs, "pdr-pocket", "evaluate", run, "--distance-m", "0") == \
        "pdr-pocket: error: --distance-m: a walked distance in metres, > 0, got 0.0"
    assert refusal(procs, "pdr-pocket", "evaluate", tmp_path / "nothing", "--distance-m",
                   "1") == f"pdr-pocket: error: {tmp_path / 'nothing'}: no such bag"


def test_export_refusals(procs, tmp_path):
    line = refusal(procs, "pdr-sim", "export-csv", FOOT_WALK, "--out", tmp_path / "foot.csv",
                   "--steps-out", tmp_path / "steps.csv")
    assert line.startswith(f"pdr-sim: error: {FOOT_WALK}: no topic /ground_truth/step (the "
                           "bag has: ")
    assert list(tmp_path.iterdir()) == [], "nothing written"
    (tmp_path / "walk.csv").write_text("mine\n")
    assert refusal(procs, "pdr-sim", "export-csv", FOOT_WALK, "--out", tmp_path / "walk.csv"
                   ) == f"pdr-sim: error: {tmp_path / 'walk.csv'}: output exists already " \
                        "(remove it or pass --overwrite)"
    assert (tmp_path / "walk.csv").read_text() == "mine\n"
    replaced = procs.run("pdr-sim", "export-csv", str(FOOT_WALK), "--out",
                         str(tmp_path / "walk.csv"), "--overwrite")
    assert replaced.returncode == 0, replaced.stderr
    assert len((tmp_path / "walk.csv").read_text().splitlines()) == 6095 + 1
