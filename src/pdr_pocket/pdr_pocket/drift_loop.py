"""The pocket navigator with the landmark drift corrections in one process
(``pdr-pocket run --drift online|offline``; Muñoz Díaz 2016, Sections 6.1 and 6.2).

- :func:`navigate_online`: the record in chunks of :data:`CHUNK_S`; each step goes to
  :class:`pdr_drift.estimator.DriftEstimator`, and each correction it returns goes to the
  navigator through :meth:`PocketNavigator.apply_correction`, the code the
  ``pocket_pdr`` node's service runs (Section 6.1). A correction is applied right after
  the sample that confirmed its step, where the live graph applies it too, whenever the
  call comes: the request carries that step's stamp (pdr_pocket.streaming). Here the
  chunk is run again from a copy of the navigator taken before it (a checkpoint,
  pdr_core.checkpoints), up to that sample. Applied at the end of the chunk instead, the
  poses ended 0.13 m from the live graph's.
- :func:`navigate_offline`: a first pass collects every association's drift, ε₀ of
  Eq. (6.5) (outliers rejected), and a second pass takes ε₀·t off every step's heading
  and applies no correction: the path has no jumps (Section 6.2). The thesis reprocesses
  with b_z = ε₀ instead, in a filter whose b_z the data barely moves; ours learns b_z
  from the differential magnetic update, which pulled a start of b̂_z + ε₀ back within a
  minute (0.061 → 0.056 °/s on the Theresienhöhe walk) while the heading still drifted
  by ε₀: the residual drift is not in b_z, so it is taken off the heading itself.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from pdr_core.checkpoints import Checkpoints
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
    navigator = PocketNavigator(config)
    estimator = DriftEstimator(drift, feedback=apply)
    log = DriftLog()
    # the navigator before the chunk; the chunk is the record's, so no inputs are recorded
    before: Checkpoints[PocketNavigator, None] = Checkpoints(
        PocketNavigator.copy_state, np.inf, capacity=1)

    def run(start: int, stop: int) -> NavigatorOutput:
        return navigator.process(samples.part(start, stop))

    if not apply:
        out = run(0, len(t))
        for step in out.steps:
            _record(estimator.push(step_sample(step)), log)
        _record(estimator.finish(), log)
        return navigator, out, log
    outputs, start = [], 0
    for end in np.searchsorted(t, np.arange(t[0], t[-1] + CHUNK_S, CHUNK_S)[1:], "left"):
        while start < end:
            before.remember(t[start], navigator)
            out = run(start, end)
            step, corrections = _estimate(estimator, out.steps, log)
            if step is None:
                outputs.append(out)
                start = end
                continue
            stop = max(int(np.searchsorted(t, step.t_confirm, "right")), start + 1)
            navigator = before.revert_to(t[stop - 1]).state
            outputs.append(run(start, stop))
            for correction in corrections:
                ok, message = navigator.apply_correction(correction)
                log.corrections.append((step.t, ok, message))
            start = stop
    return navigator, NavigatorOutput.concatenate(outputs), log


def _estimate(estimator: DriftEstimator, steps: list[StepRecord], log: DriftLog):
    """Steps to the drift estimator until one brings corrections: that step and its
    corrections, or (None, [])."""
    for step in steps:
        result = _record(estimator.push(step_sample(step)), log)
        if result.corrections:
            return step, result.corrections
    return None, []


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
