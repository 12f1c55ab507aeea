"""``pdr-pocket evaluate --truth-steps`` read as ``--truth-steps-format``, ``-time``, ``-unit``
and ``-cols`` say (pdr_pocket.evaluation.read_truth_steps): true times or a foot switch's
0→1 edges, from the input's first imu/data message or on its stamps, in any time unit.
The run output is made up (a few steps and the run record, as pdr-pocket run writes
them), so no navigator runs; the CLI runs in the test's process (wstest.cli)."""
from __future__ import annotations

import json

import numpy as np
import pytest
import yaml

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.frames import MAP_FRAME
from pdr_core.io.bag import write_batches
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import POSE_WITH_COVARIANCE_STAMPED, STEP
from pdr_pocket.evaluation import TruthStepsFormat, read_truth_steps
from pdr_pocket.messages import pose_fields, step_fields
from pdr_pocket.pocket_offline import RUN_RECORD, run_record
from pdr_pocket.records import StepRecord
from wstest import cli

# The made-up input: 20 s at 100 Hz, stamped on a phone's clock (ns since its boot)
FIRST_NS = 579_518_702_739_258
IMU_NS = FIRST_NS + np.arange(2000) * 10_000_000
FOOTFALLS = 6
# A foot switch on that clock (t_ns, left, right): the left foot down in the first row
# (no footfall: its edge came before), then 5 edges, two of them in one row
SWITCHES = [(0, 1, 0), (1, 0, 0), (2, 0, 1), (3, 0, 0), (4, 1, 1), (5, 0, 0), (6, 1, 0),
            (7, 1, 1)]
SWITCH_ROWS = "".join(f"{FIRST_NS + int(2e9) * (k + 1)},{left},{right}\n"
                      for k, left, right in SWITCHES)
EDGES_S = (FIRST_NS + 2e9 * np.array([3, 5, 5, 7, 8])) * 1e-9    # rows 3, 5, 5, 7, 8


@pytest.fixture(scope="module")
def run_out(tmp_path_factory):
    """A pdr-pocket run output of three steps and FOOTFALLS footfalls on IMU_NS."""
    out = tmp_path_factory.mktemp("evaluate") / "run"
    steps = [StepRecord(index=k, t=2.0 + k, t_confirm=2.3 + k, length=1.4,
                        vertical_displacement=0.0, heading=0.0, pitch_max=0.5, pitch_min=-0.3,
                        duration=1.0, activity=0, position=np.array([1.4 * (k + 1), 0.0, 0.0]),
                        covariance=0.01 * np.eye(3), floor=0, vertical_force_range=1.0)
             for k in range(3)]
    stamps = IMU_NS[[230 + 100 * k for k in range(3)]]
    record = run_record(steps, IMU_NS, int(IMU_NS[0]), FOOTFALLS, 3.0)
    write_batches(out, {
        topics.POCKET_STEP: MessageBatch(STEP, stamps, MAP_FRAME, step_fields(steps)),
        topics.POCKET_POSE: MessageBatch(POSE_WITH_COVARIANCE_STAMPED, stamps, MAP_FRAME,
                                         pose_fields(steps, np.tile(np.eye(3), (3, 1, 1))))},
        custom_data={RUN_RECORD: yaml.safe_dump(record, sort_keys=False)})
    return out


def evaluate(run_out, truth_steps, *args):
    result = cli("pdr-pocket", "evaluate", run_out, "--truth-steps", truth_steps, *args)
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert [f"pdr-pocket: warning: {w}" for w in report["warnings"]] == \
        result.stderr.splitlines()
    return report


def refusal(*args) -> str:
    result = cli("pdr-pocket", "evaluate", *args)
    assert result.returncode == 2 and result.stdout == "", result.stdout + result.stderr
    [line] = result.stderr.splitlines()
    return line


def test_foot_switch_edges_are_the_footfalls(tmp_path):
    csv = tmp_path / "switch.csv"
    csv.write_text(SWITCH_ROWS)
    foot_switch = TruthStepsFormat("foot-switch", "stamps", "ns")
    np.testing.assert_allclose(read_truth_steps(csv, foot_switch), EDGES_S, rtol=0, atol=1e-6)
    # the same by header names, in another order, beside another column
    named = tmp_path / "named.csv"
    named.write_text("t_ns,status,right,left\n" + "".join(
        f"{t},7,{right},{left}\n" for t, left, right in
        (row.split(",") for row in SWITCH_ROWS.split())))
    by_name = TruthStepsFormat("foot-switch", "stamps", "ns", ("t_ns", "left", "right"))
    np.testing.assert_array_equal(read_truth_steps(named, by_name),
                                  read_truth_steps(csv, foot_switch))


@pytest.mark.parametrize("content, fmt, problem", [
    ("0,0,0\n1,2,0\n", TruthStepsFormat("foot-switch"),
     "row 2: foot switch column 1 reads 2, not 0 or 1 (contact): check --truth-steps-cols "
     "(time,left,right)"),
    ("t,l,r\n0,1,1\n1,1,0\n", TruthStepsFormat("foot-switch"),
     "no footfall: no 0→1 edge in the foot switch columns 1, 2"),
    ("t\n1.0\nnan\n", TruthStepsFormat(), "row 3: step time nan is not a number"),
], ids=["a switch reading 2", "feet down from the first row on", "a time not a number"])
def test_what_cannot_be_footfalls_is_refused(tmp_path, content, fmt, problem):
    csv = tmp_path / "bad.csv"
    csv.write_text(content)
    with pytest.raises(InputError) as refused:
        read_truth_steps(csv, fmt)
    assert str(refused.value) == f"{csv}: {problem}"


def test_a_foot_switch_on_the_recordings_stamps(run_out, tmp_path):
    csv = tmp_path / "switch.csv"
    csv.write_text(SWITCH_ROWS)
    report = evaluate(run_out, csv, "--truth-steps-format", "foot-switch",
                      "--truth-steps-time", "stamps", "--truth-steps-unit", "ns")
    assert report["truth_steps"] == {"file": str(csv), "per": "footfall", "rows": 5,
                                     "counted": FOOTFALLS, "error": 1, "error_pct": 20.0}
    assert report["warnings"] == []
    # read from the start instead: outside the recording, and the options that fit named
    [warning] = evaluate(run_out, csv, "--truth-steps-format", "foot-switch",
                         "--truth-steps-cols", "0,1,2")["warnings"]
    assert warning == (f"{csv}: the step times span 579524702739258.000-579534702739258.000 "
                       "s, the recording 0.000-19.990 s (from its first imu/data message): in "
                       "another unit, or on another time axis? (they fit with "
                       "--truth-steps-time stamps --truth-steps-unit ns; only their count is "
                       "compared)")


def test_times_on_either_axis_in_any_unit(run_out, tmp_path):
    stamped = tmp_path / "stamped.csv"
    stamped.write_text("id,t_ms\n" + "".join(f"{k},{(FIRST_NS * 1e-6 + 1000 * k):.3f}\n"
                                             for k in range(1, 6)))
    on_stamps = evaluate(run_out, stamped, "--truth-steps-cols", "t_ms",
                         "--truth-steps-time", "stamps", "--truth-steps-unit", "ms")
    assert on_stamps["truth_steps"]["rows"] == 5 and on_stamps["warnings"] == []
    from_start = tmp_path / "from_start.csv"
    from_start.write_text("1.5\n2.5\n19.0\n")
    assert evaluate(run_out, from_start)["warnings"] == []
    [warning] = evaluate(run_out, from_start, "--truth-steps-time", "stamps")["warnings"]
    assert warning == (f"{from_start}: the step times span 1.500-19.000 s, the recording "
                       "579518.703-579538.693 s (its stamps): in another unit, or on another "
                       "time axis? (they fit with --truth-steps-time from-start "
                       "--truth-steps-unit s; only their count is compared)")


def test_refusals_name_the_option(run_out, tmp_path):
    csv = tmp_path / "switch.csv"
    csv.write_text(SWITCH_ROWS)
    assert refusal(run_out, "--truth-steps", csv, "--truth-steps-format", "foot-switch",
                   "--truth-steps-per", "cycle") == (
        "pdr-pocket: error: --truth-steps-per: a foot switch gives footfalls of either foot: "
        "footfall, not cycle")
    assert refusal(run_out, "--truth-steps", csv, "--truth-steps-format", "foot-switch",
                   "--truth-steps-cols", "0,1") == (
        "pdr-pocket: error: --truth-steps-cols: --truth-steps-format foot-switch reads 3 "
        "column(s) (time,left,right), got 0,1")
