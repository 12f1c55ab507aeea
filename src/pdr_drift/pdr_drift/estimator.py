"""The drift estimator step by step (Muñoz Díaz 2016, chapter 5 and Section 6.1).

:class:`DriftEstimator` takes the navigator's steps as :class:`~pdr_drift.corners.StepSample`
and returns what happened at each: the landmark detected (a corner or a flight of
stairs), and when it revisits a stored one, the association, the drift estimate and the
online correction of Section 6.1 (:class:`pdr_core.corrections.correction.Correction`, carried by
pdr_msgs/srv/ApplyCorrection): the yaw to add, δ, so that the heading is the first
visit's again (direction-adjusted), with the variance of one landmark yaw; the drift ε to
add to the z gyro bias with its variance; and the first visit's position with its
covariance (Eq. (6.3)), carried forward by the steps walked since the revisit's landmark.
It imports no navigator: the pocket and the foot alike can feed it.

The association is the thesis' nearest one (``association: nearest``, the default) or
the multi-hypothesis one of pdr_drift.hypotheses (``multi_hypothesis``), whose
associations, drifts and one correction come when a hypothesis dominates, possibly
steps after the landmarks, the correction then expressed as of the step that commits it.
``feedback`` says whether the corrections reach the navigator (the live loop) or not
(a walk only analysed).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.corrections.correction import Correction
from pdr_drift.config import DriftConfig
from pdr_drift.corners import BufferCornerDetector, StepSample, TurnCornerDetector
from pdr_drift.drift import DriftEstimate, drift_of
from pdr_drift.hypotheses import Commit, HypothesisSet
from pdr_drift.landmarks import Association, Landmark, LandmarkDatabase, StairsTracker, from_corner


@dataclass
class StepResult:
    landmarks: list[Landmark] = field(default_factory=list)
    associations: list[Association] = field(default_factory=list)
    drifts: list[DriftEstimate] = field(default_factory=list)
    corrections: list[Correction] = field(default_factory=list)


def corner_detector(config: DriftConfig):
    if config.corner_detector == "buffer":
        return BufferCornerDetector(config.q_steps, config.m_steps, config.r1_deg,
                                    config.r2_deg)
    return TurnCornerDetector(config.turn_rate_min_deg_per_step, config.q_steps,
                              config.turn_tolerance_deg)


class DriftEstimator:
    def __init__(self, config: DriftConfig | None = None, feedback: bool = True) -> None:
        self.config = config or DriftConfig()
        self.corners = corner_detector(self.config)
        self.stairs = StairsTracker()
        self.database = LandmarkDatabase(self.config.gate_probability, self.config.gate_dof,
                                         self.config.min_revisit_s)
        self.hypotheses = None if self.config.association == "nearest" else HypothesisSet(
            self.database, self.config, feedback)
        self.yaw_sigma_rad = np.radians(self.config.landmark_yaw_sigma_deg)
        self.next_id = 0
        self.last: StepSample | None = None

    def push(self, step: StepSample) -> StepResult:
        result = StepResult()
        corner = self.corners.push(step)
        found = [] if corner is None else [from_corner(corner, self._id())]
        flight = self.stairs.push(step, self.next_id)
        if flight is not None:
            self._id()
            found.append(flight)
        result.landmarks += found
        self.last = step
        if self.hypotheses is not None:
            return _with_commit(result, self.hypotheses.push(step, found))
        for landmark in found:
            association = self.database.associate(landmark)
            if association is None:
                continue
            estimate = drift_of(association, yaw_sigma_rad=self.yaw_sigma_rad)
            result.associations.append(association)
            result.drifts.append(estimate)
            # the landmark lies a few steps back (a corner is known once the heading has
            # settled after it): the fix is the first visit's position carried forward by
            # what was walked since the revisit's landmark
            since = np.asarray(step.position, float) - np.asarray(landmark.position, float)
            result.corrections.append(Correction(
                estimate.deviation, self.yaw_sigma_rad**2, estimate.drift,
                estimate.drift_variance,
                np.asarray(association.first.position, float) + since,
                np.asarray(association.first.covariance, float)))
        return result

    def finish(self) -> StepResult:
        """The end of the walk: the best hypothesis' associations not yet committed (none
        with the nearest association)."""
        if self.hypotheses is None or self.last is None:
            return StepResult()
        return _with_commit(StepResult(), self.hypotheses.finish(self.last))

    def _id(self) -> int:
        self.next_id += 1
        return self.next_id - 1


def _with_commit(result: StepResult, commit: Commit | None) -> StepResult:
    """``result`` with what a hypothesis committed."""
    if commit is None:
        return result
    result.associations += commit.associations
    result.drifts += commit.drifts
    result.corrections.append(Correction(commit.yaw_rad, commit.yaw_variance,
                                         commit.drift_radps, commit.drift_variance,
                                         commit.position, commit.position_covariance))
    return result
