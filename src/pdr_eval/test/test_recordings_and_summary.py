"""pdr_eval's plain parts: recordings' names and datasets, the manifest, the figures."""
from pathlib import Path

import pytest
from pdr_eval.job import Outcome
from pdr_eval.recordings import Recording, from_manifest, from_paths, named
from pdr_eval.summary import NOT_A_POCKET_WALK, figure, known_scores, status
from pdr_eval.walk_figures import barometer_use

from pdr_core.errors import InputError


def test_names_are_unique_and_say_their_dataset_where_stems_meet():
    entries = [(Path("a/walk"), "a", "foot", (), ()), (Path("b/walk"), "b", "foot", (), ()),
               (Path("b/run.mcap"), "b", "pocket", (), ()),
               (Path("c/x/walk"), "b", "foot", (), ())]
    assert [r.name for r in named(entries)] == ["a_walk", "b_walk_1", "run", "b_walk_2"]


def test_a_manifest_row_takes_its_folder_as_dataset_and_its_options(tmp_path):
    manifest = tmp_path / "m.csv"
    manifest.write_text("recording,dataset,navigator,import_options\n"
                        "trials/t1.csv,,foot,\"--time-col t_s --acc-cols 'a,b,c'\"\n"
                        "/abs/bag,mine,pocket,\n")
    first, second = from_manifest(manifest, "foot")
    assert first.source == tmp_path / "trials" / "t1.csv" and first.dataset == "trials"
    assert first.is_csv and first.import_options == ("--time-col", "t_s", "--acc-cols",
                                                     "a,b,c")
    assert (second.source, second.dataset, second.navigator) == (Path("/abs/bag"), "mine",
                                                                 "pocket")


def test_a_manifest_with_an_unknown_navigator_or_column_is_refused(tmp_path):
    manifest = tmp_path / "m.csv"
    manifest.write_text("recording,navigator\nx,thigh\n")
    with pytest.raises(InputError, match="line 2: navigator 'thigh'"):
        from_manifest(manifest, "foot")
    manifest.write_text("recording,truth\nx,y\n")
    with pytest.raises(InputError, match="unknown columns"):
        from_manifest(manifest, "foot")


def test_a_missing_path_is_kept_and_an_empty_glob_refused(tmp_path):
    [missing] = from_paths([str(tmp_path / "gone")], "pocket")
    assert missing.name == "gone" and missing.dataset == tmp_path.name
    with pytest.raises(InputError, match="matches no recording"):
        from_paths([str(tmp_path / "*.mcap")], "foot")


def test_figures_are_numbers_at_dotted_names():
    report = {"armse_3d_m": 0.1, "stance": {"recall": 1, "precision": None}, "ok": True}
    assert figure(report, "armse_3d_m") == 0.1 and figure(report, "stance.recall") == 1.0
    assert figure(report, "stance.precision") is None and figure(report, "ok") is None
    assert figure(report, "stance.missing") is None and figure(report, "x.y") is None


def test_known_figures_of_a_manifest_are_numbers_and_scored(tmp_path):
    """A walker's count (the folder says 27 steps) and a known distance: read per row,
    scored as error and % (None where not given)."""
    manifest = tmp_path / "m.csv"
    manifest.write_text("recording,navigator,true_footfalls,true_distance_m\n"
                        "inhand-27-steps,auto,27,\nwalk,,,40\n")
    first, second = from_manifest(manifest, "pocket")
    assert first.known == (("true_footfalls", 27.0),) and first.navigator == "auto"
    assert second.known == (("true_distance_m", 40.0),) and second.navigator == "pocket"
    scores = known_scores(dict(first.known), {"footfalls": 30, "steps": 15,
                                              "distance_m": 20.0})
    assert scores["footfall_error"] == 3 and scores["footfall_error_pct"] == \
        pytest.approx(100 * 3 / 27)
    assert scores["true_steps"] is None and scores["step_error"] is None
    assert known_scores(dict(second.known), {"distance_m": 42.0})[
        "known_distance_error_pct"] == \
        pytest.approx(5.0)
    manifest.write_text("recording,true_steps\nx,many\n")
    with pytest.raises(InputError, match="line 2: true_steps 'many' is not a number"):
        from_manifest(manifest, "foot")


def test_a_pocket_run_in_no_pocket_is_not_a_pocket_walk():
    recording = Recording("hand", Path("hand"), "phones", "auto")

    def outcome(navigator: str, placement: str, skipped: bool = False) -> Outcome:
        report = {"eval": {"navigator": navigator, "walk": {"placement": placement}}}
        return Outcome(recording, report, "", 1.0, skipped)

    assert status(outcome("pocket", "not in a pocket")) == NOT_A_POCKET_WALK
    assert status(outcome("pocket", "not in a pocket", skipped=True)) == NOT_A_POCKET_WALK
    assert status(outcome("pocket", "front pocket")) == "done"
    assert status(outcome("foot", "foot", skipped=True)) == "kept"
    assert status(Outcome(recording, None, "bad", 1.0)) == "failed"


def test_the_barometer_use_from_either_report():
    assert barometer_use({"inputs": {"barometer": {"status": "not fused"}}}) == "not fused"
    assert barometer_use({"barometer": {"fused": True}}) == "fused"
    assert barometer_use({}) == "absent"
