"""Start, watch and stop a launch's processes, with ``ros2 launch``'s log lines.

As ``launch``'s ``LaunchService`` and ``actions/execute_local.py`` do (ROS 2 Jazzy):
every process starts at once; its lines are printed prefixed ``[<label>] `` (``screen``
and ``both``: both streams; ``log``, the default: stderr only) and all of them go to
``launch.log`` in a folder under ``$ROS_LOG_DIR`` (or ``$ROS_HOME/log``, or
``~/.ros/log``); ``process started with pid``, ``process has finished cleanly``, ``process
has died`` as launch words them. The launch ends when every process has ended, or shuts
down when a process with ``on_exit="shutdown"`` ends, on Ctrl-C (SIGINT) or on SIGTERM.

Shutting down, each running process gets SIGINT, then SIGINT again after
half of ``sigterm_timeout`` (a node seen once to keep spinning after its first), SIGTERM after
``sigterm_timeout`` and SIGKILL after ``sigkill_timeout``: by default every process is gone
within 5 s. Real launch waits ``sigterm_timeout`` = 5 s before SIGTERM and sends no second
SIGINT; the launch configurations ``sigterm_timeout`` and ``sigkill_timeout`` are read by
both. Processes run in sessions of their own, so a terminal's Ctrl-C reaches them only
through the runner, once; each gets SIGTERM if the runner itself dies (Linux's
``PR_SET_PDEATHSIG``), so no node outlives a killed launch. Exit status 1 when a process
died (a non-zero status before the shutdown began), 0 otherwise.
"""
from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from datetime import datetime
from pathlib import Path

from pdr_ros2.launch_description import LaunchProcess

SIGTERM_TIMEOUT_S = 3.0   # [s] after the first SIGINT (launch's default: 5 s); the
                          # second SIGINT comes halfway

SIGKILL_TIMEOUT_S = 1.5   # [s] after SIGTERM (launch's default: 5 s)
POLL_S = 0.02             # how often the processes are looked at
PR_SET_PDEATHSIG = 1      # prctl(2): the signal a child gets when its parent dies
LIBC = ctypes.CDLL(None, use_errno=True)
STREAMS_SHOWN = {"screen": ("stdout", "stderr"), "both": ("stdout", "stderr"),
                 "log": ("stderr",)}


@dataclass
class Running:
    """A started process and where its shutdown stands."""

    spec: LaunchProcess
    popen: subprocess.Popen
    signals_sent: int = 0
    last_signal: signal.Signals = signal.SIGINT
    reported: bool = False


class LaunchRunner:
    """The processes of one launch, from start to the last exit."""

    def __init__(self, processes: list[LaunchProcess], sigterm_timeout_s: float =
                 SIGTERM_TIMEOUT_S, sigkill_timeout_s: float = SIGKILL_TIMEOUT_S):
        self.specs = processes
        self.escalation = ((sigterm_timeout_s / 2, signal.SIGINT),
                           (sigterm_timeout_s, signal.SIGTERM),
                           (sigterm_timeout_s + sigkill_timeout_s, signal.SIGKILL))
        self.log_folder = log_folder()
        self.log = (self.log_folder / "launch.log").open("a", encoding="utf-8")
        self.lock = threading.Lock()
        self.running: list[Running] = []
        self.shutdown_at: float | None = None
        self.died = False
        self.interrupts = 0

    def run(self) -> int:
        """Start every process, watch them until the last has ended; the exit status."""
        previous = {sig: signal.signal(sig, self.on_signal)
                    for sig in (signal.SIGINT, signal.SIGTERM)}
        self.say("INFO", "launch", f"All log files can be found below {self.log_folder}")
        self.say("INFO", "launch", "Default logging verbosity is set to INFO")
        try:
            with tempfile.TemporaryDirectory(prefix="pdr_launch_") as folder:
                for spec in self.specs:
                    if self.shutdown_at is None:
                        self.start(spec, Path(folder))
                while not all(self.watch()):
                    time.sleep(POLL_S)
        finally:
            for sig, handler in previous.items():
                signal.signal(sig, handler)
            self.log.close()
        return 1 if self.died else 0

    def start(self, spec: LaunchProcess, folder: Path) -> None:
        """Start one process and the threads that copy its lines."""
        env = {**os.environ, **spec.env, "PYTHONUNBUFFERED": "1"}
        argv = spec.argv(folder)
        try:
            popen = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     stdin=subprocess.DEVNULL, env=env, cwd=spec.cwd,
                                     start_new_session=True, preexec_fn=end_with_parent)
        except OSError as error:
            self.say("ERROR", spec.label, f"process failed to start: {error}")
            self.died = True
            self.shut_down()
            return
        self.running.append(Running(spec, popen))
        self.say("INFO", spec.label, f"process started with pid [{popen.pid}]")
        for stream_name in ("stdout", "stderr"):
            shown = stream_name in STREAMS_SHOWN[spec.output]
            threading.Thread(target=self.copy_lines, daemon=True,
                             args=(getattr(popen, stream_name), spec.label, shown)).start()

    def copy_lines(self, stream, label: str, shown: bool) -> None:
        """Each line of a process' stream to launch.log and, if ``shown``, the screen."""
        for raw in stream:
            line = f"[{label}] {raw.decode(errors='replace').rstrip()}"
            self.write(line, shown)

    def watch(self) -> list[bool]:
        """Report processes that ended, escalate the shutdown; which have ended."""
        ended = []
        for proc in self.running:
            code = proc.popen.poll()
            if code is not None and not proc.reported:
                self.report_exit(proc, code)
            elif code is None and self.shutdown_at is not None:
                self.escalate(proc)
            ended.append(code is not None)
        return ended

    def report_exit(self, proc: Running, code: int) -> None:
        proc.reported = True
        label, pid = proc.spec.label, proc.popen.pid
        if code == 0:
            self.say("INFO", label, f"process has finished cleanly [pid {pid}]")
        else:
            self.say("ERROR", label, f"process has died [pid {pid}, exit code {code}, cmd "
                                     f"'{' '.join(proc.popen.args)}'].")
            self.died = self.died or self.shutdown_at is None
        if proc.spec.shutdown_on_exit:
            self.shut_down()

    def escalate(self, proc: Running) -> None:
        """Send the process the next signal of the shutdown once its time has come:
        SIGINT at once, then each of ``self.escalation`` at its time after the first."""
        if proc.signals_sent == 0:
            self.signal(proc, signal.SIGINT)
            return
        step = proc.signals_sent - 1
        if step >= len(self.escalation):
            return
        due, sig = self.escalation[step]
        if time.monotonic() - self.shutdown_at < due:
            return
        since = due - (self.escalation[step - 1][0] if step else 0.0)
        self.say("WARNING" if sig == signal.SIGINT else "ERROR", proc.spec.label,
                 f"process[{proc.spec.label}] failed to terminate '{since:g}' seconds after "
                 f"receiving '{proc.last_signal.name}', escalating to '{sig.name}'")
        self.signal(proc, sig)

    def signal(self, proc: Running, sig: signal.Signals) -> None:
        proc.signals_sent += 1
        proc.last_signal = sig
        with contextlib.suppress(ProcessLookupError):     # it ended meanwhile
            proc.popen.send_signal(sig)

    def shut_down(self) -> None:
        """Begin the shutdown (once): the next watch sends every process SIGINT."""
        if self.shutdown_at is None:
            self.shutdown_at = time.monotonic()

    def on_signal(self, signum: int, frame) -> None:
        """Ctrl-C or SIGTERM: shut down; a second Ctrl-C is ignored, as launch does."""
        if signum == signal.SIGTERM:
            self.say("WARNING", "launch", "using SIGTERM or SIGQUIT can result in orphaned "
                                          "processes")
        elif self.interrupts:
            self.say("WARNING", "launch", "user interrupted with ctrl-c (SIGINT) again, "
                                          "ignoring...")
        else:
            self.say("WARNING", "launch", "user interrupted with ctrl-c (SIGINT)")
        self.interrupts += signum == signal.SIGINT
        self.shut_down()

    def say(self, level: str, who: str, text: str) -> None:
        """A launch log line, ``[LEVEL] [who]: text``, on the screen and in launch.log."""
        self.write(f"[{level}] [{who}]: {text}", True)

    def write(self, line: str, shown: bool) -> None:
        with self.lock:
            if shown:
                print(line, file=sys.stdout, flush=True)
            self.log.write(line + "\n")
            self.log.flush()


def log_folder() -> Path:
    """A new folder for this launch's logs, named as launch names it."""
    base = os.environ.get("ROS_LOG_DIR") or os.path.join(
        os.environ.get("ROS_HOME", os.path.expanduser("~/.ros")), "log")
    stamp = datetime.now().strftime("%Y-%m-%d-%H-%M-%S-%f")
    folder = Path(base) / f"{stamp}-{socket.gethostname()}-{os.getpid()}"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def end_with_parent() -> None:
    """In a started child: SIGTERM when the runner dies (``prctl(PR_SET_PDEATHSIG)``)."""
    LIBC.prctl(PR_SET_PDEATHSIG, signal.SIGTERM)
