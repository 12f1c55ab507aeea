"""``pdr-ekf analytic`` and ``pdr-ekf study sweep``: the closed-form ZUPT error levels of
Wang et al. 2020, section III (:mod:`pdr_ins_ekf.studies.zupt_error_model`), in the
paper's units at the edge, and their check against the EKF (section IV-A,
:mod:`pdr_ins_ekf.studies.error_sweep`).

Defaults: the VN-200 of the paper (ARW 0.21 °/√h, VRW 0.14 mg/√Hz, RRW 0.048 °/s/√h) at
800 Hz with r = 0.02 m/s, a_c = 0.84 and the paper's simulated walk (100 strides, 77 m,
53.6 s: t_stride 0.536 s, s_N 0.77 m); the paper gives no stance time, 0.2 s is the
stance of :data:`pdr_ins_ekf.studies.error_sweep.SWEEP_STEP`.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from pdr_core import units
from pdr_core.errors import InputError
from pdr_ins_ekf.studies.zupt_error_model import Gait, NoiseDensities, ZuptErrorModel

DEFAULT_TIMES_S = (10.0, 53.6, 100.0)
DENSITY_ARGS = ("arw_deg_per_sqrt_h", "vrw_mg_per_sqrt_hz", "rrw_deg_per_s_per_sqrt_h")


def _floats(text: str) -> list[float]:
    try:
        return [float(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}"
                                         ) from None


def add_analytic(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "analytic", help="closed-form ZUPT error levels (Wang et al. 2020, Eqs. (38)-(57))",
        description="Steady σ_v (Eq. (44)), σ_θ (Eq. (50)) and σ_gN (Eq. (48)) of a ZUPT-aided "
                    "foot INS, and σ_∥ (Eq. (56)), σ_⊥ (Eq. (57)) and σ_ψ (Eq. (38)) at "
                    "the given times. Defaults: VN-200 at 800 Hz (Wang et al. 2020, section IV).")
    p.add_argument("--arw-deg-per-sqrt-h", type=float, default=0.21,
                   help="gyroscope angular random walk [°/√h]")
    p.add_argument("--vrw-mg-per-sqrt-hz", type=float, default=0.14,
                   help="accelerometer velocity random walk [mg/√Hz]")
    p.add_argument("--rrw-deg-per-s-per-sqrt-h", type=float, default=0.048,
                   help="gyroscope rate random walk [°/s/√h]")
    p.add_argument("--zupt-sigma-mps", type=float, default=0.02,
                   help="velocity uncertainty r of the ZUPT [m/s]")
    p.add_argument("--rate-hz", type=float, default=800.0, help="f_s [Hz]")
    p.add_argument("--t-stance-s", type=float, default=0.2,
                   help="stance duration of a stride [s]")
    p.add_argument("--t-stride-s", type=float, default=0.536, help="stride duration [s]")
    p.add_argument("--cos-pitch-mean", type=float, default=0.84,
                   help="a_c, the gait-cycle mean of cos θ of the foot pitch (dimensionless)")
    p.add_argument("--sin-pitch-mean", type=float, default=0.0,
                   help="a_s, the gait-cycle mean of sin θ of the foot pitch (dimensionless)")
    p.add_argument("--stride-m", type=float, default=0.77, help="s_N [m]")
    p.add_argument("--times", type=_floats, default=list(DEFAULT_TIMES_S),
                   help="navigation times [s], comma separated")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run_analytic)


def model_from_args(args: argparse.Namespace) -> ZuptErrorModel:
    """The model of the command line, SI inside; a bad value is an InputError."""
    for name in DENSITY_ARGS:
        value = getattr(args, name)
        if not np.isfinite(value) or value < 0:
            raise InputError(f"--{name.replace('_', '-')}",
                             f"a noise density must be finite and >= 0, got {value}")
    try:
        noise = NoiseDensities(units.arw_to_si(args.arw_deg_per_sqrt_h),
                               units.mg_to_si(args.vrw_mg_per_sqrt_hz),
                               units.rrw_to_si(args.rrw_deg_per_s_per_sqrt_h))
        gait = Gait(args.t_stance_s, args.t_stride_s, args.cos_pitch_mean,
                    args.sin_pitch_mean, args.stride_m)
        return ZuptErrorModel(noise, gait, args.zupt_sigma_mps, args.rate_hz)
    except ValueError as exc:
        name = str(exc).split(" ")[0]
        source = (f"--{name.replace('_', '-')}" if name in vars(args)
                  else "--t-stance-s/--rate-hz")
        raise InputError(source, str(exc)) from None


def run_analytic(args: argparse.Namespace) -> int:
    model = model_from_args(args)
    try:
        times = np.asarray(args.times, float)
        steady = model.steady_state()
        result = {"sigma_v_mps": steady.sigma_v_mps, "sigma_theta_rad": steady.sigma_theta_rad,
                  "sigma_gN_radps": steady.sigma_gn_radps, "times_s": times.tolist(),
                  "sigma_par_m": model.sigma_par_m(times).tolist(),
                  "sigma_perp_m": model.sigma_perp_m(times).tolist(),
                  "sigma_yaw_rad": model.sigma_yaw_rad(times).tolist()}
    except ValueError as exc:
        raise InputError("--times", str(exc)) from None
    if args.json:
        print(json.dumps(result))
        return 0
    print(f"σ_v  = {steady.sigma_v_mps * 1e3:.4g} mm/s   (Eq. 44)\n"
          f"σ_θ  = {np.degrees(steady.sigma_theta_rad):.4g} °      (Eq. 50)\n"
          f"σ_gN = {np.degrees(steady.sigma_gn_radps) * 3600:.4g} °/h    (Eq. 48)\n\n"
          "|   t [s] | σ_∥ [m] (56) | σ_⊥ [m] (57) | σ_ψ [°] (38) |\n"
          "|---:|---:|---:|---:|")
    for row in zip(times, result["sigma_par_m"], result["sigma_perp_m"],
                   result["sigma_yaw_rad"], strict=True):
        print(f"| {row[0]:g} | {row[1]:.4g} | {row[2]:.4g} | {np.degrees(row[3]):.4g} |")
    return 0


def add_sweep(studies: argparse._SubParsersAction) -> None:
    p = studies.add_parser(
        "sweep", help="analytic against simulated error levels (Wang et al. 2020, Figs. 3-6)",
        description="Sweep ARW (0.01-10 °/√h), VRW (0.01-10 mg/√Hz) and RRW (0.6-600 "
                    "mdeg/s/√h) on the paper's 100-stride walk at 800 Hz, comparing the "
                    "closed-form σ_v, σ_θ, σ_∥ and σ_⊥ with the ZUPT EKF's covariance (and "
                    "the Monte-Carlo spread of the final position).")
    p.add_argument("--points", type=int, default=7, help="values per swept parameter")
    p.add_argument("--runs", type=int, default=10,
                   help="Monte-Carlo runs per value (0: covariance only)")
    p.add_argument("--steps", type=int, default=100, help="strides of the walk")
    p.add_argument("--seed", type=int, default=0, help="seed of the Monte-Carlo runs")
    p.add_argument("--scheduler", help="a Dask scheduler's address (tcp://HOST:8786): run "
                                       "the Monte-Carlo batches on its workers")
    p.add_argument("--out", type=Path, help="write DIR/sweep.csv, sweep.md and sweep.png")
    p.set_defaults(func=run_sweep)


def run_sweep(args: argparse.Namespace) -> int:
    from pdr_ins_ekf.studies import error_sweep, plots  # heavy (simulator, SciPy, Matplotlib)

    if args.points < 2 or args.steps < 3 or args.runs < 0 or args.runs == 1:
        raise InputError("--points/--steps/--runs", "need points >= 2, steps >= 3 and runs "
                                                    "0 or >= 2")
    walk = error_sweep.paper_walk(args.steps)
    gait = error_sweep.gait_of(walk)
    points = []
    for parameter in error_sweep.RANGES:
        for value in error_sweep.sweep_values(parameter, args.points):
            points.append(error_sweep.sweep_point(walk, gait, parameter, float(value),
                                                  args.runs, args.seed,
                                                  scheduler=args.scheduler))
            print(f"{parameter} = {value:.3g} {error_sweep.UNITS[parameter]}: done",
                  file=sys.stderr, flush=True)
    table = error_sweep.sweep_markdown(points, gait)
    print(table, end="")
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "sweep.md").write_text(table)
        (args.out / "sweep.csv").write_text(error_sweep.sweep_csv(points))
        plots.sweep_png(points, args.out / "sweep.png")
        print(f"wrote {args.out}/{{sweep.csv, sweep.md, sweep.png}}")
    return 0
