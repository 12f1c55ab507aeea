"""``pdr-eval``: a navigator over many recordings in parallel, summarised (issue 43)."""
from __future__ import annotations

import csv
import json
import os
import re
import shutil
import signal
import subprocess
import time

import numpy as np
import pytest

from pdr_core.io.bag import write_batches
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import IMU
from wstest import ROOT, cli, installed

REPORTS = ROOT / "docs" / "reports.md"
TRUTH_CONDITIONS = {"pose", "steps", "floors", "stance truth"}
RUN_SECTIONS = ("Trajectory figures", "`pdr-ekf run`", "The pocket walk", "`pdr-pocket run`")


POCKET_WALK_FOOTFALLS = 200      # a known count for the manifest to score against


def still_bag(path) -> None:
    """10 s of an IMU lying still at 100 Hz: nothing for ``auto`` to tell apart."""
    n = 1000
    stamps = 1_700_000_000_000_000_000 + np.arange(n, dtype=np.int64) * 10_000_000
    rng = np.random.default_rng(0)
    write_batches(path, {"/imu/data": MessageBatch(IMU, stamps, "imu_link", {
        "orientation": np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)),
        "orientation_covariance": np.zeros((n, 9)),
        "angular_velocity": 0.01 * rng.standard_normal((n, 3)),
        "angular_velocity_covariance": np.zeros((n, 9)),
        "linear_acceleration": [0.0, 0.0, 9.81] + 0.02 * rng.standard_normal((n, 3)),
        "linear_acceleration_covariance": np.zeros((n, 9))})})


def dataset(tmp_path):
    """Two datasets of links to the sample bags: ``sim`` (a foot and a pocket walk, their
    navigator chosen by ``auto``, the pocket walk with a known footfall count), and
    ``vicon`` (the real VICON walk), plus a corrupt bag, a missing one and a still one
    (``auto`` refuses it) in ``bad``."""
    for folder, bags in (("sim", ("foot_walk", "pocket_walk")), ("vicon", ("vicon_walk",))):
        (tmp_path / folder).mkdir()
        for bag in bags:
            (tmp_path / folder / bag).symlink_to(ROOT / "bags" / bag)
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / "corrupt.mcap").write_bytes(b"\x89MCAP0\r\n" + b"\0" * 64)
    still_bag(tmp_path / "bad" / "still")
    manifest = tmp_path / "manifest.csv"
    manifest.write_text("recording,dataset,navigator,true_footfalls\n"
                        f"sim/foot_walk,,,\nsim/pocket_walk,,,{POCKET_WALK_FOOTFALLS}\n"
                        "vicon/vicon_walk,,foot,\nbad/corrupt.mcap,bad,foot,\n"
                        "bad/missing,bad,pocket,\nbad/still,bad,auto,\n")
    return manifest


def summary_rows(out) -> list[dict]:
    with (out / "summary.csv").open() as f:
        return list(csv.DictReader(f))


def without_timing(rows: list[dict]) -> list[dict]:
    return [{k: v for k, v in r.items() if k != "seconds"} for r in rows]


@pytest.fixture(scope="module")
def evaluated(tmp_path_factory):
    """One pdr-eval run over the manifest with two processes, shared by the tests."""
    tmp_path = tmp_path_factory.mktemp("eval")
    manifest = dataset(tmp_path)
    result = cli("pdr-eval", "--manifest", str(manifest), "--out", str(tmp_path / "out"),
                 "--workers", "2")
    return tmp_path, manifest, result


def test_failures_are_listed_and_the_rest_summarised(evaluated):
    """A corrupt bag, a missing one and one too still to choose a navigator for: failed
    with their reason, the other three run and summarised per dataset, exit status 1
    (issue 43, acceptance 3)."""
    tmp_path, _, result = evaluated
    assert result.returncode == 1, result.stderr
    assert "6 recordings: 3 run, 0 kept from an earlier run, 3 failed" in result.stdout
    rows = {r["recording"]: r for r in summary_rows(tmp_path / "out") if r["recording"]}
    assert {k: r["status"] for k, r in rows.items()} == {
        "foot_walk": "done", "pocket_walk": "done", "vicon_walk": "done",
        "corrupt": "failed", "missing": "failed", "still": "failed"}
    assert "corrupt.mcap" in rows["corrupt"]["error"]
    assert "too little to tell" in rows["still"]["error"] and \
        "--navigator foot" in rows["still"]["error"]
    assert rows["missing"]["error"].endswith("missing: no such file or directory")
    assert f"failed: missing: {tmp_path / 'bad' / 'missing'}" in result.stderr
    for name in ("foot_walk", "pocket_walk", "vicon_walk"):
        report = json.loads((tmp_path / "out" / name / "run" / "report.json").read_text())
        assert float(rows[name]["armse_3d_m"]) == pytest.approx(report["armse_3d_m"])
        assert report["eval"]["input_hash"] and report["eval"]["navigator"] in ("foot", "pocket")
    assert float(rows["pocket_walk"]["missed_steps"]) == 0
    stats = [r for r in summary_rows(tmp_path / "out") if not r["recording"]]
    sim_max = next(r for r in stats if r["dataset"] == "sim" and r["statistic"] == "max")
    assert float(sim_max["armse_3d_m"]) == pytest.approx(
        max(float(rows[n]["armse_3d_m"]) for n in ("foot_walk", "pocket_walk")))
    assert sim_max["recordings"] == "2"
    text = (tmp_path / "out" / "summary.md").read_text()
    assert "6 recordings, 3 failed, 0 not pocket walks" in text and "| corrupt |" in text


def test_auto_chooses_and_the_summary_says_what_each_walk_was(evaluated):
    """Without a truth too (issue 54, point 4): the navigator ``auto`` chose, steps,
    footfalls, distance, floor, placement, barometer and warnings per recording, as the
    reports say; the known footfall count scored; per dataset their statistics."""
    tmp_path, _, _ = evaluated
    out = tmp_path / "out"
    rows = {r["recording"]: r for r in summary_rows(out) if r["recording"]}
    assert rows["foot_walk"]["navigator"] == "foot"
    assert rows["pocket_walk"]["navigator"] == "pocket"
    for name in ("foot_walk", "pocket_walk", "vicon_walk"):
        report = json.loads((out / name / "run" / "report.json").read_text())
        walk, row = report["eval"]["walk"], rows[name]
        assert int(row["steps"]) == walk["steps"] > 0
        assert int(row["footfalls"]) == walk["footfalls"] >= 2 * walk["steps"] - 1
        assert walk["distance_m"] > 0
        assert float(row["distance_m"]) == pytest.approx(walk["distance_m"])
        assert int(row["final_floor"]) == walk["final_floor"]
        assert row["placement"] == walk["placement"] and row["barometer"] == walk["barometer"]
        assert int(row["warnings"]) == len(report["eval"]["warnings"])
    pocket = json.loads((out / "pocket_walk" / "run" / "report.json").read_text())
    assert pocket["eval"]["walk"]["steps"] == pocket["steps"]
    assert rows["foot_walk"]["placement"] == "foot" and \
        rows["pocket_walk"]["placement"] == pocket["placement"]["placement"]
    assert pocket["eval"]["navigator_why"].startswith("auto: ")
    assert float(rows["pocket_walk"]["footfall_error"]) == \
        pocket["footfalls"] - POCKET_WALK_FOOTFALLS
    assert rows["foot_walk"]["footfall_error"] == ""
    stats = [r for r in summary_rows(out) if not r["recording"]]
    sim_median = next(r for r in stats if r["dataset"] == "sim" and r["statistic"] == "median")
    assert float(sim_median["steps"]) == np.median([int(rows[n]["steps"])
                                                    for n in ("foot_walk", "pocket_walk")])
    text = (out / "summary.md").read_text()
    assert "| placement | barometer | steps | footfalls | distance_m | final_floor |" in text


def test_the_summary_has_the_nees_per_recording_and_per_dataset(evaluated):
    """Issue 55, point 4: the consistency of each report with a truth, per recording, and
    per dataset its median, mean and maximum; the attitude's only where the truth has one
    (the simulated walks' foot, not the VICON trial's positions)."""
    out = evaluated[0] / "out"
    rows = {r["recording"]: r for r in summary_rows(out) if r["recording"]}
    for name in ("foot_walk", "pocket_walk", "vicon_walk"):
        consistency = json.loads((out / name / "run" / "report.json").read_text())[
            "consistency"]
        for part, figures in consistency.items():
            for key in ("samples", "nees", "nees_per_dof"):
                cell = rows[name][f"consistency.{part}.{key}"]
                assert (cell == "" if figures[key] is None else
                        float(cell) == pytest.approx(figures[key])), (name, part, key)
    assert rows["foot_walk"]["consistency.attitude.nees_per_dof"] != ""
    assert rows["vicon_walk"]["consistency.attitude.nees_per_dof"] == ""
    stats = {r["statistic"]: r for r in summary_rows(out) if r["dataset"] == "sim"}
    values = [float(rows[n]["consistency.position_2d.nees_per_dof"])
              for n in ("foot_walk", "pocket_walk")]
    for statistic, function in (("median", np.median), ("mean", np.mean), ("max", np.max)):
        assert float(stats[statistic]["consistency.position_2d.nees_per_dof"]) == \
            pytest.approx(function(values))


def test_a_dask_cluster_gives_the_same_summary(evaluated, tmp_path):
    """The same job on a LocalCluster of two workers (acceptance 2): the same summary,
    timing aside."""
    from distributed import LocalCluster

    first, manifest, _ = evaluated
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster:
        result = cli("pdr-eval", "--manifest", str(manifest), "--out",
                     str(tmp_path / "dask"), "--scheduler", cluster.scheduler_address)
    assert result.returncode == 1, result.stderr
    assert without_timing(summary_rows(tmp_path / "dask")) == \
        without_timing(summary_rows(first / "out"))


def stamped_reports(out) -> set[str]:
    """The recordings whose report pdr-eval has stamped with its input hash (a report
    the navigator wrote but pdr-eval had not stamped when killed is not one)."""
    return {p.parts[-3] for p in out.glob("*/run/report.json")
            if "eval" in json.loads(p.read_text())}


def test_a_run_killed_halfway_runs_only_the_missing_ones_again(tmp_path):
    """Killed after its first report, started again: the reports made keep, the others
    run; with another configuration all run; --overwrite runs all (acceptance 4)."""
    manifest = dataset(tmp_path)
    manifest.write_text("recording,dataset,navigator\nsim/foot_walk,,foot\n"
                        "vicon/vicon_walk,,foot\nsim/pocket_walk,,pocket\n")
    out = tmp_path / "out"
    process = subprocess.Popen([installed("pdr-eval"), "--manifest", str(manifest),
                                "--out", str(out), "--workers", "1"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    deadline = time.monotonic() + 120
    while not stamped_reports(out) and time.monotonic() < deadline:
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGKILL)       # its workers too
    process.wait()
    made = stamped_reports(out)
    assert 1 <= len(made) < 3
    again = cli("pdr-eval", "--manifest", str(manifest), "--out", str(out))
    assert again.returncode == 0, again.stderr
    assert f"3 recordings: {3 - len(made)} run, {len(made)} kept" in again.stdout
    kept = {r["recording"] for r in summary_rows(out) if r["status"] == "kept"}
    assert kept == made
    config = tmp_path / "foot.yaml"
    shutil.copy(ROOT / "src" / "pdr_ins_ekf" / "config" / "foot_ekf.yaml", config)
    manifest.write_text("recording,dataset,navigator\nsim/foot_walk,,foot\n"
                        "vicon/vicon_walk,,foot\n")
    changed = cli("pdr-eval", "--manifest", str(manifest), "--out", str(out), "--config",
                  str(config))
    assert "2 recordings: 2 run, 0 kept" in changed.stdout, changed.stderr
    overwritten = cli("pdr-eval", "--manifest", str(manifest), "--out", str(out), "--config",
                      str(config), "--overwrite")
    assert "2 recordings: 2 run, 0 kept" in overwritten.stdout, overwritten.stderr


def test_paths_globs_and_a_bad_manifest(tmp_path):
    dataset(tmp_path)
    result = cli("pdr-eval", str(tmp_path / "no_such_*"), "--out", str(tmp_path / "o"))
    assert result.returncode == 2 and "matches no recording" in result.stderr
    bad = tmp_path / "bad.csv"
    bad.write_text("bag,dataset\nx,y\n")
    result = cli("pdr-eval", "--manifest", str(bad), "--out", str(tmp_path / "o"))
    assert result.returncode == 2 and "needs a header with a 'recording' column" in result.stderr


def truth_fields() -> set[str]:
    """The numeric fields of docs/reports.md's run sections present only with a truth."""
    fields, section = set(), None
    for line in REPORTS.read_text().splitlines():
        if line.startswith("## "):
            section = line[3:]
        if not (section and section.startswith(RUN_SECTIONS)):
            continue
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) == 5 and re.fullmatch(r"`[a-z0-9_.]+`", cells[0]) and \
                cells[1].startswith(("number", "integer")) and \
                {c.strip() for c in cells[4].split(",")} & TRUTH_CONDITIONS:
            fields.add(cells[0].strip("`"))
    return fields


def test_the_summary_has_every_figure_against_a_truth_of_the_reports_page():
    from pdr_eval.summary import TRUTH_FIGURES

    assert set(TRUTH_FIGURES) == truth_fields()


def test_the_eval_object_has_exactly_the_documented_fields(evaluated):
    """reports.md's `pdr-eval` table against a report pdr-eval wrote."""
    tmp_path, _, _ = evaluated
    text = REPORTS.read_text().split("## `pdr-eval`", 1)[1].split("\n## ", 1)[0]
    documented = {line.split("|")[1].strip().strip("`") for line in text.splitlines()
                  if line.startswith("| `eval.")}
    report = json.loads((tmp_path / "out" / "foot_walk" / "run" / "report.json").read_text())
    assert {f"eval.{key}" for key in report["eval"]} == documented
