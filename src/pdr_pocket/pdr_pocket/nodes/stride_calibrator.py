"""Node ``stride_calibrator``: the foot INS calibrates the pocket's stride and riser lines
while the person walks (issue 57; Muñoz Díaz 2016, Section 7.3).

Subscribes ``pdr/pocket/step`` (pdr_msgs/Step, ``pocket_pdr``'s, one per gait cycle) and
``pdr/foot/step`` (pdr_msgs/Step, ``zupt_ekf``'s, one per stride), reliable,
transient-local, keep-all, as raw CDR decoded in blocks (pdr_core.ros.backlog), each
stream converted by the core (pdr_pocket.line_calibration.pocket_steps, .foot_strides,
each with its stream's previous heading) and pushed into one
:class:`~pdr_pocket.line_calibration.StrideCalibrator`, whose decisions depend on the
stamps alone: the fit equals ``calibrated()`` on the same messages offline. After each
push that paired a step it publishes ``pdr/pocket/stride_lines`` (pdr_msgs/StrideLines,
pdr_pocket.messages.stride_lines_fields; reliable, transient-local, depth 100), stamped
with the last pocket step decided, and hands the lines fitted from at least ``min_pairs``
pairs (then from each ``every_pairs`` more) that changed to the navigator: a call of
``<target_node>/set_parameters_atomically`` (the standard rcl_interfaces service, all
the lines of one call taken together or none) with ``step_length.a_h_m_per_deg``,
``step_length.b_h_m``, ``stairs.a_u_cm_per_deg``, ... (pdr_pocket.saved_lines
.LINE_PARAMETERS), one call at a time, the latest lines sent again once it is answered
when they changed meanwhile, and all of them to a navigator started again; each answer is
logged.

Parameters (docs/nodes.md): ``config`` (the pocket configuration whose lines are the priors,
as ``pocket_pdr``'s), ``target_node`` (``pocket_pdr``), ``min_pairs`` (30), ``every_pairs``
(20: a line is handed over again each time it has that many pairs more, so the navigator
takes and logs a line about every 20 strides, not at each), ``forgetting`` (λ of the fit,
0.999), ``save_to`` (where the saved fit, the YAML of ``pdr-pocket calibrate-step --foot``,
is written after each update of the lines and when the node shuts down; empty: not saved). A
message that cannot be decoded, with a value that is not finite or an unknown activity
(pdr_pocket.line_calibration.unusable), or stamped not after the last of its stream is
dropped and counted with a throttled warning; the refusals of the pairing
(pdr_pocket.line_calibration.REASONS) are counted in the published lines and said in a
throttled line.
"""
from __future__ import annotations

import contextlib
import math
from dataclasses import replace

from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParametersAtomically
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.io.headers import set_header
from pdr_core.io.msgtypes import STEP
from pdr_core.ros.backlog import decode_block, waiting_messages
from pdr_core.ros.node_main import spin_node
from pdr_core.ros.node_params import declare
from pdr_core.ros.node_wiring import wiring
from pdr_core.topics import graph_name
from pdr_msgs.msg import Step, StrideLines
from pdr_pocket.config import load_pocket_config
from pdr_pocket.line_calibration import (
    CalibrationSettings,
    StrideCalibrator,
    foot_strides,
    pocket_steps,
    unusable,
)
from pdr_pocket.messages import stride_lines_fields
from pdr_pocket.saved_lines import LINE_PARAMETERS, line_parameters, saved_fit, write_fit

WRITTEN_BY = "the node stride_calibrator"      # the saved fit's first line names it
MAX_BLOCK = 100         # messages taken from a subscription's queue per callback
DEPTH = 100             # history of the stride_lines publisher (messages)
WARN_S = 5.0            # dropped messages and refusals: said at most this often [s]


class StrideCalibratorNode(Node):
    """Adapter from the two streams of steps to the calibrator, its lines and the
    navigator's parameters."""

    def __init__(self) -> None:
        super().__init__("stride_calibrator")
        path = declare(self, "config", "", "pocket navigator YAML whose lines are the priors "
                       "(pdr_pocket.config); empty: the installed config/pocket_pdr.yaml")
        self.target = declare(self, "target_node", "pocket_pdr", "the navigator whose "
                              "set_parameters_atomically service takes the fitted lines")
        self.min_pairs = declare(self, "min_pairs", 30, "a line is handed to the navigator "
                                 "once fitted from this many pairs [pairs]")
        self.every_pairs = declare(self, "every_pairs", 20, "then again each time it has "
                                   "this many pairs more [pairs]")
        forgetting = declare(self, "forgetting", CalibrationSettings.forgetting,
                             "forgetting factor λ of the fit, (0, 1]; 1: none")
        self.save_to = declare(self, "save_to", "", "where the saved fit (YAML of "
                               "pdr-pocket calibrate-step --foot) is written after each "
                               "update and at shutdown; empty: not saved")
        for name in ("min_pairs", "every_pairs"):
            if getattr(self, name) < 1:
                raise InputError(f"parameter {name}", f"must be at least 1, got "
                                                      f"{getattr(self, name)}")
        config = load_pocket_config(path or None)
        try:
            settings = CalibrationSettings(forgetting=forgetting,
                                           height_m=config.person.height_m)
        except ValueError as exc:
            raise InputError("parameter forgetting", str(exc)) from None
        self.calibrator = StrideCalibrator(config.step_length, config.stairs, settings)
        qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.streams = {
            name: _Stream(self.create_subscription(
                Step, graph_name(topic), lambda raw, name=name: self.on_steps(name, raw), qos,
                raw=True), convert)
            for name, topic, convert in (("pocket", topics.POCKET_STEP, pocket_steps),
                                         ("foot", topics.FOOT_STEP, foot_strides))}
        out = QoSProfile(depth=DEPTH, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.lines_pub = self.create_publisher(StrideLines, graph_name(topics.POCKET_STRIDE_LINES),
                                               out)
        self.client = self.create_client(SetParametersAtomically,
                                         f"{self.target}/set_parameters_atomically")
        self.pocket_stamps: dict[float, int] = {}   # the pocket steps not decided: s -> ns
        self.last_decided_ns = 0
        self.offered: dict[str, float] = {}         # the lines last sent to the navigator
        self.offered_pairs: dict[str, int] = {}     # ... and their pairs then, by line
        self.in_flight = None
        self.saved_told = False
        self.create_timer(1.0, self.hand_over)
        self.get_logger().info(
            f"stride_calibrator: configuration {path or 'default'}; lines handed to "
            f"{self.client.srv_name} from {self.min_pairs} pairs; forgetting {forgetting:g}; "
            f"{wiring(self)}")

    def on_steps(self, name: str, raw: bytes) -> None:
        """One message of stream ``name`` and the ones waiting behind it, as one block:
        converted, checked and pushed one by one into the calibrator."""
        stream = self.streams[name]
        batch, malformed = decode_block(STEP, [raw, *waiting_messages(stream.subscription,
                                                                      MAX_BLOCK - 1)])
        stream.dropped["malformed_cdr"] += malformed
        items = stream.convert(batch, stream.previous_heading)
        if len(batch) and math.isfinite(batch["heading"][-1]):
            stream.previous_heading = float(batch["heading"][-1])
        push = self.calibrator.push_pocket if name == "pocket" else self.calibrator.push_foot
        decisions = []
        for item, stamp in zip(items, batch.stamp_ns, strict=True):
            problem = unusable(item)
            if problem is not None:
                stream.dropped[problem] += 1
                continue
            try:
                decisions += push([item])
            except ValueError:
                stream.dropped["stamp_not_increasing"] += 1
                continue
            if name == "pocket":
                self.pocket_stamps[item.stamp_s] = int(stamp)
        self.report(name)
        self.decided(decisions)

    def decided(self, decisions) -> None:
        """The lines published and handed over after decisions that paired a step."""
        for decision in decisions:
            self.last_decided_ns = self.pocket_stamps.pop(decision.stamp_s,
                                                          self.last_decided_ns)
        refused = [d for d in decisions if d.reason is not None]
        if refused:
            counts = ", ".join(f"{k} {n}" for k, n in self.calibrator.refused.items() if n)
            self.get_logger().info(f"stride_calibrator: pocket steps refused so far: {counts}; "
                                   f"the last for {refused[-1].reason} ({refused[-1].detail})",
                                   throttle_duration_sec=WARN_S)
        if not any(d.reason is None for d in decisions):
            return
        msg = StrideLines(**stride_lines_fields(self.calibrator))
        set_header(msg.header, self.last_decided_ns, "")
        self.lines_pub.publish(msg)
        if self.save() and self.save_to and not self.saved_told:
            self.get_logger().info(f"stride_calibrator: the fit saved to {self.save_to} "
                                   "(again after each update)")
            self.saved_told = True
        self.hand_over()

    def hand_over(self) -> None:
        """The lines fitted from ``min_pairs`` pairs, and again from each ``every_pairs``
        pairs more, that changed since they were offered, to the navigator's
        set_parameters_atomically service, one call at a time (also the timer's
        callback: a navigator that was not there yet gets them, and one started again gets
        them all)."""
        if not self.client.service_is_ready():
            self.offered.clear()
            self.offered_pairs.clear()
        if self.in_flight is not None or not self.client.service_is_ready():
            return
        fit = saved_fit(self.calibrator)
        due = {name: line for name, line in fit.lines.items() if line.fit is not None
               and line.fit.pairs >= self.offered_pairs.get(name, -self.every_pairs)
               + self.every_pairs}
        values = line_parameters(replace(fit, lines=due), self.min_pairs)
        changed = {k: v for k, v in values.items() if self.offered.get(k) != v}
        if not changed:
            return
        self.offered_pairs.update({name: line.fit.pairs for name, line in due.items()
                                   if LINE_PARAMETERS[name][0] in values})
        request = SetParametersAtomically.Request(parameters=[
            Parameter(name=k, value=ParameterValue(type=ParameterType.PARAMETER_DOUBLE,
                                                   double_value=v))
            for k, v in changed.items()])
        self.offered.update(changed)
        self.in_flight = self.client.call_async(request)
        self.in_flight.add_done_callback(lambda future: self.answered(future, changed))

    def answered(self, future, values: dict[str, float]) -> None:
        """The navigator's answer, logged (a refusal as a warning with its reason; the lines
        it refused are not offered again until they change); then the lines that changed
        meanwhile."""
        self.in_flight = None
        response = future.result()
        said = ", ".join(f"{k} = {v:.6g}" for k, v in values.items())
        if response is not None and response.result.successful:
            self.get_logger().info(f"stride_calibrator: {self.target} took {said}",
                                   throttle_duration_sec=WARN_S)
        else:
            reason = response.result.reason if response is not None else "no answer"
            self.get_logger().warning(f"stride_calibrator: {self.target} refused {said}: "
                                      f"{reason}", throttle_duration_sec=WARN_S)
        self.hand_over()

    def report(self, name: str) -> None:
        """The messages of stream ``name`` dropped so far, said when they rose
        (throttled)."""
        stream = self.streams[name]
        for key, count in stream.dropped.items():
            said = f"{stream.subscription.topic_name}: {count} messages with {key} dropped so far"
            if count and key not in stream.reported:        # the first of its kind at once
                self.get_logger().warning(said)
            elif count > stream.reported.get(key, 0):
                self.get_logger().warning(said, throttle_duration_sec=WARN_S)
            if count:
                stream.reported[key] = count

    def save(self) -> bool:
        """The saved fit written to ``save_to`` (when given); False when it could not be."""
        if not self.save_to:
            return True
        sources = {name: s.subscription.topic_name for name, s in self.streams.items()}
        try:
            write_fit(self.save_to, saved_fit(self.calibrator, sources), WRITTEN_BY)
        except OSError as exc:
            self.get_logger().error(f"stride_calibrator: the fit not saved to {self.save_to}: "
                                    f"{exc}", throttle_duration_sec=WARN_S)
            return False
        return True

    def destroy_node(self) -> None:
        """The fit saved once more before the node goes (the context may be shut down
        already: nothing logged)."""
        if self.save_to:
            with contextlib.suppress(OSError):
                write_fit(self.save_to, saved_fit(self.calibrator, {
                    name: s.subscription.topic_name for name, s in self.streams.items()}),
                    WRITTEN_BY)
        super().destroy_node()


class _Stream:
    """One input stream: its subscription, the core's converter, the previous message's
    heading [rad] (NaN before the first) and the messages dropped by reason."""

    def __init__(self, subscription, convert) -> None:
        self.subscription = subscription
        self.convert = convert
        self.previous_heading = math.nan
        self.dropped = {"malformed_cdr": 0, "non_finite": 0, "unknown_activity": 0,
                        "stamp_not_increasing": 0}
        self.reported: dict[str, int] = {}


def main(args: list[str] | None = None) -> None:
    spin_node("stride_calibrator", StrideCalibratorNode, args)


if __name__ == "__main__":
    main()
