"""The drift part of ``pdr-pocket run --drift``'s report against the simulator's truth.

- landmarks detected against ``ground_truth/landmarks``: a detection matches the true
  landmark of the same type nearest in time within :data:`MATCH_S` (one each);
- associations, correct when the two matched true landmarks are the same place: one is
  the other's ``revisit_of`` (the simulation record), or they share their revisited one;
- the final yaw and position errors with the corrections and without (a run without).
"""
from __future__ import annotations

import numpy as np

from pdr_core.io.batch import MessageBatch
from pdr_core.maths.angles import wrap_angle
from pdr_drift.drift_log import DriftLog

MATCH_S = 10.0


def match_landmarks(log: DriftLog, truth: MessageBatch, t0_ns: int) -> dict[int, int]:
    """Detected landmark id → true landmark id."""
    true_t = (truth.stamp_ns - t0_ns) * 1e-9
    taken: set[int] = set()
    out = {}
    for mark in log.landmarks:
        gaps = np.where(truth["type"] == mark.type, np.abs(true_t - mark.t), np.inf)
        for k in np.argsort(gaps):
            if gaps[k] > MATCH_S:
                break
            if int(truth["id"][k]) not in taken:
                out[mark.id] = int(truth["id"][k])
                taken.add(out[mark.id])
                break
    return out


def place_of(true_id: int, revisits: dict[int, int | None]) -> int:
    """The first visit a true landmark revisits, or itself."""
    first = revisits.get(true_id)
    return true_id if first is None else first


def truth_report(log: DriftLog, truth: MessageBatch, record_landmarks: list[dict],
                 t0_ns: int) -> dict:
    matched = match_landmarks(log, truth, t0_ns)
    revisits = {int(m["id"]): m.get("revisit_of") for m in record_landmarks}
    correct = [d.landmark_first in matched and d.landmark_revisit in matched and
               place_of(matched[d.landmark_first], revisits) ==
               place_of(matched[d.landmark_revisit], revisits) for d in log.drifts]
    return {"true_landmarks": len(truth), "landmarks_matched": len(matched),
            "false_landmarks": len(log.landmarks) - len(matched),
            "missed_landmarks": len(truth) - len(matched),
            "associations_correct": int(sum(correct)),
            "associations_wrong": len(correct) - int(sum(correct))}


def final_errors(attitude_yaw: np.ndarray, true_yaw: np.ndarray, position: np.ndarray,
                 true_position: np.ndarray) -> dict:
    """Yaw [deg] and position [m] errors at the end."""
    yaw = float(np.degrees(wrap_angle(attitude_yaw[-1] - true_yaw[-1])))
    return {"final_yaw_error_deg": yaw,
            "final_position_error_m": float(np.linalg.norm(position[-1] - true_position[-1]))}
