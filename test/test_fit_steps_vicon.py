"""``pdr-sim fit-steps`` on the VICON foot positions of ../shared/data (issue 3: the
fitting tool of Zampella et al. 2011, Eq. (5), shown on a real motion capture)."""
from __future__ import annotations

import re

import pytest
import yaml

from wstest import PYSHOE, PYSHOE_ARGS, needs_shared

# 2017-12-15-18-03-05 is mostly shuffling in place: one swing passes the step filter.
TOO_FEW = {"2017-12-15-18-03-05"}


@pytest.mark.parametrize("csv", [pytest.param(p, id=p.stem, marks=needs_shared(p))
                                 for p in PYSHOE])
def test_fit_steps_on_vicon(procs, tmp_path, csv):
    imported = procs.run("pdr-sim", "import-csv", str(csv), "--out", str(tmp_path / "bag"),
                         *PYSHOE_ARGS)
    assert imported.returncode == 0, imported.stderr
    out = tmp_path / "pattern.yaml"
    fitted = procs.run("pdr-sim", "fit-steps", str(tmp_path / "bag"), "--out", str(out),
                       "--plot", str(tmp_path / "fit.png"))
    if csv.stem in TOO_FEW:
        assert fitted.returncode == 2
        assert f"{tmp_path / 'bag'}: only 1 valid steps to fit (need 3)" in fitted.stderr
        return
    assert fitted.returncode == 0, fitted.stderr
    print(fitted.stdout)
    found = re.search(r"(\d+) steps fitted.*along-track ([\d.]+) m, height ([\d.]+) m",
                      fitted.stdout)
    steps, along, height = int(found[1]), float(found[2]), float(found[3])
    assert steps >= 5 and along < 0.2 and height < 0.05
    pattern = yaml.safe_load(out.read_text())
    assert 0.6 < pattern["swing_s"] < 1.0
    assert (tmp_path / "fit.png").stat().st_size > 10_000
