"""Corner detection from the heading (Muñoz Díaz 2016, Section 5.1.1).

Both detectors read one heading per step: the navigator's step heading is the circular
mean of the thigh's heading over the gait cycle, the thesis' buffer of q = 1 s at one
step per second, so the hip's sway (about 20° peak to peak) is already averaged out and
q and m follow the walking speed by counting steps, not seconds.

- :class:`BufferCornerDetector`, the basic detector: the mean heading of ``q_steps``
  before, ψ̄_B, and of ``q_steps`` after a gap of ``m_steps``, ψ̄_A (Eq. (5.2)); a corner
  when r1 < |ψ̄_A − ψ̄_B| < r2 (Eq. (5.3)), either way round. The condition holds for a few
  consecutive steps around a turn; the step where |ψ̄_A − ψ̄_B| is nearest 90° wins.
- :class:`TurnCornerDetector`, the improved detector of Fig. 5.3: the heading's rate per
  step delimits each turn (a step turning by ``rate_min_deg_per_step``, or two steps by
  twice it), and the jump from before the turn to after it (means over
  ``q_steps``) is a corner when within ``tolerance_deg`` of 90° or of 180°, whatever the
  radius and speed.

Headings are ENU yaw [rad]; :class:`Corner` carries the step indices it spans.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from pdr_core.maths.angles import circular_mean, wrap_angle


@dataclass(frozen=True)
class StepSample:
    """What the drift estimator needs of a step: time [s], heading [rad], activity
    (pdr_msgs/Step), position [m] (3,) and its covariance (3, 3), floor."""

    t: float
    heading: float
    activity: int
    position: np.ndarray
    covariance: np.ndarray
    floor: int


@dataclass(frozen=True)
class Corner:
    t: float                  # the turn's middle step [s]
    yaw_before: float         # [rad]
    yaw_after: float
    position: np.ndarray      # the turn's middle step
    covariance: np.ndarray
    floor: int
    turn: float               # yaw_after − yaw_before, wrapped [rad]


def _corner(steps: list[StepSample], before: list[float], after: list[float]) -> Corner:
    middle = steps[len(steps) // 2]
    b, a = circular_mean(before), circular_mean(after)
    return Corner(middle.t, b, a, middle.position, middle.covariance, middle.floor,
                  float(wrap_angle(a - b)))


class BufferCornerDetector:
    """Eqs. (5.2)-(5.3) on step headings (module docstring)."""

    def __init__(self, q_steps: int = 1, m_steps: int = 5, r1_deg: float = 80.0,
                 r2_deg: float = 100.0) -> None:
        self.q, self.m = q_steps, m_steps
        self.r1, self.r2 = np.radians(r1_deg), np.radians(r2_deg)
        self.window: deque = deque(maxlen=2 * q_steps + m_steps)
        self.candidate: tuple[float, Corner] | None = None

    def push(self, step: StepSample) -> Corner | None:
        """A step; the corner found once the condition stops holding (or None)."""
        self.window.append(step)
        if len(self.window) < self.window.maxlen:
            return None
        steps = list(self.window)
        before = [s.heading for s in steps[:self.q]]
        after = [s.heading for s in steps[-self.q:]]
        jump = abs(float(wrap_angle(circular_mean(after) - circular_mean(before))))
        if self.r1 < jump < self.r2:
            corner = _corner(steps, before, after)
            if self.candidate is None or abs(jump - np.pi / 2) < self.candidate[0]:
                self.candidate = (abs(jump - np.pi / 2), corner)
            return None
        found, self.candidate = self.candidate, None
        return None if found is None else found[1]


class TurnCornerDetector:
    """Fig. 5.3: turns delimited by the heading's rate (module docstring)."""

    def __init__(self, rate_min_deg_per_step: float = 6.0, q_steps: int = 2,
                 tolerance_deg: float = 15.0) -> None:
        self.rate_min = np.radians(rate_min_deg_per_step)
        self.q = q_steps
        self.tolerance = np.radians(tolerance_deg)
        self.recent: deque = deque(maxlen=3)            # the last three headings
        self.straight: deque = deque(maxlen=q_steps)    # headings before a turn
        self.before: list[float] = []
        self.turn: list[StepSample] = []
        self.after: list[float] = []

    def _turning(self) -> bool:
        """The last step turned by ``rate_min``, or the last two by twice it (a slow
        wide turn with one straighter step inside)."""
        h = list(self.recent)
        one = len(h) >= 2 and abs(float(wrap_angle(h[-1] - h[-2]))) >= self.rate_min
        two = len(h) == 3 and abs(float(wrap_angle(h[-1] - h[-3]))) >= 2 * self.rate_min
        return one or two

    def push(self, step: StepSample) -> Corner | None:
        """A step; a corner once the heading has settled after a turn (or None)."""
        self.recent.append(step.heading)
        turning = self._turning()
        found = None
        if turning:
            if self.after:                            # a new turn before this one settled
                found = self._judge()
            if not self.turn:
                self.before = list(self.straight)
            self.turn.append(step)
        elif self.turn:
            self.after.append(step.heading)
            if len(self.after) == self.q:
                found = self._judge()
        else:
            self.straight.append(step.heading)
        return found

    def _judge(self) -> Corner | None:
        before, turn, after = self.before, self.turn, self.after
        self.straight.clear()
        self.straight.extend(after)
        self.before, self.turn, self.after = [], [], []
        if not before or not turn:
            return None
        corner = _corner(turn, before, after)
        size = abs(corner.turn)
        if min(abs(size - np.pi / 2), abs(size - np.pi)) <= self.tolerance:
            return corner
        return None
