"""The health of a navigator node from its counters (no rclpy here): the status that
pdr_core.ros.node_diagnostics publishes on ``/diagnostics`` once a second (issue 42).

- :class:`Level`: OK, WARN and ERROR, with the values of diagnostic_msgs/DiagnosticStatus.
- :class:`Counters`: what a node has counted so far, read at a report.
- :class:`Status`: a level, its reason and the key-values.
- :func:`status`: the status of one report period, from the counters at its start and at
  its end.
- :class:`StatusReports`: the reports of one node in turn, each against the one before.

The rules (docs/nodes.md, "Diagnostics"), applied in this order:

- **ERROR** while the node is not navigating (:attr:`Counters.failed`: data in g or deg/s
  refused until ``~/reset``); the message is ``not navigating: <why>``.
- **WARN** when, since the last report, a problem counter rose (:attr:`Counters.problems`:
  samples dropped as ``non_finite``, ``implausible`` or ``stamp_not_increasing``, messages
  ``malformed_cdr``, ``gaps`` in the stamps, ``corrections_refused``, ...), or while a
  condition holds (:attr:`Counters.conditions`: ``mag_paused``, ``mag_off``). The message
  names each counter that rose with how many since the last report, in the counters'
  order, then each condition with its reason: ``non_finite +1, corrections_refused +1
  since the last report; mag_paused: ...``. An ERROR's message carries them after its
  own reason.
- **OK** otherwise: a report period that passes clean is OK, whatever came before. The
  message says ``navigating``, or ``waiting for IMU samples`` before the first, or ``no
  IMU sample since the last report`` when the input has stopped (a bag played to its end:
  no fault of the node's).

A counter lower than at the last report was started again (``~/reset`` zeroes the
navigator's counts): its whole value counts as risen since the last report.

The input rate (``input_rate_hz``, samples/s) is that of the arrivals: the IMU messages
received in the report period over its length in wall-clock seconds, so it tells what the
node is given per second of its process's life. A bag played at ×10 shows ten times the
sensor's rate, and the rate falls to 0 when the input stops.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import IntEnum


class Level(IntEnum):
    """A status's level: the byte values of diagnostic_msgs/DiagnosticStatus."""

    OK = 0
    WARN = 1
    ERROR = 2


@dataclass(frozen=True)
class Counters:
    """What a navigator node has counted so far (since its start, or its navigator's since
    ``~/reset``), read at a report.

    Attributes:
        samples_in: IMU messages received, kept or not (malformed ones too).
        problems: counter name -> count; one that rose since the last report is a WARN
            (dropped samples by reason, malformed messages, gaps, refused corrections).
            Their order is the order of the message and of the key-values.
        tallies: counter name -> count, reported and never warned of (accepted
            corrections, samples without a magnetometer reading).
        conditions: condition name -> its reason while it holds, None while it does not
            (``mag_paused``, ``mag_off``): a WARN for as long as it holds.
        failed: why the node is not navigating (an ERROR), or None.
        inputs: input name -> what the navigator does with it ("fused", "not fused: why"),
            reported as key-values after the counters, never warned of.
    """

    samples_in: int = 0
    problems: Mapping[str, int] = field(default_factory=dict)
    tallies: Mapping[str, int] = field(default_factory=dict)
    conditions: Mapping[str, str | None] = field(default_factory=dict)
    failed: str | None = None
    inputs: Mapping[str, str] = field(default_factory=dict)


@dataclass(frozen=True)
class Status:
    """One report: its level, the reason (``message``) and the key-values (key, value),
    as diagnostic_msgs/DiagnosticStatus carries them (values are strings)."""

    level: Level
    message: str
    values: list[tuple[str, str]]


def risen(previous: int, current: int) -> int:
    """How much a counter rose between two reports: its whole value when it is lower than
    before (started again at ``~/reset``)."""
    return current if current < previous else current - previous


def status(previous: Counters, current: Counters, period_s: float) -> Status:
    """The status of a report period of ``period_s`` [s of wall-clock time] from the
    counters at its start (``previous``, all zero at the node's start) and at its end
    (``current``), by the rules of the module docstring."""
    new_samples = risen(previous.samples_in, current.samples_in)
    rises = {name: risen(previous.problems.get(name, 0), count)
             for name, count in current.problems.items()}
    reasons = [f"{name} +{count}" for name, count in rises.items() if count > 0]
    warnings = [f"{', '.join(reasons)} since the last report"] if reasons else []
    warnings += [f"{name}: {why}" for name, why in current.conditions.items()
                 if why is not None]
    if current.failed is not None:
        level, message = Level.ERROR, "; ".join([f"not navigating: {current.failed}",
                                                 *warnings])
    elif warnings:
        level, message = Level.WARN, "; ".join(warnings)
    elif current.samples_in == 0:
        level, message = Level.OK, "waiting for IMU samples"
    elif new_samples == 0:
        level, message = Level.OK, "no IMU sample since the last report"
    else:
        level, message = Level.OK, "navigating"
    rate_hz = new_samples / period_s if period_s > 0 else 0.0
    values = [("samples_in", str(current.samples_in)), ("input_rate_hz", f"{rate_hz:.1f}"),
              ("navigating", _flag(current.failed is None))]
    values += [(name, str(count)) for name, count in
               {**current.problems, **current.tallies}.items()]
    values += [(name, _flag(why is not None)) for name, why in current.conditions.items()]
    values += list(current.inputs.items())
    return Status(level, message, values)


def _flag(value: bool) -> str:
    return "true" if value else "false"


class StatusReports:
    """The reports of one node in turn: each :meth:`report` is the status of the period
    since the one before (since ``start_s`` for the first, with every counter at 0)."""

    def __init__(self, start_s: float) -> None:
        """``start_s``: the wall-clock time of the node's start [s] (any monotonic clock,
        the one the reports are timed with)."""
        self.previous = Counters()
        self.previous_s = start_s

    def report(self, counters: Counters, now_s: float) -> Status:
        """The status of the period from the last report to ``now_s`` [s], whose counters
        at its end are ``counters``; they become the next period's start."""
        out = status(self.previous, counters, now_s - self.previous_s)
        self.previous, self.previous_s = counters, now_s
        return out
