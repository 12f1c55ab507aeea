"""The navigators' health on ``/diagnostics``: the rclpy side of pdr_core.ros.diagnostics,
shared by ``pocket_pdr`` and ``zupt_ekf`` (issue 42).

:class:`NodeDiagnostics` publishes a diagnostic_msgs/DiagnosticArray on ``/diagnostics``
every :data:`PERIOD_S` with one DiagnosticStatus: named ``<node>: navigator`` (the node's
fully qualified name without the leading slash, so ``alice/pocket_pdr: navigator`` in
namespace ``/alice``), ``hardware_id`` the ``frame_id`` of the last IMU message received
(empty before the first), and the level, reason and key-values of
:func:`pdr_core.ros.diagnostics.status` on the counters the node reads at that moment.

The clocks. The 1 Hz cadence runs on the steady (wall) clock: diagnostics tell how the
process is doing, and a node with ``use_sim_time`` (a bag played with ``clock:=true``)
must go on reporting when the simulated time stops or jumps, and must not report ten
times a second under a bag played at ×10; the input rate is per wall-clock second for the
same reason. The array's ``header.stamp`` is the node's clock (ROS time: the simulated
time under ``use_sim_time``, 0 until the first ``/clock``), as every message of the node
is stamped in the graph's time, so that it lines up with the rest of a bag recorded with
it.

``/diagnostics`` is absolute, as diagnostic_updater's (the aggregator and viewers listen
there whatever a node's namespace); reliable, volatile, depth :data:`DEPTH`.

rclpy and diagnostic_msgs are imported inside the functions, as pdr_core's other node
helpers do (pdr_core imports without ROS).
"""
from __future__ import annotations

import time
from collections.abc import Callable

from pdr_core import topics
from pdr_core.io.batch import MessageBatch
from pdr_core.ros.diagnostics import Counters, Status, StatusReports

PERIOD_S = 1.0
"""Time between two reports [s of wall-clock time]."""
DEPTH = 10
"""History of the ``/diagnostics`` publisher (messages)."""


class NodeDiagnostics:
    """A node's 1 Hz report on ``/diagnostics``. The node tells it each block of IMU
    messages received (:meth:`received`: the arrivals and the hardware id); at each
    report it reads the node's other counters with ``counters()``."""

    def __init__(self, node, counters: Callable[[], Counters], task: str = "navigator") -> None:
        """``node``: the rclpy Node; ``counters``: its counters now
        (pdr_core.ros.diagnostics.Counters, copies of the node's, with :attr:`samples_in` for
        the arrivals); ``task``: the part of the status's name after the node's."""
        from diagnostic_msgs.msg import DiagnosticArray
        from rclpy.clock import Clock, ClockType

        self.node = node
        self.counters = counters
        self.name = f"{node.get_fully_qualified_name().lstrip('/')}: {task}"
        self.samples_in = 0
        self.hardware_id = ""
        self.reports = StatusReports(time.monotonic())
        self.publisher = node.create_publisher(DiagnosticArray, topics.DIAGNOSTICS, DEPTH)
        self.timer = node.create_timer(PERIOD_S, self.publish,
                                       clock=Clock(clock_type=ClockType.STEADY_TIME))

    def received(self, imu: MessageBatch, malformed: int = 0) -> None:
        """A block of IMU messages received: ``imu`` decoded, and ``malformed`` that were
        not (counted in :attr:`samples_in` too)."""
        self.samples_in += len(imu) + malformed
        if len(imu):
            self.hardware_id = str(imu.frame_id[-1])

    def publish(self) -> None:
        """The report of the period since the last one (the timer's callback)."""
        report = self.reports.report(self.counters(), time.monotonic())
        self.publisher.publish(diagnostic_array(report, self.name, self.hardware_id,
                                                self.node.get_clock().now().to_msg()))


def diagnostic_array(status: Status, name: str, hardware_id: str, stamp):
    """A diagnostic_msgs/DiagnosticArray stamped ``stamp`` (builtin_interfaces/Time)
    holding ``status`` as one DiagnosticStatus named ``name``."""
    from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

    array = DiagnosticArray()
    array.header.stamp = stamp
    array.status = [DiagnosticStatus(
        level=bytes([int(status.level)]), name=name, message=status.message,
        hardware_id=hardware_id,
        values=[KeyValue(key=key, value=value) for key, value in status.values])]
    return array
