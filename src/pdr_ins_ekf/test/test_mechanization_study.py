"""The mechanization study reproduces the ranking of Zampella et al. 2011, Fig. 6:
Padé [1,1] clearly worst; Padé [2,2], [3,3], Eq. (12) and expm close to each other."""
import numpy as np

from pdr_ins_ekf.studies.mechanization_study import run_study
from wstest import cli


def test_ranking_matches_the_paper():
    study = run_study(rates_hz=(50.0, 200.0, 1000.0))
    errors = dict(zip(study.methods, study.errors_m.T, strict=True))
    best = errors["closed_form"]
    for method in ("pade22", "pade33", "expm", "quaternion"):
        np.testing.assert_allclose(errors[method], best, rtol=1e-3)
    assert (errors["pade11"] > 2.0 * best).all()
    assert best[1] / best[2] > 15.0, "second order: 5x the rate, 25x less error"
    assert best[-1] < 0.005


def test_cli_refuses_rates_outside_the_simulator_range(tmp_path):
    result = cli("pdr-ekf", "study", "mechanization", "--rates", "10,100")
    assert result.returncode == 2
    assert result.stderr == "pdr-ekf: error: --rates: 10 Hz is outside 50-1000 Hz\n"
