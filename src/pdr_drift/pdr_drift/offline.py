"""``pdr-drift run``: the offline drift correction of a pocket navigator's output
(Muñoz Díaz 2016, Section 6.2) from its steps and poses alone.

The steps (``pdr/pocket/step``) and poses (``pdr/pocket/pose``) of ``pdr-pocket run`` or
of ``pocket_pdr`` recorded by ``bag_record`` go through the drift estimator as the live
node sees them; every association's drift is collected, ε₀ (Eq. (6.5), outliers
rejected) is taken, and the path is integrated again from the steps (Eq. (5.1)) with each
step's heading less ε₀·t: a drift-compensated path without jumps. No IMU data is needed.

t counts from the walk's start, the first IMU sample: the first ``pdr/pocket/attitude``
message (``pdr-pocket run`` writes it at every sample; record it with the steps and
poses). A bag without it counts from the first step's start (its stamp less its
duration) and says so in the report's ``warnings``. The report's ``duration_s``,
``distance_m`` and ``loop_gap_m`` are :func:`pdr_core.evaluation.metrics.walk_figures` of the
corrected path from that start and the position before the first step, the figures
``pdr-pocket run`` gives for the same walk; :func:`report` lists every field.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.evaluation.metrics import walk_figures
from pdr_core.frames import MAP_FRAME
from pdr_core.io import cdr
from pdr_core.io.bag import BagReader, BagWriter
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import DRIFT_ESTIMATE, LANDMARK, PATH, POSE_STAMPED
from pdr_core.io.nav_path import encode_path
from pdr_core.report_files import write_report
from pdr_drift.config import DriftConfig
from pdr_drift.drift import DriftEstimate, offline_drift
from pdr_drift.landmarks import Landmark
from pdr_drift.streaming import StreamingDrift


@dataclass
class OfflineResult:
    start_ns: int                       # the walk's start [ns] (module docstring)
    start: np.ndarray                   # (3,) the position before the first step [m]
    stamps: np.ndarray                  # of the steps [ns]
    paired: np.ndarray                  # (N,) bool: the steps with a pose
    before: np.ndarray                  # (M, 3) the navigator's positions of those steps
    after: np.ndarray                   # (N, 3) re-integrated with ε₀ taken off
    landmarks: list[tuple[int, Landmark]]
    drifts: list[tuple[int, DriftEstimate]]
    epsilon: float | None
    kept: list[DriftEstimate]


def correct(steps: MessageBatch, poses: MessageBatch, config: DriftConfig,
            floor_height_m: float, start_ns: int | None = None) -> OfflineResult:
    """The drift estimator over the steps, ε₀ and the re-integrated path, ε₀·t with t
    from ``start_ns`` (the first IMU sample; None: the first step's start)."""
    if len(steps) == 0:
        raise InputError(topics.POCKET_STEP, "no steps to correct")
    if start_ns is None:
        start_ns = int(steps.stamp_ns[0] - round(steps["duration"][0] * 1e9))
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
    t = (steps.stamp_ns - start_ns) * 1e-9
    heading = steps["heading"] - (0.0 if epsilon is None else epsilon) * t
    moves = np.c_[steps["length"] * np.cos(heading), steps["length"] * np.sin(heading),
                  steps["vertical_displacement"]]
    paired = np.array([int(s) in pose_of for s in steps.stamp_ns])
    before = np.array([position[pose_of[int(s)]] for s in steps.stamp_ns[paired]])
    start = before[0] - np.r_[steps["length"][0] * np.cos(steps["heading"][0]),
                              steps["length"][0] * np.sin(steps["heading"][0]),
                              steps["vertical_displacement"][0]]
    return OfflineResult(start_ns, start, steps.stamp_ns, paired, before,
                         start + np.cumsum(moves, axis=0), landmarks, drifts, epsilon, kept)


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
    return {topics.LANDMARKS: landmark, topics.DRIFT: drift}


def walk_path(result: OfflineResult, positions: np.ndarray, stamps: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """Times [s] from the walk's start and positions [m] from the start position, each
    with the start first, for :func:`pdr_core.evaluation.metrics.walk_figures`."""
    return (np.r_[result.start_ns, stamps] - result.start_ns) * 1e-9, \
        np.vstack([result.start, positions])


def report(result: OfflineResult, warnings: list[str] = ()) -> dict:
    """``report.json``:

    - ``duration_s``, ``distance_m``, ``loop_gap_m``:
      :func:`pdr_core.evaluation.metrics.walk_figures` of the corrected path (module
      docstring) [s, m, m];
    - ``steps``, ``landmarks``, ``associations``; ``drift_deg_per_s``: each association's
      drift [°/s]; ``kept``: the drifts ε₀ is taken from (outliers rejected);
      ``offline_drift_deg_per_s``: ε₀ [°/s], None without an association;
    - ``correction_applied``: whether ε₀·t was taken off the headings (False without ε₀:
      the corrected path is the navigator's steps integrated again as they are);
    - ``correction_shift_m``: how far the correction moved the path, the largest
      horizontal distance between a step's position as navigated and corrected [m]; 0
      when no correction was applied;
    - ``loop_gap_before_m``, ``loop_gap_after_m``: ``loop_gap_m`` of the navigator's path
      and of the corrected one [m];
    - ``longest_step_m``: the longest step of the corrected path [m] (one stride: the
      correction is smooth, it makes no jump);
    - ``warnings``: what the figures could not take into account (no walk start).
    """
    applied = result.epsilon is not None
    after = walk_path(result, result.after, result.stamps)
    before = walk_path(result, result.before, result.stamps[result.paired])
    figures = walk_figures(*after)
    shift = np.linalg.norm(result.after[result.paired, :2] - result.before[:, :2], axis=1)
    return figures | {
        "steps": len(result.after), "landmarks": len(result.landmarks),
        "associations": len(result.drifts),
        "drift_deg_per_s": [float(np.degrees(d.drift)) for _, d in result.drifts],
        "kept": len(result.kept),
        "offline_drift_deg_per_s": None if result.epsilon is None
        else float(np.degrees(result.epsilon)),
        "correction_applied": applied,
        "correction_shift_m": float(shift.max(initial=0.0)) if applied else 0.0,
        "loop_gap_before_m": walk_figures(*before)["loop_gap_m"],
        "loop_gap_after_m": figures["loop_gap_m"],
        "longest_step_m": float(np.linalg.norm(np.diff(after[1], axis=0), axis=1).max()),
        "warnings": list(warnings)}


def walk_start_ns(reader: BagReader) -> int | None:
    """The stamp [ns] of the first ``pdr/pocket/attitude`` message (the first IMU
    sample), None when the bag has no such topic."""
    if topics.POCKET_ATTITUDE not in reader.topics:
        return None
    first = next(reader.raw_messages([topics.POCKET_ATTITUDE]), None)
    if first is None:
        return None
    stamp = cdr.decode_generic(first.msgtype, first.data).header.stamp
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def run(bag: Path, out: Path, config: DriftConfig, floor_height_m: float, *,
        plot: bool = False, overwrite: bool = False) -> dict:
    reader = BagReader(bag)
    reader.require_topics([topics.POCKET_STEP, topics.POCKET_POSE])
    data = reader.read_batches([topics.POCKET_STEP, topics.POCKET_POSE])
    start_ns = walk_start_ns(reader)
    result = correct(data[topics.POCKET_STEP], data[topics.POCKET_POSE], config, floor_height_m,
                     start_ns)
    summary = report(result, [] if start_ns is not None else [
        f"no {topics.POCKET_ATTITUDE}: the walk's figures and ε₀·t count from the first "
        "step's start (its stamp less its duration), not from the first IMU sample; record "
        f"{topics.POCKET_ATTITUDE} with the steps and poses"])
    quat = np.zeros((len(result.after), 4))
    quat[:, 3] = 1.0
    path = MessageBatch(POSE_STAMPED, result.stamps, MAP_FRAME,
                        {"pose.position": result.after, "pose.orientation": quat})
    with BagWriter(out, overwrite=overwrite) as writer:
        writer.write_merged({t: b for t, b in batches(result).items() if len(b)})
        stamp = int(result.stamps[-1])
        writer.write_raw(topics.POCKET_CORRECTED_PATH, PATH, stamp,
                         encode_path(path, stamp, MAP_FRAME))
        write_report(writer.staging, summary)
        if plot:
            from pdr_drift.plots import paths_png
            paths_png(walk_path(result, result.after, result.stamps)[1],
                      walk_path(result, result.before, result.stamps[result.paired])[1],
                      np.array([m.position for _, m in result.landmarks]).reshape(-1, 3),
                      writer.staging / "drift.png", bag,
                      corrected_label="offline drift correction (ε₀·t off the headings)"
                      if result.epsilon is not None else "no association: nothing corrected",
                      uncorrected_label="as navigated",
                      shows="the offline drift correction (pdr-drift run)")
    return summary
