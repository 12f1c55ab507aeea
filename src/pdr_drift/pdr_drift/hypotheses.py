"""Multi-hypothesis association of revisits: beyond Muñoz Díaz 2016, Section 5.2, which
names a multi-hypothesis filter as the remedy for a wrong nearest association (with a
large position uncertainty several stored landmarks pass the gate, and the nearest one
can be wrong) and leaves it out.

**Hypotheses.** A :class:`Hypothesis` is one account of the walk: which stored landmark
each revisit was (its association history), its own landmark database, and its own
correction of the navigator's output since the last committed one (a :class:`Frame`):
the yaw to add, the drift ε still in the navigator, and the position the navigator
should be at. Every step moves each hypothesis' position by the navigator's step turned
by its yaw correction (Eq. (5.1) with the corrected heading), so each hypothesis sees
every new landmark where its own corrections put it.

**Branching.** A new landmark is offered, in each hypothesis, to every stored landmark
of its type and floor that passes the thesis' gate (:meth:`LandmarkDatabase.candidates`,
Eq. (5.4), κ = √χ²(p, n)); each gives a child hypothesis, and one more child stores it
as a new place. A child that associates takes the correction of Section 6.1 (yaw δ of
Eqs. (5.5)/(5.6), the first visit's position) into its frame, and its drift ε
(Eq. (5.8), from its last correction on) as a Kalman update of the drift it holds (prior σ
``drift_sigma_deg_per_s``), and spreads the correction over the landmarks it stored
since the first visit or its last correction, in proportion to time (the heading error
grew from there; the loop closure's usual linear distribution), so that its database
stays in its corrected frame and is never cleared: later laps revisit the first one's
landmarks.

**Score.** Each hypothesis' cost is −2 log of its likelihood up to a constant shared by
all, summed over the landmarks:

- an association: Δ² + log det(2π S) with S what can open the loop between the two
  visits (:meth:`HypothesisSet._association_cost`: the drift the hypothesis still
  allows, a heading error in proportion to the angle turned and a heading random walk,
  each through the walked path, pdr_drift.walked_path, and ``place_sigma_m`` per visit),
  plus
  δ²/(σ_δ² + (σ_ε·Δt)²), the deviation against the drift's prior σ_ε
  (``drift_sigma_deg_per_s``) over the time since the last correction and the yaw noise
  of Section 5.3;
- a new place: −2 log λ, λ = ``places_per_km2`` the density of corners and stairs.
  Every hypothesis pays it for the same first visits; a wrong one, whose corrections
  put the later revisits in the wrong place, pays it again for each revisit it can no
  longer associate, or pays their large Δ².

So the consistency of the later associations' positions, of the drifts, and the
Mahalanobis distances all enter one number. The best ``hypotheses_k`` are kept.

**Commit.** The best hypothesis' associations are committed when every other hypothesis
that pairs some revisit with another place is ``commit_margin`` worse (one that only left
out some of its associations, or made more, does not stand against it): the others are
dropped, and its correction is sent as one, expressed from the current step: the yaw
its frame adds now (δ with the drift's effect since carried forward, the contract of
pdr_core.corrections.checkpoints for a correction committed late), the drift it holds for the z
gyro bias, and the position its frame puts the current step at, with the covariance.
When the navigator takes the corrections (``feedback``, the live loop), the hypothesis
then starts again from the navigator's own output at the next step; otherwise it keeps
its frame (the navigator never hears of it). :meth:`HypothesisSet.finish` commits the
best one at the end of a walk (offline).

**Drift estimates.** With ``feedback`` each association's estimate is the drift its
hypothesis still found in the navigator, from its last correction on (what the gyro bias
correction adds). Without, the navigator is never corrected, and the estimate is the
thesis' one between the two visits as the navigator saw them (Eq. (5.8)), the input of
ε₀ (Eq. (6.5)).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from pdr_core.maths.angles import wrap_angle
from pdr_core.maths.rotations import about_vertical
from pdr_drift.config import DriftConfig
from pdr_drift.corners import StepSample
from pdr_drift.drift import DriftEstimate, drift_of
from pdr_drift.landmarks import Association, Landmark, LandmarkDatabase, distance
from pdr_drift.walked_path import WalkedPath


@dataclass(frozen=True)
class Frame:
    """A hypothesis' correction of the navigator's output since the last commit (ENU):
    the yaw to add [rad] is ``yaw_rad − drift_radps·(t − t_ref_s)``; the drift ε [rad/s] is
    what its associations found still in the navigator (the z gyro bias to add)."""

    yaw_rad: float = 0.0
    drift_radps: float = 0.0
    t_ref_s: float = 0.0
    drift_variance: float = 0.0     # of drift_radps [rad²/s²]

    def yaw_at(self, t_s: float) -> float:
        return self.yaw_rad - self.drift_radps * (t_s - self.t_ref_s)


@dataclass
class Hypothesis:
    """One account of the walk (module docstring)."""

    database: LandmarkDatabase
    frame: Frame = field(default_factory=Frame)
    cost: float = 0.0                   # −2 log-likelihood up to a shared constant
    position: np.ndarray | None = None  # the last step's position in this frame [m] (3,)
    covariance_shift: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    last_fix_s: float = -np.inf         # the last association's revisit [s]
    history: tuple[tuple[int, int], ...] = ()    # (first id, revisit id), all
    pending: list[tuple[Association, DriftEstimate]] = field(default_factory=list)

    def copy(self) -> Hypothesis:
        return replace(self, database=replace(self.database, stored=list(self.database.stored)),
                       pending=list(self.pending))


@dataclass(frozen=True)
class Commit:
    """What a hypothesis that dominates commits: its associations and drift estimates, and
    its one correction as of the committing step: the yaw [rad] and z gyro bias [rad/s]
    to add with their variances, the position [m] (3,) with its covariance (3, 3)."""

    associations: list[Association]
    drifts: list[DriftEstimate]
    yaw_rad: float
    yaw_variance: float
    drift_radps: float
    drift_variance: float
    position: np.ndarray
    position_covariance: np.ndarray


def psd(matrix: np.ndarray) -> np.ndarray:
    """The nearest symmetric positive semi-definite matrix (negative eigenvalues to 0)."""
    values, vectors = np.linalg.eigh(0.5 * (matrix + matrix.T))
    return (vectors * np.maximum(values, 0.0)) @ vectors.T


def _spread(stored: list[Landmark], association: Association, delta: float,
            last_fix_s: float) -> list[Landmark]:
    """The stored landmarks, each with its share of an association's correction: none
    before the first visit or the hypothesis' last correction, whichever is later (the
    error grew from there), all of it at the revisit, in proportion to time in between:
    the yaw δ [rad] and the position shift from the revisit to the first visit [m]."""
    start = max(association.first.t, last_fix_s)
    shift = np.asarray(association.first.position, float) - association.revisit.position
    duration = association.revisit.t - start

    def corrected(mark: Landmark) -> Landmark:
        share = (mark.t - start) / duration
        return replace(mark, position=mark.position + share * shift,
                       yaw_before=float(wrap_angle(mark.yaw_before + share * delta)),
                       yaw_after=float(wrap_angle(mark.yaw_after + share * delta)))

    return [corrected(m) if m.t > start else m for m in stored]


class HypothesisSet:
    """The hypotheses of a walk (module docstring): :meth:`push` every step with the
    landmarks it ended, :meth:`finish` at the end offline."""

    def __init__(self, database: LandmarkDatabase, config: DriftConfig, feedback: bool
                 ) -> None:
        self.k, self.commit_margin = config.hypotheses_k, config.commit_margin
        self.wander_variance = np.radians(config.heading_wander_deg_per_sqrt_s) ** 2
        self.turn_scale_variance = config.turn_scale_sigma ** 2
        self.place_variance = config.place_sigma_m ** 2
        self.new_place_cost = -2.0 * np.log(config.places_per_km2 * 1e-6)
        self.feedback = feedback
        self.drift_sigma_radps = np.radians(config.drift_sigma_deg_per_s)
        self.yaw_sigma_rad = np.radians(config.landmark_yaw_sigma_deg)
        self.hypotheses = [Hypothesis(database, Frame(drift_variance=self.drift_sigma_radps ** 2))]
        self.detected: dict[int, Landmark] = {}     # as the navigator saw them, by id
        self.last: StepSample | None = None
        self.path = WalkedPath()     # the navigator's steps, without the fixes' jumps
        self.rebase = False
        self.confirmed = False       # a commit made: one association is then enough

    def push(self, step: StepSample, landmarks: list[Landmark]) -> Commit | None:
        """A step of the navigator and the landmarks it ended; a commit or None."""
        self._move(step)
        if not landmarks:
            return None
        for landmark in landmarks:
            self.detected[landmark.id] = landmark
            children = [c for h in self.hypotheses for c in self._branch(h, landmark, step)]
            children.sort(key=lambda h: h.cost)
            self.hypotheses = children[:self.k]
        return self._commit_if_dominant(step)

    def finish(self, step: StepSample) -> Commit | None:
        """The best hypothesis committed, whatever the others (the end of a walk)."""
        self.hypotheses = self.hypotheses[:1]
        return self._commit(step) if self.hypotheses[0].pending else None

    # --- each step ------------------------------------------------------------------
    def _move(self, step: StepSample) -> None:
        """Each hypothesis' position moved by the navigator's step, turned by its yaw
        correction (module docstring); after a commit the navigator's own."""
        position = np.asarray(step.position, float)
        walked = self.last is not None and not self.rebase
        self.path.append(step.t, step.heading,
                         position - self.last.position if walked else np.zeros(3))
        for h in self.hypotheses:
            if h.position is None or self.rebase:
                h.position = position.copy()
                h.covariance_shift = np.zeros((3, 3))
            else:
                move = position - np.asarray(self.last.position, float)
                h.position = h.position + about_vertical(move, h.frame.yaw_at(step.t))
        self.rebase = False
        self.last = step

    def seen_in(self, h: Hypothesis, landmark: Landmark, step: StepSample) -> Landmark:
        """``landmark`` (a few steps before ``step``) where ``h``'s corrections put it."""
        offset = np.asarray(landmark.position, float) - np.asarray(step.position, float)
        yaw = h.frame.yaw_at(landmark.t)
        turned = about_vertical(offset, h.frame.yaw_at(step.t))
        return replace(landmark, position=h.position + turned,
                       covariance=psd(np.asarray(landmark.covariance, float) + h.covariance_shift),
                       yaw_before=float(wrap_angle(landmark.yaw_before + yaw)),
                       yaw_after=float(wrap_angle(landmark.yaw_after + yaw)))

    # --- each landmark --------------------------------------------------------------
    def _branch(self, h: Hypothesis, landmark: Landmark, step: StepSample) -> list[Hypothesis]:
        """The children of ``h`` for a new landmark: one per gated stored landmark, and
        one that stores it as a new place."""
        seen = self.seen_in(h, landmark, step)
        children = [self._associate(h.copy(), a, self._association_cost(h, a), step)
                    for a in h.database.candidates(seen)]
        new = h.copy()
        new.database.stored.append(seen)
        new.cost += self.new_place_cost
        return [*children, new]

    def _association_cost(self, h: Hypothesis, association: Association) -> float:
        """−2 log of the likelihood that the revisit lies where ``h`` found it, if it is
        the first visit's place: Δ² + log det(2π S) over the horizontal axes, where S is
        what can open the loop between the two visits: the drift ``h`` still allows
        (its variance) times the path's spread v vᵀ, the heading error in proportion to
        the angle turned (``turn_scale_sigma``) times w wᵀ, the heading's random walk
        (``heading_wander_deg_per_sqrt_s``) through the path (pdr_drift.walked_path), and
        ``place_sigma_m`` for each visit on each horizontal axis; the height's, the
        difference of the two visits' variances. Eq. (5.4) adds both visits' absolute
        covariances instead, counting twice the error they share (the heading's at the
        start, which turns the loop and opens nothing). A large S makes an association
        cheap in Δ² but dear in log det: a place found anywhere in it says little."""
        first, revisit = association.first, association.revisit
        yaw = h.frame.yaw_at(revisit.t)
        turn = np.array([[np.cos(yaw), -np.sin(yaw)], [np.sin(yaw), np.cos(yaw)]])
        v, w = (turn @ x for x in self.path.spreads(first.t, revisit.t))
        wander = turn @ self.path.wander(first.t, revisit.t) @ turn.T
        spread = np.zeros((3, 3))
        spread[:2, :2] = h.frame.drift_variance * np.outer(v, v) \
            + self.turn_scale_variance * np.outer(w, w) + self.wander_variance * wander \
            + 2 * self.place_variance * np.eye(2)
        spread[2, 2] = abs(revisit.covariance[2, 2] - first.covariance[2, 2])
        d = np.asarray(revisit.position, float) - np.asarray(first.position, float)
        return distance(d, spread) ** 2 + float(np.linalg.slogdet(2 * np.pi * spread[:2, :2])[1])

    def _associate(self, h: Hypothesis, association: Association, cost: float,
                   step: StepSample) -> Hypothesis:
        """``h`` with the association taken into its frame and database (module
        docstring); ``cost``: that of :meth:`_association_cost`."""
        first, revisit = association.first, association.revisit
        estimate = drift_of(association, h.last_fix_s, self.yaw_sigma_rad)
        delta = estimate.deviation
        allowed = estimate.deviation_variance + (self.drift_sigma_radps * estimate.elapsed) ** 2
        h.cost += cost + delta ** 2 / allowed
        h.database.stored = _spread(h.database.stored, association, delta, h.last_fix_s)
        h.position = np.asarray(first.position, float) + about_vertical(
            h.position - revisit.position, delta)
        h.covariance_shift = np.asarray(first.covariance, float) - np.asarray(step.covariance,
                                                                              float)
        gain = h.frame.drift_variance / (h.frame.drift_variance + estimate.drift_variance)
        h.frame = Frame(h.frame.yaw_at(revisit.t) + delta,
                        h.frame.drift_radps + gain * estimate.drift, revisit.t,
                        (1.0 - gain) * h.frame.drift_variance)
        h.last_fix_s = revisit.t
        h.history += ((first.id, revisit.id),)
        h.pending.append((association, estimate if self.feedback else drift_of(
            Association(self.detected[first.id], self.detected[revisit.id],
                        association.distance), yaw_sigma_rad=self.yaw_sigma_rad)))
        return h

    # --- commits --------------------------------------------------------------------
    def _commit_if_dominant(self, step: StepSample) -> Commit | None:
        """The best hypothesis committed when every other that pairs some revisit with
        another place is ``commit_margin`` worse: those that only left out some of its
        associations, or made more, do not stand against it (module docstring)."""
        best = self.hypotheses[0]
        if not best.pending or (len(best.pending) < 2 and not self.confirmed):
            return None
        paired = dict((revisit, first) for first, revisit in best.history)
        for other in self.hypotheses[1:]:
            if other.cost - best.cost >= self.commit_margin:
                break
            if any(paired.get(revisit, first) != first for first, revisit in other.history):
                return None
        self.hypotheses = [best]
        return self._commit(step)

    def _commit(self, step: StepSample) -> Commit:
        """The only hypothesis' pending associations and its correction as of ``step``."""
        h = self.hypotheses[0]
        commit = Commit([a for a, _ in h.pending], [e for _, e in h.pending],
                        h.frame.yaw_at(step.t), self.yaw_sigma_rad ** 2, h.frame.drift_radps,
                        h.frame.drift_variance, h.position.copy(),
                        psd(np.asarray(step.covariance, float) + h.covariance_shift))
        h.pending = []
        self.confirmed = True
        if self.feedback:
            h.frame = Frame(t_ref_s=step.t, drift_variance=h.frame.drift_variance)
            self.rebase = True
        return commit
