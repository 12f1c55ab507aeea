"""The pocket graph with the drift loop (pocket_pdr ⇄ landmark_drift, recorded by
bag_record) on the demo's kind of walk: the walk, the in-process loop (``pdr-pocket run
--drift online``), what a graph run left and the check that it equals the in-process
loop; shared by test_landmark_drift.py, test_landmark_drift_restarts.py and
test_demo.py."""
from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from pdr_core.io.bag import BagReader
from pdr_core.io.nav_path import last_path
from wstest import ROOT, Processes

NO_MAG = str(ROOT / "src" / "pdr_pocket" / "config" / "pocket_pdr_no_mag.yaml")


def generate(folder, seed: int):
    """Two laps of a block, a phone in the pocket, Table 6.1's z gyro bias."""
    generated = Processes(0, folder).run(
        "pdr-sim", "generate", "--placement", "pocket", "--scenario", "block_two_laps",
        "--imu", "thesis_table_6_1", "--seed", str(seed), "--out", str(folder / "walk"))
    assert generated.returncode == 0, generated.stderr
    return folder / "walk"


def in_process(walk, out, *drift_args: str) -> dict:
    """``pdr-pocket run --drift online`` on ``walk`` into ``out``: its report."""
    result = Processes(0, out.parent).run("pdr-pocket", "run", str(walk), "--config", NO_MAG,
                                          "--out", str(out), "--drift", "online", *drift_args)
    assert result.returncode == 0, result.stderr
    return json.loads((out / "report.json").read_text())




@dataclass
class GraphRun:
    """What a live graph left: its recording and the two nodes' logs."""

    live: BagReader
    navigator_log: str
    estimator_log: str


RECORDED = "[pdr/pocket/pose, pdr/pocket/path, pdr/landmarks, pdr/drift]"


def demo_walk(tmp_path_factory):
    """The walk of make demo (seed 1), whose figures the README gives: a module's fixture
    (``walk = pytest.fixture(scope="module")(demo_walk)``)."""
    return generate(tmp_path_factory.mktemp("block"), seed=1)


def in_process_loop(walk, tmp_path_factory):
    """The in-process loop on the walk (nearest association): its output and report; a
    module's fixture, as :func:`demo_walk`."""
    out = tmp_path_factory.mktemp("online") / "run"
    return out, in_process(walk, out)


def expected_messages(report: dict) -> int:
    """What the recorder of a graph run gets for the in-process ``report``: a path per
    step, one again per accepted correction, and the estimator's outputs."""
    drift = report["drift"]
    return (2 * report["steps"] + drift["landmarks"] + drift["associations"]
            + drift["corrections_accepted"])


def launched(live: BagReader, launch_log: str) -> GraphRun:
    """A graph run of ``ros2 launch``: each node's log is its prefixed lines of the
    launch's (``[pocket_pdr-1] ...``)."""
    lines = launch_log.splitlines()
    return GraphRun(live, *("\n".join(line for line in lines if line.startswith(f"[{node}-"))
                           for node in ("pocket_pdr", "landmark_drift")))


def final_path(live: BagReader) -> np.ndarray:
    """The positions of the last ``pdr/pocket/path`` recorded (N, 3) [m]."""
    return last_path(live, "/pdr/pocket/path")["pose.position"]


def assert_equals_in_process(run: GraphRun, offline, report: dict, atol: float) -> None:
    """The live graph gives the in-process loop's landmarks and drifts, and its poses to
    ``atol`` [m]: every step of the last path, and every pose published up to the first
    correction's step (the ones after it, published before the answer came, are the
    steps the answer revised)."""
    drift = report["drift"]
    assert "correction" in run.navigator_log and "accepted" in run.navigator_log
    assert "correction accepted" in run.estimator_log, run.estimator_log
    assert len(run.live.read("/pdr/landmarks")) == drift["landmarks"]
    estimates = run.live.read("/pdr/drift")
    # the same headings and the same instants (the steps' confirmations, the messages'
    # stamps): the same drift
    np.testing.assert_allclose(np.degrees(estimates["drift"]), drift["drift_deg_per_s"],
                               rtol=1e-6)
    expected = BagReader(offline).read("/pdr/pocket/pose")
    np.testing.assert_allclose(final_path(run.live), expected["pose.pose.position"],
                               rtol=0, atol=atol)
    poses = run.live.read("/pdr/pocket/pose")
    assert len(poses) == len(expected)
    np.testing.assert_array_equal(poses.stamp_ns, expected.stamp_ns)
    before = poses.stamp_ns <= estimates.stamp_ns.min()
    np.testing.assert_allclose(poses["pose.pose.position"][before],
                               expected["pose.pose.position"][before], rtol=0, atol=atol)
