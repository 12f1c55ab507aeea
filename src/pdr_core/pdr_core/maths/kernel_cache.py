"""Keep numba's on-disk cache honest across modules, and say when it is being filled.

numba checks a cached function against its own source file only: a kernel that calls
into another module (the smoother and the Monte-Carlo batches calling
:mod:`pdr_ins_ekf.compiled_filter`, every caller of :mod:`pdr_core.maths.small_matrix`) keeps
running its old machine code, inlined callees
and all, after that module changed. Found the hard way: an edit of
``compiled_filter.compensate`` left the cached Monte-Carlo batch on the old equations,
and the batch no longer equalled the single run.

:func:`forget_if_changed`, called at the import of such a module, removes its cache files
when the sources it depends on differ from those it was last compiled against.

A fresh clone has no cache: the first run compiles every kernel it calls, about 75 s
for all of them (``make demo``, issue 54), which looked like a hang.
:class:`CompileProgress` prints a line before the first compilation of a process (what
is being compiled and roughly how long it takes), one per kernel compiled (its
module, name, seconds and the kernels it called that were compiled with it) and,
while one compiles, how far it is every few seconds;
:func:`announce_compiles` (called by :func:`forget_if_changed`) installs it when
standard error is a terminal or :data:`PROGRESS_VARIABLE` is set (tools/warm_kernels.sh
sets it), so tests that read a tool's standard error see nothing new. A kernel loaded
from the cache is not compiled and prints nothing.
"""
from __future__ import annotations

import hashlib
import os
import sys
import time
from pathlib import Path
from typing import TextIO

from numba.core import config, event

PROGRESS_VARIABLE = "PDR_COMPILE_PROGRESS"   # set (to anything): announce compilations
FIRST_COMPILE_S = 75    # all the kernels' first compilation at -O1, make demo on 2 cores [s]
PROGRESS_EVERY_S = 10.0     # a progress line when a callee is done this long after the last [s]
OPT_LEVEL = "1"
"""LLVM's optimisation level of the kernels (``NUMBA_OPT``; numba's default is 3). At 1 a
fresh clone compiles the foot filter and smoother in 56 s instead of 80 and the pocket's
kernels in 85 s instead of 105, and they run as fast: the foot filter at 769,000 samples/s
against 740,000, the segmented smoother at 806,000 against 874,000, ``pdr-pocket run`` on
the demo's 7-min walk in 0.57 s against 0.63 (test/benchmarks/bench_ekf.py, one machine;
docs/testing.md, "Issue 58 and the budget")."""


def choose_opt_level() -> None:
    """Compile at :data:`OPT_LEVEL` unless the user set ``NUMBA_OPT``: numba reads it
    again (its configuration), and the processes this one starts inherit it."""
    if "NUMBA_OPT" not in os.environ:
        os.environ["NUMBA_OPT"] = OPT_LEVEL
        config.reload_config()


choose_opt_level()


def forget_if_changed(module_file: str, *dependencies: str) -> None:
    """Delete the numba cache files of ``module_file`` (``__pycache__/<stem>.*.nbi|nbc``
    beside it) when the contents of ``dependencies`` (source files) have changed since
    the last call; record their fingerprint. A cache directory that cannot be written
    is left alone (numba then keeps no cache there either). Announces the compilations
    to come (:func:`announce_compiles`)."""
    announce_compiles()
    source = Path(module_file)
    cache = source.parent / "__pycache__"
    digest = hashlib.sha256()
    for dependency in dependencies:
        digest.update(Path(dependency).read_bytes())
    stamp = cache / f"{source.stem}.dependencies.sha256"
    try:
        if stamp.is_file() and stamp.read_text() == digest.hexdigest():
            return
        for stale in [*cache.glob(f"{source.stem}.*.nbi"), *cache.glob(f"{source.stem}.*.nbc")]:
            stale.unlink(missing_ok=True)
        cache.mkdir(exist_ok=True)
        stamp.write_text(digest.hexdigest())
    except OSError:
        return


class CompileProgress(event.Listener):
    """A numba listener of ``numba:compile`` events (one per kernel and signature that is
    not in the cache, nested for the kernels a kernel calls) writing to ``stream``: before
    the first, what is being compiled and roughly how long it takes; while an outermost
    kernel compiles, every :data:`PROGRESS_EVERY_S` how many of the kernels it calls are
    compiled so far (one took 84 s on a busy machine); at its end, its module, name and
    seconds and how many kernels it called were compiled with it."""

    def __init__(self, stream: TextIO) -> None:
        self.stream = stream
        self.announced = False
        self.depth = 0              # compilations under way, nested
        self.start_s = 0.0          # the outermost's start (perf_counter) [s]
        self.said_s = 0.0           # the last line's time [s]
        self.callees = 0            # the outermost's callees compiled so far

    def on_start(self, ev: event.Event) -> None:
        if not self.announced:
            self.announced = True
            self._say(f"[numba] compiling the workspace's kernels to machine code, once "
                      f"(starting with {_kernel(ev)}): about {FIRST_COMPILE_S} s for all "
                      "of them on a fresh clone with two free cores, then loaded from the "
                      "cache beside the sources")
        if self.depth == 0:
            self.start_s = self.said_s = time.perf_counter()
            self.callees = 0
        self.depth += 1

    def on_end(self, ev: event.Event) -> None:
        self.depth -= 1
        now_s = time.perf_counter()
        if self.depth == 0:
            with_them = "" if not self.callees else \
                f" (and {self.callees} kernel{'s' if self.callees > 1 else ''} it calls)"
            self._say(f"[numba] compiled {_kernel(ev)}{with_them} in "
                      f"{now_s - self.start_s:.1f} s")
            return
        self.callees += 1
        if now_s - self.said_s >= PROGRESS_EVERY_S:
            self._say(f"[numba]   so far {now_s - self.start_s:.0f} s and {self.callees} of "
                      f"the kernels it calls (the last: {_kernel(ev)})")

    def _say(self, line: str) -> None:
        print(line, file=self.stream, flush=True)
        self.said_s = time.perf_counter()


def _kernel(ev: event.Event) -> str:
    """``module.name`` of the kernel an event compiles."""
    function = ev.data["dispatcher"].py_func
    return f"{function.__module__}.{function.__qualname__}"


_installed: list[CompileProgress] = []


def announce_compiles() -> None:
    """Install a :class:`CompileProgress` on standard error, once per process, when it is
    a terminal or :data:`PROGRESS_VARIABLE` is set."""
    if _installed or not (os.environ.get(PROGRESS_VARIABLE) or sys.stderr.isatty()):
        return
    _installed.append(CompileProgress(sys.stderr))
    event.register("numba:compile", _installed[0])
