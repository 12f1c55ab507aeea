"""The suite itself: every package's tests are collected, and a missing shared recording
is a skip that names it on a plain clone and a failure in CI."""
from __future__ import annotations

import os
import re
import subprocess
import sys
import tomllib

from suite_budget import MAX_SLOW_TESTS, slow_reason

from wstest import ROOT

SHARED_TEST = "test/test_import_shared_datasets.py::test_xio_without_drop_duplicates_names_the_row"


def test_every_package_test_directory_is_collected():
    options = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["pytest"]
    packages = sorted(str(p.relative_to(ROOT)) for p in ROOT.glob("src/*/test") if p.is_dir())
    assert len(packages) == 7                    # pdr_msgs: test/test_pdr_msgs.py
    assert set(packages) <= set(options["ini_options"]["testpaths"])
    assert (ROOT / "test" / "test_pdr_msgs.py").is_file() and "test" in \
        options["ini_options"]["testpaths"]


def run_without_shared(tmp_path, **env) -> subprocess.CompletedProcess:
    """pytest on one shared-data test, the recordings pointed at an empty folder."""
    env = {**os.environ, "PDR_SHARED_DATA": str(tmp_path), "PDR_REQUIRE_SHARED_DATA": "0",
           **env}
    return subprocess.run([sys.executable, "-m", "pytest", "-q", SHARED_TEST], cwd=ROOT,
                          capture_output=True, text=True, timeout=120, env=env)


def test_a_missing_recording_is_skipped_with_its_path(tmp_path):
    result = run_without_shared(tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    missing = tmp_path / "foot" / "xio_gait_tracking" / "short_walk.csv"
    [line] = [x for x in result.stdout.splitlines() if x.startswith("SKIPPED")]
    assert line.startswith("SKIPPED [1] test/test_import_shared_datasets.py:")
    assert line.endswith(f"{missing}: shared recording missing (clone the repository beside "
                         "shared/ or set PDR_SHARED_DATA)")
    assert "1 skipped" in result.stdout


def test_a_missing_recording_fails_when_required(tmp_path):
    result = run_without_shared(tmp_path, PDR_REQUIRE_SHARED_DATA="1")
    assert result.returncode == 1, result.stdout + result.stderr
    assert "shared recording missing" in result.stdout and "1 error" in result.stdout
    assert "PDR_REQUIRE_SHARED_DATA=1" in result.stdout


def test_few_tests_are_slow_and_each_says_why(request):
    """At most MAX_SLOW_TESTS tests carry ``slow``, each with its reason (the marker
    without one does not excuse a test: test/suite_budget.py). Counted on this session's
    items when it collected the whole suite (every xdist worker does), else on a
    collection of its own."""
    items = request.session.items
    if any(i.nodeid.startswith("test/test_demo.py") for i in items):
        slow = [i.nodeid for i in items if i.get_closest_marker("slow") is not None]
        assert all(slow_reason(i) for i in items if i.get_closest_marker("slow")), slow
    else:
        result = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q",
                                 "-m", "slow"], cwd=ROOT, capture_output=True, text=True,
                                timeout=300)
        assert result.returncode in (0, 5), result.stdout + result.stderr
        slow = [line for line in result.stdout.splitlines() if "::" in line]
    assert len(slow) <= MAX_SLOW_TESTS, "\n".join(slow)
    reasons = re.findall(r"pytest\.mark\.slow\((.*?)\)", "".join(
        p.read_text() for p in [*ROOT.glob("test/*.py"), *ROOT.glob("src/*/test/*.py")]
        if p.name != "suite_budget.py"), re.S)
    assert all(r.strip(" \n\"'") for r in reasons), reasons


def test_a_test_over_the_budget_fails_unless_marked_slow_with_a_reason(tmp_path):
    """The rule itself, on three tests that each take 0.3 s against a budget of 0.1 s."""
    (tmp_path / "test_timed.py").write_text(
        "import time\nimport pytest\n\n"
        "def test_unmarked():\n    time.sleep(0.3)\n\n"
        "@pytest.mark.slow\ndef test_without_reason():\n    time.sleep(0.3)\n\n"
        "@pytest.mark.slow('plays a walk at real time')\n"
        "def test_with_reason():\n    time.sleep(0.3)\n")
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "suite_budget", "-p", "no:cacheprovider",
         "-o", "markers=slow", "-o", "addopts=", str(tmp_path / "test_timed.py")],
        cwd=tmp_path, capture_output=True, text=True, timeout=120,
        env={**os.environ, "PDR_SLOW_TEST_S": "0.1", "PYTHONPATH": str(ROOT / "test")})
    assert result.returncode == 1, result.stdout + result.stderr
    assert "2 failed, 1 passed" in result.stdout, result.stdout
    assert "test_unmarked: its call took" in result.stdout
    assert "over the suite's 0.1 s per test" in result.stdout
    assert "test_with_reason" not in result.stdout.split("short test summary")[-1]
