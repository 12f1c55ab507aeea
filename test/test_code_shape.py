"""The code's shape, read from its syntax trees (issue 31): compiled kernels take few,
named arguments; the navigators import no evaluation or study module; papers are cited
by author and year."""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from wstest import ROOT

SOURCES = sorted(p for p in (ROOT / "src").glob("*/*/**/*.py") if "__pycache__" not in p.parts)
MAX_KERNEL_ARGUMENTS = 8
MAX_MODULE_LINES = 600      # issue 56: a module longer than this does more than one job


def tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(), str(path))


def is_compiled(function: ast.FunctionDef) -> bool:
    """Decorated with numba's njit or jit (bare or called)."""
    for decorator in function.decorator_list:
        target = decorator.func if isinstance(decorator, ast.Call) else decorator
        name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
        if name in ("njit", "jit"):
            return True
    return False


def kernels() -> list[tuple[str, ast.FunctionDef]]:
    return [(f"{path.relative_to(ROOT)}:{node.lineno} {node.name}", node)
            for path in SOURCES for node in ast.walk(tree(path))
            if isinstance(node, ast.FunctionDef) and is_compiled(node)]


def test_no_source_module_is_longer_than_600_lines():
    """Issue 56: each module does one job; the packages' tests are not sources."""
    long = [f"{path.relative_to(ROOT)}: {n} lines" for path in SOURCES if "test" not in path.parts
            and (n := len(path.read_text().splitlines())) > MAX_MODULE_LINES]
    assert long == []


def test_the_tree_has_compiled_kernels_to_check():
    assert len(kernels()) > 50


def test_no_compiled_kernel_takes_more_than_eight_arguments():
    """State, parameters and inputs travel as named tuples, not as loose arrays."""
    wide = [f"{where} ({len(node.args.args)})" for where, node in kernels()
            if len(node.args.args) > MAX_KERNEL_ARGUMENTS]
    assert wide == []


PAPER_FILE = re.compile(r"\b00[0-4]_[0-9a-f]{16}\b")
PAPER_NUMBER = re.compile(r"[Pp]apers? 00[0-4]\b|Paper00[0-4]|PAPER_00[0-4]|\(00[0-4][,)]"
                          r"|\b00[0-4]'s\b|\b00[0-4],? (?:[Ss]ection|Eqs?\.|Tables?|Fig)")


@pytest.mark.parametrize("folder", ["src", "test", "tools"])
def test_papers_are_cited_by_author_not_by_file_name_or_number(folder):
    hits = [f"{path.relative_to(ROOT)}:{n}: {line.strip()}"
            for path in sorted((ROOT / folder).rglob("*"))
            if path.is_file() and path.suffix in (".py", ".yaml", ".msg", ".srv", ".sh", ".xml")
            and "__pycache__" not in path.parts and path != Path(__file__)
            for n, line in enumerate(path.read_text().splitlines(), 1)
            if PAPER_FILE.search(line) or PAPER_NUMBER.search(line)]
    assert hits == []


def test_the_citation_patterns_catch_what_they_are_for():
    for cited in ("see 000_fbd401126d10f515.txt", "papers 000, 001", "Paper000Detector",
                  "PAPER_004_STEP", "(001, Eq. (8))", "004, section II", "000's Fig. 2a",
                  "(000, Fig. 6)", "003, Eq. (3.10)"):
        assert PAPER_FILE.search(cited) or PAPER_NUMBER.search(cited), cited
    for fine in ("0.002", "σ 0.001 m", "Zampella et al. 2011, Eq. (12)", "x[004]"):
        assert not (PAPER_FILE.search(fine) or PAPER_NUMBER.search(fine)), fine


# What the navigators may not depend on: scores against a truth, and the studies.
EVALUATION = re.compile(r"^pdr_core\.evaluation(\.|$)|^pdr_\w+\.studies(\.|$)|\.evaluation$"
                        r"|\.drift_report$|\.run_report$")
# Offline jobs and presentation, which may: the command lines, the plots, the runs of
# whole bags that write reports.
JOBS = re.compile(r"\.cli$|\.plots$|^pdr_pocket\.pocket_offline$|^pdr_ins_ekf\.foot_offline$"
                  r"|^pdr_drift\.offline$")
NAVIGATOR_PACKAGES = ("pdr_ins_ekf", "pdr_pocket", "pdr_drift")


def module_name(path: Path) -> str:
    name = ".".join(path.relative_to(ROOT / "src").parts[1:])[:-3]
    return name.removesuffix(".__init__")


def imported(path: Path, known: set[str]) -> set[str]:
    """The project modules a file imports, at its top or inside functions."""
    found = set()
    for node in ast.walk(tree(path)):
        if isinstance(node, ast.ImportFrom) and node.module:
            found |= {node.module} | {f"{node.module}.{a.name}" for a in node.names}
        elif isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
    return found & known


def import_closure() -> dict[str, set[str]]:
    modules = {module_name(p): p for p in SOURCES if "test" not in p.parts}
    direct = {m: imported(p, set(modules)) for m, p in modules.items()}
    closure = {}
    for start in modules:
        seen, todo = set(), [start]
        while todo:
            for nxt in direct[todo.pop()] - seen:
                seen.add(nxt)
                todo.append(nxt)
        closure[start] = seen
    return closure


def test_the_navigators_import_no_evaluation_or_study_module():
    """Not even through another module: a node or a navigator that reached
    pdr_core.evaluation (its metrics, say) or a study would carry scoring code into a
    robot's graph (issue 31)."""
    closure = import_closure()
    navigators = [m for m in closure if m.startswith(NAVIGATOR_PACKAGES)
                  and not EVALUATION.search(m) and not JOBS.search(m)]
    assert {"pdr_pocket.navigator", "pdr_pocket.nodes.pocket_pdr",
            "pdr_ins_ekf.nodes.zupt_ekf", "pdr_drift.nodes.landmark_drift"} <= set(navigators)
    reached = {m: sorted(x for x in closure[m] if EVALUATION.search(x)) for m in navigators}
    assert {m: x for m, x in reached.items() if x} == {}


# One vocabulary (issue 31): the angle wraps, the topic names, the frame names, the
# activities and the landmark types each have one home in pdr_core.
MODULES = [p for p in SOURCES if "test" not in p.relative_to(ROOT / "src").parts[1:]]
WRAP = re.compile(r"np\.angle\(np\.exp\(|%\s*\(2(\.0)?\s*\*\s*(np|math)\.pi\)"
                  r"|arctan2\(np\.sin\((\w+)\),\s*np\.cos\(\3\)\)")
TOPIC = re.compile(r"/?(pdr|imu|ground_truth)(/\w+)+")
VOCABULARY = {"STANDING", "WALKING", "UPSTAIRS", "DOWNSTAIRS", "SITTING", "ACTIVITY_NAMES",
              "CORNER", "STAIRS", "LANDMARK_NAMES", "FLOOR_HEIGHT_M", "ACTIVITY_COLOURS",
              "ACTIVITY_LABELS", "ACTIVITY_VALUES", "LANDMARK_MARKERS"}
# an activity or landmark type compared with a number, or a table sized by their count
LITERAL_WORD = re.compile(r"\b(activity|activities|type)\b\s*(==|!=|<=|>=|<|>)\s*\d"
                          r"|\d\s*(<=|<)\s*activity\b|\bzeros\(\(5, 5\)")
HOMES = {"wrap": "pdr_core/maths/angles.py", "topic": "pdr_core/topics.py",
         "frame": "pdr_core/frames.py", "vocabulary": "pdr_core/vocabulary.py"}


def outside(home: str) -> list[Path]:
    return [p for p in MODULES if not p.as_posix().endswith(HOMES[home])]


def string_constants(path: Path) -> list[ast.Constant]:
    """The string constants of a module that are not docstrings."""
    module = tree(path)
    docstrings = {id(node.body[0].value) for node in ast.walk(module)
                  if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef))
                  and node.body and isinstance(node.body[0], ast.Expr)}
    return [node for node in ast.walk(module) if isinstance(node, ast.Constant)
            and isinstance(node.value, str) and id(node) not in docstrings]


def test_angles_are_wrapped_by_pdr_core_angles():
    hits = [f"{path.relative_to(ROOT)}:{n}: {line.strip()}" for path in outside("wrap")
            for n, line in enumerate(path.read_text().splitlines(), 1) if WRAP.search(line)]
    assert hits == []


def test_topic_and_frame_names_are_spelled_in_pdr_core_only():
    """Nodes, bag writers, readers and command lines take them from pdr_core.topics and
    pdr_core.frames; prose that names a topic is fine."""
    topics = [f"{p.relative_to(ROOT)}:{c.lineno}: {c.value}" for p in outside("topic")
              for c in string_constants(p) if TOPIC.fullmatch(c.value)]
    frames = [f"{p.relative_to(ROOT)}:{c.lineno}: {c.value}" for p in outside("frame")
              for c in string_constants(p) if c.value in ("map", "imu_link")]
    assert topics == [] and frames == []


def test_the_activities_and_landmark_types_are_defined_once():
    """No module but pdr_core.vocabulary assigns them (``WALKING = 1``, ``... = range(5)``):
    the others import Activity, LandmarkType and the names from it."""
    hits = []
    for path in outside("vocabulary"):
        for node in tree(path).body:
            if not isinstance(node, (ast.Assign, ast.AnnAssign)):
                continue
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names = {n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name)}
            hits += [f"{path.relative_to(ROOT)}:{node.lineno}: {name}"
                     for name in sorted(names & VOCABULARY)]
    assert hits == []


def test_no_module_counts_or_numbers_the_activities_itself():
    """Issue 56: a sixth activity or a third landmark type needs pdr_core.vocabulary and
    pdr_msgs only: no ``activity <= 4``, ``type == 0`` or 5 × 5 table elsewhere."""
    hits = [f"{path.relative_to(ROOT)}:{n}: {line.strip()}" for path in outside("vocabulary")
            for n, line in enumerate(path.read_text().splitlines(), 1)
            if LITERAL_WORD.search(line)]
    assert hits == []


def test_the_vocabulary_patterns_catch_what_they_are_for():
    for literal in ("not 0 <= activity <= 4", "if m.type == 0", "period.activity != 1",
                    "confusion = np.zeros((5, 5), int)"):
        assert LITERAL_WORD.search(literal), literal
    for named in ("activity not in ACTIVITY_VALUES", "m.type == LandmarkType.CORNER",
                  "np.zeros((len(Activity), len(Activity)))", "activity_index"):
        assert not LITERAL_WORD.search(named), named
    for wrap in ("np.angle(np.exp(1j * x))", "(a + np.pi) % (2.0 * np.pi) - np.pi",
                 "(a + np.pi) % (2 * np.pi)", "np.arctan2(np.sin(d), np.cos(d))"):
        assert WRAP.search(wrap), wrap
    assert not WRAP.search("np.arctan2(np.sin(a).sum(), np.cos(b).sum())")
    for topic in ("pdr/foot/pose", "/pdr/pocket/apply_correction", "pdr/drift"):
        assert TOPIC.fullmatch(topic), topic
    assert not TOPIC.fullmatch("Reads pdr/pocket/step and pdr/pocket/pose")
