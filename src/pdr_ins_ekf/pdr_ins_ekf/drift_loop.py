"""The foot navigator with the landmark drift corrections in one process
(``pdr-ekf run --drift online|offline``; Muñoz Díaz 2016, Sections 6.1 and 6.2), the loop
``zupt_ekf`` ⇄ ``landmark_drift`` makes over the graph.

- :func:`navigate_online`: the samples go through the live node's navigator
  (pdr_ins_ekf.streaming) in blocks; each stride goes to the drift estimator as
  ``landmark_drift`` gets it (pdr_drift.streaming: the step and the pose at its stamp),
  and each correction it returns goes back stamped with that stride, as the service call
  does. The navigator takes it there, filters the samples since again
  (pdr_ins_ekf.correctable), and the strides it revises replace the ones not yet read,
  as ``landmark_drift`` takes an answer's revised steps in place of those it held. So the
  result does not depend on the blocks, and equals the graph's at any replay speed.
- :func:`navigate_offline`: a first pass collects every association's drift, ε₀ of
  Eq. (6.5) (outliers rejected); the second takes ε₀·t off the heading of the whole run,
  turning every sample's pose and velocity about the start: the path has no jumps
  (Section 6.2; as pdr_pocket.drift_loop).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core.io.batch import MessageBatch
from pdr_core.maths.rotations import about_vertical
from pdr_core.vocabulary import FLOOR_HEIGHT_M
from pdr_drift.config import DriftConfig
from pdr_drift.drift import offline_drift
from pdr_drift.drift_log import DriftLog
from pdr_drift.estimator import StepResult
from pdr_drift.streaming import StreamingDrift
from pdr_ins_ekf.config import RunConfig
from pdr_ins_ekf.correctable import Filtered, concatenated
from pdr_ins_ekf.offline import FootRun
from pdr_ins_ekf.streaming import StreamingNavigator
from pdr_ins_ekf.strides import Stride, StrideTracker
from pdr_ins_ekf.zupt_ekf import FilterOutput

BLOCK_SAMPLES = 1000    # samples pushed at a time: any size gives the same result


class _Outputs:
    """The run's estimates so far, a revision replacing those after its stamp."""

    def __init__(self) -> None:
        self.parts: list[FootRun] = []
        self.strides: list[Stride] = []

    def add(self, run: FootRun) -> None:
        if len(run.stamp_ns):
            self.parts.append(run)
            self.strides += run.strides

    def revise(self, stamp_ns: int, revised: Filtered) -> None:
        """The estimates after ``stamp_ns`` [ns] filtered again."""
        whole = self.whole()
        keep = int(np.searchsorted(whole.stamp_ns, stamp_ns, side="right"))
        if not np.array_equal(whole.stamp_ns[keep:], revised.block.stamp_ns):
            raise RuntimeError("a revision must cover the samples after its stamp")
        output = FilterOutput.concatenate([whole.output.part(slice(keep)), revised.output])
        self.parts = [replace(whole, output=output)]
        self.strides = [s for s in self.strides if s.stamp_ns <= stamp_ns] + revised.strides

    def whole(self) -> FootRun:
        return replace(self.parts[0],
                       stamp_ns=np.concatenate([p.stamp_ns for p in self.parts]),
                       stance=np.concatenate([p.stance for p in self.parts]),
                       statistic=np.concatenate([p.statistic for p in self.parts]),
                       output=FilterOutput.concatenate([p.output for p in self.parts]),
                       strides=self.strides)


def estimator_input(stream: StreamingDrift, stride: Stride) -> StepResult | None:
    """A stride to the drift estimator as ``landmark_drift`` takes it: the step and the
    pose at its stamp (the pose completes the pair)."""
    stream.push_step(stride.stamp_ns, stride.heading_rad, stride.activity)
    return stream.push_pose(stride.stamp_ns, stride.position_m, stride.covariance_m2)


def navigate_online(imu: MessageBatch, config: RunConfig, drift: DriftConfig,
                    floor_height_m: float = FLOOR_HEIGHT_M, apply: bool = True
                    ) -> tuple[FootRun, DriftLog]:
    """The online loop (module docstring) over the record's samples; ``apply=False`` only
    records what the estimator found."""
    navigator = StreamingNavigator(config)
    stream = StreamingDrift(drift, floor_height_m)
    log, outputs = DriftLog(), _Outputs()
    stamps, accel, gyro = imu.stamp_ns, imu["linear_acceleration"], imu["angular_velocity"]
    blocks = [slice(k, k + BLOCK_SAMPLES) for k in range(0, len(stamps), BLOCK_SAMPLES)]
    for block in [*blocks, None]:
        run = (navigator.flush() if block is None
               else navigator.push_many(stamps[block], accel[block], gyro[block]))
        outputs.add(run)
        pending = list(run.strides)
        while pending:
            stride = pending.pop(0)
            result = estimator_input(stream, stride)
            if result is None:
                continue
            log.landmarks += result.landmarks
            log.drifts += result.drifts
            for correction in result.corrections if apply else []:
                answer = navigator.apply_correction(replace(correction,
                                                            stamp_ns=stride.stamp_ns))
                log.corrections.append(((stride.stamp_ns - stamps[0]) * 1e-9,
                                        answer.accepted, answer.message))
                if answer.accepted and answer.revised:
                    revised = concatenated(answer.revised)
                    outputs.revise(stride.stamp_ns, revised)
                    pending = list(revised.strides)
    run = outputs.whole()
    # the usable samples before the alignment's start, where the filter starts
    run.counts = {**navigator.counts, "before_alignment": navigator.filter_start}
    return run, log


def navigate_offline(imu: MessageBatch, config: RunConfig, drift: DriftConfig,
                     floor_height_m: float = FLOOR_HEIGHT_M) -> tuple[FootRun, DriftLog]:
    """The two passes of Section 6.2 (module docstring)."""
    run, log = navigate_online(imu, config, drift, floor_height_m, apply=False)
    epsilon, kept = offline_drift(log.drifts, np.radians(drift.max_drift_deg_per_s),
                                  drift.outlier_spread)
    log.offline_drift, log.kept = epsilon, kept
    if epsilon is None:
        return run, log
    return without_drift(run, epsilon), log


def without_drift(run: FootRun, drift_radps: float) -> FootRun:
    """``run`` with the heading turned by −ε·t from its first sample (ε [rad/s]): each
    sample's displacement, velocity and attitude turned about the up axis, the strides
    found again on the turned path."""
    angle = -drift_radps * (run.stamp_ns - run.stamp_ns[0]) * 1e-9
    turn = Rotation.from_euler("z", angle[:, None]).as_matrix()
    out = run.output
    steps = about_vertical(np.diff(out.position, axis=0), angle[1:])
    position = np.concatenate([out.position[:1], out.position[0] + np.cumsum(steps, axis=0)])
    output = replace(out, position=position, velocity=about_vertical(out.velocity, angle),
                     attitude=turn @ out.attitude,
                     position_cov=turn @ out.position_cov @ turn.transpose(0, 2, 1),
                     velocity_cov=turn @ out.velocity_cov @ turn.transpose(0, 2, 1))
    strides = StrideTracker().push(run.stamp_ns, run.stance, output)
    return replace(run, output=output, strides=strides)
