"""``pdr-drift run``: the offline drift correction of a pocket navigator's output
(Muñoz Díaz 2016, Section 6.2) from its steps and poses alone.

The steps (``pdr/pocket/step``) and poses (``pdr/pocket/pose``) of ``pdr-pocket run`` or
of ``pocket_pdr`` recorded by ``bag_record`` go through the drift estimator as the live
node sees them; every association's drift is collected, ε₀ (Eq. (6.5), outliers
rejected) is taken, and the path is integrated again from the steps (Eq. (5.1)) with each
step's heading less ε₀·t: a drift-compensated path without jumps. No IMU data is needed.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdr_core.bag import BagReader, BagWriter
from pdr_core.batch import MessageBatch
from pdr_core.errors import InputError
from pdr_core.msgtypes import DRIFT_ESTIMATE, LANDMARK, PATH, POSE_STAMPED
from pdr_core.nav_path import encode_path
from pdr_drift.config import DriftConfig
from pdr_drift.drift import DriftEstimate, offline_drift
from pdr_drift.landmarks import Landmark
from pdr_drift.streaming import StreamingDrift

STEP_TOPIC, POSE_TOPIC = "/pdr/pocket/step", "/pdr/pocket/pose"
LANDMARK_TOPIC, DRIFT_TOPIC = "/pdr/landmarks", "/pdr/drift"
CORRECTED_PATH_TOPIC = "/pdr/pocket/corrected_path"
MAP_FRAME = "map"


@dataclass
class OfflineResult:
    stamps: np.ndarray                  # of the steps [ns]
    before: np.ndarray                  # (N, 3) the navigator's positions
    after: np.ndarray                   # (N, 3) re-integrated with ε₀ taken off
    landmarks: list[tuple[int, Landmark]]
    drifts: list[tuple[int, DriftEstimate]]
    epsilon: float | None
    kept: list[DriftEstimate]


def correct(steps: MessageBatch, poses: MessageBatch, config: DriftConfig,
            floor_height_m: float) -> OfflineResult:
    """The drift estimator over the steps, ε₀ and the re-integrated path."""
    if len(steps) == 0:
        raise InputError(STEP_TOPIC, "no steps to correct")
    stream = StreamingDrift(config, floor_height_m)
    landmarks, drifts = [], []
    position = poses["pose.pose.position"]
    covariance = poses["pose.covariance"].reshape(-1, 6, 6)[:, :3, :3]
    pose_of = {int(s): i for i, s in enumerate(poses.stamp_ns)}
    for k, stamp in enumerate(steps.stamp_ns.tolist()):
        if stamp not in pose_of:
            continue
        stream.push_step(stamp, steps["heading"][k], int(steps["activity"][k]))
        i = pose_of[stamp]
        result = stream.push_pose(stamp, position[i], covariance[i])
        if result is not None:
            landmarks += [(stamp, m) for m in result.landmarks]
            drifts += [(stamp, d) for d in result.drifts]
    epsilon, kept = offline_drift([d for _, d in drifts],
                                  np.radians(config.max_drift_deg_per_s), config.outlier_spread)
    t = (steps.stamp_ns - steps.stamp_ns[0]) * 1e-9
    heading = steps["heading"] - (0.0 if epsilon is None else epsilon) * t
    moves = np.c_[steps["length"] * np.cos(heading), steps["length"] * np.sin(heading),
                  steps["vertical_displacement"]]
    before = np.array([position[pose_of[int(s)]] for s in steps.stamp_ns
                       if int(s) in pose_of])
    start = before[0] - np.r_[steps["length"][0] * np.cos(steps["heading"][0]),
                              steps["length"][0] * np.sin(steps["heading"][0]),
                              steps["vertical_displacement"][0]]
    return OfflineResult(steps.stamp_ns, before, start + np.cumsum(moves, axis=0), landmarks,
                         drifts, epsilon, kept)


def batches(result: OfflineResult) -> dict[str, MessageBatch]:
    marks = [m for _, m in result.landmarks]
    landmark = MessageBatch(LANDMARK, np.array([s for s, _ in result.landmarks], np.int64),
                            MAP_FRAME, {
        "id": np.array([m.id for m in marks], np.uint32),
        "type": np.array([m.type for m in marks], np.uint8),
        "position": np.array([m.position for m in marks]).reshape(-1, 3),
        "position_covariance": np.array([np.ravel(m.covariance) for m in marks]).reshape(-1, 9),
        "yaw_before": np.array([m.yaw_before for m in marks]),
        "yaw_after": np.array([m.yaw_after for m in marks]),
        "floor": np.array([m.floor for m in marks], np.int32)})
    estimates = [d for _, d in result.drifts]
    drift = MessageBatch(DRIFT_ESTIMATE, np.array([s for s, _ in result.drifts], np.int64),
                         MAP_FRAME, {
        "landmark_first": np.array([d.landmark_first for d in estimates], np.uint32),
        "landmark_revisit": np.array([d.landmark_revisit for d in estimates], np.uint32),
        "deviation": np.array([d.deviation for d in estimates]),
        "elapsed": np.array([d.elapsed for d in estimates]),
        "drift": np.array([d.drift for d in estimates]),
        "drift_variance": np.array([d.drift_variance for d in estimates])})
    return {LANDMARK_TOPIC: landmark, DRIFT_TOPIC: drift}


def _gap(path: np.ndarray) -> float:
    return float(np.linalg.norm(path[-1, :2] - path[0, :2]))


def report(result: OfflineResult) -> dict:
    moves = np.linalg.norm(np.diff(result.after, axis=0), axis=1)
    return {"duration_s": float((result.stamps[-1] - result.stamps[0]) * 1e-9),
            "distance_m": float(moves.sum()), "loop_gap_m": _gap(result.after),
            "steps": len(result.after), "landmarks": len(result.landmarks),
            "associations": len(result.drifts),
            "drift_deg_per_s": [float(np.degrees(d.drift)) for _, d in result.drifts],
            "kept": len(result.kept),
            "offline_drift_deg_per_s": None if result.epsilon is None
            else float(np.degrees(result.epsilon)),
            "loop_gap_before_m": _gap(result.before), "loop_gap_after_m": _gap(result.after),
            "largest_move_m": float(np.max(moves, initial=0.0))}


def run(bag: Path, out: Path, config: DriftConfig, floor_height_m: float, *,
        plot: bool = False, overwrite: bool = False) -> dict:
    reader = BagReader(bag)
    reader.require_topics([STEP_TOPIC, POSE_TOPIC])
    data = reader.read_batches([STEP_TOPIC, POSE_TOPIC])
    result = correct(data[STEP_TOPIC], data[POSE_TOPIC], config, floor_height_m)
    summary = report(result)
    quat = np.zeros((len(result.after), 4))
    quat[:, 3] = 1.0
    path = MessageBatch(POSE_STAMPED, result.stamps, MAP_FRAME,
                        {"pose.position": result.after, "pose.orientation": quat})
    with BagWriter(out, overwrite=overwrite) as writer:
        writer.write_merged({t: b for t, b in batches(result).items() if len(b)})
        stamp = int(result.stamps[-1])
        writer.write_raw(CORRECTED_PATH_TOPIC, PATH, stamp, encode_path(path, stamp, MAP_FRAME))
        (writer.staging / "report.json").write_text(json.dumps(summary, indent=2) + "\n")
        if plot:
            from pdr_drift.plots import paths_png
            paths_png([(result.before, "as navigated", "tab:red"),
                       (result.after, "offline drift correction (ε₀·t off the headings)",
                        "tab:blue")],
                      np.array([m.position for _, m in result.landmarks]).reshape(-1, 3),
                      writer.staging / "drift.png", str(bag))
    return summary
