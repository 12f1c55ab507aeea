"""docs/reports.md against the code: every CLI of its index runs once on a sample bag, in
each case the doc distinguishes, and its report has exactly the fields the doc lists for
that case (the doc's "present" column), each of the JSON type the doc gives (issue 29);
a CLI that writes OUT/report.json prints the same text.

The doc is read as it stands: its index table says which sections make up each CLI's
report, each section's table gives the fields, and the legend the condition terms. A
field added to a report without a row, a row left behind by a removed field, or a
condition that says the wrong case, fails here."""
from __future__ import annotations

import json
import re

import numpy as np
import pytest

from pdr_core.io.bag import BagReader, write_batches
from pdr_core.report_files import write_report
from pdr_pocket.line_calibration import StrideCalibrator
from pdr_pocket.saved_lines import saved_fit, write_fit
from wstest import ROOT, Processes

pytestmark = pytest.mark.ros
DOC = ROOT / "docs" / "reports.md"
FOOT_WALK, POCKET_WALK = ROOT / "bags" / "foot_walk", ROOT / "bags" / "pocket_walk"
FOOT_DRIFT = ROOT / "src" / "pdr_ins_ekf" / "config" / "foot_drift.yaml"
POCKET_THESIS = ROOT / "src" / "pdr_pocket" / "config" / "pocket_pdr_thesis.yaml"


def anchor(heading: str) -> str:
    """GitHub's anchor of a Markdown heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def read_doc() -> tuple[dict, dict, set]:
    """{CLI: [section anchors]} of the index, {anchor: [(field, type, conditions)]} of the
    sections' tables, and the legend's condition terms."""
    text = DOC.read_text()
    index, sections, section = {}, {}, None
    for line in text.splitlines():
        if line.startswith("#"):
            section = anchor(line.lstrip("#"))
            sections.setdefault(section, [])
        elif line.startswith("| `") and section == anchor("Reports: the `report.json` of "
                                                            "every CLI"):
            row = cells(line)
            index[row[0].strip("`")] = re.findall(r"\]\(#([^)]+)\)", row[-1])
        elif line.startswith("| `"):
            row = cells(line)
            conditions = set() if row[-1] == "always" else set(row[-1].split(", "))
            sections[section].append((row[0].strip("`"), row[1], conditions))
    start = text.index("**When a field is there**") + len("**When a field is there**")
    legend = text[start:text.index("A name `a.b`")]
    return index, sections, set(re.findall(r"\*([^*]+)\*", legend))


def test_a_report_is_json_indented_by_two_with_one_final_newline(tmp_path):
    """pdr_core.report_files, which every CLI writes and prints its report with."""
    path = write_report(tmp_path, {"steps": 3, "figures": {"rmse_m": 0.1}, "warnings": []})
    assert path == tmp_path / "report.json"
    assert path.read_text() == ('{\n  "steps": 3,\n  "figures": {\n    "rmse_m": 0.1\n  },'
                                '\n  "warnings": []\n}\n')


def test_the_index_and_the_conditions_are_consistent():
    index, sections, terms = read_doc()
    assert set(index) == set(CASES_BY_CLI), "a CLI of the index without a case here, or back"
    for cli, anchors in index.items():
        assert anchors and all(a in sections and sections[a] for a in anchors), cli
    used = {c for rows in sections.values() for _, _, conds in rows for c in conds}
    assert used <= terms, used - terms


TYPES = {"number": (int, float), "integer": int, "string": str, "boolean": bool,
         "object": dict}


def type_ok(value, doc_type: str) -> bool:
    if value is None:
        return doc_type.endswith("or null")
    kind = doc_type.removesuffix(" or null")
    if kind.startswith("array"):
        return isinstance(value, list)
    return isinstance(value, TYPES[kind]) and (kind == "boolean") == isinstance(value, bool)


def flatten(report: dict, documented: set, prefix: str = "") -> dict:
    """Each field's dotted name and value, descending into the objects (and arrays of
    objects, ``a[].b``) whose fields the doc lists."""
    out = {}
    for key, value in report.items():
        name = prefix + key
        out[name] = value
        if isinstance(value, dict) and any(d.startswith(name + ".") for d in documented):
            out |= flatten(value, documented, name + ".")
        elif isinstance(value, list) and any(d.startswith(name + "[].") for d in documented):
            for item in value:
                out |= flatten(item, documented, name + "[].")
    return out


class Runs:
    """Each case's CLI run once, on demand, in one folder."""

    def __init__(self, folder):
        self.folder = folder
        self.procs = Processes(0, folder)
        self.done = {}
        made = self.procs.run("pdr-sim", "generate", "--scenario", "stepping_in_place",
                              "--rate", "100", "--seed", "1", "--out", str(folder / "gait"))
        assert made.returncode == 0, made.stderr      # a foot bag with ground_truth/stance
        stripped = folder / "imu_only"        # the pocket walk without any truth
        write_batches(stripped, BagReader(POCKET_WALK).read_batches(["/imu/data", "/imu/mag"]))
        ends = BagReader(POCKET_WALK).read("/ground_truth/step").stamp_ns
        np.savetxt(folder / "cycles.csv", (ends - 1_700_000_000_000_000_000) * 1e-9,
                   header="t_s", comments="")
        write_fit(folder / "fit.yaml", saved_fit(StrideCalibrator()))   # no line walked

    def report(self, case: str):
        if case not in self.done:
            args, writes = CASES[case][1], CASES[case][3]
            for needed in CASES[case][4]:
                self.report(needed)
            result = self.procs.run(*(str(a).format(out=self.folder) for a in args),
                                    timeout=300)
            assert result.returncode == 0, f"{case}: {result.stderr}"
            text = (self.folder / case / "report.json").read_text() if writes else result.stdout
            assert result.stdout == text, f"{case}: the printed report is not the written one"
            self.done[case] = json.loads(text)
        return self.done[case]


OUT = "{out}"
# case: (CLI as the doc's index names it, arguments, conditions, writes OUT/report.json,
#        cases it reads the output of)
CASES = {
    "ekf_truth_smoothed": ("pdr-ekf run", ["pdr-ekf", "run", FOOT_WALK, "--out",
                                           f"{OUT}/ekf_truth_smoothed", "--smoother",
                                           "segmented"],
                           {"pose", "attitude truth", "smoother", "stance truth", "2 swings"},
                           True, ()),
    "ekf_no_truth": ("pdr-ekf run", ["pdr-ekf", "run", FOOT_WALK, "--out", f"{OUT}/ekf_no_truth",
                                     "--truth-topic", "/none"],
                     {"no pose", "stance truth", "2 swings"}, True,
                     ()),
    "ekf_stance_truth": ("pdr-ekf run", ["pdr-ekf", "run", f"{OUT}/gait", "--out",
                                         f"{OUT}/ekf_stance_truth"],
                         {"pose", "attitude truth", "stance truth", "2 swings"}, True, ()),
    "ekf_drift_truth": ("pdr-ekf run", ["pdr-ekf", "run", FOOT_WALK, "--out",
                                        f"{OUT}/ekf_drift_truth", "--drift", "online",
                                        "--config", FOOT_DRIFT],
                        {"pose", "attitude truth", "stance truth", "2 swings", "--drift"},
                        True, ()),
    "ekf_evaluate": ("pdr-ekf evaluate", ["pdr-ekf", "evaluate", f"{OUT}/ekf_truth_smoothed",
                                          "--truth", FOOT_WALK], {"pose"}, False,
                     ("ekf_truth_smoothed",)),
    "pocket_truth": ("pdr-pocket run", ["pdr-pocket", "run", POCKET_WALK, "--out",
                                        f"{OUT}/pocket_truth"], {"pose", "steps", "floors"}, True,
                     ()),
    "pocket_drift_truth": ("pdr-pocket run", ["pdr-pocket", "run", POCKET_WALK, "--out",
                                              f"{OUT}/pocket_drift_truth", "--drift", "online"],
                           {"pose", "steps", "floors", "landmarks", "--drift"}, True, ()),
    "pocket_drift_no_truth": ("pdr-pocket run", ["pdr-pocket", "run", f"{OUT}/imu_only", "--out",
                                                 f"{OUT}/pocket_drift_no_truth", "--drift",
                                                 "offline"], {"no pose", "--drift"}, True, ()),
    "pocket_step_calibration": ("pdr-pocket run", ["pdr-pocket", "run", f"{OUT}/imu_only",
                                                   "--out", f"{OUT}/pocket_step_calibration",
                                                   "--step-calibration", f"{OUT}/fit.yaml"],
                                {"no pose", "--step-calibration"}, True, ()),
    "evaluate_everything": ("pdr-pocket evaluate",
                            ["pdr-pocket", "evaluate", f"{OUT}/pocket_drift_no_truth", "--truth",
                             POCKET_WALK, "--truth-steps", f"{OUT}/cycles.csv",
                             "--truth-steps-per", "cycle", "--distance-m", "150"],
                            {"pose", "steps", "floors", "--truth", "--truth-steps",
                             "--distance-m"}, False, ("pocket_drift_no_truth",)),
    "evaluate_distance": ("pdr-pocket evaluate",
                          ["pdr-pocket", "evaluate", f"{OUT}/pocket_truth", "--distance-m",
                           "150"], {"no pose", "--distance-m"}, False, ("pocket_truth",)),
    "attitude_truth": ("pdr-pocket attitude", ["pdr-pocket", "attitude", POCKET_WALK, "--out",
                                               f"{OUT}/attitude_truth"],
                       {"pose", "attitude truth", "true biases", "ekf"}, True, ()),
    "attitude_no_truth": ("pdr-pocket attitude", ["pdr-pocket", "attitude", f"{OUT}/imu_only",
                                                  "--out", f"{OUT}/attitude_no_truth"], {"ekf"},
                          True, ()),
    "attitude_thesis": ("pdr-pocket attitude", ["pdr-pocket", "attitude", POCKET_WALK, "--out",
                                                f"{OUT}/attitude_thesis", "--config",
                                                POCKET_THESIS],
                        {"pose", "attitude truth", "true biases", "thesis"}, True, ()),
    "drift": ("pdr-drift run", ["pdr-drift", "run", f"{OUT}/pocket_truth", "--out",
                                f"{OUT}/drift"], set(), True, ("pocket_truth",)),
    "analytic": ("pdr-ekf analytic --json", ["pdr-ekf", "analytic", "--json"], set(), False,
                 ()),
    "table_steps": ("pdr-pocket table-steps --json", ["pdr-pocket", "table-steps", POCKET_WALK,
                                                      "--json"], set(), False, ()),
    "table_stride": ("pdr-pocket table-stride --json", ["pdr-pocket", "table-stride",
                                                        POCKET_WALK, "--json"], set(), False,
                     ()),
}
CASES_BY_CLI = {cli for cli, *_ in CASES.values()}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    return Runs(tmp_path_factory.mktemp("reports"))


@pytest.mark.parametrize("case", CASES)
def test_the_report_has_exactly_the_documented_fields(runs, case):
    index, sections, _ = read_doc()
    cli, _, conditions, _, _ = CASES[case]
    rows = [row for a in index[cli] for row in sections[a]]
    documented = {name for name, _, _ in rows}
    report = runs.report(case)
    items = report if isinstance(report, list) else [report]
    assert items, f"{case}: an empty report tells nothing about its fields"
    found = {}
    for item in items:
        found |= flatten(item, documented)
    empty = {name + "[]." for name, value in found.items() if value == []}
    expected = {name for name, _, conds in rows if conds <= conditions | {"always"}
                and not any(name.startswith(e) for e in empty)}
    assert set(found) == expected, (f"{case}: in the report only: {set(found) - expected}; "
                                    f"in docs/reports.md only: {expected - set(found)}")
    types = {name: doc_type for name, doc_type, _ in rows}
    wrong = {name: value for name, value in found.items() if not type_ok(value, types[name])}
    assert not wrong, f"{case}: not of the documented type: {wrong}"
