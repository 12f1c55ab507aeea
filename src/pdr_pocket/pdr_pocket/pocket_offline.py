"""The pocket navigator on a whole bag: ``pdr-pocket run``'s outputs and report.

- :func:`step_batches`: ``pdr/pocket/step`` (pdr_msgs/Step), ``pdr/pocket/pose``
  (geometry_msgs/PoseWithCovarianceStamped, the thigh's attitude and the position with
  its covariance) at each step's confirmation, stamped with the IMU sample that
  confirmed it, as the live node publishes them;
- :func:`navigation_report`: without truth, steps, footfalls, the distance walked (sum of
  the strides, ``step_distance_m``), height gained and lost, floors, and the walk's
  ``duration_s``, ``distance_m`` and ``loop_gap_m`` of :func:`pdr_core.metrics.walk_figures`
  (from the first IMU sample and the origin to the last step's confirmation, the stamp
  of its messages: ``pdr-drift run`` gives the same figures for the same walk); with
  ``ground_truth/pose`` ``distance_m`` is the true path's and the error metrics of
  pdr_core.metrics on the per-step positions replace the loop gap; with
  ``ground_truth/step`` (the simulator's) steps matched, missed and false (a true step is
  found when one detection falls within its cycle), the activity confusion matrix, the
  distance error % (Muñoz Díaz 2016, Table 4.4: total estimated over total true), the
  riser height error % per staircase (Table 4.5) and the floor error. Every field, its
  unit and when it is there: docs/reports.md;
- :func:`run_record`: what ``pdr-pocket evaluate`` (pdr_pocket.evaluation) needs beyond
  the messages, kept in the output's metadata.yaml.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from pdr_core.batch import MessageBatch
from pdr_core.frames import MAP_FRAME
from pdr_core.metrics import error_report
from pdr_core.msgtypes import POSE_WITH_COVARIANCE_STAMPED, STEP
from pdr_core.rotations import quaternion_from_orthonormal
from pdr_pocket.activity import ACTIVITY_NAMES
from pdr_pocket.compiled_gait import CHANGES
from pdr_pocket.navigator import NavigatorOutput, StepRecord
from pdr_pocket.stairs import Staircases
from pdr_pocket.step_length import height_scale

STEP_TOPIC, POSE_TOPIC, PATH_TOPIC = "/pdr/pocket/step", "/pdr/pocket/pose", "/pdr/pocket/path"


def step_stamps(steps: list[StepRecord], stamp_ns: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The IMU stamp [ns] of the sample that confirmed each step."""
    confirms = np.array([s.t_confirm for s in steps])
    return stamp_ns[np.clip(np.searchsorted(t, confirms), 0, len(t) - 1)]


def step_fields(steps: list[StepRecord]) -> dict[str, np.ndarray]:
    return {"index": np.array([s.index for s in steps], np.uint32),
            "length": np.array([s.length for s in steps]),
            "vertical_displacement": np.array([s.vertical_displacement for s in steps]),
            "heading": np.array([s.heading for s in steps]),
            "pitch_max": np.array([s.pitch_max for s in steps]),
            "pitch_min": np.array([s.pitch_min for s in steps]),
            "pitch_amplitude": np.array([s.pitch_amplitude for s in steps]),
            "duration": np.array([s.duration for s in steps]),
            "activity": np.array([s.activity for s in steps], np.uint8)}


def pose_fields(steps: list[StepRecord], attitude: np.ndarray) -> dict[str, np.ndarray]:
    """Position and covariance (x, y, z block; orientation variances unknown: −1 on the
    diagonal per REP-145 would be read as "no orientation", so the attitude filter's are
    not repeated here and the block is left 0) and the sensor attitude (N, 3, 3)."""
    cov = np.zeros((len(steps), 6, 6))
    cov[:, :3, :3] = np.reshape([s.covariance for s in steps], (-1, 3, 3))
    return {"pose.pose.position": np.array([s.position for s in steps]).reshape(-1, 3),
            "pose.pose.orientation": quaternion_from_orthonormal(attitude),
            "pose.covariance": cov.reshape(-1, 36)}


def step_batches(out: NavigatorOutput, stamp_ns: np.ndarray) -> dict[str, MessageBatch]:
    steps, t = out.steps, out.attitude.t
    stamps = step_stamps(steps, stamp_ns, t)
    at = np.clip(np.searchsorted(t, [s.t_confirm for s in steps]), 0, len(t) - 1)
    return {STEP_TOPIC: MessageBatch(STEP, stamps, MAP_FRAME, step_fields(steps)),
            POSE_TOPIC: MessageBatch(POSE_WITH_COVARIANCE_STAMPED, stamps, MAP_FRAME,
                                     pose_fields(steps, out.attitude.attitude[at]))}


def _step_positions(steps: list[StepRecord]) -> np.ndarray:
    return np.vstack([np.zeros(3), *(s.position for s in steps)])


def summary(steps: list[StepRecord], staircases: Staircases, footfalls: int | None = None
            ) -> dict:
    """What a walk without truth tells: steps, footfalls (those counted, or None: two per
    step), distance, height, floors, staircases."""
    z = np.diff(_step_positions(steps)[:, 2])
    return {"steps": len(steps),
            "footfalls": 2 * len(steps) if footfalls is None else footfalls,
            "step_distance_m": float(sum(s.length for s in steps)),
            "height_gained_m": float(z[z > 0].sum()), "height_lost_m": float(0.0 - z[z < 0].sum()),
            "final_floor": steps[-1].floor if steps else 0,
            "highest_floor": max((s.floor for s in steps), default=0),
            "activities": {name: int(sum(s.activity == i for s in steps))
                           for i, name in enumerate(ACTIVITY_NAMES)},
            "staircases": [{"direction": ACTIVITY_NAMES[c.direction], "steps": len(c.steps),
                            "riser_m": c.riser_m, "height_m": c.height_m}
                           for c in staircases.done]}


def match_steps(detected_t: np.ndarray, true_end: np.ndarray, true_duration: np.ndarray
                ) -> np.ndarray:
    """For each true step the index of the detection within its cycle (−1: missed); a
    second detection in one cycle counts as false."""
    owner = np.searchsorted(true_end, detected_t, side="left")
    inside = (owner < len(true_end)) & (detected_t > true_end[np.minimum(owner, len(true_end) - 1)]
                                        - true_duration[np.minimum(owner, len(true_end) - 1)])
    match = np.full(len(true_end), -1)
    for k in np.flatnonzero(inside)[::-1]:
        match[owner[k]] = k
    return match


def steps_since(steps: list[StepRecord], true_end: np.ndarray, true_duration: np.ndarray,
                since_s: float) -> tuple[list[StepRecord], np.ndarray]:
    """The true gait cycles ending after ``since_s`` [s], the detected steps inside their
    span and the :func:`match_steps` of the two (a step in the first cycle's span, before
    ``since_s``, is not counted false)."""
    later = true_end > since_s
    first = (true_end - true_duration)[later][0]
    kept = [s for s in steps if s.t > first]
    return kept, match_steps(np.array([s.t for s in kept]), true_end[later],
                             true_duration[later])


def true_staircases(activity: np.ndarray, vertical: np.ndarray, end_s: np.ndarray
                    ) -> list[dict]:
    """Flights: runs of stairs steps of one direction, as
    :class:`~pdr_pocket.stairs.Staircases` groups the estimated ones."""
    book = Staircases()
    for i, (a, v, t) in enumerate(zip(activity, vertical, end_s, strict=True)):
        book.add(i, float(t), int(a), float(v))
    return [{"direction": c.direction, "start_s": c.start_s, "end_s": c.end_s,
             "riser_m": c.riser_m} for c in book.done]


def navigation_report(out_steps: list[StepRecord], staircases: Staircases,
                      truth_steps: MessageBatch | None, truth_positions: np.ndarray | None,
                      t0_ns: int, true_floors: tuple[int, int] | None = None,
                      footfalls: int | None = None) -> dict:
    """The report (module docstring; every field: docs/reports.md). ``truth_steps``:
    ground_truth/step, each true step's end stamped on the clock of ``t0_ns`` (the first
    IMU sample); ``truth_positions``: ground_truth/pose at the start and at each step's
    stamp (N + 1, 3); ``true_floors``: the final and the highest floor of the simulated
    walk; ``footfalls``: as :func:`summary`."""
    det_t = np.array([s.t for s in out_steps])
    confirmed = np.array([s.t_confirm for s in out_steps])
    report = summary(out_steps, staircases, footfalls) | error_report(
        np.r_[0.0, confirmed], _step_positions(out_steps), truth_positions)
    if truth_steps is None:
        return report
    end = (truth_steps.stamp_ns - t0_ns) * 1e-9
    match = match_steps(det_t, end, truth_steps["duration"])
    true_activity = truth_steps["activity"]
    matched = match >= 0
    est_activity = np.array([s.activity for s in out_steps], int)
    confusion = np.zeros((5, 5), int)
    np.add.at(confusion, (true_activity[matched], est_activity[match[matched]]), 1)
    true_distance = float(truth_steps["length"].sum())
    report |= {
        "true_steps": len(end), "matched_steps": int(matched.sum()),
        "missed_steps": int((~matched).sum()),
        "false_steps": int(len(det_t) - matched.sum()),
        "missed_pct": float(100 * (~matched).mean()) if len(end) else 0.0,
        "false_pct": float(100 * (len(det_t) - matched.sum()) / max(len(end), 1)),
        "activity_confusion": {"rows_true_columns_estimated": list(ACTIVITY_NAMES),
                               "matrix": confusion.tolist()},
        "activity_correct_pct": float(100 * np.trace(confusion) / max(matched.sum(), 1)),
        "true_step_distance_m": true_distance,
        "distance_error_pct": float(100 * (report["step_distance_m"] - true_distance)
                                    / true_distance) if true_distance else 0.0,
        "staircase_riser_error_pct": riser_errors(staircases, truth_steps, end),
    }
    if true_floors is not None:
        report["true_final_floor"], report["true_highest_floor"] = true_floors
        report["floor_error"] = report["final_floor"] - true_floors[0]
        report["highest_floor_error"] = report["highest_floor"] - true_floors[1]
    return report


def riser_errors(staircases: Staircases, truth_steps: MessageBatch, end: np.ndarray
                  ) -> list[dict]:
    """Each true staircase against the estimated one overlapping it most in time."""
    out = []
    for true in true_staircases(truth_steps["activity"], truth_steps["vertical_displacement"],
                                end):
        best = max(staircases.done, default=None, key=lambda c: min(c.end_s, true["end_s"])
                   - max(c.start_s, true["start_s"]))
        found = best is not None and best.direction == true["direction"] and \
            min(best.end_s, true["end_s"]) >= max(best.start_s, true["start_s"])
        out.append({"direction": ACTIVITY_NAMES[true["direction"]],
                    "true_riser_m": true["riser_m"],
                    "riser_m": best.riser_m if found else None,
                    "error_pct": 100 * (best.riser_m / true["riser_m"] - 1) if found else None})
    return out



def path_batch(steps: list[StepRecord], stamps: np.ndarray) -> MessageBatch:
    """The steps' poses as a PoseStamped batch for ``pdr/pocket/path``."""
    from pdr_core.msgtypes import POSE_STAMPED

    quat = np.zeros((len(steps), 4))
    quat[:, 2], quat[:, 3] = np.sin([s.heading / 2 for s in steps]), \
        np.cos([s.heading / 2 for s in steps])
    return MessageBatch(POSE_STAMPED, stamps, MAP_FRAME, {
        "pose.position": np.array([s.position for s in steps]).reshape(-1, 3),
        "pose.orientation": quat})


def true_floors(record: dict) -> tuple[int, int] | None:
    """The final and the highest floor of a simulated walk (its ``pdr.simulation``
    record), None when the record does not tell."""
    marks = record.get("landmarks")
    if not marks:
        return (0, 0) if record.get("placement") == "pocket" else None
    floors = [m["floor"] for m in marks]
    return floors[-1], max(0, *floors)


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
    errors with and without the corrections (pdr_pocket.drift_report)."""
    from scipy.spatial.transform import Rotation

    from pdr_core import topics
    from pdr_core.metrics import truth_orientation_at
    from pdr_pocket.drift_report import final_errors, truth_report

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


def run_bag(bag: Path, out: Path, config, mag_calibration: Path | None = None, *,
            plot: bool = False, overwrite: bool = False, drift: str = "none",
            drift_config=None, strict: bool = False) -> dict:
    """``pdr-pocket run``: navigate ``bag`` and write ``out`` (module docstring); with
    ``drift`` online or offline, with the landmark drift corrections
    (pdr_pocket.drift_loop)."""
    from pdr_core import topics
    from pdr_core.bag import BagWriter
    from pdr_core.metrics import truth_at
    from pdr_core.msgtypes import PATH
    from pdr_core.nav_path import encode_path
    from pdr_pocket.attitude_offline import attitude_batches, read_pocket_bag
    from pdr_pocket.navigator import PocketNavigator

    reader, batches, inputs = read_pocket_bag(bag, mag_calibration
                                              or config.magnetometer_calibration, strict=strict)
    drift_log = None
    if drift == "none":
        navigator = PocketNavigator(config)
        result = navigator.process(inputs.t, inputs.gyro_or_none, inputs.accel, inputs.mag)
    else:
        from pdr_drift.config import DriftConfig
        from pdr_pocket.drift_loop import navigate_offline, navigate_online

        loop = navigate_online if drift == "online" else navigate_offline
        navigator, result, drift_log = loop(config, drift_config or DriftConfig(), inputs.t,
                                            inputs.gyro_or_none, inputs.accel, inputs.mag)
    steps = result.steps
    stamps = step_stamps(steps, inputs.stamp_ns, inputs.t)
    truth_steps = batches.get(topics.GROUND_TRUTH_STEP)
    truth_pose = batches.get(topics.GROUND_TRUTH_POSE)
    truth_positions = None
    if truth_pose is not None:
        truth_positions = truth_at(truth_pose, np.r_[inputs.stamp_ns[0], stamps])
    record = reader.custom_data("pdr.simulation") or {}
    report = navigation_report(steps, navigator.staircases, truth_steps, truth_positions,
                               int(inputs.stamp_ns[0]), true_floors(record),
                               navigator.footfalls)
    report |= {"samples": len(inputs.t), "dropped": inputs.counts,
               "mounting_changes": int(navigator.mounting.scalars[CHANGES]),
               "detection": navigator.detection(),
               "step_length": {"model": config.step_length.model,
                               "calibrated": config.step_length.calibrated,
                               "height_m": config.person.height_m,
                               "scale": height_scale(config.step_length, config.person.height_m)},
               "warnings": [w for w in (navigator.no_step_reason(),) if w is not None]}
    if drift_log is not None:
        report["drift"] = {"mode": drift, **drift_log.summary()}
        if truth_steps is not None and topics.GROUND_TRUTH_LANDMARKS in batches:
            report["drift"] |= _drift_against_truth(
                drift_log, reader, batches, inputs, result, truth_positions,
                PocketNavigator(config).process(inputs.t, inputs.gyro_or_none, inputs.accel,
                                                inputs.mag))
    import yaml

    record_text = yaml.safe_dump(run_record(
        steps, batches[topics.IMU_DATA].stamp_ns, int(inputs.stamp_ns[0]), navigator.footfalls,
        config.stairs.floor_height_m), default_flow_style=None, sort_keys=False)
    with BagWriter(out, overwrite=overwrite, custom_data={RUN_RECORD: record_text}) as writer:
        writer.write_merged(attitude_batches(inputs, result.attitude,
                                             navigator.orientation.params.gyro_noise_var)
                            | step_batches(result, inputs.stamp_ns))
        if steps:
            writer.write_raw(PATH_TOPIC, PATH, int(stamps[-1]),
                             encode_path(path_batch(steps, stamps), int(stamps[-1]), MAP_FRAME))
        (writer.staging / "report.json").write_text(json.dumps(report, indent=2) + "\n")
        if plot:
            from pdr_pocket import plots
            positions = _step_positions(steps)
            covariances = np.concatenate([
                np.zeros((1, 3, 3)), np.array([s.covariance for s in steps]).reshape(-1, 3, 3)])
            activity = np.r_[0, [s.activity for s in steps]].astype(int)
            true_t = None if truth_steps is None else \
                (truth_steps.stamp_ns - inputs.stamp_ns[0]) * 1e-9
            plots.navigation_png(positions, covariances, activity,
                                 None if truth_positions is None
                                 else truth_positions - truth_positions[0],
                                 inputs.t, np.degrees(result.pitch),
                                 np.array([s.t for s in steps]), true_t,
                                 writer.staging / "path.png", bag, *_drift_marks(drift_log),
                                 final_error_m=report.get("final_error_m"),
                                 loop_gap_m=report.get("loop_gap_m"))
    return report
