"""One recording of a dataset run: imported if it is a CSV or a phone's export, its
navigator chosen from the data for ``auto`` (pdr_eval.auto_navigator), navigated by the
navigators' Python entry points (:func:`pdr_ins_ekf.foot_offline.run`,
:func:`pdr_pocket.pocket_offline.run`: what ``pdr-ekf run`` and ``pdr-pocket run`` do, in
the worker's process, printing nothing) into ``OUT/<name>/run``, its
``report.json`` stamped (``eval``) with the hash of what made it, the navigator and why,
the warnings of the import and the run and what the walk was (pdr_eval.walk_figures).

:func:`run_recording` never raises: a recording that fails comes back with the last line
its command said, as its CLI says it (or the exception), and the others go on. A run whose
report carries the same hash (the input's bytes, the configuration's, the navigator, the
import options and the packages' versions) is skipped unless ``overwrite``.
"""
from __future__ import annotations

import hashlib
import json
import os
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path
from typing import Any

from pdr_core.errors import InputError, InputWarning
from pdr_eval.auto_navigator import bag_navigator, refusal
from pdr_eval.recordings import Recording
from pdr_eval.walk_figures import foot_walk, pocket_walk
from pdr_ins_ekf.foot_offline import FootOptions
from pdr_ins_ekf.foot_offline import run as run_foot
from pdr_pocket.pocket_offline import PocketOptions
from pdr_pocket.pocket_offline import run as run_pocket
from pdr_sim.import_cli import OptionsError, import_recording

# each navigator's entry point, its options and the CLI that names its errors
ENTRY_POINTS = {"foot": (run_foot, FootOptions, "pdr-ekf"),
                "pocket": (run_pocket, PocketOptions, "pdr-pocket")}
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


def _said(function: Callable, *args: Any) -> tuple[Any, list[str]]:
    """``function(*args)`` and the InputWarnings it raised, as their text (what a CLI
    prints after ``PROG: warning: ``)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InputWarning)
        result = function(*args)
    return result, [str(w.message) for w in caught if issubclass(w.category, InputWarning)]


def import_input(recording: Recording, bag: Path) -> list[str]:
    """``recording`` imported into ``bag`` by its ``pdr-sim`` import command
    (pdr_sim.import_cli.import_recording): the warnings it said. Its errors propagate."""
    _, said = _said(import_recording, recording.importer, recording.source,
                    recording.import_options, bag)
    return said


def navigate(navigator: str, bag: Path, out: Path, config: Path | None
             ) -> tuple[dict, list[str]]:
    """The ``navigator``'s entry point on ``bag`` with the YAML ``config`` (None: its
    shipped one), its outputs written to ``out``: its report and its warnings as its CLI
    says them (the input's InputWarnings, then the report's after the bag's name). Its
    errors propagate."""
    run, options, _ = ENTRY_POINTS[navigator]
    report, said = _said(run, bag, options(config=config, overwrite=True), out)
    return report, said + [f"{bag}: {warning}" for warning in report["warnings"]]


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
        bag, told = recording.source, []
        if recording.importer is not None:
            bag = folder / "input"
            try:
                told = import_input(recording, bag)
            except OptionsError as exc:
                return Outcome(recording, None, f"{exc.source}: error: {exc.problem}",
                               time.perf_counter() - start)
            except InputError as exc:
                return Outcome(recording, None, f"pdr-sim: error: {exc}",
                               time.perf_counter() - start)
        navigator, why = recording.navigator, "given"
        if navigator == "auto":
            choice = bag_navigator(bag)
            if choice.navigator is None:
                return Outcome(recording, None, refusal(choice), time.perf_counter() - start)
            navigator, why = choice.navigator, f"auto: {choice.why} ({choice.figures()})"
        try:
            report, said = navigate(navigator, bag, folder / "run", config)
        except InputError as exc:
            return Outcome(recording, None, f"{ENTRY_POINTS[navigator][2]}: error: {exc}",
                           time.perf_counter() - start)
        walk = foot_walk(folder / "run") if navigator == "foot" else pocket_walk(report)
        report["eval"] = {"input_hash": digest, "versions": versions(),
                          "navigator": navigator, "navigator_why": why,
                          "dataset": recording.dataset, "worker_pid": os.getpid(),
                          "warnings": told + said, "walk": walk}
        stamped = (folder / REPORT).with_suffix(".stamped")
        stamped.write_text(json.dumps(report, indent=2) + "\n")
        stamped.replace(folder / REPORT)      # at once: a run killed here keeps no half
        return Outcome(recording, report, "", time.perf_counter() - start)
    except Exception as exc:    # one recording's failure, named, stops no other
        return Outcome(recording, None, f"{type(exc).__name__}: {exc}",
                       time.perf_counter() - start)
