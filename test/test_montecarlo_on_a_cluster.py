"""Monte-Carlo studies split into batches over a Dask cluster equal the unsplit ones
(issue 43, acceptance 5): each run's noise is seeded by its index (pdr_core.evaluation.parallel)."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pdr_ins_ekf.studies import error_sweep
from pdr_ins_ekf.studies.ekf_montecarlo import (
    XSENS_MTI,
    EkfStudy,
    ekf_study,
    estimator_detector,
    filter_for,
)
from pdr_ins_ekf.studies.montecarlo import InsStudy, ins_study, straight_walk
from wstest import cli

RUNS = 6


@pytest.fixture(scope="module")
def scheduler():
    """A LocalCluster of two worker processes, one thread each."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster:
        yield cluster.scheduler_address


def assert_same(split, whole) -> None:
    """Every array of two studies (nested dataclasses of arrays) equal, bit for bit."""
    for name in whole.__dataclass_fields__:
        a, b = getattr(split, name), getattr(whole, name)
        if hasattr(b, "__dataclass_fields__"):
            assert_same(a, b)
        else:
            np.testing.assert_array_equal(a, b, err_msg=name)


def test_a_pure_ins_study_split_over_the_cluster_is_the_unsplit_one(scheduler):
    walk = straight_walk(5, 100.0)
    whole = ins_study(walk, XSENS_MTI, RUNS, seed=3, block=RUNS)
    split = ins_study(walk, XSENS_MTI, RUNS, seed=3, block=2, scheduler=scheduler)
    assert isinstance(split, InsStudy)
    assert_same(split, whole)
    assert whole.noise_only.sigma_p_m[-1] > 0


def test_an_ekf_study_split_over_the_cluster_is_the_unsplit_one(scheduler):
    walk = straight_walk(5, 100.0, rest_s=2.0)
    study = {"walk": walk, "noise": XSENS_MTI, "runs": RUNS, "seed": 4,
             "detector": estimator_detector("ekf_limited"), "config": filter_for(XSENS_MTI)}
    whole = ekf_study(**study, block=RUNS)
    split = ekf_study(**study, block=4, scheduler=scheduler)
    assert isinstance(split, EkfStudy)
    assert_same(split, whole)


def test_the_sweeps_runs_split_into_batches_are_the_unsplit_ones(scheduler):
    """The sweep's Monte-Carlo (batches of SWEEP_BATCH_RUNS): on the cluster and here, and
    both against all runs in one batch."""
    walk = error_sweep.paper_walk(steps=4)
    gait = error_sweep.gait_of(walk)
    runs = error_sweep.SWEEP_BATCH_RUNS + 2
    here = error_sweep.sweep_point(walk, gait, "arw", 1.0, runs, seed=5)
    there = error_sweep.sweep_point(walk, gait, "arw", 1.0, runs, seed=5, scheduler=scheduler)
    assert here.monte_carlo == there.monte_carlo
    _, noise = error_sweep.noise_point(**{**error_sweep.BASELINE, "arw": 1.0})
    config = replace(filter_for(noise, error_sweep.SWEEP_ZUPT_SIGMA_MPS),
                     **error_sweep.KNOWN_START)
    whole = error_sweep.final_errors(walk, noise, config, 5, 0, runs)
    parts = [error_sweep.final_errors(walk, noise, config, 5, first, count)
             for first, count in ((0, 3), (3, runs - 3))]
    np.testing.assert_array_equal(np.concatenate(parts), whole)


def test_pdr_ekf_montecarlo_on_a_cluster_writes_the_same_tables(scheduler, tmp_path):
    common = ["montecarlo", "--runs", str(RUNS), "--steps", "3", "--rest-s", "2",
              "--source", "gyro_bias", "--estimator", "ins,ekf_retarded"]
    whole = cli("pdr-ekf", *common, "--out", str(tmp_path / "whole"))
    split = cli("pdr-ekf", *common, "--batch", "2", "--scheduler", scheduler,
                "--out", str(tmp_path / "split"))
    assert whole.returncode == 0, whole.stderr
    assert split.returncode == 0, split.stderr
    assert "gyro_bias ekf_retarded: 6/6 runs" in split.stderr
    for table in ("fits.csv", "sigma.csv", "consistency.csv"):
        assert (tmp_path / "split" / table).read_text() == \
            (tmp_path / "whole" / table).read_text(), table
    refused = cli("pdr-ekf", *common, "--batch", "0")
    assert refused.returncode != 0 and "--batch" in refused.stderr


def test_every_task_on_the_cluster_runs_with_one_numba_thread(scheduler):
    import numba

    from pdr_core.evaluation.parallel import cluster_map

    ended = dict(cluster_map(scheduler, numba.get_num_threads, [()] * 4, "threads"))
    assert ended == {0: 1, 1: 1, 2: 1, 3: 1}
