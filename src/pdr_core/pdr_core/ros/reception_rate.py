"""The rate at which a topic's messages arrive, as ``ros2 topic hz`` reports it (no rclpy).

The rules are those of ros2cli's ``ros2topic/verb/hz.py`` (Jazzy: ``ROSTopicHz``'s
``callback_hz``, ``get_hz`` and ``print_hz``), written again because ros2cli is not on
PyPI (docs/ros2.md):

- Each message's reception time [ns] is taken; the first one only starts the count, each
  next one adds the interval since the one before. The last ``window`` intervals are kept
  (ros2cli's default 10000 messages).
- A report is due once the last message came at least 1 s (of reception time) after the
  one the previous report was made at. The first message that finds an interval kept
  only sets that mark: nothing is printed before about 1 s of messages, and nothing while
  no message comes.
- The report: rate = 1 / mean interval [Hz] (0 for a zero mean), the smallest and largest
  interval and their population standard deviation [s], and the number of intervals.
"""
from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

DEFAULT_WINDOW = 10000          # ros2 topic hz's --window default [messages]
REPORT_PERIOD_NS = 1_000_000_000  # reception time between two reports [ns]


@dataclass(frozen=True)
class RateReport:
    """One report of ``ros2 topic hz``."""

    rate_hz: float      # 1 / mean interval [Hz]
    min_s: float        # shortest interval [s]
    max_s: float        # longest interval [s]
    std_s: float        # population standard deviation of the intervals [s]
    window: int         # number of intervals the report is made of

    def text(self) -> str:
        """The block ros2cli's ``print_hz`` prints (two lines, no final newline)."""
        return (f"average rate: {self.rate_hz:.3f}\n\tmin: {self.min_s:.3f}s max: "
                f"{self.max_s:.3f}s std dev: {self.std_s:.5f}s window: {self.window}")


def rate_report(intervals_ns: Sequence[int]) -> RateReport:
    """The report of these intervals between receptions [ns] (at least one)."""
    n = len(intervals_ns)
    mean = sum(intervals_ns) / n
    std = math.sqrt(sum((x - mean) ** 2 for x in intervals_ns) / n)
    return RateReport(rate_hz=1e9 / mean if mean > 0 else 0.0, min_s=min(intervals_ns) * 1e-9,
                      max_s=max(intervals_ns) * 1e-9, std_s=std * 1e-9, window=n)


class ReceptionRate:
    """One topic's receptions and the reports due on them (ros2cli's ``ROSTopicHz`` for one
    topic, on a clock that does not jump: ros2cli's resets on a clock going back or to 0
    are not needed)."""

    def __init__(self, window: int = DEFAULT_WINDOW) -> None:
        self.intervals: deque[int] = deque(maxlen=window)
        self.last_ns: int | None = None         # the latest reception
        self.reported_ns: int | None = None     # the reception the last report was made at

    def received(self, now_ns: int) -> None:
        """A message came at ``now_ns`` [ns, a monotonic clock]."""
        if self.last_ns is not None:
            self.intervals.append(now_ns - self.last_ns)
        self.last_ns = now_ns

    def report(self) -> RateReport | None:
        """The report, when one is due (see the module's docstring); else None."""
        if not self.intervals:
            return None
        if self.reported_ns is None:
            self.reported_ns = self.last_ns
            return None
        if self.last_ns < self.reported_ns + REPORT_PERIOD_NS:
            return None
        self.reported_ns = self.last_ns
        return rate_report(self.intervals)
