"""``pdr-ekf``: offline tools of the foot-mounted INS (no ROS graph needed).

Subcommands:
    study mechanization   pure-INS position error per attitude method and rate
                          (000_fbd401126d10f515.txt, Fig. 6): table, CSV and PNG.

Errors in the input exit with status 2 and one line naming the problem.
"""
from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from pdr_core.errors import InputError, run_cli
from pdr_ins_ekf import plots
from pdr_ins_ekf.attitude_update import METHODS
from pdr_ins_ekf.mechanization_study import RATES_HZ, run_study
from pdr_ins_ekf.strapdown import INTEGRATIONS
from pdr_sim.simulation import MAX_RATE_HZ, MIN_RATE_HZ


def _add_study(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("study", help="reproduce the studies of the papers")
    studies = p.add_subparsers(dest="study", required=True)
    m = studies.add_parser(
        "mechanization", help="attitude methods against sample rate (000, Fig. 6)",
        description="Mechanize a noiseless simulated 10-stride walk with every attitude "
                    "method (Padé [1,1], [2,2], [3,3], Eq. (12), expm, quaternion) at each "
                    "rate and report the final position error.")
    m.add_argument("--rates", type=lambda s: [float(x) for x in s.split(",")],
                   default=list(RATES_HZ), help="sample rates [Hz], comma separated")
    m.add_argument("--integration", choices=INTEGRATIONS, default="trapezoidal")
    m.add_argument("--out", type=Path, help="write DIR/mechanization.csv and .png")
    m.set_defaults(func=_run_mechanization)


def _run_mechanization(args: argparse.Namespace) -> int:
    bad = [r for r in args.rates if not MIN_RATE_HZ <= r <= MAX_RATE_HZ]
    if bad:
        raise InputError("--rates", f"{bad[0]:g} Hz is outside {MIN_RATE_HZ:g}-{MAX_RATE_HZ:g} Hz")
    study = run_study(tuple(args.rates), METHODS, args.integration)
    print(study.table())
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "mechanization.csv").write_text(study.csv())
        plots.mechanization_png(study, args.out / "mechanization.png")
        print(f"wrote {args.out / 'mechanization.csv'} and {args.out / 'mechanization.png'}")
    return 0


def parser() -> argparse.ArgumentParser:
    top = argparse.ArgumentParser(prog="pdr-ekf", description=__doc__.split("\n")[0])
    sub = top.add_subparsers(dest="command", required=True)
    _add_study(sub)
    return top


def _main(argv: Sequence[str] | None) -> int:
    args = parser().parse_args(argv)
    return args.func(args)


def main(argv: Sequence[str] | None = None) -> None:
    sys.exit(run_cli("pdr-ekf", _main, argv))


if __name__ == "__main__":
    main()
