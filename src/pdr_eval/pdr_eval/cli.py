"""``pdr-eval``: a navigator over a whole dataset, in parallel, with one summary.

    pdr-eval RECORDINGS... [--navigator auto|foot|pocket] --out OUT [--config YAML]
    pdr-eval --manifest MANIFEST.csv --out OUT [--scheduler tcp://HOST:8786]

Each recording (a bag directory, an ``.mcap`` file, or a CSV with its ``pdr-sim
import-csv`` options in a manifest; paths, globs or a manifest: pdr_eval.recordings) is
navigated by ``pdr-ekf run`` or ``pdr-pocket run`` (``auto``, the default: the one its
data fit, pdr_core.walking.navigator_choice) into ``OUT/<name>/run`` (the output bag and
``report.json``), in parallel: a process per core here, or the workers of a Dask cluster
with ``--scheduler``. ``OUT/summary.csv`` and ``OUT/summary.md`` hold a line per
recording (steps, footfalls, distance, floor, placement, barometer, warnings, the
manifest's known figures scored, the figures against a truth) and, per dataset, the
median, mean and maximum of each (pdr_eval.summary). A recording that fails is listed with its
reason and stops no other; the exit status is 1 when any failed, 2 for a bad command
line or manifest. A second run over the same OUT keeps each report made from the same
input, configuration and package versions (its ``eval.input_hash``); ``--overwrite``
runs everything again. docs/datasets.md says more.
"""
from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from pdr_core.errors import InputError, cli_parser, dispatch
from pdr_eval.execution import run_all
from pdr_eval.recordings import NAVIGATORS, from_manifest, from_paths
from pdr_eval.summary import write_summary

EXIT_FAILED = 1


def parser() -> argparse.ArgumentParser:
    p = cli_parser("pdr-eval", __doc__)
    p.add_argument("recordings", nargs="*", help="bag directories, .mcap files or globs "
                                                 "(quoted, so that pdr-eval expands them)")
    p.add_argument("--manifest", type=Path, help="CSV of recordings: recording, dataset, "
                                                 "navigator, import_options, true_footfalls, "
                                                 "true_steps, true_distance_m")
    p.add_argument("--navigator", choices=NAVIGATORS, default="auto",
                   help="the navigator of the recordings a manifest row does not name: "
                        "auto, the foot's for a foot's still stances or swing, else the "
                        "pocket's (a recording with too little motion is refused)")
    p.add_argument("--config", type=Path, help="the navigator's YAML (default: its shipped one)")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                   help="processes on this machine (without --scheduler)")
    p.add_argument("--scheduler", help="a Dask scheduler's address (tcp://HOST:8786): run "
                                       "on its workers, which must reach OUT and the inputs")
    p.add_argument("--overwrite", action="store_true",
                   help="run every recording again, even those with a report of the same input")
    p.set_defaults(func=_run)
    return p


def _run(args: argparse.Namespace) -> int:
    recordings = from_paths(args.recordings, args.navigator)
    if args.manifest is not None:
        recordings += from_manifest(args.manifest, args.navigator)
    if not recordings:
        raise InputError("pdr-eval", "no recording given (paths, globs or --manifest)")
    if args.config is not None and not args.config.is_file():
        raise InputError(args.config, "no such configuration file")
    if args.workers < 1:
        raise InputError("--workers", f"must be at least 1, got {args.workers}")
    args.out.mkdir(parents=True, exist_ok=True)
    out = args.out.resolve()
    config = None if args.config is None else args.config.resolve()
    outcomes = run_all(recordings, out, config, args.overwrite, args.workers, args.scheduler,
                       lambda line: print(f"pdr-eval: {line}", file=sys.stderr))
    csv_path, md_path = write_summary(outcomes, out)
    failed = sum(o.report is None for o in outcomes)
    kept = sum(o.skipped for o in outcomes)
    print(f"{len(outcomes)} recordings: {len(outcomes) - failed - kept} run, {kept} kept "
          f"from an earlier run, {failed} failed; {csv_path}, {md_path}")
    return EXIT_FAILED if failed else 0


def main(argv: Sequence[str] | None = None) -> None:
    dispatch("pdr-eval", parser(), argv)


if __name__ == "__main__":
    main()
