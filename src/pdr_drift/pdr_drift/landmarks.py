"""Landmarks, their database and the association of revisits (Muñoz Díaz 2016,
Sections 5.1.2 and 5.2, Table 5.1).

- :class:`StairsTracker`: one landmark per flight from the step activities (Section
  5.1.2): consecutive steps up (or down); the landmark at the flight's middle step, its
  yaw the direction of travel (the circular mean of the flight's step headings). A flight
  split by a landing gives two, which is harmless (Section 5.5.1).
- :class:`LandmarkDatabase`: the landmarks of Table 5.1; :meth:`~LandmarkDatabase.associate`
  compares a new landmark with the stored ones of the same type and floor that are at
  least ``min_revisit_s`` older (Section 5.3: shorter revisits give a drift too
  uncertain), by the Mahalanobis distance of the positions with both covariances
  (Eq. (5.4)), gated at κ = √χ²(p, n) (Section 5.2: p = 99.7 %, n = 6, κ = 4.48). The
  smallest distance wins; the database is then cleared, as the thesis does online (the
  drift between associated landmarks is then a slowly changing one). Unassociated
  landmarks are stored.

Stairs are associated on the floor below the flight, so that a flight climbed and
descended is one landmark; corners on the floor they are on.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.maths.angles import circular_mean
from pdr_core.maths.chi2 import chi2_quantile
from pdr_core.vocabulary import STAIRS_ACTIVITIES, LandmarkType
from pdr_drift.corners import Corner, StepSample


@dataclass(frozen=True)
class Landmark:
    """Table 5.1: type, time [s], position [m] and its covariance (3, 3), the yaw before
    and after [rad] (stairs: the direction of travel, twice), the floor after it and the
    floor it is associated on."""

    id: int
    type: int
    t: float
    position: np.ndarray
    covariance: np.ndarray
    yaw_before: float
    yaw_after: float
    floor: int
    key_floor: int


@dataclass(frozen=True)
class Association:
    first: Landmark
    revisit: Landmark
    distance: float             # Mahalanobis Δ (Eq. (5.4))


def from_corner(corner: Corner, id_: int) -> Landmark:
    return Landmark(id_, LandmarkType.CORNER, corner.t, corner.position, corner.covariance,
                    corner.yaw_before, corner.yaw_after, corner.floor, corner.floor)


class StairsTracker:
    """Flights of stairs from the steps' activities (module docstring)."""

    def __init__(self) -> None:
        self.flight: list[StepSample] = []
        self.floor_before = 0

    def push(self, step: StepSample, id_: int) -> Landmark | None:
        """A step; the landmark of the flight it ends (or None)."""
        on_stairs = step.activity in STAIRS_ACTIVITIES
        landmark = None
        if self.flight and (not on_stairs or step.activity != self.flight[-1].activity):
            landmark = self._landmark(id_)
            self.flight = []
            self.floor_before = landmark.floor
        if on_stairs:
            self.flight.append(step)
        else:
            self.floor_before = step.floor
        return landmark

    def _landmark(self, id_: int) -> Landmark:
        middle = self.flight[len(self.flight) // 2]
        yaw = circular_mean([s.heading for s in self.flight])
        after = self.flight[-1].floor
        return Landmark(id_, LandmarkType.STAIRS, middle.t, middle.position,
                        middle.covariance, yaw, yaw, after, min(after, self.floor_before))


@dataclass
class LandmarkDatabase:
    """Table 5.1 and the association of Section 5.2 (module docstring)."""

    gate_probability: float = 0.997
    gate_dof: int = 6
    min_revisit_s: float = 120.0
    stored: list[Landmark] = field(default_factory=list)

    @property
    def kappa(self) -> float:
        return float(np.sqrt(chi2_quantile(self.gate_probability, self.gate_dof)))

    def candidates(self, landmark: Landmark) -> list[Association]:
        """Every stored landmark ``landmark`` may revisit: of its type and floor, at least
        ``min_revisit_s`` older, within the gate; in the order stored."""
        out = []
        for old in self.stored:
            if old.type != landmark.type or old.key_floor != landmark.key_floor:
                continue
            if landmark.t - old.t < self.min_revisit_s:
                continue
            distance = mahalanobis(old, landmark)
            if distance < self.kappa:
                out.append(Association(old, landmark, distance))
        return out

    def associate(self, landmark: Landmark) -> Association | None:
        """The association of ``landmark`` with the nearest candidate (the database then
        cleared), or None (it is stored)."""
        gated = self.candidates(landmark)
        if not gated:
            self.stored.append(landmark)
            return None
        self.stored.clear()
        return min(gated, key=lambda a: a.distance)


def mahalanobis(a: Landmark, b: Landmark) -> float:
    """Δ of Eq. (5.4) [dimensionless], with both covariances (module docstring)."""
    return distance(np.asarray(a.position, float) - np.asarray(b.position, float),
                    np.asarray(a.covariance, float) + np.asarray(b.covariance, float))


def distance(d: np.ndarray, p: np.ndarray) -> float:
    """√(dᵀ p⁻¹ d) [dimensionless] of a difference d (3,) [m] with covariance p (3, 3)
    [m²]; dimensions without any variance (a level walk's height) must agree exactly and
    are left out."""
    keep = np.diag(p) > 1e-12
    if not np.all(np.abs(d[~keep]) < 1e-6):
        return float("inf")
    return float(np.sqrt(d[keep] @ np.linalg.solve(p[np.ix_(keep, keep)], d[keep])))
