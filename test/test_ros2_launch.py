"""``ros2 launch`` of the project's graphs (issue 58, acceptance 2): the pocket graph with
the drift loop started from its launch file stops on Ctrl-C, every node within 5 s. That
the launched graph gives the in-process loop's final path is test_demo.py's
``test_make_demo`` (``make demo`` runs its graphs from the launch files)."""
from __future__ import annotations

import os
import re
import signal
import time

import pytest

from wstest import log_text, wait_for_log

pytestmark = pytest.mark.ros
STOP_WITHIN_S = 5.0     # issue 58: Ctrl-C stops every node within 5 s


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def test_ctrl_c_stops_every_node_of_the_drift_graph_within_5_s(procs):
    launcher = procs.start("ros2", "launch", "pdr_drift", "pocket_drift.launch.xml",
                           name="launch")
    wait_for_log(launcher, "[pocket_pdr]: pocket_pdr: configuration",
                 "[landmark_drift]: landmark_drift: configuration")
    pids = [int(pid) for pid in re.findall(r"process started with pid \[(\d+)\]",
                                           log_text(launcher))]
    assert len(pids) == 2 and all(map(alive, pids))
    start = time.monotonic()
    launcher.send_signal(signal.SIGINT)
    assert launcher.wait(timeout=STOP_WITHIN_S + 5) == 0, log_text(launcher)
    stopped = time.monotonic() - start
    log = log_text(launcher)
    assert stopped < STOP_WITHIN_S and not any(map(alive, pids)), log
    assert "[WARNING] [launch]: user interrupted with ctrl-c (SIGINT)" in log
    assert log.count("process has finished cleanly") == 2, log
