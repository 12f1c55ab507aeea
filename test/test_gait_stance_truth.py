"""Foot gaits with a stance truth, end to end (issue 30): ``pdr-sim generate`` writes
``ground_truth/stance`` beside the other topics, ``pdr-ekf run`` reports the detector's
precision and recall against it, and ``--level-walk`` makes the level walk of the same
duration to compare a gait against."""
from __future__ import annotations

import json

import numpy as np
import pytest

from pdr_core import topics
from pdr_core.evaluation.metrics import error_report, truth_at
from pdr_core.io.bag import BagReader
from pdr_ins_ekf.config import load_run_config
from pdr_ins_ekf.offline import alignment_window
from pdr_ins_ekf.zupt_ekf import run
from pdr_sim.scenario import load_scenario
from pdr_sim.simulation import SimulationConfig, simulate

FOOT_TOPICS = {"/imu/data", "/imu/mag", "/ground_truth/pose", "/ground_truth/stance", "/tf",
               "/tf_static"}


@pytest.fixture
def crawl(tmp_path):
    """A short crawl: kneel down, eight strides, stand up."""
    scenario = tmp_path / "crawl.yaml"
    scenario.write_text("segments: [{type: standing, duration_s: 3.0}, "
                        "{type: crawl, steps: 8}, {type: standing, duration_s: 3.0}]\n")
    return scenario


def test_generate_writes_the_stance_truth_and_run_reports_against_it(procs, tmp_path, crawl):
    made = procs.run("pdr-sim", "generate", "--scenario", str(crawl), "--imu", "xsens_mtw",
                     "--rate", "100", "--seed", "1", "--out", str(tmp_path / "bag"))
    assert made.returncode == 0, made.stderr
    reader = BagReader(tmp_path / "bag")
    assert set(reader.topics) == FOOT_TOPICS
    truth, imu = reader.read("/ground_truth/stance"), reader.read("/imu/data")
    np.testing.assert_array_equal(truth.stamp_ns, imu.stamp_ns)
    assert (truth["detector"] == 255).all()
    assert truth["stationary"][:300].all(), "standing at the start"
    assert not truth["stationary"][500:1400].any(), "the crawling foot is never still"

    result = procs.run("pdr-ekf", "run", str(tmp_path / "bag"), "--out", str(tmp_path / "out"),
                       "--imu-profile", "xsens_mtw")
    assert result.returncode == 0, result.stderr
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    detected = BagReader(tmp_path / "out").read("/pdr/foot/stance")
    k = np.searchsorted(truth.stamp_ns, detected.stamp_ns)
    true, found = truth["stationary"][k], detected["stationary"]
    assert report["stance"] == pytest.approx({
        "samples": len(found), "precision": (true & found).sum() / found.sum(),
        "recall": (true & found).sum() / true.sum(), "true_fraction": true.mean(),
        "detected_fraction": found.mean()})
    assert report["stance"]["precision"] < 0.9, "a crawling foot is taken for a still one"


def test_the_level_walk_lasts_as_long_as_the_gait(procs, tmp_path, crawl):
    for name, extra in (("gait", []), ("level", ["--level-walk"])):
        made = procs.run("pdr-sim", "generate", "--scenario", str(crawl), *extra, "--rate",
                         "100", "--out", str(tmp_path / name))
        assert made.returncode == 0, made.stderr
    gait, level = (BagReader(tmp_path / n).read("/imu/data").stamp_ns for n in ("gait", "level"))
    assert len(gait) == len(level) and gait[-1] == level[-1]


def test_a_turn_in_place_is_not_stance_and_the_true_stance_navigates():
    """A turn in place has v = 0 but ω ≠ 0: not stance (a ZARU there would take the turn
    for gyroscope bias). The filter given the true stance as its ZUPT and ZARU mask
    (no detector) navigates the realistic level walk to a few centimetres: the signals
    are the exact derivatives of the truth."""

    scenario, data = load_scenario("level_walk_matched")
    sim = simulate(SimulationConfig(scenario, data, "xsens_mtw", {}, 100.0, 1))
    mask = sim.truth[topics.GROUND_TRUTH_STANCE]["stationary"]
    turning = np.abs(sim.trajectory.body_rate[:, 2]) > 0.1
    assert turning.any() and not mask[turning].any()
    config = load_run_config(None, "xsens_mtw")
    t = (sim.imu.stamp_ns - sim.imu.stamp_ns[0]) * 1e-9
    window = alignment_window(mask, t, config.alignment_min_s)
    out = run(t, sim.imu["linear_acceleration"], sim.imu["angular_velocity"], mask,
              config.filter, window, 0.0)
    report = error_report(t, out.position, truth_at(sim.pose, sim.imu.stamp_ns))
    assert report["armse_3d_m"] < 0.05
