"""``pdr-ekf``: offline tools of the foot-mounted INS (no ROS graph needed).

Subcommands:
    run BAG --out OUT     the ZUPT EKF on imu/data: output bag, report.json, PNG;
                          --smoother segmented|full adds the RTS-smoothed trajectory;
                          --drift online|offline the landmark drift corrections.
    evaluate BAG --truth TRUTH_BAG
                          the report of recorded poses (pdr/foot/pose, pdr/pocket/pose)
                          against ground truth.
    montecarlo --source S --estimator E --runs N --out DIR
                          error growth of pure INS or the ZUPT EKF over N noise
                          realisations (Zampella et al. 2011, Eqs. (13)–(14), Tables
                          I–III): fits, σ(t) and consistency CSV, PNG.
    analytic              closed-form ZUPT error levels (Wang et al. 2020, Eqs. (38)-(57)).
    study mechanization   pure-INS position error per attitude method and rate
                          (Zampella et al. 2011, Fig. 6): table, CSV and PNG.
    study sweep           analytic against EKF error levels over ARW, VRW, RRW
                          (Wang et al. 2020, Figs. 3–6): table, CSV, PNG.

Errors in the input exit with status 2 and one line naming the problem. ``run`` on input
no walk gives (a median |f| beyond 0.5-2.5 g, pdr_core.walking.walk_plausibility) warns on the
first line of its output and in the report's ``warnings``; --strict refuses it (status 2).
Plotting modules
are imported only when a figure is asked for (Matplotlib alone costs 0.4 s of start-up).
"""
from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from pdr_core import topics
from pdr_core.errors import InputError, cli_parser, dispatch
from pdr_core.evaluation.metrics import error_report, truth_at
from pdr_core.io.bag import BagReader, add_strict_option
from pdr_core.io.msgtypes import POSE_STAMPED, POSE_WITH_COVARIANCE_STAMPED
from pdr_core.report_files import print_report
from pdr_ins_ekf.foot_offline import DRIFT_MODES, FootOptions, run
from pdr_ins_ekf.studies.cli import add_study_commands
from pdr_ins_ekf.zupt_ekf import SMOOTHER_MODES


def _add_run(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "run", help="run the foot navigator on a bag",
        description="Run the ZUPT-aided INS on imu/data of a bag. Writes OUT/ as a bag with "
                    "pdr/foot/pose, velocity, stance and path, and OUT/report.json with the "
                    "metrics of docs/reports.md (against ground_truth/pose when the bag has "
                    "it, and the stance's precision and recall against ground_truth/stance "
                    "when it has that).")
    p.add_argument("bag", type=Path, help="bag with imu/data (and ground_truth/pose)")
    p.add_argument("--out", type=Path, required=True,
                   help="output directory: a bag with OUT/report.json")
    p.add_argument("--config", type=Path,
                   help="YAML configuration (see pdr_ins_ekf.config); default: the installed "
                        "config/foot_ekf.yaml")
    p.add_argument("--imu-profile", help="use the shipped config/foot_ekf_<PROFILE>.yaml "
                                         "(xsens_mti, xsens_mtw, vn200, consumer_phone)")
    p.add_argument("--imu-topic", default=topics.IMU_DATA, help="IMU topic (sensor_msgs/Imu)")
    p.add_argument("--truth-topic", default=topics.GROUND_TRUTH_POSE,
                   help="ground-truth topic (geometry_msgs/PoseStamped), used when present")
    p.add_argument("--stance-truth-topic", default=topics.GROUND_TRUTH_STANCE,
                   help="true stance per sample (pdr_msgs/Stance, e.g. pdr-sim generate's), "
                        "used when present: report key 'stance'")
    p.add_argument("--smoother", choices=SMOOTHER_MODES,
                   help="RTS smoothing (Simón Colomar et al. 2012): adds pdr/foot/smoothed_path "
                        "and report key 'smoothed'; default: the configuration's smoother.mode")
    p.add_argument("--drift", choices=DRIFT_MODES, default="none",
                   help="landmark drift corrections (pdr_drift; Muñoz Díaz 2016, Sections "
                        "6.1-6.2): online, taken at each revisit's stride as zupt_ekf takes "
                        "landmark_drift's; offline, the walk's drift ε₀ taken off the heading "
                        "in a second pass. Use a 15-state configuration "
                        "(config/foot_ekf_drift.yaml; docs/foot_ins.md)")
    p.add_argument("--drift-config", type=Path,
                   help="YAML of the drift estimator (pdr_drift.config); default: the "
                        "installed config/landmark_drift.yaml")
    p.add_argument("--plot", action="store_true",
                   help="also write OUT/path.png (and OUT/smoothing.png when smoothing)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output")
    add_strict_option(p)
    p.epilog = ("--strict also refuses input no walk gives (a median |f| beyond 0.5-2.5 g), "
                "exit 2; without it that is a warning.")
    p.set_defaults(func=_run_run)


def _run_run(args: argparse.Namespace) -> int:
    options = FootOptions(args.config, args.imu_profile, args.smoother, args.drift,
                          args.drift_config, args.imu_topic, args.truth_topic,
                          args.stance_truth_topic, args.strict, args.plot, args.overwrite)
    print_report(run(args.bag, options, args.out, lambda warning: print(
        f"pdr-ekf: warning: {args.bag}: {warning}", file=sys.stderr, flush=True)))
    return 0


def _add_evaluate(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "evaluate", help="report of recorded estimates against ground truth",
        description="Compute the report of docs/reports.md for the poses of a bag (recorded "
                    "from zupt_ekf or pocket_pdr, or written by pdr-ekf run or pdr-pocket "
                    "run) against ground_truth/pose of another bag.")
    p.add_argument("bag", type=Path, help="bag with the estimated poses")
    p.add_argument("--truth", type=Path, required=True, help="bag with ground_truth/pose")
    p.add_argument("--topic",
                   help="topic of the estimated poses (geometry_msgs/PoseWithCovarianceStamped);"
                        " default: the bag's only such topic, or its only navigator pose, "
                        "/pdr/foot/pose or /pdr/pocket/pose")
    p.add_argument("--plot", type=Path, help="PNG of the estimate against the truth")
    p.set_defaults(func=_run_evaluate)


# The position field of each message type evaluate reads
POSITION_FIELD = {POSE_WITH_COVARIANCE_STAMPED: "pose.pose.position",
                  POSE_STAMPED: "pose.position"}


def estimate_topic(reader: BagReader) -> str:
    """The bag's topic of pose estimates (geometry_msgs/PoseWithCovarianceStamped): its only
    one, or its only navigator pose (``pdr/foot/pose``, ``pdr/pocket/pose``) beside the
    foot's ``pdr/foot/step_pose``; InputError naming the candidates and --topic when there
    is none or more than one."""
    candidates = sorted(topic for topic, msgtype in reader.topics.items()
                        if msgtype == POSE_WITH_COVARIANCE_STAMPED)
    main = [topic for topic in candidates if topic in (topics.FOOT_POSE, topics.POCKET_POSE)]
    if len(candidates) == 1 or len(main) == 1:
        return candidates[0] if len(candidates) == 1 else main[0]
    if not candidates:
        have = ", ".join(f"{t} ({m})" for t, m in sorted(reader.topics.items())) or "none"
        raise InputError(reader.path, f"no topic of pose estimates ("
                                      f"{POSE_WITH_COVARIANCE_STAMPED}) to evaluate (the bag "
                                      f"has: {have}); name one with --topic")
    raise InputError(reader.path, f"{len(candidates)} topics of pose estimates: "
                                  f"{', '.join(candidates)}; choose one with --topic")


def _run_evaluate(args: argparse.Namespace) -> int:
    reader = BagReader(args.bag)
    topic = args.topic or estimate_topic(reader)
    estimate = reader.read(topic)
    if estimate.msgtype not in POSITION_FIELD:
        raise InputError(topic, f"{estimate.msgtype} holds no pose (evaluate reads "
                                f"{' or '.join(POSITION_FIELD)})")
    if len(estimate) == 0:
        raise InputError(topic, "no messages to evaluate")
    truth = truth_at(BagReader(args.truth).read(topics.GROUND_TRUTH_POSE), estimate.stamp_ns)
    t_s = (estimate.stamp_ns - estimate.stamp_ns[0]) * 1e-9
    position = estimate[POSITION_FIELD[estimate.msgtype]]
    report = error_report(t_s, position, truth)
    print_report(report)
    if args.plot:
        from pdr_ins_ekf import plots
        plots.path_png(t_s, position, truth, args.plot, str(args.bag))
        print(f"plot: {args.plot}")
    return 0


def parser() -> argparse.ArgumentParser:
    top = cli_parser("pdr-ekf", __doc__)
    sub = top.add_subparsers(dest="command", required=True)
    _add_run(sub)
    _add_evaluate(sub)
    add_study_commands(sub)
    return top


def main(argv: Sequence[str] | None = None) -> None:
    dispatch("pdr-ekf", parser(), argv)

if __name__ == "__main__":
    main()
