"""The drift estimator on the navigator's messages, for the live node (no rclpy here).

:class:`StreamingDrift` pairs each ``pdr/pocket/step`` with the ``pdr/pocket/pose`` of the
same stamp (they travel separately and either may come first), and feeds the pair to
:class:`~pdr_drift.estimator.DriftEstimator`. The floor is the pose's height over
``floor_height_m``. A message that cannot be used (not finite, a covariance that is not
symmetric positive semi-definite, a stamp older than the last step) is dropped and
counted, so one bad message never stops it. Unpaired messages are kept for at most
:data:`MAX_UNPAIRED`. A state restored from a file (pdr_drift.state_file) counts the
messages stamped at or before its last step as ``before_restart`` (a navigator's
transient-local history sent again to the restarted node) and drops them: they were
taken into account before.
"""
from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass, field

import numpy as np

from pdr_core.vocabulary import ACTIVITY_VALUES, FLOOR_HEIGHT_M
from pdr_drift.config import DriftConfig
from pdr_drift.corners import StepSample
from pdr_drift.estimator import DriftEstimator, StepResult

MAX_UNPAIRED = 100


@dataclass
class StreamingDrift:
    config: DriftConfig = field(default_factory=DriftConfig)
    floor_height_m: float = FLOOR_HEIGHT_M
    counts: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        self.estimator = DriftEstimator(self.config)
        self.steps: OrderedDict[int, tuple[float, int]] = OrderedDict()
        self.poses: OrderedDict[int, tuple[np.ndarray, np.ndarray]] = OrderedDict()
        self.last_stamp_ns: int | None = None
        self.t0_ns: int | None = None
        self.restored_until_ns: int | None = None
        self.counts = {"bad_step": 0, "bad_pose": 0, "old_stamp": 0, "unpaired": 0,
                       "before_restart": 0}

    def push_step(self, stamp_ns: int, heading: float, activity: int) -> StepResult | None:
        if not np.isfinite(heading) or activity not in ACTIVITY_VALUES:
            self.counts["bad_step"] += 1
            return None
        return self._add(self.steps, stamp_ns, (float(heading), int(activity)))

    def push_pose(self, stamp_ns: int, position, covariance) -> StepResult | None:
        p = np.asarray(position, float).reshape(3)
        c = np.asarray(covariance, float).reshape(3, 3)
        if not (np.isfinite(p).all() and np.isfinite(c).all() and np.allclose(c, c.T)
                and np.linalg.eigvalsh(c).min() >= -1e-9):
            self.counts["bad_pose"] += 1
            return None
        return self._add(self.poses, stamp_ns, (p, c))

    def _add(self, book: OrderedDict, stamp_ns: int, value) -> StepResult | None:
        if self.restored_until_ns is not None and stamp_ns <= self.restored_until_ns:
            self.counts["before_restart"] += 1
            return None
        if self.last_stamp_ns is not None and stamp_ns <= self.last_stamp_ns:
            self.counts["old_stamp"] += 1
            return None
        book[int(stamp_ns)] = value
        while len(book) > MAX_UNPAIRED:
            book.popitem(last=False)
            self.counts["unpaired"] += 1
        if stamp_ns not in self.steps or stamp_ns not in self.poses:
            return None
        heading, activity = self.steps.pop(stamp_ns)
        position, covariance = self.poses.pop(stamp_ns)
        self._forget_before(stamp_ns)
        self.last_stamp_ns = int(stamp_ns)
        if self.t0_ns is None:
            self.t0_ns = int(stamp_ns)
        floor = int(np.round(position[2] / self.floor_height_m))
        return self.estimator.push(StepSample((stamp_ns - self.t0_ns) * 1e-9, heading, activity,
                                              position, covariance, floor))

    def _forget_before(self, stamp_ns: int) -> None:
        """Messages older than a completed pair will never be paired."""
        for book in (self.steps, self.poses):
            for old in [s for s in book if s < stamp_ns]:
                del book[old]
                self.counts["unpaired"] += 1
