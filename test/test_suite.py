"""The suite itself: every package's tests are collected, and a missing shared recording
is a skip that names it on a plain clone and a failure in CI."""
from __future__ import annotations

import os
import subprocess
import sys
import tomllib

from wstest import ROOT

SHARED_TEST = "test/test_import_shared_datasets.py::test_xio_without_drop_duplicates_names_the_row"


def test_every_package_test_directory_is_collected():
    options = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["pytest"]
    packages = sorted(str(p.relative_to(ROOT)) for p in ROOT.glob("src/*/test") if p.is_dir())
    assert len(packages) == 5                    # pdr_msgs: test/test_pdr_msgs.py
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
