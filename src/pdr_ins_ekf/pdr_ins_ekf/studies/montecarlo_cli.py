"""``pdr-ekf montecarlo``: error growth over N noise realisations of a simulated straight
walk, per error source and estimator (Zampella et al. 2011, Tables I–III).

Estimators: ``ins`` (pure mechanization, :mod:`pdr_ins_ekf.studies.montecarlo`; fitted on the
error the source adds, against the noiseless mechanization) and ``ekf_original``,
``ekf_limited``, ``ekf_retarded`` (the 15-state ZUPT + ZARU EKF with the detector and window
of Zampella et al. 2011, :mod:`pdr_ins_ekf.studies.ekf_montecarlo`; fitted against the truth at
stance samples, t from the first stride, as the paper's tables).

The runs go in batches (``--batch``), here or on a Dask cluster (``--scheduler``); each run's
noise is seeded by its index, so the figures do not depend on the split.
"""
from __future__ import annotations

import argparse
import sys
from dataclasses import fields
from pathlib import Path

from pdr_core.errors import InputError
from pdr_ins_ekf.studies.ekf_montecarlo import (
    ESTIMATORS,
    PUBLISHED_EKF_GROWTH,
    VOTE_WINDOWS,
    XSENS_MTI,
    EkfStudy,
    ekf_study,
    estimator_detector,
    filter_for,
    polynomial_fit,
)
from pdr_ins_ekf.studies.montecarlo import (
    SOURCES,
    ErrorGrowth,
    NoiseLevels,
    ins_study,
    power_law,
    straight_walk,
)
from pdr_sim.simulation import MAX_RATE_HZ, MIN_RATE_HZ

PROFILES = {"xsens_mti": XSENS_MTI}
INS_BATCH_RUNS = 100    # memory: batch × T × 6 doubles of signals
EKF_BATCH_RUNS = 20     # plus a filter history per numba thread
CLI_LEVELS = {"acc_noise": 0.01, "gyro_noise": 1e-3, "acc_bias": 0.01, "gyro_bias": 1e-3}
UNITS = {"acc_noise": "m/s²/√Hz", "gyro_noise": "rad/s/√Hz", "acc_bias": "m/s², σ",
         "gyro_bias": "rad/s, σ"}


def _estimators(text: str) -> list[str]:
    names = text.split(",")
    bad = [n for n in names if n not in ESTIMATORS]
    if bad:
        raise argparse.ArgumentTypeError(f"unknown estimator {bad[0]!r}; choose from "
                                         f"{', '.join(ESTIMATORS)} (comma separated)")
    return names


def add_montecarlo(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "montecarlo", help="Monte-Carlo error growth (Zampella et al. 2011, Tables I-III)",
        description="Process N noisy copies of a noiseless simulated straight walk, one "
                    "error source at a time (or 'combined': all at once), batched over "
                    "runs, with each estimator; fit σ_p(t) and σ_ψ(t) (Eqs. (13)-(14)) with "
                    "c·t^e in log-log. EKF estimators stand --rest-s first to align on.")
    p.add_argument("--source", choices=(*SOURCES, "combined", "all"), default="all",
                   help="all: each source in turn; combined: all sources together")
    p.add_argument("--estimator", type=_estimators, default=["ins"],
                   help=f"comma separated, of {', '.join(ESTIMATORS)}")
    p.add_argument("--runs", type=int, default=200, help="noise realisations, at least 2")
    p.add_argument("--steps", type=int, default=25, help="strides of the walk (1.2 s each)")
    p.add_argument("--rate", type=float, default=100.0, help="sample rate [Hz]")
    p.add_argument("--rest-s", type=float, default=10.0,
                   help="standing before the walk, for the EKF's alignment [s]")
    p.add_argument("--seed", type=int, default=0, help="seed of the noise realisations")
    p.add_argument("--batch", type=int,
                   help=f"runs per batch (default {INS_BATCH_RUNS} for ins, "
                        f"{EKF_BATCH_RUNS} for the EKF); the figures do not depend on it")
    p.add_argument("--scheduler", help="a Dask scheduler's address (tcp://HOST:8786): run "
                                       "the batches on its workers, one numba thread each")
    p.add_argument("--profile", choices=sorted(PROFILES),
                   help="take every level from this IMU (Zampella et al. 2011, section IV-B: "
                        "xsens_mti)")
    for source, default in CLI_LEVELS.items():
        p.add_argument(f"--{source.replace('_', '-')}", type=float, default=default,
                       help=f"[{UNITS[source]}]")
    p.add_argument("--states", type=int, choices=(9, 15), default=15,
                   help="EKF: 15 (ZUPT + ZARU, bias states) or 9 (ZUPT, no bias states)")
    p.add_argument("--no-rest-gyro-bias", dest="rest_gyro_bias", action="store_false",
                   help="EKF: start from a zero gyro bias instead of the mean rate at rest, "
                        "leaving it to ZARU (closer to the filter of Zampella et al. 2011, "
                        "whose yaw drifts with the gyro bias)")
    p.add_argument("--out", type=Path, help="write DIR/fits.csv, fits.md, sigma.csv, "
                                            "growth.png (and consistency.csv for the EKF)")
    p.set_defaults(func=run_montecarlo)


def _levels(args: argparse.Namespace) -> NoiseLevels:
    if args.profile:
        return PROFILES[args.profile]
    values = {}
    for f in fields(NoiseLevels):
        source = next((s for s in SOURCES if f.name.startswith(s)), None)
        if source is not None:
            values[f.name] = getattr(args, source)
    try:
        return NoiseLevels(**values)
    except ValueError as exc:
        name = str(exc).split(" ")[0]
        flag = next(s for s in SOURCES if name.startswith(s)).replace("_", "-")
        raise InputError(f"--{flag}", str(exc)) from None


def _check(args: argparse.Namespace) -> None:
    if args.runs < 2:
        raise InputError("--runs", f"need at least 2 runs, got {args.runs}")
    if args.batch is not None and args.batch < 1:
        raise InputError("--batch", f"need at least 1 run per batch, got {args.batch}")
    if args.steps < 1 or not MIN_RATE_HZ <= args.rate <= MAX_RATE_HZ:
        raise InputError("--steps/--rate", f"need steps >= 1 and a rate in "
                                           f"{MIN_RATE_HZ:g}-{MAX_RATE_HZ:g} Hz")
    if any(e != "ins" for e in args.estimator) and not args.rest_s >= 1:
        raise InputError("--rest-s", f"the EKF aligns on the standing period: need >= 1 s, "
                                     f"got {args.rest_s}")


def _source_noise(levels: NoiseLevels, source: str) -> NoiseLevels:
    if source == "combined":
        return levels
    field = next(f.name for f in fields(NoiseLevels) if f.name.startswith(source))
    return NoiseLevels.only(source, getattr(levels, field))


def run_montecarlo(args: argparse.Namespace) -> int:
    _check(args)
    levels = _levels(args)
    sources = SOURCES if args.source == "all" else (args.source,)
    walks = {}  # the pure INS starts moving; the EKF stands first to align on
    if "ins" in args.estimator:
        walks["ins"] = straight_walk(args.steps, args.rate)
    if any(e != "ins" for e in args.estimator):
        walks["ekf"] = straight_walk(args.steps, args.rate, rest_s=args.rest_s)
    growths: dict[tuple[str, str], ErrorGrowth] = {}
    extra: dict[tuple[str, str], ErrorGrowth] = {}
    checks: dict[tuple[str, str], EkfStudy] = {}
    for estimator in args.estimator:
        for source in sources:
            noise = _source_noise(levels, source)

            def progress(done: int, total: int, label: str = f"{source} {estimator}") -> None:
                print(f"{label}: {done}/{total} runs", file=sys.stderr, flush=True)

            if estimator == "ins":
                study = ins_study(walks["ins"], noise, args.runs, args.seed,
                                  args.batch or INS_BATCH_RUNS, progress=progress,
                                  scheduler=args.scheduler)
                growths[source, estimator] = study.noise_only
                extra[source, estimator] = study.against_truth
            else:
                study = ekf_study(walks["ekf"], noise, args.runs, estimator_detector(estimator),
                                  filter_for(levels, states=args.states), args.seed,
                                  args.batch or EKF_BATCH_RUNS, progress=progress,
                                  rest_gyro_bias=args.rest_gyro_bias,
                                  scheduler=args.scheduler)
                growths[source, estimator] = study.growth
                checks[source, estimator] = study
    rows = fits_rows(growths)
    print(fits_markdown(rows, growths), end="")
    if args.out:
        write_outputs(args, rows, growths, extra, checks)
    return 0


def fits_rows(growths: dict[tuple[str, str], ErrorGrowth]) -> list[dict]:
    """Rows of fits.csv: c, e of σ ≈ c·tᵉ per source, estimator and quantity."""
    rows = []
    for (source, estimator), growth in growths.items():
        for quantity, sigma in (("sigma_p", growth.sigma_p_m),
                                ("sigma_yaw", growth.sigma_yaw_rad)):
            coefficient, exponent = power_law(growth.t_s, sigma)
            rows.append({"source": source, "estimator": estimator, "quantity": quantity,
                         "coefficient": coefficient, "exponent": exponent})
    return rows


def fits_markdown(rows: list[dict], growths: dict[tuple[str, str], ErrorGrowth]) -> str:
    """The power-law table, then for the EKF the a·t + b·t² fits next to Zampella et al.
    2011, Tables II–III."""
    text = ("| source | estimator | quantity | coefficient | exponent |\n|---|---|---|---|---|\n"
            + "".join(f"| {r['source']} | {r['estimator']} | {r['quantity']} | "
                      f"{r['coefficient']:.4g} | {r['exponent']:.3f} |\n" for r in rows))
    paper = [(key, g) for key, g in growths.items()
             if key[1] != "ins" and key[0] in PUBLISHED_EKF_GROWTH["sigma_p"]]
    if paper:
        text += ("\n| source | estimator | quantity | ours: a·t + b·t² | Zampella et al. 2011 |\n"
                 "|---|---|---|---|---|\n")
        for (source, estimator), growth in paper:
            window = VOTE_WINDOWS.index(estimator.removeprefix("ekf_"))
            for quantity, sigma in (("sigma_p", growth.sigma_p_m),
                                    ("sigma_yaw", growth.sigma_yaw_rad)):
                a, b = polynomial_fit(growth.t_s, sigma)
                text += (f"| {source} | {estimator} | {quantity} | {a:.2g}·t + {b:.2g}·t² | "
                         f"{PUBLISHED_EKF_GROWTH[quantity][source][window]} |\n")
    return text


def write_outputs(args: argparse.Namespace, rows: list[dict], growths: dict,
                  extra: dict, checks: dict) -> None:
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    (out / "fits.md").write_text(fits_markdown(rows, growths))
    (out / "fits.csv").write_text(
        "source,estimator,quantity,coefficient,exponent\n" + "".join(
            f"{r['source']},{r['estimator']},{r['quantity']},{r['coefficient']:.6g},"
            f"{r['exponent']:.6g}\n" for r in rows))
    lines = ["source,estimator,t_s,sigma_p_m,sigma_yaw_rad,sigma_p_vs_truth_m,"
             "sigma_yaw_vs_truth_rad"]
    for (source, estimator), own in growths.items():
        truth = extra.get((source, estimator), own)
        lines += [f"{source},{estimator},{t:.6g},{a:.6g},{b:.6g},{c:.6g},{d:.6g}"
                  for t, a, b, c, d in zip(own.t_s, own.sigma_p_m, own.sigma_yaw_rad,
                                           truth.sigma_p_m, truth.sigma_yaw_rad, strict=True)]
    (out / "sigma.csv").write_text("\n".join(lines) + "\n")
    if checks:
        lines = ["source,estimator,t_s,sigma_p_m,predicted_sigma_p_m,predicted_sigma_p_q05_m,"
                 "predicted_sigma_p_q95_m,sigma_yaw_rad,predicted_sigma_yaw_rad,nees_position"]
        for (source, estimator), study in checks.items():
            g, c = study.growth, study.consistency
            lines += [",".join([source, estimator] + [f"{x:.6g}" for x in row])
                      for row in zip(g.t_s, g.sigma_p_m, c.sigma_p_m, c.sigma_p_q05_m,
                                     c.sigma_p_q95_m, g.sigma_yaw_rad, c.sigma_yaw_rad,
                                     c.nees_position, strict=True)]
        (out / "consistency.csv").write_text("\n".join(lines) + "\n")
    from pdr_ins_ekf.studies import plots  # Matplotlib: imported only to draw

    labelled = {f"{s} {e}": g for (s, e), g in growths.items()}
    plots.error_growth_png(labelled, out / "growth.png",
                           f"{args.runs} runs, {args.steps}-stride walk, "
                           f"{', '.join(args.estimator)}")
    written = "fits.csv, fits.md, sigma.csv, growth.png" + (", consistency.csv" if checks
                                                             else "")
    print(f"wrote {out}/{{{written}}}")
