"""The report of a pocket navigator's run, and its figures against a truth.

- :func:`navigation_report`: without truth, steps, footfalls, the distance walked (sum of
  the strides, ``step_distance_m``), height gained and lost, floors (:func:`summary`),
  and the walk's ``duration_s``, ``distance_m`` and ``loop_gap_m`` of
  :func:`pdr_core.evaluation.metrics.walk_figures` (from the first IMU sample and the origin to the
  last step's confirmation, the stamp of its messages: ``pdr-drift run`` gives the same
  figures for the same walk); with ``ground_truth/pose`` ``distance_m`` is the true
  path's and the error metrics of pdr_core.evaluation.metrics on the per-step positions replace the
  loop gap; with ``ground_truth/step`` (the simulator's) steps matched, missed and false
  (a true step is found when one detection falls within its cycle, :func:`match_steps`),
  the activity confusion matrix, the distance error % (Muñoz Díaz 2016, Table 4.4: total
  estimated over total true), the riser height error % per staircase (Table 4.5,
  :func:`riser_errors`) and the floor error. Every field, its unit and when it is there:
  docs/reports.md;
- :func:`attitude_report`: ``pdr-pocket attitude``'s roll, pitch and yaw RMSE, the tilt
  and the heading error (pdr_core.evaluation.attitude_metrics) against ``ground_truth/pose``, the
  gyro bias estimates and their final errors against the simulation's true biases, and
  the share of samples each update ran.
"""
from __future__ import annotations

import numpy as np

from pdr_core.evaluation.attitude_metrics import (
    HEADING_REFERENCE_S,
    error_summary,
    heading_error,
    level_axis,
    tilt_error,
)
from pdr_core.evaluation.consistency import (
    attitude_consistency,
    checkpoints,
    consistency_report,
    has_attitude,
)
from pdr_core.evaluation.metrics import error_report
from pdr_core.io.batch import MessageBatch
from pdr_core.maths.angles import wrap_angle
from pdr_core.vocabulary import ACTIVITY_NAMES, Activity
from pdr_pocket.compiled_orientation_data import ATT_ROWS
from pdr_pocket.inputs import PocketInputs
from pdr_pocket.messages import step_positions
from pdr_pocket.orientation import AttitudeEstimate
from pdr_pocket.records import StepRecord
from pdr_pocket.stairs import Staircases


def summary(steps: list[StepRecord], staircases: Staircases, footfalls: int | None = None
            ) -> dict:
    """What a walk without truth tells: steps, footfalls (those counted, or None: two per
    step), distance, height, floors, staircases."""
    z = np.diff(step_positions(steps)[:, 2])
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


def step_consistency(steps: list[StepRecord], truth_positions: np.ndarray) -> dict:
    """The report's ``consistency`` (pdr_core.evaluation.consistency): the position NEES of the
    first step confirmed in each second, with the covariance ``pdr/pocket/pose`` publishes,
    against ``truth_positions`` (N + 1, 3) [m] at the start and at each step's stamp."""
    at = checkpoints(np.r_[0.0, [s.t_confirm for s in steps]])
    cov = np.reshape([s.covariance for s in steps], (-1, 3, 3))[at - 1]
    return consistency_report(step_positions(steps), truth_positions, at, cov)


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
        np.r_[0.0, confirmed], step_positions(out_steps), truth_positions)
    if truth_positions is not None:
        report["consistency"] = step_consistency(out_steps, truth_positions)
    if truth_steps is None:
        return report
    end = (truth_steps.stamp_ns - t0_ns) * 1e-9
    match = match_steps(det_t, end, truth_steps["duration"])
    true_activity = truth_steps["activity"]
    matched = match >= 0
    est_activity = np.array([s.activity for s in out_steps], int)
    confusion = np.zeros((len(Activity), len(Activity)), int)
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


def true_floors(record: dict) -> tuple[int, int] | None:
    """The final and the highest floor of a simulated walk (its ``pdr.simulation``
    record: the landmarks' floors, and the lift rides' floors after the last landmark
    before them), None when the record does not tell."""
    marks = record.get("landmarks")
    if not marks:
        return (0, 0) if record.get("placement") == "pocket" else None
    events = sorted([(m.get("time_s", 0.0), "at", m["floor"]) for m in marks] +
                    [(r["end_s"], "by", r["floors"]) for r in record.get("lift_rides", [])])
    floor, floors = 0, [0]
    for _, kind, value in events:
        floor = value if kind == "at" else floor + value
        floors.append(floor)
    return floor, max(floors)


def attitude_errors(estimate: AttitudeEstimate, truth_quat: np.ndarray) -> np.ndarray:
    """Roll, pitch, yaw of the estimate minus the truth's [rad], wrapped, (N, 3)."""
    from scipy.spatial.transform import Rotation

    truth = Rotation.from_quat(truth_quat).as_euler("ZYX")[:, ::-1]
    return wrap_angle(estimate.euler - truth)


def truth_heading_error(estimate: AttitudeEstimate, truth_quat: np.ndarray) -> np.ndarray:
    """The heading error [rad] of pdr_core.evaluation.attitude_metrics (the truth's most level body
    axis, relative to the first seconds), (N,)."""
    from scipy.spatial.transform import Rotation

    return heading_error(estimate.t, estimate.attitude,
                         Rotation.from_quat(truth_quat).as_matrix())


def attitude_report(inputs: PocketInputs, estimate: AttitudeEstimate,
                    truth_quat: np.ndarray | None,
                    true_bias_radps: np.ndarray | None) -> dict:
    """The report of ``pdr-pocket attitude`` (angles in degrees, biases in °/s): the
    updates that ran and the detectors' shares, the bias estimates (final, with σ, and
    the largest |b| of the walk), and with a truth the roll, pitch and yaw RMSE and final
    errors, the tilt error and the heading error of pdr_core.evaluation.attitude_metrics (every
    field: docs/reports.md)."""
    report: dict = {"samples": len(inputs.t), "duration_s": float(inputs.t[-1]),
                    "dropped": inputs.counts,
                    "update_fraction": estimate.fraction_ran(),
                    "detector_fraction": {name: float(estimate.detector(name).mean())
                                          for name in estimate.detector_names},
                    "saturated_fraction": float(estimate.detector("saturated").mean()),
                    "final_bias_deg_per_s": np.degrees(estimate.bias[-1]).tolist(),
                    "final_bias_sigma_deg_per_s": np.degrees(estimate.bias_sigma[-1]).tolist(),
                    "largest_bias_deg_per_s": np.degrees(
                        np.abs(estimate.bias).max(axis=0)).tolist()}
    if truth_quat is not None:
        from scipy.spatial.transform import Rotation

        err = np.degrees(attitude_errors(estimate, truth_quat))
        report["rmse_deg"] = dict(zip(("roll", "pitch", "yaw"),
                                      np.sqrt(np.mean(err**2, axis=0)).tolist(), strict=True))
        report["final_error_deg"] = dict(zip(("roll", "pitch", "yaw"), err[-1].tolist(),
                                             strict=True))
        truth = Rotation.from_quat(truth_quat).as_matrix()
        report["tilt_error"] = error_summary(tilt_error(estimate.attitude, truth))
        report["heading_error"] = {"axis": "xyz"[level_axis(truth)],
                                   "reference_s": HEADING_REFERENCE_S} | error_summary(
            truth_heading_error(estimate, truth_quat))
        if has_attitude(truth_quat):
            report["consistency"] = attitude_consistency(
                estimate.t, estimate.attitude, estimate.covariance[:, ATT_ROWS, ATT_ROWS],
                truth)
    if true_bias_radps is not None:
        report["final_bias_error_deg_per_s"] = np.degrees(
            estimate.bias[-1] - np.asarray(true_bias_radps)).tolist()
    return report
