"""The sample bags in bags/ are reproduced by the command in bags/README.md (pdr-sim
generate for the simulated walks, import-csv for the real recording): every message bit
for bit, but for the last bits of floating-point values that NumPy's vector maths takes
from the CPU. Its sin, cos and exp round differently with AVX-512 (X86_V4) than without
it: bags/foot_walk, written on a machine with it, differs on one without it in 96 of its
6,095 true poses, by 1 ULP (3.6e-15 m), and in its IMU readings by 3e-14. Those values
are held to 1e-12 (relative, or absolute below 1), a thousand times the CPUs'
difference and ten million times below any change of the simulation."""
from __future__ import annotations

import shlex

import numpy as np
import pytest

from pdr_core.io.bag import BagReader, RawMessage
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
    # the first message whose topic, type or time differs, named (pytest's diff of 35,000
    # messages takes minutes)
    pairs = enumerate(zip(committed, regenerated, strict=True))
    differing = next((k for k, (a, b) in pairs if heading(a) != heading(b)), None)
    assert differing is None, f"message {differing}: {regenerated[differing]}"
    for topic in sorted({a.topic for a, b in zip(committed, regenerated, strict=True) if a != b}):
        assert_equal_to_the_last_bits(BagReader(ROOT / "bags" / bag).read(topic),
                                      BagReader(tmp_path / "again").read(topic), topic)
    assert BagReader(ROOT / "bags" / bag).custom_data("pdr.simulation") == \
        BagReader(tmp_path / "again").custom_data("pdr.simulation")


def heading(message: RawMessage) -> tuple[str, str, int]:
    """What a message is, without its bytes: topic, type and log time."""
    return message.topic, message.msgtype, message.log_time_ns


CPU_BITS = 1e-12     # relative (absolute below 1): the CPUs' vector maths differ by 3e-14


def assert_equal_to_the_last_bits(committed, regenerated, topic: str) -> None:
    """Every field of ``topic``'s messages equal, floating-point ones to :data:`CPU_BITS`
    (the module docstring)."""
    assert committed.fields.keys() == regenerated.fields.keys(), topic
    for name, value in committed.fields.items():
        ours = regenerated.fields[name]
        if np.asarray(value).dtype.kind == "f":
            gap = np.abs(np.asarray(ours) - np.asarray(value))
            bound = CPU_BITS * np.maximum(1.0, np.abs(np.asarray(value)))
            worst = np.unravel_index(np.argmax(gap - bound), gap.shape)
            assert (gap <= bound).all(), \
                f"{topic} {name}: message {worst[0]} differs by {gap[worst]:.3g}"
        else:
            assert np.array_equal(np.asarray(ours), np.asarray(value)), f"{topic} {name}"
