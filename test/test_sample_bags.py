"""The sample bags in bags/ are reproduced bit for bit by the command in bags/README.md
(pdr-sim generate for the simulated walks, import-csv for the real recording)."""
from __future__ import annotations

import shlex

import pytest

from pdr_core.io.bag import BagReader
from wstest import ROOT


def readme_command(bag: str) -> list[str]:
    text = (ROOT / "bags" / "README.md").read_text()
    block = text.split(f"## {bag}", 1)[1].split("```bash", 1)[1].split("```", 1)[0]
    return shlex.split(block.replace("\\\n", " "))


# per sample: the IMU's topics, the true pose and its /tf; one /tf_static
@pytest.mark.parametrize(("bag", "messages"), [("foot_walk", 5 * 6095 + 1),
                                               ("pocket_walk", 4 * 11538 + 122 + 9 + 1),
                                               ("vicon_walk", 3 * 3890 + 1)])
def test_sample_bag_is_reproduced(procs, tmp_path, bag, messages):
    command = readme_command(bag)
    assert command[:2] == ["./ws", "pdr-sim"] and command[2] in ("generate", "import-csv")
    assert command[-2] == "--out"
    result = procs.run(*command[1:-1], str(tmp_path / "again"))
    assert result.returncode == 0, result.stderr
    committed = list(BagReader(ROOT / "bags" / bag).raw_messages())
    regenerated = list(BagReader(tmp_path / "again").raw_messages())
    assert len(committed) == messages
    assert len(regenerated) == messages
    # the first message that differs, named (pytest's diff of 35,000 messages takes minutes)
    pairs = enumerate(zip(committed, regenerated, strict=True))
    differing = next((k for k, (a, b) in pairs if a != b), None)
    assert differing is None, f"message {differing}: {regenerated[differing]}"
    assert BagReader(ROOT / "bags" / bag).custom_data("pdr.simulation") == \
        BagReader(tmp_path / "again").custom_data("pdr.simulation")
