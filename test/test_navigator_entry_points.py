"""The navigators' Python entry points (issue 56, point 6): ``pdr_ins_ekf.foot_offline.run``
and ``pdr_pocket.pocket_offline.run`` return the report their CLI writes to report.json
(no field of it is a timing), print nothing, and write the same report when given a
folder; ``pdr_sim.import_cli.import_recording`` returns the lines ``pdr-sim import-csv``
prints. ``pdr-eval`` (pdr_eval.job), which calls them, says the warnings and errors the
commands print."""
from __future__ import annotations

import shutil

import pytest
from pdr_eval.job import navigate, run_recording
from pdr_eval.recordings import Recording

from pdr_core.report_files import report_text
from pdr_ins_ekf.foot_offline import FootOptions
from pdr_ins_ekf.foot_offline import run as run_foot
from pdr_pocket.pocket_offline import PocketOptions
from pdr_pocket.pocket_offline import run as run_pocket
from pdr_sim.import_cli import import_recording
from wstest import PYSHOE_ARGS, ROOT, cli

# the navigator's CLI, its sample bag, its entry point and its options
NAVIGATORS = {"foot": ("pdr-ekf", "foot_walk", run_foot, FootOptions),
              "pocket": ("pdr-pocket", "pocket_walk", run_pocket, PocketOptions)}
VICON_CSV = ROOT / "bags" / "pyshoe_vicon_2018-02-22-10-10-29.csv"
WARNING = ": warning: "


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


@pytest.mark.parametrize("navigator", NAVIGATORS)
def test_pdr_eval_says_the_warnings_the_cli_prints(navigator, tmp_path):
    """A bag without its metadata.yaml (an InputWarning of the bag reader) holding a foot's
    walk: the pocket navigator warns of its strides too (a report warning)."""
    bag = tmp_path / "no_metadata"
    bag.mkdir()
    shutil.copy(ROOT / "bags" / "foot_walk" / "foot_walk.mcap", bag)
    ran = cli(NAVIGATORS[navigator][0], "run", bag, "--out", tmp_path / "cli")
    assert ran.returncode == 0, ran.stderr
    _, said = navigate(navigator, bag, tmp_path / "python", None)
    printed = [line.split(WARNING, 1)[1] for line in ran.stderr.splitlines() if WARNING in line]
    assert said == printed and len(said) == (2 if navigator == "pocket" else 1)


def test_an_import_returns_the_lines_its_command_prints(tmp_path, capsys):
    ran = cli("pdr-sim", "import-csv", VICON_CSV, *PYSHOE_ARGS, "--out", tmp_path / "cli")
    assert ran.returncode == 0, ran.stderr
    capsys.readouterr()
    lines = import_recording("import-csv", VICON_CSV, PYSHOE_ARGS, tmp_path / "python")
    assert capsys.readouterr() == ("", "")
    printed = ran.stdout.replace(str(tmp_path / "cli"), str(tmp_path / "python"))
    assert "\n".join(lines) + "\n" == printed


@pytest.mark.parametrize("options", [("--time-col", "t_s"),                # --acc-cols missing
                                     (*PYSHOE_ARGS, "--no-such-option"),
                                     ("--time-col", "no_such", "--acc-cols", "a,b,c")])
def test_pdr_eval_names_a_failed_import_as_pdr_sim_does(options, tmp_path, capsys):
    ran = cli("pdr-sim", "import-csv", VICON_CSV, *options, "--out", tmp_path / "bag")
    assert ran.returncode == 2
    capsys.readouterr()
    outcome = run_recording(Recording("walk", VICON_CSV, "d", "foot", options),
                            tmp_path / "out", None, False)
    assert capsys.readouterr() == ("", "")
    assert outcome.error == ran.stderr.strip().splitlines()[-1]
