"""What the CLIs that read a bag answer to the inputs a newcomer gives them (issue 29): a CSV
log where a bag belongs points to ``pdr-sim import-csv`` with a command to run, and
``pdr-ekf evaluate`` finds the estimate's topic of a pocket bag by itself."""
from __future__ import annotations

import json
import shlex

import pytest

from pdr_core.io.bag import BagReader, write_batches
from wstest import ROOT, cli

POCKET_WALK = ROOT / "bags" / "pocket_walk"
REPORT_KEYS = ("duration_s", "distance_m", "final_error_m", "final_error_pct",
               "mean_error_3d_m", "armse_3d_m", "armse_2d_m")


LOG = "t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n0.00,0,0,9.8,0,0,0\n0.01,0,0,9.8,0,0,0\n"
# Every subcommand that reads a bag, with its other required options
READS_A_BAG = [("pdr-pocket", "run", "--out", "o"), ("pdr-pocket", "attitude", "--out", "o"),
               ("pdr-pocket", "calibrate-step", "--distance-m", "10", "--out", "o.yaml"),
               ("pdr-pocket", "table-steps"), ("pdr-pocket", "table-stride"),
               ("pdr-ekf", "run", "--out", "o"), ("pdr-ekf", "evaluate", "--truth", "t"),
               ("pdr-drift", "run", "--out", "o"), ("pdr-sim", "info"),
               ("pdr-sim", "repair"), ("pdr-sim", "fit-steps", "--out", "o.yaml")]


@pytest.mark.parametrize("suffix", [".csv", ".txt"])
@pytest.mark.parametrize("command", READS_A_BAG, ids=[" ".join(c[:2]) for c in READS_A_BAG])
def test_a_csv_log_for_a_bag_points_to_import_csv(tmp_path, command, suffix):
    log = tmp_path / f"walk{suffix}"
    log.write_text(LOG)
    prog, sub, *options = command
    result = cli(prog, sub, str(log), *options, cwd=tmp_path)
    assert result.returncode == 2, result.stdout
    [line] = result.stderr.splitlines()
    assert line.startswith(f"{prog}: error: {log}: a CSV log, not a bag")
    assert "MCAP file" not in line
    assert line.split("`")[1] == suggested_import(log)


def suggested_import(log) -> str:
    """The command every refusal of ``log`` suggests: the same for every subcommand."""
    return (f"pdr-sim import-csv {log} --out walk_bag --time-col t "
            "--acc-cols acc_x,acc_y,acc_z --gyro-cols gyr_x,gyr_y,gyr_z")


@pytest.mark.parametrize("suffix", [".csv", ".txt"])
def test_the_suggested_import_command_runs(tmp_path, suffix):
    """The command the refusals above suggest, run as given, writes the log's two samples
    (run once per suffix: the refusals all suggest this one)."""
    log = tmp_path / f"walk{suffix}"
    log.write_text(LOG)
    ran = cli("pdr-sim", *shlex.split(suggested_import(log))[1:], cwd=tmp_path)
    assert ran.returncode == 0, ran.stderr
    assert len(BagReader(tmp_path / "walk_bag").read("/imu/data")) == 2


def test_a_csv_without_header_gets_column_numbers(tmp_path):
    log = tmp_path / "phone.csv"
    log.write_text("0,0.1,0.2,9.8\n10000000,0.1,0.2,9.8\n")
    result = cli("pdr-pocket", "run", str(log), "--out", "o", cwd=tmp_path)
    assert result.returncode == 2
    assert (f"`pdr-sim import-csv {log} --out phone_bag --no-header --time-col 0 "
            "--acc-cols 1,2,3`") in result.stderr


def test_another_file_is_still_not_an_mcap_file(tmp_path):
    data = tmp_path / "walk.db3"
    data.write_bytes(b"SQLite format 3\0" + bytes(range(256)))
    result = cli("pdr-pocket", "run", str(data), "--out", "o", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr == f"pdr-pocket: error: {data}: not an MCAP file (bad magic bytes)\n"


@pytest.fixture(scope="module")
def pocket_out(tmp_path_factory):
    """pdr-pocket run on the sample pocket walk: a bag with pdr/pocket/pose."""
    out = tmp_path_factory.mktemp("pocket") / "out"
    result = cli("pdr-pocket", "run", str(POCKET_WALK), "--out", str(out))
    assert result.returncode == 0, result.stderr
    return out


def test_evaluate_finds_the_pocket_pose_topic_by_itself(pocket_out):
    named = cli("pdr-ekf", "evaluate", str(pocket_out), "--truth", str(POCKET_WALK),
                "--topic", "/pdr/pocket/pose")
    assert named.returncode == 0, named.stderr
    found = cli("pdr-ekf", "evaluate", str(pocket_out), "--truth", str(POCKET_WALK))
    assert found.returncode == 0, found.stderr
    report = json.loads(found.stdout)
    assert report == json.loads(named.stdout)
    assert set(REPORT_KEYS) <= report.keys()
    assert report["armse_3d_m"] < 1.0


def test_evaluate_lists_the_candidates_when_the_topic_is_ambiguous(pocket_out, tmp_path):
    reader = BagReader(pocket_out)
    pose = reader.read("/pdr/pocket/pose")
    write_batches(tmp_path / "two", {"/alice/pdr/pocket/pose": pose,
                                     "/bob/pdr/pocket/pose": pose})
    result = cli("pdr-ekf", "evaluate", str(tmp_path / "two"), "--truth", str(POCKET_WALK))
    assert result.returncode == 2
    assert result.stderr == (f"pdr-ekf: error: {tmp_path / 'two'}: 2 topics of pose "
                             "estimates: /alice/pdr/pocket/pose, /bob/pdr/pocket/pose; "
                             "choose one with --topic\n")
    chosen = cli("pdr-ekf", "evaluate", str(tmp_path / "two"), "--truth", str(POCKET_WALK),
                 "--topic", "/bob/pdr/pocket/pose")
    assert chosen.returncode == 0, chosen.stderr


def test_evaluate_names_the_topics_of_a_bag_without_estimates():
    result = cli("pdr-ekf", "evaluate", str(POCKET_WALK), "--truth", str(POCKET_WALK))
    assert result.returncode == 2
    [line] = result.stderr.splitlines()
    assert line.startswith(f"pdr-ekf: error: {POCKET_WALK}: no topic of pose estimates")
    assert "/imu/data (sensor_msgs/msg/Imu)" in line and line.endswith("with --topic")


def test_evaluate_refuses_a_topic_without_poses():
    result = cli("pdr-ekf", "evaluate", str(POCKET_WALK), "--truth", str(POCKET_WALK),
                 "--topic", "/imu/data")
    assert result.returncode == 2
    assert result.stderr.startswith("pdr-ekf: error: /imu/data: sensor_msgs/msg/Imu holds "
                                    "no pose")


def test_evaluate_help_cites_the_repository_report_schema():
    text = " ".join(cli("pdr-ekf", "evaluate", "--help").stdout.split())
    assert "docs/reports.md" in text and "INTERFACES.md" not in text


def test_repair_refuses_an_existing_output_unless_overwrite(pocket_out, tmp_path):
    """Its refusal said "pass --overwrite", which it did not take."""
    fixed = tmp_path / "fixed"
    assert cli("pdr-sim", "repair", str(pocket_out), "--out", str(fixed)).returncode == 0
    again = cli("pdr-sim", "repair", str(pocket_out), "--out", str(fixed))
    assert again.returncode == 2
    assert again.stderr == (f"pdr-sim: error: {fixed}: output exists already (remove it or "
                            "pass --overwrite)\n")
    replaced = cli("pdr-sim", "repair", str(pocket_out), "--out", str(fixed), "--overwrite")
    assert replaced.returncode == 0, replaced.stderr
    assert len(BagReader(fixed).read("/pdr/pocket/pose")) == 122
