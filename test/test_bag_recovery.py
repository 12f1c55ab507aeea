"""Recordings that survive a crash and bags that can be repaired (issue 19, acceptance 1
and 2)."""
from __future__ import annotations

import json
import signal
import time

import numpy as np
import pytest
from rosbags.rosbag2 import Reader

from pdr_core.errors import InputWarning
from pdr_core.io.bag import BagReader, readable_extent
from pdr_ins_ekf import cli as ekf_cli
from wstest import ROOT, imu_bag, log_text, play

FLUSH_INTERVAL_S = 0.5


@pytest.mark.ros
def test_sigkill_keeps_every_message_older_than_the_flush_interval(procs, tmp_path):
    """bag_record killed with SIGKILL after the player is done and a flush interval has
    passed: every message is read back (with a warning), `pdr-sim repair` gives a bag
    that `pdr-sim info` and rosbags' reader open."""
    bag, out = tmp_path / "in", tmp_path / "out"
    batch = imu_bag(bag, 2000)
    recorder = procs.start("bag_record", "--ros-args", "-p", f"out:={out}",
                           "-p", "topics:=[imu/data]",
                           "-p", f"flush_interval_s:={FLUSH_INTERVAL_S}", name="record")
    played = play(procs, bag, "rate:=0.0")
    assert played.returncode == 0, played.stderr
    time.sleep(2 * FLUSH_INTERVAL_S + 0.5)
    assert procs.stop(recorder, signal.SIGKILL) == -signal.SIGKILL, log_text(recorder)
    assert (out / "metadata.yaml").is_file()
    info = procs.run("pdr-sim", "info", str(out))
    assert info.returncode == 0, info.stderr
    assert "pdr-sim: warning:" in info.stderr and "messages: 2000" in info.stdout
    repaired = procs.run("pdr-sim", "repair", str(out), "--out", str(tmp_path / "fixed"))
    assert repaired.returncode == 0, repaired.stderr
    info = procs.run("pdr-sim", "info", str(tmp_path / "fixed"))
    assert info.returncode == 0 and "warning" not in info.stderr, info.stderr
    with Reader(tmp_path / "fixed") as reader:
        assert reader.message_count == 2000
    np.testing.assert_array_equal(BagReader(tmp_path / "fixed", strict=True)
                                  .read("/imu/data").stamp_ns, batch.stamp_ns)


def ekf_run(capsys, *argv: str) -> tuple[int, str]:
    """``pdr-ekf run`` in process (its exit status and stderr)."""
    with pytest.raises(SystemExit) as done:
        ekf_cli.main(["run", *argv])
    return done.value.code, capsys.readouterr().err


def test_a_bag_cut_at_ten_offsets_is_run_with_a_warning_or_refused_when_strict(
        tmp_path, capsys):
    """The sample foot bag's MCAP cut at 10 random offsets (past its first chunk):
    `pdr-ekf run` navigates what is left and says so; `--strict` refuses it, naming the
    file and the offset its readable part ends at."""
    source = (ROOT / "bags" / "foot_walk" / "foot_walk.mcap").read_bytes()
    metadata = (ROOT / "bags" / "foot_walk" / "metadata.yaml").read_text()
    rng = np.random.default_rng(19)
    for k, cut in enumerate(rng.integers(len(source) // 3, len(source) - 1, size=10)):
        bag = tmp_path / f"cut{k}"
        bag.mkdir()
        (bag / "metadata.yaml").write_text(metadata)
        mcap = bag / "foot_walk.mcap"
        mcap.write_bytes(source[:cut])
        extent = readable_extent(mcap)
        status, err = ekf_run(capsys, str(bag), "--out", str(tmp_path / f"out{k}"))
        assert status == 0, err
        assert f"pdr-ekf: warning: {mcap}: cut short or unindexed: readable to byte " \
               f"{extent.good_bytes} of {cut}" in err
        report = json.loads((tmp_path / f"out{k}" / "report.json").read_text())
        with pytest.warns(InputWarning):
            readable = len(BagReader(bag).read("/imu/data"))
        assert 0 < report["samples"] == readable <= 6095
        status, err = ekf_run(capsys, str(bag), "--out", str(tmp_path / f"strict{k}"),
                              "--strict")
        assert status == 2 and not (tmp_path / f"strict{k}").exists()
        assert err.startswith(f"pdr-ekf: error: {mcap}: cut short or unindexed: readable to "
                              f"byte {extent.good_bytes} of {cut}")
        assert "refused (--strict" in err
