"""pdr_eval's plain parts: recordings' names and datasets, the manifest, the figures."""
from pathlib import Path

import pytest
from pdr_eval.recordings import from_manifest, from_paths, named
from pdr_eval.summary import figure

from pdr_core.errors import InputError


def test_names_are_unique_and_say_their_dataset_where_stems_meet():
    entries = [(Path("a/walk"), "a", "foot", ()), (Path("b/walk"), "b", "foot", ()),
               (Path("b/run.mcap"), "b", "pocket", ()), (Path("c/x/walk"), "b", "foot", ())]
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
