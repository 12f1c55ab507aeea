"""``pdr-pocket``: offline tools of the pocket navigator (no ROS graph needed).

Subcommands:
    run BAG --out OUT           the whole navigator (Muñoz Díaz 2016, chapters 3, 4 and 6):
                                OUT/ as a bag with pdr/pocket/attitude, gyro_bias, step,
                                pose and path, OUT/report.json, with --plot OUT/path.png.
    evaluate RUN_OUT            the report of a run's output against a truth given
                                afterwards: --truth BAG (ground_truth/step and pose),
                                --truth-steps CSV (true footfall or gait cycle times),
                                --distance-m D (a known walked distance).
    attitude BAG --out OUT      the orientation filter (Muñoz Díaz 2016, chapter 3) on
                                imu/data and imu/mag: OUT/ as a bag with
                                pdr/pocket/attitude and pdr/pocket/gyro_bias at every
                                sample, OUT/report.json, and with --plot OUT/attitude.png.
    calibrate-step BAG --distance-m D
                                b_H of the stride line (Eq. (4.2)) from a walk of known
                                length (a_H too with --fit-slope and walks at two speeds).
    calibrate-step --foot FOOT --pocket POCKET --out FIT
                                the person's stride and riser lines (Eqs. (4.2), (4.4),
                                (4.5)) from a foot INS on the same walk (Section 7.3):
                                the saved fit run --step-calibration takes.
    table-steps BAG...          Table 4.1 on simulated bags: the pitch maximum and the
                                three baseline detectors, undetected and false steps.
    table-stride BAG...         Table 4.4: the distance error of the pitch line, and of the
                                frequency and Weinberg models calibrated on the first bag.
    calibrate-mag BAG|CSV       ellipsoid fit of raw magnetometer readings (Section 3.4.4):
                                writes the YAML the filter loads, prints the residual and
                                the sphere coverage, draws the raw cloud and the sphere.

Errors in the input exit with status 2 and one line naming the file and the problem.
``run`` on a phone that is not in a trouser pocket (held in the hand: its pitch does not
swing once every two footfalls, pdr_pocket.placement) says so on the first line of its
output, ``pdr-pocket: refused: BAG: not in a pocket: WHY``, writes OUT/report.json
(``refused`` true, no step) and the attitude but no step, pose or path, and exits with
status 3: a refusal, told apart from bad input (2) and a crash (1). Input no walk gives
(a median |f| beyond 0.5-2.5 g, a pitch swing over twice a thigh's) is a warning on the
first line, with --strict an error (status 2).
"""
from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pdr_core import topics
from pdr_core.errors import InputError, cli_parser, dispatch
from pdr_core.evaluation.metrics import truth_orientation_at
from pdr_core.io.bag import BagReader, BagWriter, add_strict_option
from pdr_core.io.csv_import import MAG_UNITS_T, implausible, refuse_implausible
from pdr_core.io.csv_table import read_columns
from pdr_core.report_files import print_report, write_report, write_report_file
from pdr_core.sensors.imu_checks import FIELD_RANGE, median_field_t
from pdr_core.sensors.magnetic_field import homogeneous
from pdr_core.walking.walk_plausibility import EXIT_REFUSED
from pdr_pocket.config import load_pocket_config
from pdr_pocket.evaluation import STEPS_PER
from pdr_pocket.inputs import read_pocket_bag
from pdr_pocket.magnetometer import MIN_COVERAGE, calibrate
from pdr_pocket.messages import attitude_batches
from pdr_pocket.orientation import OrientationFilter
from pdr_pocket.orientation_config import orientation_from_allan
from pdr_pocket.run_report import attitude_errors, attitude_report, truth_heading_error


def _add_navigator_options(p: argparse.ArgumentParser) -> None:
    """The bag, --out, --config, --mag-calibration, --overwrite and --strict of run and
    attitude."""
    p.add_argument("bag", type=Path, help="bag with imu/data (and imu/mag, and the truth "
                                          "topics of a simulated walk)")
    p.add_argument("--out", type=Path, required=True,
                   help="output directory: a bag with OUT/report.json")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output")
    p.add_argument("--config", type=Path, help="YAML configuration (pdr_pocket.config); "
                                               "default: the installed config/pocket_pdr.yaml")
    p.add_argument("--mag-calibration", type=Path,
                   help="YAML of pdr-pocket calibrate-mag (overrides the configuration's)")
    add_strict_option(p)


def _add_attitude(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "attitude", help="the orientation filter on a bag",
        description="Run the orientation UKF (Muñoz Díaz 2016, chapter 3) on imu/data and "
                    "imu/mag. Writes OUT/ as a bag with pdr/pocket/attitude (sensor_msgs/Imu "
                    "with orientation and covariance) and pdr/pocket/gyro_bias, and "
                    "OUT/report.json (roll/pitch/yaw RMSE against ground_truth/pose and the "
                    "final bias errors when the bag has the truth, the share of samples "
                    "each update ran).")
    _add_navigator_options(p)
    p.add_argument("--allan", type=Path, help="take the gyroscope noise from this allan.csv "
                                              "of pdr-sim allan")
    p.add_argument("--plot", action="store_true", help="also write OUT/attitude.png")
    p.set_defaults(func=_run_attitude)


def _run_attitude(args: argparse.Namespace) -> int:
    config = load_pocket_config(args.config)
    orientation = config.orientation
    if args.allan:
        orientation = orientation_from_allan(args.allan, orientation)
    reader, batches, inputs = read_pocket_bag(
        args.bag, args.mag_calibration or config.magnetometer_calibration, strict=args.strict)
    filt = OrientationFilter(orientation)
    estimate = filt.run(inputs.t, inputs.gyro, inputs.accel, inputs.mag)
    truth = truth_orientation_at(batches[topics.GROUND_TRUTH_POSE], inputs.stamp_ns) \
        if topics.GROUND_TRUTH_POSE in batches else None
    record = reader.custom_data("pdr.simulation") or {}
    true_bias = record.get("true_gyro_bias_radps")
    report = attitude_report(inputs, estimate, truth, true_bias)
    with BagWriter(args.out, overwrite=args.overwrite) as writer:
        writer.write_merged(attitude_batches(inputs, estimate, filt.gyro_noise_var))
        write_report(writer.staging, report)
        if args.plot:
            from pdr_pocket import plots
            errors = None if truth is None else np.degrees(attitude_errors(estimate, truth))
            heading = None if truth is None else np.degrees(truth_heading_error(estimate, truth))
            plots.attitude_png(estimate, errors, heading,
                               None if true_bias is None else np.degrees(true_bias),
                               writer.staging / "attitude.png", str(args.bag))
    print_report(report)
    return 0


def _add_run(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "run", help="the pocket navigator on a bag",
        description="Steps, activities, stride, stairs and the 3D position from imu/data and "
                    "imu/mag (Muñoz Díaz 2016, chapters 3, 4 and 6). Writes OUT/ as a bag "
                    "with pdr/pocket/attitude and gyro_bias at every sample, pdr/pocket/step "
                    "and pose at every step and pdr/pocket/path at the end, and "
                    "OUT/report.json: steps, distance, height and floors, and with the "
                    "simulator's truth the steps missed and false, the activity confusion, "
                    "the distance and riser errors and the trajectory metrics of "
                    "docs/reports.md.")
    _add_navigator_options(p)
    p.add_argument("--drift", choices=("none", "online", "offline"), default="none",
                   help="landmark drift corrections (Sections 6.1-6.2): online, applied at "
                        "each association as pocket_pdr's service does, or offline, a "
                        "second pass from the walk's drift ε₀")
    p.add_argument("--drift-config", type=Path,
                   help="YAML of the drift estimator (pdr_drift.config); default: built in")
    p.add_argument("--plot", action="store_true", help="also write OUT/path.png")
    p.add_argument("--step-calibration", type=Path, metavar="FIT_YAML",
                   help="the person's stride and riser lines, YAML of pdr-pocket "
                        "calibrate-step --foot: each line fitted replaces the configured "
                        "one, a line not walked keeps it (overrides the configuration's "
                        "step_calibration)")
    p.set_defaults(func=_run_navigator)


def _run_navigator(args: argparse.Namespace) -> int:
    from pdr_pocket.pocket_offline import PocketOptions, run

    options = PocketOptions(args.config, args.mag_calibration, args.drift, args.drift_config,
                            args.strict, args.plot, args.overwrite, args.step_calibration)
    report = run(args.bag, options, args.out)
    if report["refused"]:
        print(f"pdr-pocket: refused: {args.bag}: {report['placement']['placement']}: "
              f"{report['placement']['why']}; no step written", file=sys.stderr)
    _print_report(report, f"{args.bag}: ")
    return EXIT_REFUSED if report["refused"] else 0


def _print_report(report: dict, source: str = "") -> None:
    """Each of the report's warnings as one stderr line, after ``source`` (the file it is
    about, when the warnings do not name it), then the report as JSON on stdout."""
    for warning in report["warnings"]:
        print(f"pdr-pocket: warning: {source}{warning}", file=sys.stderr)
    sys.stderr.flush()
    print_report(report)


def _add_evaluate(sub: argparse._SubParsersAction) -> None:
    from pdr_core.units import TIME_UNITS_S
    from pdr_pocket.evaluation import TRUTH_STEPS_FORMATS, TRUTH_STEPS_TIMES

    p = sub.add_parser(
        "evaluate", help="the report of a run's output against a truth",
        description="The report of a pdr-pocket run output against a truth given "
                    "afterwards (the fields of docs/reports.md): with --truth, a bag's "
                    "ground_truth/step (steps matched, missed and false, activities, "
                    "distance and riser errors: the figures pdr-pocket run gives when its "
                    "input holds that truth) and ground_truth/pose (the trajectory errors), "
                    "timed from each bag's first imu/data message; with --truth-steps, a "
                    "CSV (header optional) of true times, one row per footfall of either "
                    "foot (or per gait cycle of the sensor leg with --truth-steps-per "
                    "cycle), or a foot switch's log (time, left, right: each 0→1 edge a "
                    "footfall, --truth-steps-format foot-switch), "
                    "compared by count with the run's footfalls (or steps), its times "
                    "from the input's first imu/data message or on its stamps "
                    "(--truth-steps-time); with --distance-m, the distance walked against "
                    "a known one. Prints the report; --out writes it too.")
    p.add_argument("run_out", type=Path, metavar="RUN_OUT",
                   help="the output directory of pdr-pocket run")
    p.add_argument("--truth", type=Path, metavar="BAG",
                   help="bag with ground_truth/step and/or ground_truth/pose (a simulated "
                        "walk, or a CSV log imported with --pos-cols)")
    p.add_argument("--truth-steps", type=Path, metavar="CSV",
                   help="CSV of the true step times (--truth-steps-format times) or a foot "
                        "switch's log (foot-switch), header optional")
    p.add_argument("--truth-steps-format", choices=TRUTH_STEPS_FORMATS, default="times",
                   help="what --truth-steps holds: times, one true time a row (of what: "
                        "--truth-steps-per); foot-switch, the columns time, left and right, "
                        "each foot's contact 0 or 1, every 0→1 edge of either a footfall")
    p.add_argument("--truth-steps-time", choices=TRUTH_STEPS_TIMES, default="from-start",
                   help="the time axis of --truth-steps: from-start, from the input bag's "
                        "first imu/data message (the t_s of pdr-sim export-csv, the shared "
                        "thigh recordings' step_times.csv); stamps, on the input bag's "
                        "message stamps, where pdr-sim import-csv put the CSV log's time "
                        "column (read in its --time-unit, plus its --time-offset-s)")
    p.add_argument("--truth-steps-unit", choices=sorted(TIME_UNITS_S), default="s",
                   help="unit of the --truth-steps times: s, ms, us (µs) or ns, as "
                        "pdr-sim import-csv --time-unit")
    p.add_argument("--truth-steps-cols", metavar="COLS",
                   help="the columns of --truth-steps, header names or 0-based indices: "
                        "the time (default 0); with foot-switch time,left,right (default "
                        "0,1,2)")
    p.add_argument("--truth-steps-per", choices=STEPS_PER, default="footfall",
                   help="what one row of --truth-steps is: a footfall of either foot (a "
                        "foot switch, the shared thigh recordings' step_times.csv) or a "
                        "gait cycle of the sensor leg (pdr-sim export-csv --steps-out)")
    p.add_argument("--distance-m", type=float,
                   help="the walked distance, known [m]: the error of the sum of the strides")
    p.add_argument("--out", type=Path, metavar="REPORT_JSON",
                   help="also write the report to this file")
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out")
    add_strict_option(p)
    p.set_defaults(func=_run_evaluate)


def _run_evaluate(args: argparse.Namespace) -> int:
    from pdr_pocket.evaluation import TruthStepsFormat, evaluate

    if args.out is not None and args.out.exists() and not args.overwrite:
        raise InputError(args.out, "output exists already (remove it or pass --overwrite)")
    cols = () if args.truth_steps_cols is None else tuple(
        c.strip() for c in args.truth_steps_cols.split(","))
    steps_format = TruthStepsFormat(args.truth_steps_format, args.truth_steps_time,
                                    args.truth_steps_unit, cols)
    report = evaluate(args.run_out, args.truth, args.truth_steps, args.truth_steps_per,
                      args.distance_m, steps_format=steps_format, strict=args.strict)
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        write_report_file(args.out, report)
    _print_report(report)
    return 0


def _add_calibrate_step(sub: argparse._SubParsersAction) -> None:
    from pdr_pocket.line_calibration import CalibrationSettings

    p = sub.add_parser(
        "calibrate-step", help="fit the person's stride line from walks of known length, "
                               "or their stride and riser lines from a foot INS",
        description="The stride line s = a_H·Δθ + b_H (Muñoz Díaz 2016, Eq. (4.2), Section "
                    "4.2.3), two ways. From walks of known length (BAG... --distance-m D): "
                    "b_H with the universal a_H from a walk at a comfortable speed, or with "
                    "--fit-slope both from two or more walks at different speeds; writes the "
                    "person's YAML (its step_length section), to pass as --config, and "
                    "refuses walks too short or too uniform, saying why. From a foot INS "
                    "worn on the same walk (--foot FOOT --pocket POCKET, Section 7.3): the "
                    "pocket's steps (pdr/pocket/step of pdr-pocket run --out) paired by "
                    "their stamps with the foot's strides (pdr/foot/step of pdr-ekf run "
                    "--out), what is not one cycle of one line walked by both refused, the "
                    "level line and the stairs lines (Eqs. (4.4), (4.5)) by recursive least "
                    "squares from the configured lines; writes the saved fit, to pass as "
                    "pdr-pocket run --step-calibration (docs/pocket.md), and prints each "
                    "line's pairs, slope, offset and 1σ and the refusals by reason.")
    p.add_argument("bags", type=Path, nargs="*", metavar="BAG",
                   help="bags of walks of known length (imu/data, imu/mag)")
    p.add_argument("--distance-m",
                   help="the length of each walk [m], comma-separated in the bags' order")
    p.add_argument("--fit-slope", action="store_true", help="fit a_H too (walks of known "
                                                            "length; --foot always does)")
    p.add_argument("--foot", type=Path, metavar="FOOT",
                   help="a bag with the foot INS's pdr/foot/step: the output of pdr-ekf run "
                        "--out on the foot IMU of the walk")
    p.add_argument("--pocket", type=Path, metavar="POCKET",
                   help="a bag with the pocket's pdr/pocket/step: the output of pdr-pocket "
                        "run --out on the phone of the same walk (default: the --foot bag, "
                        "when it holds both topics)")
    p.add_argument("--forgetting", type=float, default=CalibrationSettings.forgetting,
                   help="λ of the recursive least squares with --foot, dimensionless "
                        "within (0, 1]: a memory of about 1/(1 − λ) pairs")
    p.add_argument("--height-m", type=float,
                   help="the person's height [m] with --foot: bounds the foot strides "
                        "taken (default: the configuration's person.height_m, else the "
                        "population's adult)")
    p.add_argument("--config", type=Path, help="YAML configuration (default: the installed "
                                               "one); its a_H is kept without --fit-slope, "
                                               "its lines are the priors with --foot")
    p.add_argument("--out", type=Path, required=True,
                   help="the person's YAML to write (with --foot, the saved fit)")
    p.set_defaults(func=_run_calibrate_step)


def _run_calibrate_step(args: argparse.Namespace) -> int:
    foot_options = [name for name, given in (("--pocket", args.pocket is not None),
                                             ("--height-m", args.height_m is not None))
                    if given]
    if args.foot is None:
        if not args.bags:
            raise InputError("calibrate-step", "give walks of known length (BAG... "
                                               "--distance-m D) or a foot INS's strides "
                                               "(--foot FOOT --pocket POCKET)")
        if foot_options:
            raise InputError(foot_options[0], "goes with --foot")
        return _calibrate_from_distances(args)
    if args.bags or args.distance_m is not None or args.fit_slope:
        raise InputError("--foot", "one way at a time: walks of known length (BAG... "
                                   "--distance-m D) or a foot INS (--foot), not both")
    return _calibrate_from_foot(args)


def _calibrate_from_distances(args: argparse.Namespace) -> int:
    import yaml

    from pdr_pocket.step_length import fit_line, fit_offset
    from pdr_pocket.studies.tables import level_amplitudes

    if args.distance_m is None:
        raise InputError("--distance-m", "the length of each walk is needed with BAG...")
    try:
        distances = [float(d) for d in args.distance_m.split(",")]
    except ValueError:
        raise InputError("--distance-m", f"expected numbers, got {args.distance_m!r}") from None
    if len(distances) != len(args.bags) or min(distances) <= 0:
        raise InputError("--distance-m", f"one positive length per bag ({len(args.bags)}), "
                                         f"got {args.distance_m!r}")
    config = load_pocket_config(args.config)
    amplitudes = [level_amplitudes(bag, config) for bag in args.bags]
    where = ", ".join(str(b) for b in args.bags)
    if args.fit_slope:
        segment = np.concatenate([np.full(len(a), i) for i, a in enumerate(amplitudes)])
        a_h, b_h = fit_line(np.concatenate(amplitudes), segment, np.array(distances), where)
    else:
        a_h = config.step_length.a_h_m_per_deg
        b_h = fit_offset(np.concatenate(amplitudes), sum(distances), a_h, where)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("# The person's stride line (pdr-pocket calibrate-step), Eq. (4.2)\n" +
                        yaml.safe_dump({"step_length": {"a_h_m_per_deg": round(float(a_h), 6),
                                                        "b_h_m": round(float(b_h), 6),
                                                        "calibrated": True}}))
    steps = sum(len(a) for a in amplitudes)
    print(f"{where}: {steps} level steps, mean pitch amplitude "
          f"{np.mean(np.concatenate(amplitudes)):.1f} deg\n"
          f"a_H {a_h:.5f} m/deg{' (fitted)' if args.fit_slope else ' (kept)'}  b_H {b_h:.4f} m"
          f"\nwrote {args.out}")
    return 0


def _step_batch(path: Path, topic: str):
    """The pdr_msgs/Step messages of ``topic`` in the bag ``path``; InputError naming the
    bag when it has none."""
    batch = BagReader(path).read(topic)     # InputError for a bag without it
    if len(batch) == 0:
        raise InputError(path, f"{topic} has no messages")
    return batch


def _calibrate_from_foot(args: argparse.Namespace) -> int:
    from pdr_pocket.line_calibration import (
        LEVEL,
        CalibrationSettings,
        StrideCalibrator,
        calibrated,
    )
    from pdr_pocket.saved_lines import saved_fit, write_fit

    pocket_path = args.pocket or args.foot
    foot = _step_batch(args.foot, topics.FOOT_STEP)
    pocket = _step_batch(pocket_path, topics.POCKET_STEP)
    config = load_pocket_config(args.config)
    height_m = config.person.height_m if args.height_m is None else args.height_m
    try:       # the node stride_calibrator's settings, so that both fit alike
        settings = CalibrationSettings(forgetting=args.forgetting, height_m=height_m)
    except ValueError as exc:
        raise InputError("--forgetting", str(exc)) from None
    try:
        cal = calibrated(pocket, foot, StrideCalibrator(config.step_length, config.stairs,
                                                        settings))
    except ValueError as exc:       # stamps not increasing
        raise InputError(f"{pocket_path}, {args.foot}", str(exc)) from None
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write_fit(args.out, saved_fit(cal, sources={"foot": str(args.foot),
                                                "pocket": str(pocket_path)}))
    print(f"{pocket_path}: {len(pocket)} pocket steps, {args.foot}: {len(foot)} foot strides")
    for name, fit in cal.fits.items():
        unit = ("m/deg", "m") if name == LEVEL else ("cm/deg", "cm")
        if fit.pairs == 0:
            print(f"{name}: no pair, the configured line kept: a {fit.slope:.5g} {unit[0]}  "
                  f"b {fit.offset:.4g} {unit[1]}")
            continue
        sigma = np.sqrt(np.diag(fit.covariance))
        print(f"{name}: {fit.pairs} pairs  a {fit.slope:.5g} ± {sigma[0]:.2g} {unit[0]}  "
              f"b {fit.offset:.4g} ± {sigma[1]:.2g} {unit[1]} (1σ)  residual "
              f"{fit.residual_sigma:.3g} {unit[1]}")
    if not any(fit.pairs for fit in cal.fits.values()):
        print(f"pdr-pocket: warning: {pocket_path}, {args.foot}: no step paired with a stride "
              "(one walk on one clock?); the saved fit is the configured lines", file=sys.stderr)
    refused = ", ".join(f"{reason} {count}" for reason, count in cal.refused.items() if count)
    print(f"refused: {refused or 'none'}; undecided at the end: {cal.pending}\nwrote {args.out}")
    return 0


def _add_tables(sub: argparse._SubParsersAction) -> None:
    for name, what in (("table-steps", "Table 4.1: step detectors, undetected and false "
                                       "steps in percent"),
                       ("table-stride", "Table 4.4: stride models, distance error in percent")):
        p = sub.add_parser(name, help=what, description=f"Muñoz Díaz 2016, {what}, on "
                                                        "simulated bags (they need "
                                                        "ground_truth/step).")
        p.add_argument("bags", type=Path, nargs="+", metavar="BAG",
                       help="simulated bags (pdr-sim generate --placement pocket)")
        p.add_argument("--config", type=Path, help="YAML configuration (pdr_pocket.config); "
                                                   "default: the installed one")
        p.add_argument("--json", action="store_true", help="print the rows as JSON")
        p.set_defaults(func=_run_table, table=name)


def _run_table(args: argparse.Namespace) -> int:
    from pdr_pocket.studies.tables import detector_rows, stride_rows

    config = load_pocket_config(args.config)
    rows = (detector_rows if args.table == "table-steps" else stride_rows)(args.bags, config)
    if args.json:
        print(json.dumps(rows, indent=2))
        return 0
    keys = list(rows[0])
    widths = [max(len(k), *(len(_cell(r[k])) for r in rows)) for k in keys]
    print("  ".join(k.ljust(w) for k, w in zip(keys, widths, strict=True)))
    for r in rows:
        print("  ".join(_cell(r[k]).ljust(w) for k, w in zip(keys, widths, strict=True)))
    return 0


def _cell(value) -> str:
    return f"{value:.2f}" if isinstance(value, float) else str(value)


def _add_calibrate_mag(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "calibrate-mag", help="fit the magnetometer's hard and soft iron",
        description="Least-squares ellipsoid fit (Muñoz Díaz 2016, Section 3.4.4) of raw "
                    "magnetometer readings taken while turning the sensor through all "
                    "directions in a homogeneous field: rotation M, offset l and scale ξ. "
                    "Writes the YAML the filter loads (configuration key "
                    "magnetometer_calibration, or --mag-calibration), prints the residual "
                    "and the share of the sphere the readings cover, and refuses data that "
                    "covers too little.")
    p.add_argument("source", type=Path, help="bag (imu/mag) or CSV file")
    p.add_argument("--out", type=Path, required=True, help="calibration YAML to write")
    p.add_argument("--field-norm-ut", type=float,
                   help="strength of the local field [µT] (default: a simulated bag's "
                        "field, else the readings' median norm)")
    p.add_argument("--min-coverage", type=float, default=MIN_COVERAGE,
                   help="least share of the sphere of directions to accept (0-1, "
                        "dimensionless)")
    p.add_argument("--mag-cols", default="mag_x,mag_y,mag_z",
                   help="magnetometer x,y,z columns of a CSV source")
    p.add_argument("--mag-unit", choices=sorted(MAG_UNITS_T), default="ut",
                   help="unit of a CSV source's columns: ut (µT), nt (nT), t (T) or gauss (G)")
    p.add_argument("--force", action="store_true",
                   help="use CSV readings whose median |B| is beyond 1-1000 µT in --mag-unit "
                        "(with a warning) instead of refusing them")
    p.add_argument("--topic", default=topics.IMU_MAG,
                   help="magnetometer topic of a bag source (sensor_msgs/MagneticField)")
    p.add_argument("--plot", type=Path, metavar="PNG", help="raw cloud and fitted sphere")
    p.set_defaults(func=_run_calibrate_mag)


def _simulated_field_norm_t(reader: BagReader) -> float | None:
    """|H∞| of a simulated bag's homogeneous field (None when not known)."""
    record = reader.custom_data("pdr.simulation") or {}
    spec = ((record.get("scenario") or {}).get("environment") or {}).get("magnetic_field") or {}
    if spec.get("vector_ut") is not None:
        return float(np.linalg.norm(spec["vector_ut"])) * 1e-6
    preset = spec.get("preset", "munich") if record else None
    return None if preset is None else float(np.linalg.norm(homogeneous(preset)))


def _run_calibrate_mag(args: argparse.Namespace) -> int:
    norm = None if args.field_norm_ut is None else args.field_norm_ut * 1e-6
    if args.source.suffix.lower() == ".csv":
        columns = tuple(c.strip() for c in args.mag_cols.split(","))
        raw = read_columns(args.source, columns) * MAG_UNITS_T[args.mag_unit]
        finite = raw[np.isfinite(raw).all(axis=1)]
        if len(finite):
            refuse_implausible(args.source, [implausible(
                args.mag_cols, FIELD_RANGE, median_field_t(finite), args.mag_unit, MAG_UNITS_T,
                "--mag-unit")], accept=args.force)
    else:
        reader = BagReader(args.source)
        raw = reader.read(args.topic)["magnetic_field"]
        norm = norm or _simulated_field_norm_t(reader)
    result = calibrate(raw, norm, args.min_coverage, str(args.source))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(result.to_yaml())
    d = result.distortion
    print(f"{args.source}: {len(raw)} readings covering {100 * result.coverage:.0f} % of the "
          f"sphere, |H| {result.field_norm_t * 1e6:.2f} µT\n"
          f"xi {d.xi:.4f}  offset {np.round(d.offset, 4).tolist()}  "
          f"M {np.round(d.M, 4).tolist()}\n"
          f"residual RMS of |calibrated|/|H| - 1: {result.residual_rms:.5f}\nwrote {args.out}")
    if args.plot:
        from pdr_pocket import plots
        finite = raw[np.isfinite(raw).all(axis=1)]
        plots.magnetometer_png(finite * 1e6, result.apply(finite) * 1e6, args.plot,
                               str(args.source))
        print(f"plot: {args.plot}")
    return 0


def parser() -> argparse.ArgumentParser:
    top = cli_parser("pdr-pocket", __doc__)
    sub = top.add_subparsers(dest="command", required=True)
    _add_run(sub)
    _add_evaluate(sub)
    _add_attitude(sub)
    _add_calibrate_step(sub)
    _add_tables(sub)
    _add_calibrate_mag(sub)
    return top


def main(argv: Sequence[str] | None = None) -> None:
    dispatch("pdr-pocket", parser(), argv)

if __name__ == "__main__":
    main()
