"""README.md is the user's guide: short, the two commands first, and every quickstart block
(a ```bash block right after a ``<!-- quickstart -->`` line) runs as written, from the
repository root, in CI, twice in a row: a block's outputs under ``out/`` are removed
first, so the first run starts as a fresh clone would, and the second finds them there
(a user trying a block again)."""
from __future__ import annotations

import contextlib
import os
import re
import shutil
import signal
import subprocess

import pytest

from wstest import ROOT

README = ROOT / "README.md"
MARK = "<!-- quickstart -->"


def quickstart_blocks(text: str) -> list[str]:
    """The bash blocks that follow the quickstart mark, in order."""
    return re.findall(re.escape(MARK) + r"\s*\n```bash\n(.*?)\n```", text, flags=re.S)


def outputs(block: str) -> set[str]:
    """The out/NAME paths a block writes (the first level below out/)."""
    return set(re.findall(r"\bout/[\w.\-]+", block))


def test_readme_is_short_and_starts_with_the_two_commands():
    text = README.read_text()
    assert len(text.splitlines()) <= 250
    first_block = re.search(r"```bash\n(.*?)\n```", text, flags=re.S).group(1)
    assert [line.split()[:2] for line in first_block.splitlines()] == [["make", "demo"],
                                                                         ["make", "test"]]
    assert text.index("```bash") < text.index("\n## ")


def test_every_quickstart_section_has_a_runnable_block():
    text = README.read_text()
    assert len(quickstart_blocks(text)) == text.count(MARK) == 5


def run_block(block: str, env: dict, timeout_s: float = 240) -> subprocess.CompletedProcess:
    """Run a block with bash in its own process group; on a timeout the whole group (the
    nodes it started in the background too) is killed, and the test fails."""
    proc = subprocess.Popen(["bash", "-euo", "pipefail", "-c", block], cwd=ROOT, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        pytest.fail(f"timed out after {timeout_s} s:\n{block}\n--- stdout\n{out}\n"
                    f"--- stderr\n{err}")
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, err)


# the blocks that run a live graph or simulate several walks, each run twice (a user
# trying a block again): 23-33 s from a fresh clone beside the other worker
TWICE_SLOW = {0: "the foot live graph (zupt_ekf, bag_record, bag_play) and its report",
              2: "three simulated walks and an EKF run with plots",
              4: "export, import, pocket run and evaluation of the pocket walk"}


@pytest.mark.ros
@pytest.mark.parametrize("index", [pytest.param(i, marks=pytest.mark.slow(
    f"README quickstart block {i} run twice as written: {TWICE_SLOW[i]}"))
    if i in TWICE_SLOW else i for i in range(5)])
def test_quickstart_block_runs(index, domain_id):
    block = quickstart_blocks(README.read_text())[index]
    for path in outputs(block):
        target = ROOT / path
        if target.is_dir():
            shutil.rmtree(target)
        else:
            target.unlink(missing_ok=True)
    (ROOT / "out").mkdir(exist_ok=True)
    for run in ("first", "second"):
        result = run_block(block, {**os.environ, "ROS_DOMAIN_ID": str(domain_id)})
        assert result.returncode == 0, f"{run} run\n{block}\n--- stdout\n{result.stdout}\n" \
                                       f"--- stderr\n{result.stderr}"
        for path in outputs(block):
            assert (ROOT / path).exists(), f"{path} was not written"
        if "phone_eval" in block:       # the pocket walk's 122 true steps, each matched
            assert result.stdout.splitlines()[-1].split()[0] == "122", result.stdout


def test_relative_links_of_readme_and_docs_resolve():
    broken = []
    for page in [README, *sorted((ROOT / "docs").glob("*.md"))]:
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", page.read_text()):
            if "://" not in target and not (page.parent / target).exists():
                broken.append(f"{page.relative_to(ROOT)}: {target}")
    assert broken == []
