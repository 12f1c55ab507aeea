"""``pdr-drift``: offline tools of the drift estimator (no ROS graph needed).

Subcommands:
    run POCKET_OUT --out OUT    the offline drift correction (Muñoz Díaz 2016, Section 6.2)
                                of a pocket navigator's output bag: OUT/ as a bag with
                                pdr/landmarks, pdr/drift and pdr/pocket/corrected_path,
                                OUT/report.json and with --plot OUT/drift.png.

Errors in the input exit with status 2 and one line naming the file and the problem.
"""
from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

from pdr_core.errors import cli_parser, dispatch
from pdr_core.report_files import print_report
from pdr_core.vocabulary import FLOOR_HEIGHT_M
from pdr_drift.config import load_drift_config
from pdr_drift.offline import run


def _add_run(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "run", help="offline drift correction of a pocket navigator's output",
        description="Reads pdr/pocket/step and pdr/pocket/pose (of pdr-pocket run, or of "
                    "pocket_pdr recorded by bag_record), detects corners and stairs, "
                    "associates their revisits, takes the walk's drift ε₀ (Eq. (6.5)) and "
                    "integrates the steps again with ε₀·t off their headings (Section 6.2).")
    p.add_argument("bag", type=Path, help="the navigator's output bag")
    p.add_argument("--out", type=Path, required=True,
                   help="output directory: a bag with OUT/report.json")
    p.add_argument("--config", type=Path, help="YAML of the drift estimator "
                                               "(pdr_drift.config); default: built in")
    p.add_argument("--floor-height-m", type=float, default=FLOOR_HEIGHT_M,
                   help="height of one floor [m]: the floor of a pose is its height over this")
    p.add_argument("--plot", action="store_true", help="also write OUT/drift.png")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output")
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    summary = run(args.bag, args.out, load_drift_config(args.config), args.floor_height_m,
                  plot=args.plot, overwrite=args.overwrite)
    print_report(summary)
    return 0


def parser() -> argparse.ArgumentParser:
    top = cli_parser("pdr-drift", __doc__)
    sub = top.add_subparsers(dest="command", required=True)
    _add_run(sub)
    return top


def main(argv: Sequence[str] | None = None) -> None:
    dispatch("pdr-drift", parser(), argv)


if __name__ == "__main__":
    main()
