"""RecordingBag: a bag written as it is recorded (issue 19)."""
from __future__ import annotations

import shutil
import time

import pytest
from rosbags.rosbag2 import Reader

from pdr_core.errors import InputError, InputWarning
from pdr_core.io.bag import BagReader, repair, write_batches
from pdr_core.io.recording import RecordingBag


@pytest.fixture
def messages(tmp_path, make_imu):
    write_batches(tmp_path / "source", {"/imu/data": make_imu(6000)})
    return list(BagReader(tmp_path / "source").raw_messages())


def write(bag: RecordingBag, messages) -> None:
    for m in messages:
        bag.write_raw(m.topic, m.msgtype, m.log_time_ns, m.data)


def test_a_crash_keeps_every_flushed_message_and_repair_rebuilds_the_index(tmp_path, messages):
    bag = RecordingBag(tmp_path / "rec", flush_interval_s=60.0)
    assert (tmp_path / "rec" / "metadata.yaml").is_file(), "written at the start"
    write(bag, messages[:4000])
    bag.flush()
    write(bag, messages[4000:4100])            # still in the open chunk
    shutil.copytree(tmp_path / "rec", tmp_path / "killed")    # what a SIGKILL leaves
    with pytest.warns(InputWarning, match="4000 messages: those are used"):
        reader = BagReader(tmp_path / "killed")
    got = [m.data for m in reader.raw_messages()]
    assert got == [m.data for m in messages[:4000]]
    with pytest.warns(InputWarning):
        counts = repair(tmp_path / "killed", tmp_path / "repaired")
    assert counts == {"/imu/data": 4000}
    with Reader(tmp_path / "repaired") as repaired:
        assert repaired.message_count == 4000
    assert [m.data for m in BagReader(tmp_path / "repaired", strict=True).raw_messages()] == got
    bag.close()
    with Reader(tmp_path / "rec") as closed:
        assert closed.message_count == 4100


def test_the_open_chunk_is_flushed_after_the_interval(tmp_path, messages):
    bag = RecordingBag(tmp_path / "rec", flush_interval_s=0.05)
    write(bag, messages[:10])
    time.sleep(0.06)
    bag.flush_if_due()
    shutil.copytree(tmp_path / "rec", tmp_path / "killed")
    with pytest.warns(InputWarning):
        assert len(BagReader(tmp_path / "killed").read("/imu/data")) == 10
    bag.close()


def test_a_vanished_directory_is_an_os_error_and_an_existing_one_refused(tmp_path, messages):
    with pytest.raises(InputError, match="exists already"):
        RecordingBag(tmp_path)
    bag = RecordingBag(tmp_path / "rec")
    write(bag, messages[:10])
    shutil.rmtree(tmp_path / "rec")
    with pytest.raises(OSError):
        bag.flush()
