"""The recordings of a dataset run (``pdr-eval``): bag directories, MCAP files, CSV logs or
phones' own exports (a folder of one CSV per sensor, or its zip: ``pdr-sim import-phone``),
given on the command line (paths and globs) or in a manifest.

A manifest is a CSV file with a header and one row per recording:

- ``recording`` (required): a bag directory, an ``.mcap`` file, a ``.csv`` log or a phone's
  export (folder or zip), relative to the manifest's folder unless absolute;
- ``dataset``: the name its figures are grouped under (default: the recording's parent
  folder, as for paths given on the command line);
- ``navigator``: ``auto`` (chosen from the data: pdr_core.walking.navigator_choice), ``foot`` or
  ``pocket`` (default: ``--navigator``);
- ``import_options``: for a CSV, the ``pdr-sim import-csv`` options that read it, as one
  shell-quoted string (``--time-col t_s --acc-cols ax,ay,az``); its truth columns
  (``--pos-cols``) are what the run is scored against; for a phone's export, those of
  ``pdr-sim import-phone`` (none for Sensor Logger's; ``--acc FILE:TIME:X,Y,Z ...`` for
  another app's);
- ``true_footfalls``, ``true_steps``, ``true_distance_m``: what the walker knows of the
  walk (the footfalls of both feet, the gait cycles of the sensor leg, the distance [m]),
  each scored when given (pdr_eval.summary).

A recording that does not exist is kept: its run fails, named, and the rest go on.
"""
from __future__ import annotations

import csv
import glob
import shlex
from dataclasses import dataclass
from pathlib import Path

from pdr_core.errors import InputError

NAVIGATORS = ("auto", "foot", "pocket")
KNOWN_COLUMNS = ("true_footfalls", "true_steps", "true_distance_m")
MANIFEST_COLUMNS = ("recording", "dataset", "navigator", "import_options", *KNOWN_COLUMNS)


@dataclass(frozen=True)
class Recording:
    """One recording to navigate: its output folder's ``name`` (unique in the run), its
    ``source`` path, ``dataset``, ``navigator`` (``auto``, ``foot`` or ``pocket``), for a
    CSV the import options, and what is known of the walk (``KNOWN_COLUMNS``: number)."""

    name: str
    source: Path
    dataset: str
    navigator: str
    import_options: tuple[str, ...] = ()
    known: tuple[tuple[str, float], ...] = ()

    @property
    def is_csv(self) -> bool:
        return self.source.suffix.lower() == ".csv"

    @property
    def importer(self) -> str | None:
        """The ``pdr-sim`` command that turns the source into a bag: ``import-csv`` for a
        CSV log, ``import-phone`` for a phone's own export (a zip, or a folder of CSV
        files that is no bag: no ``metadata.yaml``, no ``.mcap``), None for a bag."""
        if self.is_csv:
            return "import-csv"
        if self.source.suffix.lower() == ".zip":
            return "import-phone"
        if self.source.is_dir() and any(self.source.glob("*.csv")) and not (
                (self.source / "metadata.yaml").exists() or any(self.source.glob("*.mcap"))):
            return "import-phone"
        return None


def from_paths(patterns: list[str], navigator: str) -> list[Recording]:
    """Recordings of paths and globs (a glob that matches nothing is refused; a plain
    path is kept even when missing, to fail by name)."""
    found: list[Path] = []
    for pattern in patterns:
        if glob.has_magic(pattern):
            matches = sorted(glob.glob(pattern))
            if not matches:
                raise InputError(pattern, "matches no recording")
            found += [Path(m) for m in matches]
        else:
            found.append(Path(pattern))
    return named([(path, path.absolute().parent.name, navigator, (), ()) for path in found])


def from_manifest(manifest: Path, navigator: str) -> list[Recording]:
    """Recordings of a manifest (see the module)."""
    try:
        with manifest.open(newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as exc:
        raise InputError(manifest, f"cannot be read: {exc.strerror}") from exc
    if not rows or "recording" not in rows[0]:
        raise InputError(manifest, "needs a header with a 'recording' column "
                                   f"(columns: {', '.join(MANIFEST_COLUMNS)})")
    unknown = set(rows[0]) - set(MANIFEST_COLUMNS)
    if unknown:
        raise InputError(manifest, f"unknown columns {sorted(unknown)} (columns: "
                                   f"{', '.join(MANIFEST_COLUMNS)})")
    entries = []
    for line, row in enumerate(rows, start=2):
        path = Path(row["recording"])
        path = path if path.is_absolute() else manifest.parent / path
        chosen = row.get("navigator") or navigator
        if chosen not in NAVIGATORS:
            raise InputError(manifest, f"line {line}: navigator {chosen!r} is not one of "
                                       f"{', '.join(NAVIGATORS)}")
        entries.append((path, row.get("dataset") or path.absolute().parent.name, chosen,
                        tuple(shlex.split(row.get("import_options") or "")),
                        known_figures(manifest, line, row)))
    return named(entries)


def known_figures(manifest: Path, line: int, row: dict) -> tuple[tuple[str, float], ...]:
    """The ``KNOWN_COLUMNS`` a manifest row fills, as numbers (a negative or non-numeric
    cell is refused, naming its line and column)."""
    known = []
    for column in KNOWN_COLUMNS:
        cell = (row.get(column) or "").strip()
        if not cell:
            continue
        try:
            value = float(cell)
        except ValueError:
            value = -1.0
        if not value >= 0:
            raise InputError(manifest, f"line {line}: {column} {cell!r} is not a number "
                                       "of at least 0")
        known.append((column, value))
    return tuple(known)


Entry = tuple[Path, str, str, tuple[str, ...], tuple[tuple[str, float], ...]]


def named(entries: list[Entry]) -> list[Recording]:
    """Recordings with unique folder names: the file's stem, prefixed by its dataset
    where two stems meet, and numbered where that is not enough."""
    stems = [path.stem if path.suffix else path.name for path, *_ in entries]
    names = [stem if stems.count(stem) == 1 else f"{dataset}_{stem}"
             for stem, (_, dataset, *_) in zip(stems, entries, strict=True)]
    seen: dict[str, int] = {}
    recordings = []
    for name, (path, dataset, navigator, options, known) in zip(names, entries, strict=True):
        seen[name] = seen.get(name, 0) + 1
        unique = name if names.count(name) == 1 else f"{name}_{seen[name]}"
        recordings.append(Recording(unique, path, dataset, navigator, options, known))
    return recordings
