"""The study subcommands of ``pdr-ekf``: ``montecarlo``, ``analytic``, ``study mechanization``
and ``study sweep``. They reproduce the papers' error analyses with the navigator's own
kernels; :func:`add_study_commands` registers them on the ``pdr-ekf`` parser.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from pdr_core.errors import InputError
from pdr_ins_ekf.attitude_update import METHODS
from pdr_ins_ekf.strapdown import INTEGRATIONS
from pdr_ins_ekf.studies.analytic_cli import add_analytic, add_sweep
from pdr_ins_ekf.studies.mechanization_study import RATES_HZ, run_study
from pdr_ins_ekf.studies.montecarlo_cli import add_montecarlo
from pdr_sim.simulation import MAX_RATE_HZ, MIN_RATE_HZ


def add_study_commands(sub: argparse._SubParsersAction) -> None:
    """Add ``montecarlo``, ``analytic`` and ``study`` to the ``pdr-ekf`` subcommands."""
    add_montecarlo(sub)
    add_analytic(sub)
    _add_study(sub)


def _add_study(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("study", help="reproduce the studies of the papers")
    studies = p.add_subparsers(dest="study", required=True)
    m = studies.add_parser(
        "mechanization", help="attitude methods against sample rate (Zampella et al. 2011, Fig. 6)",
        description="Mechanize a noiseless simulated 10-stride walk with every attitude "
                    "method (Padé [1,1], [2,2], [3,3], Eq. (12), expm, quaternion) at each "
                    "rate and report the final position error.")
    m.add_argument("--rates", type=lambda s: [float(x) for x in s.split(",")],
                   default=list(RATES_HZ), help="sample rates [Hz], comma separated")
    m.add_argument("--integration", choices=INTEGRATIONS, default="trapezoidal",
                   help="the angular rate over each sample interval: the mean of its two "
                        "samples (trapezoidal) or the later (rectangular)")
    m.add_argument("--out", type=Path, help="write DIR/mechanization.csv and .png")
    m.set_defaults(func=_run_mechanization)
    add_sweep(studies)


def _run_mechanization(args: argparse.Namespace) -> int:
    bad = [r for r in args.rates if not MIN_RATE_HZ <= r <= MAX_RATE_HZ]
    if bad:
        raise InputError("--rates", f"{bad[0]:g} Hz is outside {MIN_RATE_HZ:g}-{MAX_RATE_HZ:g} Hz")
    study = run_study(tuple(args.rates), METHODS, args.integration)
    print(study.table())
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "mechanization.csv").write_text(study.csv())
        from pdr_ins_ekf.studies import plots
        plots.mechanization_png(study, args.out / "mechanization.png")
        print(f"wrote {args.out / 'mechanization.csv'} and {args.out / 'mechanization.png'}")
    return 0
