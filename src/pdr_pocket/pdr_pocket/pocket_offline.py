"""``pdr-pocket run``: the pocket navigator on a whole bag, with or without the landmark
drift corrections, writing its messages (:mod:`pdr_pocket.messages`), its report
(:mod:`pdr_pocket.run_report`, and the drift's against the truth,
:mod:`pdr_drift.drift_report`) and optionally its plot.

- :func:`run`: the Python entry point, ``pdr-eval``'s and the CLI's: a bag and its
  :class:`PocketOptions` in, the report out (the dict ``report.json`` holds), the outputs
  written to ``out`` when it is given. It prints nothing and sets no process-wide state
  (no stdout, no working directory, no global configuration): the CLI prints its
  warnings, its refusal and its report. Three jobs: :func:`navigate_bag` (the navigator
  on the bag, a :class:`PocketRun`), :func:`report_of` (what it gave) and
  :func:`write_run` (the messages, the report and the plot, :func:`plot_run`). Its input
  is checked first (pdr_core.walking.walk_plausibility: a median |f| no walk gives, a swing many
  times a thigh's): each problem a warning, the first of the report's, or with ``strict``
  an InputError. A phone that is not in a
  pocket (pdr_pocket.placement's verdict) is refused: its report and attitude are
  written, no step, pose or path (``report["refused"]``; the CLI exits
  pdr_core.walking.walk_plausibility.EXIT_REFUSED, 3);
- :func:`run_record`: what ``pdr-pocket evaluate`` (pdr_pocket.evaluation) needs beyond
  the messages, kept in the output's metadata.yaml;
- :func:`magnetometer_use`: the report's ``inputs.magnetometer`` (``inputs.barometer``:
  pdr_pocket.height_records.BarometerStatus).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from pdr_core.frames import MAP_FRAME
from pdr_core.report_files import write_report
from pdr_core.walking.walk_plausibility import (
    implausible_input,
    specific_force_problem,
    swing_problem,
)
from pdr_pocket.compiled_mounting import CHANGES
from pdr_pocket.inputs import PocketInputs
from pdr_pocket.messages import (
    attitude_batches,
    path_batch,
    step_batches,
    step_positions,
    step_stamps,
    step_tf,
)
from pdr_pocket.orientation import AttitudeEstimate
from pdr_pocket.placement import NOT_IN_POCKET, placement_summary
from pdr_pocket.records import NavigatorOutput, StepRecord
from pdr_pocket.run_report import navigation_report, true_floors
from pdr_pocket.stairs import Staircases
from pdr_pocket.step_length import height_scale


def _drift_marks(log) -> tuple:
    """Landmark positions (N, 3) and the associations' pairs of positions, for the plot."""
    if log is None:
        return None, []
    by_id = {m.id: m for m in log.landmarks}
    marks = np.array([m.position for m in log.landmarks]).reshape(-1, 3)
    pairs = [(by_id[d.landmark_first].position, by_id[d.landmark_revisit].position)
             for d in log.drifts]
    return marks, pairs


def _drift_against_truth(log, reader, truth, inputs, corrected, truth_positions,
                         uncorrected) -> dict:
    """Landmarks and associations against the truth, and the final yaw and position
    errors with and without the corrections (pdr_drift.drift_report)."""
    from scipy.spatial.transform import Rotation

    from pdr_core import topics
    from pdr_core.evaluation.metrics import truth_orientation_at
    from pdr_drift.drift_report import final_errors, truth_report

    record = reader.custom_data("pdr.simulation") or {}
    out = truth_report(log, truth[topics.GROUND_TRUTH_LANDMARKS], record.get("landmarks", []),
                       int(inputs.stamp_ns[0]))
    true_yaw = Rotation.from_quat(truth_orientation_at(
        truth[topics.GROUND_TRUTH_POSE], inputs.stamp_ns)).as_euler("ZYX")[:, 0]
    relative = truth_positions[1:] - truth_positions[0]
    for name, run_ in (("corrected", corrected), ("uncorrected", uncorrected)):
        position = np.array([s.position for s in run_.steps])
        out[name] = final_errors(run_.attitude.euler[:, 2], true_yaw, position, relative)
    return out


RUN_RECORD = "pdr.pocket_run"
# the orientation filters' updates that use the magnetometer (pdr_pocket.orientation)
MAGNETIC_UPDATES = ("field", "absolute_magnetic", "differential_magnetic", "compass")


def magnetometer_use(inputs: PocketInputs, attitude: AttitudeEstimate) -> str:
    """``absent`` (no reading), ``fused`` (a magnetic update ran) or ``not fused``."""
    if not np.isfinite(inputs.mag).any():
        return "absent"
    ran = attitude.fraction_ran()
    return "fused" if any(ran.get(name, 0.0) > 0 for name in MAGNETIC_UPDATES) else "not fused"


def refused(result: NavigatorOutput) -> NavigatorOutput:
    """The output of a walk refused: its attitude, no step."""
    return NavigatorOutput(result.attitude, result.pitch, result.heading, result.activity, [])


def run_record(steps: list[StepRecord], imu_stamp_ns: np.ndarray, start_ns: int,
               footfalls: int, floor_height_m: float) -> dict:
    """What a run knows that its messages do not carry, for ``pdr-pocket evaluate``: kept
    in the output bag's metadata.yaml (custom_data :data:`RUN_RECORD`).

    - ``start_ns``: the walk's start, the first IMU sample used [ns];
    - ``end_ns``: the last IMU message's stamp [ns];
    - ``input_first_ns``: the input's first ``imu/data`` message's stamp [ns], where a
      CSV log exported from a bag (``pdr-sim export-csv``) has t = 0;
    - ``footfalls``: as :func:`summary`;
    - ``floor_height_m``: the configuration's, for each step's floor [m];
    - ``step_t_s``: each step's pitch maximum from ``start_ns`` [s] (its messages are
      stamped at its confirmation, later).
    """
    return {"start_ns": int(start_ns), "end_ns": int(imu_stamp_ns[-1]),
            "input_first_ns": int(imu_stamp_ns[0]), "footfalls": int(footfalls),
            "floor_height_m": float(floor_height_m),
            "step_t_s": [float(s.t) for s in steps]}


@dataclass
class PocketRun:
    """What the navigator made of a bag (:func:`navigate_bag`): the bag's ``reader``, its
    topics read (``batches``) and the navigator's ``inputs``; the ``navigator`` after the
    walk, its ``result`` (no step when the walk is refused) and the ``drift_log`` (None
    without the drift loop); the ``placement`` found, the input's ``problems`` and whether
    the walk is ``refused``; each step's stamp [ns] and the true positions at the start
    and at each step (None without a truth)."""

    reader: Any
    batches: dict
    inputs: PocketInputs
    navigator: Any
    result: NavigatorOutput
    drift_log: Any
    placement: dict
    problems: list[str]
    refused: bool
    stamps: np.ndarray
    truth_positions: np.ndarray | None

    @property
    def truth_steps(self):
        """ground_truth/step (None: none)."""
        from pdr_core import topics
        return self.batches.get(topics.GROUND_TRUTH_STEP)


def navigate_bag(bag: Path, config, mag_calibration: Path | None = None, *,
                 drift: str = "none", drift_config=None, strict: bool = False) -> PocketRun:
    """The pocket navigator on ``bag``: with ``drift`` online or offline, with the
    landmark drift corrections (pdr_pocket.drift_loop); its input checked (module
    docstring). Nothing is written: :func:`report_of` says what it gave."""
    from pdr_core import topics
    from pdr_core.evaluation.metrics import truth_at
    from pdr_pocket.inputs import read_pocket_bag
    from pdr_pocket.navigator import PocketNavigator

    reader, batches, inputs = read_pocket_bag(bag, mag_calibration
                                              or config.magnetometer_calibration, strict=strict)
    drift_log = None
    if drift == "none":
        navigator = PocketNavigator(config)
        result = navigator.process(inputs.samples)
    else:
        from pdr_drift.config import DriftConfig
        from pdr_pocket.drift_loop import navigate_offline, navigate_online

        loop = navigate_online if drift == "online" else navigate_offline
        navigator, result, drift_log = loop(config, drift_config or DriftConfig(),
                                            inputs.samples)
    placement = placement_summary(navigator)
    problems = implausible_input(bag, [specific_force_problem(inputs.t, inputs.accel),
                                       swing_problem(placement["swing_ratio"])], strict)
    refusal = placement["placement"] == NOT_IN_POCKET
    if refusal:
        result = refused(result)
    stamps = step_stamps(result.steps, inputs.stamp_ns, inputs.t)
    truth_pose = batches.get(topics.GROUND_TRUTH_POSE)
    truth_positions = None if truth_pose is None else \
        truth_at(truth_pose, np.r_[inputs.stamp_ns[0], stamps])
    return PocketRun(reader, batches, inputs, navigator, result, drift_log, placement,
                     problems, refusal, stamps, truth_positions)


def report_of(run: PocketRun, config, drift: str = "none") -> dict:
    """The report of a run (pdr_pocket.run_report; every field: docs/reports.md), with
    the drift's against the truth when the bag has one."""
    from pdr_core import topics
    from pdr_pocket.navigator import PocketNavigator

    navigator, inputs, steps = run.navigator, run.inputs, run.result.steps
    footfalls = 0 if run.refused else navigator.footfalls
    report = navigation_report(steps, Staircases() if run.refused else navigator.staircases,
                               run.truth_steps, run.truth_positions, int(inputs.stamp_ns[0]),
                               true_floors(run.reader.custom_data("pdr.simulation") or {}),
                               footfalls)
    report |= {"refused": run.refused, "samples": len(inputs.t), "dropped": inputs.counts,
               "mounting_changes": int(navigator.mounting.scalars[CHANGES]),
               "detection": navigator.detection(),
               "placement": run.placement,
               "inputs": {"magnetometer": magnetometer_use(inputs, run.result.attitude),
                          "barometer": navigator.barometer_status().as_dict()},
               "stairs_refused": dict(navigator.staircases.check.refused),
               "step_length": {"model": config.step_length.model,
                               "calibrated": config.step_length.calibrated,
                               "height_m": config.person.height_m,
                               "scale": height_scale(config.step_length, config.person.height_m),
                               "bounded_steps": navigator.bounded_steps},
               "warnings": run.problems + ([] if run.refused else navigator.warnings())}
    if navigator.barometer() is not None:
        report["barometer"] = navigator.barometer()
    if run.drift_log is not None:
        report["drift"] = {"mode": drift, **run.drift_log.summary()}
        if run.truth_steps is not None and topics.GROUND_TRUTH_LANDMARKS in run.batches:
            report["drift"] |= _drift_against_truth(
                run.drift_log, run.reader, run.batches, inputs, run.result,
                run.truth_positions, PocketNavigator(config).process(inputs.samples))
    return report


def write_run(run: PocketRun, report: dict, out: Path, floor_height_m: float, *,
              overwrite: bool = False, plot_source: Path | None = None) -> None:
    """The run's messages, its record (:func:`run_record`) and ``report`` into the bag
    ``out``; with ``plot_source`` (the input's name for the title), its plot too."""
    import yaml

    from pdr_core import topics
    from pdr_core.io.bag import BagWriter
    from pdr_core.io.msgtypes import PATH
    from pdr_core.io.nav_path import encode_path

    inputs, result, steps, stamps = run.inputs, run.result, run.result.steps, run.stamps
    record_text = yaml.safe_dump(run_record(
        steps, run.batches[topics.IMU_DATA].stamp_ns, int(inputs.stamp_ns[0]),
        report["footfalls"], floor_height_m), default_flow_style=None, sort_keys=False)
    with BagWriter(out, overwrite=overwrite, custom_data={RUN_RECORD: record_text}) as writer:
        writer.write_merged(attitude_batches(inputs, result.attitude,
                                             run.navigator.gyro_noise_var)
                            | step_batches(result, inputs.stamp_ns)
                            | step_tf(result, inputs.stamp_ns))
        if steps:
            writer.write_raw(topics.POCKET_PATH, PATH, int(stamps[-1]),
                             encode_path(path_batch(steps, stamps), int(stamps[-1]), MAP_FRAME))
        write_report(writer.staging, report)
        if plot_source is not None:
            plot_run(run, report, writer.staging / "path.png", plot_source)


def plot_run(run: PocketRun, report: dict, path: Path, source: Path) -> None:
    """The run's path, pitch and steps (pdr_pocket.plots.navigation_png) into ``path``."""
    from pdr_pocket import plots

    steps, inputs, truth_steps = run.result.steps, run.inputs, run.truth_steps
    covariances = np.concatenate([
        np.zeros((1, 3, 3)), np.array([s.covariance for s in steps]).reshape(-1, 3, 3)])
    activity = np.r_[0, [s.activity for s in steps]].astype(int)
    true_t = None if truth_steps is None else \
        (truth_steps.stamp_ns - inputs.stamp_ns[0]) * 1e-9
    truth = None if run.truth_positions is None else \
        run.truth_positions - run.truth_positions[0]
    plots.navigation_png(step_positions(steps), covariances, activity, truth, inputs.t,
                         np.degrees(run.result.pitch), np.array([s.t for s in steps]),
                         true_t, path, source, *_drift_marks(run.drift_log),
                         final_error_m=report.get("final_error_m"),
                         loop_gap_m=report.get("loop_gap_m"), warnings=report["warnings"])


@dataclass(frozen=True)
class PocketOptions:
    """What ``pdr-pocket run`` takes beside the bag and ``--out``, each as its option of
    the same name: the YAML ``config`` (None: the installed config/pocket_pdr.yaml), the
    ``mag_calibration`` YAML (None: the configuration's), the ``drift`` corrections
    (none, online or offline) and their ``drift_config`` YAML (None: built in),
    ``strict`` (refuse input no walk gives, and damaged bags), ``plot`` and ``overwrite``
    (of ``out``), the ``step_calibration`` YAML (None: the configuration's)."""

    config: Path | None = None
    mag_calibration: Path | None = None
    drift: str = "none"
    drift_config: Path | None = None
    strict: bool = False
    plot: bool = False
    overwrite: bool = False
    step_calibration: Path | None = None


def run(bag: Path, options: PocketOptions = PocketOptions(), out: Path | None = None
        ) -> dict:
    """``pdr-pocket run`` in Python: navigate ``bag`` (:func:`navigate_bag`), report
    (:func:`report_of`) and, when ``out`` is given, write it (:func:`write_run`, the plot
    with ``options.plot``); the report, as ``out/report.json`` holds it. Prints nothing.
    A saved fit of the person's lines (``options.step_calibration``, else the
    configuration's) is applied to the configuration first (pdr_pocket.saved_lines), and
    the report's ``step_calibration`` says which lines it took."""
    from pdr_drift.config import load_drift_config
    from pdr_pocket.config import load_pocket_config
    from pdr_pocket.saved_lines import applied, fitted, read_fit

    bag = Path(bag)
    config = load_pocket_config(options.config)
    fit_path = options.step_calibration or config.step_calibration
    if fit_path is not None:
        fit = read_fit(fit_path)
        config = applied(config, fit, fit_path)
    run_ = navigate_bag(bag, config, options.mag_calibration, drift=options.drift,
                        drift_config=load_drift_config(options.drift_config),
                        strict=options.strict)
    report = report_of(run_, config, options.drift)
    if fit_path is not None:
        report["step_calibration"] = {"file": str(fit_path), "lines": list(fitted(fit))}
    if out is not None:
        write_run(run_, report, Path(out), config.stairs.floor_height_m,
                  overwrite=options.overwrite, plot_source=bag if options.plot else None)
    return report
