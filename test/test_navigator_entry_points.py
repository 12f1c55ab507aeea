"""The navigators' Python entry points (issue 56, point 6): ``pdr_ins_ekf.foot_offline.run``
and ``pdr_pocket.pocket_offline.run`` return the report their CLI writes to report.json
(no field of it is a timing), print nothing, and write the same report when given a
folder."""
from __future__ import annotations

import pytest

from pdr_core.report_files import report_text
from pdr_ins_ekf.foot_offline import FootOptions
from pdr_ins_ekf.foot_offline import run as run_foot
from pdr_pocket.pocket_offline import PocketOptions
from pdr_pocket.pocket_offline import run as run_pocket
from wstest import ROOT, cli

# the navigator's CLI, its sample bag, its entry point and its options
NAVIGATORS = {"foot": ("pdr-ekf", "foot_walk", run_foot, FootOptions),
              "pocket": ("pdr-pocket", "pocket_walk", run_pocket, PocketOptions)}


@pytest.mark.parametrize("navigator", NAVIGATORS)
def test_the_entry_point_returns_the_report_the_cli_writes_and_prints_nothing(
        navigator, tmp_path, capsys):
    prog, bag_name, run, options = NAVIGATORS[navigator]
    bag = ROOT / "bags" / bag_name
    ran = cli(prog, "run", bag, "--out", tmp_path / "cli")
    assert ran.returncode == 0, ran.stderr
    written = (tmp_path / "cli" / "report.json").read_text()
    capsys.readouterr()
    report = run(bag, options())
    assert capsys.readouterr() == ("", "")
    assert report_text(report) == written == ran.stdout
    again = run(bag, options(), tmp_path / "python")
    assert capsys.readouterr() == ("", "")
    assert report_text(again) == (tmp_path / "python" / "report.json").read_text() == written
    assert not list(tmp_path.glob("python/*.png"))

