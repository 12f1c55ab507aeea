"""``pdr-sim``: offline tools of the simulator package (no ROS graph needed).

Subcommands:
    generate     simulate a scenario -> bag (imu/data, imu/mag, ground_truth/pose; the
                 barometer's imu/pressure with --pressure).
    allan        Allan deviation and noise parameters of static data (bag or CSV).
    fit-steps    fit the raised-cosine step pattern (Eqs. 3-5) to recorded foot positions.
    import-csv   CSV IMU log -> rosbag2 MCAP bag (imu/data, ground_truth/pose with
                 positions and attitudes, imu/mag, imu/pressure).
    import-oxiod an OxIOD sequence (imuK.csv + viK.csv) -> bag (imu/data, imu/mag,
                 ground_truth/pose with the phone's attitude).
    import-phone a phone's own export, one CSV per sensor (Sensor Logger's folder or zip,
                 or files you name) -> bag (imu/data, imu/mag, imu/pressure).
    export-csv   a bag's imu/data, imu/mag, imu/pressure and ground_truth/pose -> one
                 CSV log, each topic at its own stamps, that import-csv reads back; the
                 true step times with --steps-out.
    info         topics, types, message counts and time span of a bag.
    repair       a bag cut short -> a new bag with its index and metadata rebuilt.

Errors in the input exit with status 2 and one line naming the file and the problem.
"""
from __future__ import annotations

import argparse
import shlex
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import yaml

from pdr_core import topics
from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError, cli_parser, dispatch
from pdr_core.io.bag import BagReader, add_strict_option, repair, write_batches
from pdr_core.io.csv_export import export_bag, import_arguments
from pdr_core.io.csv_import import (
    import_csv,
)
from pdr_core.io.odometry import truth_tf
from pdr_core.sensors.imu_profiles import PROFILES
from pdr_sim.allan_report import allan_report
from pdr_sim.cli_options import add_bag_output, add_csv_format, csv_format
from pdr_sim.foot_trajectory import level_walk_like
from pdr_sim.import_cli import add_import_csv, add_import_oxiod, add_import_phone
from pdr_sim.overrides import with_overrides
from pdr_sim.paired_foot import foot_simulation, namespaced
from pdr_sim.pocket_scenario import POCKET_BUILTIN
from pdr_sim.scenario import BUILTIN
from pdr_sim.simulation import (
    SimulationConfig,
    load_placement_scenario,
    scenario_of,
    simulate,
    simulation_record,
)
from pdr_sim.step_fit import cut_steps, fit_pattern, pattern_to_dict, rms_error


def _add_generate(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "generate", help="simulate a walk and write its bag",
        description="Simulate the IMU of a walking pedestrian along a scenario and write "
                    "imu/data, imu/mag and ground_truth/pose (every sample) to a bag; the "
                    "pocket placement adds ground_truth/step and ground_truth/landmarks. The "
                    "complete configuration is stored in the bag's metadata "
                    "(custom_data 'pdr.simulation') so the run can be reproduced.")
    p.add_argument("--placement", default="foot", choices=["foot", *CARRIED_BY_PLACEMENT],
                   help="foot-mounted IMU, or a phone in the front trouser pocket (thigh), "
                        "in a back pocket (buttock) or held in the hand (the last three walk "
                        "pocket scenarios; their key 'carried')")
    p.add_argument("--scenario",
                   help=f"built-in (foot: {', '.join(BUILTIN)}; pocket: "
                        f"{', '.join(POCKET_BUILTIN)}) or a YAML file; default: straight "
                        "(foot), h1_rectangle (pocket)")
    p.add_argument("--imu", default="xsens_mtw", help=f"profile ({', '.join(PROFILES)})")
    p.add_argument("--rate", type=float, default=100.0, help="sample rate [Hz], 50-1000")
    p.add_argument("--seed", type=int, default=0, help="seed of the sensor errors")
    p.add_argument("--gravity", type=float, default=STANDARD_GRAVITY_MPS2,
                   help="local gravity [m/s²]")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scenario value, e.g. step.length_m=1.2 or "
                        "segments[1].steps=20 (YAML value; repeatable)")
    p.add_argument("--imu-set", action="append", default=[], metavar="SENSOR.KEY=VALUE",
                   help="override a profile value, e.g. gyro.arw_deg_per_sqrt_h=1.0")
    p.add_argument("--pressure", action="store_true",
                   help="also simulate the barometer beside the IMU and write imu/pressure "
                        "(sensor_msgs/FluidPressure, Pa) at its own rate; off, every other "
                        "topic is the same. Its errors are the profile's baro section "
                        "(consumer_phone's for a profile without one: 25 Hz, 0.03 hPa noise, "
                        "0.01 hPa steps, a random weather drift of 0.3 hPa/h std); set them "
                        "with --imu-set, e.g. baro.drift_hpa_per_h=1.0 (a fixed weather drift), "
                        "'baro.offsets=[{at_s: 300, size_hpa: 0.3, duration_s: 60}]' (a "
                        "sudden offset: a ventilated stairwell), baro.reference_hpa=1013.25 "
                        "(the pressure at z = 0), baro.noise_hpa=0.0")
    p.add_argument("--level-walk", action="store_true",
                   help="foot: instead of the scenario, a level walk of the same duration, "
                        "seed, standing at start and end, and environment (walk strides out "
                        "and back), to compare a gait against")
    p.add_argument("--with-foot", action="store_true",
                   help="pocket: also the foot IMU of the pocket's leg on the same walk, "
                        "under /foot (foot/imu/data, foot/imu/mag, foot/ground_truth/pose, "
                        "foot/ground_truth/stance) on the same clock, with its own errors: "
                        "the two-IMU walk a foot INS calibrates the pocket's lines on")
    p.add_argument("--foot-imu", default="xsens_mtw",
                   help="with --with-foot: the foot IMU's profile")
    add_bag_output(p)
    p.add_argument("--plot", type=Path, metavar="DIR",
                   help="also write DIR/trajectory.png and DIR/signals.png (pocket: and "
                        "DIR/pocket.png, the 3D path, the pitch with the true steps and "
                        "activities, the yaw with the hip sway)")
    p.set_defaults(func=_run_generate)


# --placement of a pocket scenario: where the phone is carried (None: as the scenario says)
CARRIED_BY_PLACEMENT = {"pocket": None, "back_pocket": "back_pocket", "hand": "hand"}


def _run_generate(args: argparse.Namespace) -> int:
    family = "foot" if args.placement == "foot" else "pocket"
    name = args.scenario or ("h1_rectangle" if family == "pocket" else "straight")
    scenario, data = load_placement_scenario(name, family)
    carried = CARRIED_BY_PLACEMENT.get(args.placement)
    if carried is not None:
        data = {**data, "carried": carried}
    if args.set or carried is not None:
        data = with_overrides(data, args.set, "--set")
        scenario = scenario_of(data, f"{name} ({'with --set' if args.set else args.placement})",
                               family)
    if args.level_walk:
        if family != "foot":
            raise InputError("--level-walk", "is for the foot placement")
        data = level_walk_like(scenario, data)
        scenario = scenario_of(data, data["name"], family)
    overrides = with_overrides({}, args.imu_set, "--imu-set")
    config = SimulationConfig(scenario, data, args.imu, overrides, args.rate, args.seed,
                              args.gravity, family, args.pressure)
    sim = simulate(config)
    batches = sim.batches | truth_tf(sim.pose)
    records = {"pdr.simulation": simulation_record(sim)}
    if args.with_foot:
        if family != "pocket":
            raise InputError("--with-foot", "is for a pocket placement (the foot beside it)")
        foot = foot_simulation(sim, args.foot_imu, overrides)
        batches |= namespaced(foot.batches)
        records["pdr.simulation.foot"] = simulation_record(foot)
    write_batches(args.out, batches, overwrite=args.overwrite, compress=args.compress,
                  custom_data={key: yaml.safe_dump(record, sort_keys=False)
                               for key, record in records.items()})
    foot_note = f", with the foot's IMU ({args.foot_imu}) under /foot" if args.with_foot \
        else ""
    print(f"{args.out}: {scenario.name}, {len(sim.imu)} samples at {args.rate:g} Hz "
          f"({sim.trajectory.t[-1]:.1f} s), {_route_summary(sim)}, imu {args.imu}, "
          f"seed {args.seed}{foot_note}")
    if args.plot:
        from pdr_sim import plots  # Matplotlib: only for the plots

        args.plot.mkdir(parents=True, exist_ok=True)
        title = f"{scenario.name}, {args.imu}, {args.rate:g} Hz"
        plots.trajectory_png(sim.trajectory, args.plot / "trajectory.png", title,
                             steps=plots.step_count(sim.model), foot=family == "foot")
        plots.signals_png(sim.trajectory.t, sim.imu["angular_velocity"],
                          sim.imu["linear_acceleration"], sim.mag["magnetic_field"],
                          args.plot / "signals.png", title)
        written = ["trajectory.png", "signals.png"]
        if family == "pocket":
            plots.pocket_png(sim.model, sim.trajectory, args.plot / "pocket.png", title)
            written.append("pocket.png")
        print("plots: " + ", ".join(str(args.plot / w) for w in written))
    return 0


def _route_summary(sim) -> str:
    """One line on the route: path and heading change (foot), steps and floors (pocket)."""
    if sim.config.placement == "pocket":
        steps = sim.model.true_steps
        rides = sim.model.plan.rides
        floors = sorted({m.floor for m in sim.model.landmarks} | {0}
                        | set(np.cumsum([r.floors for r in rides]).tolist()))
        lifts = f", {len(rides)} lift rides" if rides else ""
        return (f"{len(steps.length)} steps, {steps.length.sum():.1f} m, "
                f"{np.abs(steps.vertical_displacement).sum():.1f} m climbed or descended, "
                f"floors {floors[0]}..{floors[-1]}, {len(sim.model.landmarks)} landmarks"
                f"{lifts}")
    phases = sim.model.phases
    return (f"path {phases.path_length_m:.2f} m, heading change "
            f"{np.degrees(phases.heading_change_rad):.1f} deg")


def _add_allan(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "allan", help="Allan deviation of static data",
        description="Overlapping Allan deviation of static gyroscope and accelerometer data "
                    "from a bag (imu/data) or a CSV (same column options as import-csv). "
                    "Prints ARW/VRW at τ = 1 s, bias instability β and t_β, random walk, and "
                    "the AR(1) parameters of thesis Eqs. (3.10)-(3.11); writes a table and a "
                    "log-log PNG.")
    p.add_argument("source", type=Path, help="bag directory or CSV file")
    p.add_argument("--topic", default=topics.IMU_DATA, help="IMU topic of a bag source")
    p.add_argument("--out", type=Path, help="write DIR/allan.csv and DIR/allan.png")
    add_csv_format(p, required=False)
    p.set_defaults(func=_run_allan)


def _run_allan(args: argparse.Namespace) -> int:
    if args.source.is_file() and args.source.suffix.lower() == ".csv":
        if not args.acc_cols:
            raise InputError("--acc-cols", "required for a CSV source")
        imu = import_csv(args.source, csv_format(args)).imu
    else:
        imu = BagReader(args.source).read(args.topic)
    if len(imu) < 100:
        raise InputError(args.source, f"{len(imu)} samples are too few for an Allan deviation")
    report = allan_report(imu)
    print(report.table())
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "allan.csv").write_text(report.csv())
        report.plot(args.out / "allan.png", str(args.source))
        print(f"wrote {args.out / 'allan.csv'} and {args.out / 'allan.png'}")
    return 0


def _add_fit_steps(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "fit-steps", help="fit step patterns to recorded foot positions",
        description="Cut the steps of a recorded foot trajectory (ground_truth/pose of a "
                    "bag, e.g. VICON imported with import-csv), align them, drop false "
                    "steps and fit the raised cosines of Eqs. (3)-(4) by Levenberg-"
                    "Marquardt (Eq. 5). The pattern file is used by scenarios with "
                    "'pattern: fitted'.")
    p.add_argument("bag", type=Path, help="bag with foot positions")
    p.add_argument("--topic", default=topics.GROUND_TRUTH_POSE,
                   help="topic of the foot positions (geometry_msgs/PoseStamped)")
    p.add_argument("--out", type=Path, required=True, help="pattern YAML to write")
    p.add_argument("--plot", type=Path, help="PNG of the steps and the fit (Fig. 2)")
    p.set_defaults(func=_run_fit_steps)


def _run_fit_steps(args: argparse.Namespace) -> int:
    poses = BagReader(args.bag).read(args.topic)
    steps = cut_steps(poses.t_s, poses["pose.position"])
    try:
        pattern = fit_pattern(steps)
    except ValueError as exc:
        raise InputError(args.bag, str(exc)) from exc
    args.out.write_text(yaml.safe_dump(pattern_to_dict(pattern), sort_keys=False))
    rms_along, rms_up = rms_error(steps, pattern)
    print(f"{args.bag}: {len(steps.t)} steps fitted, {len(steps.rejected)} rejected; swing "
          f"{pattern.swing_s:.3f} s; RMS residual along-track {rms_along:.3f} m, height "
          f"{rms_up:.3f} m; wrote {args.out}")
    if args.plot:
        from pdr_sim import plots  # Matplotlib: only for the plots

        plots.step_fit_png(steps.t, steps.xyz, pattern.s, pattern.z, args.plot, str(args.bag))
        print(f"plot: {args.plot}")
    return 0


def _add_export_csv(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "export-csv", help="write a bag's sensors and truth as one CSV log",
        description="Write a bag (simulated or not) as one CSV log, each topic at its own "
                    "stamps: a row per stamp at which any of imu/data, imu/mag, "
                    "imu/pressure and ground_truth/pose has a message, the other topics' "
                    "cells empty, the unit in each column's name: t_s (from the first "
                    "message), acc_x_mps2.., gyr_x_radps.. (left out without a gyroscope), "
                    "mag_x_t.. (tesla), pressure_pa, gt_x_m.. and gt_qx..gt_qw (the "
                    "truth's attitude). Prints the import-csv command that reads it back "
                    "(every topic, stamps to the ns from t_s = 0) and names the bag's "
                    "topics it does not write.")
    p.add_argument("bag", type=Path, help="bag with imu/data")
    p.add_argument("--out", type=Path, required=True, help="the CSV log to write")
    p.add_argument("--steps-out", type=Path, metavar="CSV",
                   help="also write the true step times of ground_truth/step (one column "
                        "t_s [s], each step's end on the log's time axis: one row per gait "
                        "cycle of the sensor leg)")
    p.add_argument("--overwrite", action="store_true", help="replace existing outputs")
    add_strict_option(p)
    p.set_defaults(func=_run_export_csv)


def _run_export_csv(args: argparse.Namespace) -> int:
    exported = export_bag(args.bag, args.out, args.steps_out, overwrite=args.overwrite,
                          strict=args.strict)
    table = exported.table
    print(f"{args.out}: {len(table.values)} rows of {args.bag}, columns "
          f"{', '.join(table.columns)}; t_s = 0 at the stamp {table.origin_ns} ns")
    if exported.unwritten:
        print(f"not written: {', '.join(exported.unwritten)}")
    if exported.steps is not None:
        print(f"{args.steps_out}: {exported.steps} true steps ({topics.GROUND_TRUTH_STEP})")
    print("read it back with: pdr-sim import-csv " + shlex.join(
        [str(args.out), "--out", "BAG", *import_arguments(table)]))
    return 0


def _add_info(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("info", help="summarise a bag",
                       description="Topics, types, message counts and time span of a bag "
                                   "(what ros2 bag info shows).")
    p.add_argument("bag", type=Path, help="bag directory or .mcap file")
    p.set_defaults(func=_run_info)


def _run_info(args: argparse.Namespace) -> int:
    reader = BagReader(args.bag)
    counts: dict[str, int] = dict.fromkeys(reader.topics, 0)
    first = last = None
    for message in reader.raw_messages():
        counts[message.topic] += 1
        first = message.log_time_ns if first is None else first
        last = message.log_time_ns
    span = 0.0 if first is None else (last - first) * 1e-9
    print(f"bag: {args.bag}\nduration: {span:.3f} s\nmessages: {sum(counts.values())}")
    for topic in sorted(counts):
        print(f"  {topic:<28} {reader.topics[topic]:<44} {counts[topic]:>9}")
    return 0


def _add_repair(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "repair", help="rebuild the index and metadata of a bag cut short",
        description="What ros2 bag reindex does: every message of a bag cut short (a "
                    "recorder killed, a copy interrupted) up to its last complete chunk, "
                    "written to a new bag with its summary, index and metadata.yaml. The "
                    "original is never touched.")
    p.add_argument("bag", type=Path, help="bag directory or .mcap file")
    p.add_argument("--out", type=Path, help="the repaired bag (default: BAG.repaired)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output")
    p.set_defaults(func=_run_repair)


def _run_repair(args: argparse.Namespace) -> int:
    out = args.out or args.bag.with_name(args.bag.name + ".repaired")
    counts = repair(args.bag, out, overwrite=args.overwrite)
    print(f"repaired {args.bag} -> {out}: {sum(counts.values())} messages on "
          f"{len(counts)} topics")
    for topic in sorted(counts):
        print(f"  {topic:<28} {counts[topic]:>9}")
    return 0


def parser() -> argparse.ArgumentParser:
    """The ``pdr-sim`` argument parser."""
    top = cli_parser("pdr-sim", __doc__)
    sub = top.add_subparsers(dest="command", required=True)
    _add_generate(sub)
    _add_allan(sub)
    _add_fit_steps(sub)
    add_import_csv(sub)
    add_import_oxiod(sub)
    add_import_phone(sub)
    _add_export_csv(sub)
    _add_info(sub)
    _add_repair(sub)
    return top


def main(argv: Sequence[str] | None = None) -> None:
    dispatch("pdr-sim", parser(), argv)

if __name__ == "__main__":
    main()
