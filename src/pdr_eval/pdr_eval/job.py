"""One recording of a dataset run: imported if it is a CSV or a phone's export, its
navigator chosen from the data for ``auto`` (pdr_eval.auto_navigator), navigated by
``pdr-ekf run`` or ``pdr-pocket run`` (their ``main``, in the worker's process) into
``OUT/<name>/run``, its
``report.json`` stamped (``eval``) with the hash of what made it, the navigator and why,
the warnings the commands printed and what the walk was (pdr_eval.walk_figures).

:func:`run_recording` never raises: a recording that fails comes back with the last line
its command said (or the exception), and the others go on. A run whose report carries the
same hash (the input's bytes, the configuration's, the navigator, the import options and
the packages' versions) is skipped unless ``overwrite``.
"""
from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import time
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

from pdr_core.walk_plausibility import EXIT_REFUSED
from pdr_eval.auto_navigator import bag_navigator, refusal
from pdr_eval.recordings import Recording
from pdr_eval.walk_figures import foot_walk, pocket_walk

CLI_MODULES = {"foot": "pdr_ins_ekf.cli", "pocket": "pdr_pocket.cli"}
PACKAGES = ("pdr_core", "pdr_sim", "pdr_ins_ekf", "pdr_pocket", "pdr_eval")
REPORT = Path("run") / "report.json"


@dataclass(frozen=True)
class Outcome:
    """What became of one recording: its report (None when it failed), the failure's
    one-line reason, the wall time [s] and whether an earlier run's report was kept."""

    recording: Recording
    report: dict | None
    error: str
    seconds: float
    skipped: bool = False


def versions() -> str:
    """The installed versions of the packages a run goes through."""
    found = []
    for name in PACKAGES:
        try:
            found.append(f"{name}={metadata.version(name)}")
        except metadata.PackageNotFoundError:
            found.append(f"{name}=?")
    return ",".join(found)


def input_hash(recording: Recording, config: Path | None) -> str:
    """SHA-256 of what a run is made from: every file of the recording (a bag directory's
    in name order), the configuration file, the navigator, the import options and the
    packages' versions."""
    digest = hashlib.sha256()
    source = recording.source
    files = sorted(p for p in source.rglob("*") if p.is_file()) if source.is_dir() else [source]
    for path in files:
        digest.update(path.name.encode())
        with path.open("rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                digest.update(block)
    if config is not None:
        digest.update(config.read_bytes())
    digest.update("\0".join([recording.navigator, *recording.import_options, versions()])
                  .encode())
    return digest.hexdigest()


def _call(module: str, argv: list[str]) -> tuple[int, str]:
    """``main(argv)`` of a CLI module in this process: its exit status and stderr."""
    import importlib

    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        try:
            importlib.import_module(module).main(argv)
            code = 0
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else 1
    return code, err.getvalue()


WARNING = ": warning: "


def warnings_of(text: str) -> list[str]:
    """The warnings a command printed (its lines ``PROG: warning: TEXT``), as TEXT."""
    return [line.split(WARNING, 1)[1] for line in text.splitlines() if WARNING in line]


def _last_line(text: str, fallback: str) -> str:
    lines = [line for line in text.strip().splitlines() if line.strip()]
    return lines[-1] if lines else fallback


def kept_report(recording: Recording, out: Path, digest: str) -> dict | None:
    """An earlier run's report of this recording made from the same input (its hash)."""
    path = out / recording.name / REPORT
    try:
        report = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return report if report.get("eval", {}).get("input_hash") == digest else None


def run_recording(recording: Recording, out: Path, config: Path | None,
                  overwrite: bool) -> Outcome:
    """Import (a CSV), navigate and report one recording (see the module)."""
    start = time.perf_counter()
    folder = out / recording.name
    try:
        if not recording.source.exists():
            return Outcome(recording, None, f"{recording.source}: no such file or directory",
                           time.perf_counter() - start)
        digest = input_hash(recording, config)
        if not overwrite and (report := kept_report(recording, out, digest)) is not None:
            return Outcome(recording, report, "", time.perf_counter() - start, skipped=True)
        bag, warnings = recording.source, []
        if recording.importer is not None:
            bag = folder / "input"
            code, err = _call("pdr_sim.cli", [recording.importer, str(recording.source),
                                              *recording.import_options, "--out", str(bag),
                                              "--overwrite"])
            if code:
                return Outcome(recording, None,
                               _last_line(err, f"{recording.importer} exit {code}"),
                               time.perf_counter() - start)
            warnings += warnings_of(err)
        navigator, why = recording.navigator, "given"
        if navigator == "auto":
            choice = bag_navigator(bag)
            if choice.navigator is None:
                return Outcome(recording, None, refusal(choice), time.perf_counter() - start)
            navigator, why = choice.navigator, f"auto: {choice.why} ({choice.figures()})"
        argv = ["run", str(bag), "--out", str(folder / "run"), "--overwrite"]
        code, err = _call(CLI_MODULES[navigator],
                          argv + (["--config", str(config)] if config else []))
        if code and not (code == EXIT_REFUSED and (folder / REPORT).is_file()):
            return Outcome(recording, None, _last_line(err, f"exit {code}"),
                           time.perf_counter() - start)
        report = json.loads((folder / REPORT).read_text())
        walk = foot_walk(folder / "run") if navigator == "foot" else pocket_walk(report)
        report["eval"] = {"input_hash": digest, "versions": versions(),
                          "navigator": navigator, "navigator_why": why,
                          "dataset": recording.dataset, "worker_pid": os.getpid(),
                          "warnings": warnings + warnings_of(err), "walk": walk}
        stamped = (folder / REPORT).with_suffix(".stamped")
        stamped.write_text(json.dumps(report, indent=2) + "\n")
        stamped.replace(folder / REPORT)      # at once: a run killed here keeps no half
        return Outcome(recording, report, "", time.perf_counter() - start)
    except Exception as exc:    # one recording's failure, named, stops no other
        return Outcome(recording, None, f"{type(exc).__name__}: {exc}",
                       time.perf_counter() - start)
