"""The pocket navigator with the landmark drift corrections in one process
(``pdr-pocket run --drift online|offline``; Muñoz Díaz 2016, Sections 6.1 and 6.2).

- :func:`navigate_online`: the record in chunks of :data:`CHUNK_S`; each step goes to
  :class:`pdr_drift.estimator.DriftEstimator`, and each correction it returns goes to the
  navigator through :meth:`PocketNavigator.apply_correction`, the code the
  ``pocket_pdr`` node's service runs (Section 6.1). A correction is applied right after
  the sample that confirmed its step, where the live graph applies it too, whenever the
  call comes: the request carries that step's stamp (pdr_pocket.streaming). Here the
  chunk is run again from a copy of the navigator taken before it, up to that sample,
  and on from there with the correction: the one replay of pdr_core.corrections.replay, the live
  navigator's (:class:`ChunkLoop`). Applied at the end of the chunk instead, the poses
  ended 0.13 m from the live graph's.
- :func:`navigate_offline`: a first pass collects every association's drift, ε₀ of
  Eq. (6.5) (outliers rejected), and a second pass takes ε₀·t off every step's heading
  and applies no correction: the path has no jumps (Section 6.2). The thesis reprocesses
  with b_z = ε₀ instead, in a filter whose b_z the data barely moves; ours learns b_z
  from the differential magnetic update, which pulled a start of b̂_z + ε₀ back within a
  minute (0.061 → 0.056 °/s on the Theresienhöhe walk) while the heading still drifted
  by ε₀: the residual drift is not in b_z, so it is taken off the heading itself.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from pdr_core.corrections.correction import Correction
from pdr_core.corrections.replay import Replay, TakenCorrection
from pdr_drift.config import DriftConfig
from pdr_drift.corners import StepSample
from pdr_drift.drift import offline_drift
from pdr_drift.drift_log import DriftLog
from pdr_drift.estimator import DriftEstimator, StepResult
from pdr_pocket.config import PocketConfig
from pdr_pocket.navigator import PocketNavigator
from pdr_pocket.records import NavigatorOutput, StepRecord
from pdr_pocket.samples import Samples

CHUNK_S = 30.0


def step_sample(step: StepRecord) -> StepSample:
    """The drift estimator's view of a step, timed at its confirmation: the instant the
    live node stamps its messages with, so that the drifts here and ``landmark_drift``'s
    are the same numbers."""
    return StepSample(step.t_confirm, step.heading, step.activity, step.position,
                      step.covariance, step.floor)


def navigate_online(config: PocketConfig, drift: DriftConfig, samples: Samples,
                    apply: bool = True) -> tuple[PocketNavigator, NavigatorOutput, DriftLog]:
    """The online loop (module docstring) over the record's samples; ``apply=False``
    only records."""
    t = samples.t
    estimator = DriftEstimator(drift, feedback=apply)
    log = DriftLog()
    if not apply:
        navigator = PocketNavigator(config)
        out = navigator.process(samples)
        for step in out.steps:
            _record(estimator.push(step_sample(step)), log)
        _record(estimator.finish(), log)
        return navigator, out, log
    loop, start = ChunkLoop(config), 0
    for end in np.searchsorted(t, np.arange(t[0], t[-1] + CHUNK_S, CHUNK_S)[1:], "left"):
        if end <= start:
            continue
        pending = list(loop.run(samples.part(start, end)).steps)
        while pending:
            step = pending.pop(0)
            for correction in _record(estimator.push(step_sample(step)), log).corrections:
                answer = loop.replay.correct(loop, correction, step.t_confirm)
                log.corrections.append((step.t, answer.accepted, answer.message))
                if answer.accepted:
                    pending = [s for out in answer.revised for s in out.steps]
        start = end
    return loop.navigator, loop.output(), log


@dataclass
class Rerun:
    """The navigator kept before a chunk, taking its samples up to a correction again
    (pdr_core.corrections.replay.Worker), with what they give: the chunk's output up to there."""

    navigator: PocketNavigator
    outputs: list[NavigatorOutput] = field(default_factory=list)

    def rerun(self, item: Samples | TakenCorrection) -> None:
        if isinstance(item, TakenCorrection):
            self.navigator.rerun(item)
        else:
            self.outputs.append(self.navigator.process(item))

    def apply_correction(self, correction: Correction) -> tuple[bool, str]:
        return self.navigator.apply_correction(correction)


class ChunkLoop:
    """The navigator over the record's chunks, its state kept before each
    (pdr_core.corrections.replay, one checkpoint), a correction taken at its step's sample and the
    chunk's samples since run again (pdr_core.corrections.replay.Replayable)."""

    def __init__(self, config: PocketConfig) -> None:
        self.navigator = PocketNavigator(config)
        self.replay: Replay[PocketNavigator, Samples] = Replay(
            PocketNavigator.copy_state, np.inf, capacity=1)
        self.done: list[NavigatorOutput] = []       # the chunks before this one
        self.chunk: list[NavigatorOutput] = []      # this one's, since its checkpoint

    def run(self, part: Samples) -> NavigatorOutput:
        """A new chunk, its checkpoint before it: its output."""
        self.done += self.chunk
        self.chunk = []
        self.replay.history.remember(float(part.t[0]), self.navigator)
        [out] = self.take(part)
        return out

    def output(self) -> NavigatorOutput:
        """The whole record's output, corrections taken."""
        return NavigatorOutput.concatenate(self.done + self.chunk)

    @staticmethod
    def worker(state: PocketNavigator) -> Rerun:
        return Rerun(state)

    def adopt(self, worker: Rerun) -> None:
        self.navigator, self.chunk = worker.navigator, worker.outputs

    def take(self, item: Samples | TakenCorrection) -> list[NavigatorOutput]:
        if isinstance(item, TakenCorrection):
            self.navigator.rerun(item)
            self.replay.history.record(item, item.t_s)
            return []
        out = self.navigator.process(item)
        self.replay.history.record(item, item.end_s)
        self.chunk.append(out)
        return [out]


def _record(result: StepResult, log: DriftLog) -> StepResult:
    log.landmarks += result.landmarks
    log.drifts += result.drifts
    return result


def navigate_offline(config: PocketConfig, drift: DriftConfig, samples: Samples
                     ) -> tuple[PocketNavigator, NavigatorOutput, DriftLog]:
    """The two passes of Section 6.2 (module docstring) over the record's samples."""
    log = navigate_online(config, drift, samples, apply=False)[2]
    epsilon, kept = offline_drift(log.drifts, np.radians(drift.max_drift_deg_per_s),
                                  drift.outlier_spread)
    log.offline_drift, log.kept = epsilon, kept
    position = replace(config.position, heading_drift_correction_deg_per_s=0.0
                       if epsilon is None else float(np.degrees(epsilon)))
    navigator = PocketNavigator(replace(config, position=position))
    return navigator, navigator.process(samples), log
