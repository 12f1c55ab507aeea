"""``pdr-ekf run``: the foot navigator on a whole bag, with or without the landmark drift
corrections, writing its messages (:mod:`pdr_ins_ekf.offline`), its report (every field:
docs/reports.md) and optionally its plots.

- :func:`run`: the Python entry point, ``pdr-eval``'s and the CLI's: a bag and its
  :class:`FootOptions` in, the report out (the dict ``report.json`` holds), the outputs
  written to ``out`` when it is given. It prints nothing and sets no process-wide state
  (no stdout, no working directory, no global configuration): the CLI prints its
  warnings and report. Input no walk gives (a median |f| beyond 0.5-2.5 g,
  pdr_core.walking.walk_plausibility) is the report's first warnings, told to ``warn`` as soon as
  found, before the navigation that may fail on it (the CLI prints them then), or with
  ``strict`` an InputError; a damaged bag read in part is an InputWarning
  (pdr_core.io.bag).
- Its three jobs: :func:`navigate_bag` (the navigator on the bag, a :class:`FootBagRun`),
  :func:`report_of` (what it gave) and :func:`write_run` (the messages, the report and
  the plots, :func:`plot_run`).
"""
from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.evaluation.consistency import checkpoints, consistency_report, has_attitude
from pdr_core.evaluation.metrics import (
    error_report,
    truth_at,
    truth_orientation_at,
    within_step_rmse,
)
from pdr_core.io.bag import BagReader, BagWriter
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import PATH
from pdr_core.io.odometry import ANGULAR, LINEAR
from pdr_core.report_files import write_report
from pdr_core.sensors.imu_checks import check_units, clean_samples
from pdr_core.walking.walk_plausibility import implausible_input, specific_force_problem
from pdr_ins_ekf.config import RunConfig, load_run_config
from pdr_ins_ekf.offline import (
    FootRun,
    navigate,
    output_batches,
    smoothed_paths,
    stance_scores,
    step_path,
    stride_batches,
    tf_batches,
)

DRIFT_MODES = ("none", "online", "offline")


@dataclass(frozen=True)
class FootOptions:
    """What ``pdr-ekf run`` takes beside the bag and ``--out``, each as its option of the
    same name: the YAML ``config`` (None: the installed config/foot_ekf.yaml) or the
    shipped ``imu_profile``'s, the ``smoother`` mode (None: the configuration's), the
    ``drift`` corrections (:data:`DRIFT_MODES`) and their ``drift_config`` YAML (None: the
    installed config/landmark_drift.yaml), the topics read, ``strict`` (refuse input
    no walk gives, and damaged bags), ``plot`` and ``overwrite`` (of ``out``)."""

    config: Path | None = None
    imu_profile: str | None = None
    smoother: str | None = None
    drift: str = "none"
    drift_config: Path | None = None
    imu_topic: str = topics.IMU_DATA
    truth_topic: str = topics.GROUND_TRUTH_POSE
    stance_truth_topic: str = topics.GROUND_TRUTH_STANCE
    strict: bool = False
    plot: bool = False
    overwrite: bool = False


def options_config(options: FootOptions) -> RunConfig:
    """The run's configuration: ``options.config`` or its IMU profile's, with its
    smoother's mode replaced by ``options.smoother`` when given."""
    config = load_run_config(options.config, options.imu_profile)
    if options.smoother:
        config = dataclasses.replace(
            config, smoother=dataclasses.replace(config.smoother, mode=options.smoother))
    return config


@dataclass
class FootBagRun:
    """What the navigator made of a bag (:func:`navigate_bag`): the ``bag``, the
    navigator's ``result``, the true pose and stance read (None: the bag has none) and the
    true positions at every sample navigated (``truth``, (N, 3) [m]), the input's
    ``problems``, the smoothed paths (stamp [ns], nav_msgs/Path CDR; none without the
    smoother) and the report's ``drift`` object (None without the corrections)."""

    bag: Path
    result: FootRun
    truth_pose: MessageBatch | None
    stance_truth: MessageBatch | None
    truth: np.ndarray | None
    problems: list[str]
    smoothed: list[tuple[int, bytes]]
    drift_report: dict | None

    @property
    def t_s(self) -> np.ndarray:
        """The time of every sample navigated from the first [s]."""
        return (self.result.stamp_ns - self.result.stamp_ns[0]) * 1e-9


def walk_problem(imu: MessageBatch) -> str | None:
    """What makes ``imu`` no walk (pdr_core.walking.walk_plausibility), once its units are checked:
    data a unit away are refused first (pdr_core.sensors.imu_checks.check_units), with one line,
    as :func:`~pdr_ins_ekf.offline.navigate` would refuse them."""
    keep, _ = clean_samples(imu)
    t_s, accel = imu.t_s[keep], imu["linear_acceleration"][keep]
    if len(t_s):
        check_units(accel, imu["angular_velocity"][keep], t_s=t_s - t_s[0])
    return specific_force_problem(t_s, accel)


def navigate_bag(bag: Path, config: RunConfig, options: FootOptions,
                 warn: Callable[[str], None] | None = None) -> FootBagRun:
    """The foot navigator on ``bag``'s ``options.imu_topic`` (with ``options.drift`` online
    or offline, the landmark drift corrections: :func:`drift_run`), its input checked
    (module docstring), each problem told to ``warn`` before navigating. Nothing is
    written: :func:`report_of` says what it gave."""
    reader = BagReader(bag, strict=options.strict)
    has_truth = options.truth_topic in reader.topics
    has_stance = options.stance_truth_topic in reader.topics
    wanted = ([options.imu_topic] + ([options.truth_topic] if has_truth else [])
              + ([options.stance_truth_topic] if has_stance else []))
    batches = reader.read_batches(wanted)
    imu = batches[options.imu_topic]
    problems = implausible_input(bag, [walk_problem(imu)], options.strict)
    for problem in problems if warn is not None else ():
        warn(problem)
    truth_pose = batches.get(options.truth_topic)
    if options.drift == "none":
        result, drift_report = navigate(imu, config), None
    else:
        result, drift_report = drift_run(imu, truth_pose, config, options)
    truth = None if truth_pose is None else truth_at(truth_pose, result.stamp_ns)
    smoothed = [] if result.smoothed is None else smoothed_paths(result)
    return FootBagRun(bag, result, truth_pose, batches.get(options.stance_truth_topic),
                      truth, problems, smoothed, drift_report)


def final_errors_against(run: FootRun, truth: MessageBatch) -> dict:
    """pdr_drift.drift_report.final_errors of a run against its ``ground_truth/pose``: the
    foot's yaw [deg] and position [m] errors at the last sample navigated."""
    from scipy.spatial.transform import Rotation

    from pdr_core.maths.rotations import yaw_of
    from pdr_drift.drift_report import final_errors

    last = run.stamp_ns[-1:]
    true_yaw = yaw_of(Rotation.from_quat(truth_orientation_at(truth, last)).as_matrix())
    return final_errors(yaw_of(run.output.attitude[-1:]), true_yaw, run.output.position[-1:],
                        truth_at(truth, last))


def drift_run(imu: MessageBatch, truth_pose: MessageBatch | None, config: RunConfig,
              options: FootOptions) -> tuple[FootRun, dict]:
    """The run with the drift corrections (pdr_ins_ekf.drift_loop) and the report's
    ``drift`` object: what the estimator did and, against ``truth_pose``, the final yaw
    and position errors with the corrections and without (a run without them)."""
    from pdr_drift.config import default_config_path, load_drift_config
    from pdr_ins_ekf.drift_loop import navigate_offline, navigate_online

    if config.smoother.mode != "none":
        raise InputError("--drift", "the smoother cannot take corrections: use --smoother "
                                    "none with --drift")
    drift = load_drift_config(options.drift_config or default_config_path())
    loop = navigate_online if options.drift == "online" else navigate_offline
    result, log = loop(imu, config, drift)
    report = {"mode": options.drift, **log.summary()}
    if truth_pose is not None:
        report["corrected"] = final_errors_against(result, truth_pose)
        report["uncorrected"] = final_errors_against(navigate(imu, config), truth_pose)
    return result, report


def foot_consistency(result: FootRun, truth_pose: MessageBatch, truth: np.ndarray) -> dict:
    """The report's ``consistency`` (pdr_core.evaluation.consistency): the NEES, one sample a
    second, of the pose ``pdr/foot/pose`` publishes (its position and, where ``truth_pose`` holds
    an attitude, its attitude with their covariances) against ``truth_pose`` (``truth``:
    its positions at every sample navigated)."""
    at = checkpoints((result.stamp_ns - result.stamp_ns[0]) * 1e-9)
    pose = output_batches(result)[topics.FOOT_POSE].take(at)
    cov = pose["pose.covariance"].reshape(-1, 6, 6)
    true_attitude = truth_orientation_at(truth_pose, result.stamp_ns[at])
    attitude = ((pose["pose.pose.orientation"], cov[:, ANGULAR, ANGULAR], true_attitude)
                if has_attitude(true_attitude) else None)
    return consistency_report(result.output.position, truth, at, cov[:, LINEAR, LINEAR],
                              attitude)


def step_report(t_s: np.ndarray, position: np.ndarray, truth: np.ndarray | None,
                stance: np.ndarray) -> dict:
    """The report of docs/reports.md, plus ``within_step_rmse_m`` (pdr_core.evaluation.metrics) over
    the steps between swings when there is a truth and at least one whole step."""
    report = error_report(t_s, position, truth)
    cuts = np.flatnonzero(stance[:-1] & ~stance[1:])
    if truth is not None and len(cuts) >= 2:
        report["within_step_rmse_m"] = within_step_rmse(position, truth, cuts)
    return report


def report_of(run_: FootBagRun) -> dict:
    """The report of a run (docs/reports.md, ``pdr-ekf run``): the trajectory's figures,
    against the truth when the bag has one, its consistency and stance scores, the
    smoothed trajectory's and the drift corrections'."""
    result, truth, t_s = run_.result, run_.truth, run_.t_s
    report = step_report(t_s, result.output.position, truth, result.stance)
    report |= {"samples": len(t_s), "stance_fraction": float(result.stance.mean()),
               "dropped": result.counts, "warnings": run_.problems}
    if run_.truth_pose is not None:
        report["consistency"] = foot_consistency(result, run_.truth_pose, truth)
    if run_.stance_truth is not None:
        report["stance"] = stance_scores(result, run_.stance_truth)
    if result.smoothed is not None:
        report["smoothed"] = step_report(t_s, result.smoothed.position, truth,
                                         result.stance) | {"segments": len(run_.smoothed)}
    if run_.drift_report is not None:
        report["drift"] = run_.drift_report
    return report


def write_run(run_: FootBagRun, report: dict, out: Path, *, overwrite: bool = False,
              plot_source: Path | None = None) -> None:
    """The run's messages and ``report`` into the bag ``out``; with ``plot_source`` (the
    input's name for the titles), its plots too (:func:`plot_run`)."""
    result = run_.result
    outputs = output_batches(result) | tf_batches(result) | stride_batches(result.strides)
    with BagWriter(out, overwrite=overwrite) as writer:
        writer.write_merged(outputs)
        writer.add_topic(topics.FOOT_PATH, PATH)
        stamp = int(result.stamp_ns[-1])
        writer.write_raw(topics.FOOT_PATH, PATH, stamp, step_path(result.strides, stamp))
        for stamp, path in run_.smoothed:
            writer.write_raw(topics.FOOT_SMOOTHED_PATH, PATH, stamp, path)
        write_report(writer.staging, report)
        if plot_source is not None:
            plot_run(run_, writer.staging, plot_source)


def plot_run(run_: FootBagRun, directory: Path, source: Path) -> None:
    """The path against the truth (``directory/path.png``) and, when smoothing, the
    smoothed trajectory's (``directory/smoothing.png``): pdr_ins_ekf.plots."""
    from pdr_ins_ekf import plots

    result, t_s = run_.result, run_.t_s
    plots.path_png(t_s, result.output.position, run_.truth, directory / "path.png", source,
                   steps=int(np.sum(result.stance[:-1] & ~result.stance[1:])),
                   shows="the foot navigator")
    if result.smoothed is not None:
        plots.smoothing_png(t_s, result, directory / "smoothing.png")


def run(bag: Path, options: FootOptions = FootOptions(), out: Path | None = None,
        warn: Callable[[str], None] | None = None) -> dict:
    """``pdr-ekf run`` in Python: navigate ``bag`` (:func:`navigate_bag`; ``warn``, when
    given, is told the input's problems as soon as they are found), report
    (:func:`report_of`) and, when ``out`` is given, write it (:func:`write_run`, the plots
    with ``options.plot``); the report, as ``out/report.json`` holds it. Prints nothing."""
    bag = Path(bag)
    run_ = navigate_bag(bag, options_config(options), options, warn)
    report = report_of(run_)
    if out is not None:
        write_run(run_, report, Path(out), overwrite=options.overwrite,
                  plot_source=bag if options.plot else None)
    return report
