"""Node ``landmark_drift``: corners and stairs as landmarks, revisits, heading drift, and
the corrections sent to ``pocket_pdr`` (Muñoz Díaz 2016, chapter 5 and Section 6.1).

Subscribes ``pdr/pocket/step`` (pdr_msgs/Step) and ``pdr/pocket/pose``
(geometry_msgs/PoseWithCovarianceStamped), paired by stamp (pdr_drift.streaming).
Publishes every landmark on ``pdr/landmarks`` (pdr_msgs/Landmark) and every drift
estimate on ``pdr/drift`` (pdr_msgs/DriftEstimate). After each association it calls
``pdr/pocket/apply_correction`` (pdr_msgs/srv/ApplyCorrection) with an asynchronous
client: a call not answered within ``correction_timeout_s`` is sent again, the same
request with the same ``request_id`` (a new random id per correction,
pdr_core.corrections.answered_requests), so the navigator applies it once and answers both alike;
the resends are counted in the log. While the service is not there the correction waits and
is retried every ``retry_period_s``, up to ``max_retries`` tries in all, so a restarting
``pocket_pdr`` is caught up with and a refused correction blocks nothing. What happens to
each correction is logged.

Each correction carries the stamp of the step it was computed from, and the navigator
takes it there, running the samples since again (pdr_pocket.streaming): the steps it had
published in between are replaced by those of its answer (``revised_steps``,
``revised_poses``). So that the estimator sees the walk as the navigator finally has it,
whatever the answer's delay, the steps and poses that come while a correction is
outstanding are held (the corrections go one at a time); once answered, the revised ones
are taken in their place, then those held that come after them, and any copy of a
replaced one that comes late is dropped. The result equals the in-process loop
(``pdr-pocket run --drift online``) at any replay speed. ``correction_delay_steps`` holds
each correction back until that many more steps have come (or ``max_retries`` retry
periods without them), to test a late answer.

With ``state_file`` set, the estimator's whole state (landmarks, hypotheses, the walk's
start and last step) is written there after every step (pdr_drift.state_file) and read
back at start: killed and started again mid-walk, the node goes on where it was, and the
steps and poses the navigator's transient-local history sends again are recognised as
taken into account (counted as ``before_restart``, not warned of). A state file it cannot
use (unreadable, another configuration) is set aside as ``<file>.refused`` and the node
starts afresh, saying why.

Parameters (docs/nodes.md): ``config`` (YAML of pdr_drift.config; default the installed
config/landmark_drift.yaml), ``state_file``, ``floor_height_m``, ``correction_timeout_s``,
``retry_period_s``, ``max_retries``, ``correction_delay_steps``, ``map_frame`` (the frame
of the poses it reads and of the landmarks and drift estimates it publishes: REP-105's
map, pdr_core.frames; steps and poses stamped in another frame are dropped and counted,
a graph wired to another person's navigator). The start-up line names the resolved
topics and services.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
from geometry_msgs.msg import PoseWithCovarianceStamped
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from pdr_core import topics
from pdr_core.corrections.answered_requests import new_request_id
from pdr_core.corrections.correction import request_fields
from pdr_core.errors import InputError
from pdr_core.frames import MAP_FRAME
from pdr_core.io.headers import set_header, set_time, stamp_ns
from pdr_core.ros.node_main import spin_node
from pdr_core.ros.node_params import declare, refuse_removed
from pdr_core.ros.node_wiring import wiring
from pdr_core.topics import graph_name
from pdr_core.vocabulary import FLOOR_HEIGHT_M, LandmarkType
from pdr_drift.config import default_config_path, load_drift_config
from pdr_drift.state_file import load_state, save_state
from pdr_drift.streaming import StreamingDrift
from pdr_msgs.msg import DriftEstimate, Landmark, Step
from pdr_msgs.srv import ApplyCorrection


class LandmarkDriftNode(Node):
    """Adapter from steps and poses to the drift estimator and the correction client."""

    def __init__(self) -> None:
        super().__init__("landmark_drift")
        refuse_removed(self, {"frame_id": "map_frame"})
        path = declare(self, "config", "", "drift estimator YAML (pdr_drift.config); empty: "
                       "the installed config/landmark_drift.yaml")
        floor_height = declare(self, "floor_height_m", FLOOR_HEIGHT_M,
                               "the floor of a pose is its height over this [m]")
        self.timeout_s = declare(self, "correction_timeout_s", 5.0, "a correction call not "
                                 "answered within this is sent again [s]")
        retry_period = declare(self, "retry_period_s", 1.0,
                               "how often waiting corrections are retried [s]")
        self.max_retries = declare(self, "max_retries", 10, "a correction waiting longer "
                                   "for the service is dropped [tries]")
        self.map_frame = declare(self, "map_frame", MAP_FRAME, "frame of the poses read and "
                                 "of the landmarks and drift estimates published")
        self.state_file = declare(self, "state_file", "", "where the estimator's state is kept "
                                  "across restarts; empty: in memory only")
        self.drift = self.restored(load_drift_config(path or default_config_path()),
                                   floor_height)
        qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.create_subscription(Step, graph_name(topics.POCKET_STEP), self.on_step, qos)
        self.create_subscription(PoseWithCovarianceStamped, graph_name(topics.POCKET_POSE),
                                 self.on_pose, qos)
        out = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.landmark_pub = self.create_publisher(Landmark, graph_name(topics.LANDMARKS), out)
        self.drift_pub = self.create_publisher(DriftEstimate, graph_name(topics.DRIFT), out)
        self.client = self.create_client(ApplyCorrection,
                                         graph_name(topics.POCKET_APPLY_CORRECTION))
        self.delay_steps = declare(self, "correction_delay_steps", 0, "hold each correction "
                                   "until this many later steps have come (to test a late "
                                   "answer) [steps]")
        self.waiting: list[list] = []        # [request, tries], sent one at a time
        self.in_flight: list[list] = []      # [future, sent at (s), request, tries]
        self.held: list = []                 # steps and poses come while one is outstanding
        self.held_steps = self.delay_ticks = 0
        self.revision = None                 # the last accepted answer not yet taken
        self.superseded_until: int | None = None   # the last revised step's stamp [ns]
        self.create_timer(retry_period, self.on_timer)
        self.reported: dict[str, int] = {}
        self.other_frame = 0
        self.resent = 0                      # calls sent again after correction_timeout_s
        self.get_logger().info(f"landmark_drift: configuration {path or 'default'}; map "
                               f"frame {self.map_frame}; {wiring(self)}")

    def restored(self, config, floor_height: float) -> StreamingDrift:
        """The estimator as ``state_file`` holds it, or a new one (module docstring)."""
        fresh = StreamingDrift(config, floor_height)
        if not self.state_file or not Path(self.state_file).exists():
            return fresh
        try:
            stream = load_state(self.state_file, config)
        except InputError as exc:
            aside = Path(self.state_file + ".refused")
            Path(self.state_file).replace(aside)
            self.get_logger().error(f"{exc}; set aside as {aside}, starting afresh")
            return fresh
        stream.floor_height_m = floor_height
        estimator = stream.estimator
        places = (estimator.database.stored if estimator.hypotheses is None
                  else estimator.hypotheses.hypotheses[0].database.stored)
        self.get_logger().info(
            f"restored from {self.state_file}: {estimator.next_id} landmarks seen, {len(places)} "
            f"stored, the walk up to {stream.last_stamp_ns} ns")
        return stream

    def save(self) -> None:
        """The estimator's state to ``state_file`` (a failure is logged, nothing stops)."""
        if not self.state_file:
            return
        try:
            save_state(self.state_file, self.drift)
        except OSError as exc:
            self.get_logger().error(f"state not saved to {self.state_file}: {exc}",
                                    throttle_duration_sec=5.0)

    def on_step(self, msg: Step) -> None:
        self.on_message(msg)

    def on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        self.on_message(msg)

    def on_message(self, msg) -> None:
        """A step or a pose from the navigator: taken now, or held while a correction is
        outstanding (module docstring); one the last revision replaced is dropped."""
        if self.in_other_frame(msg):
            return
        if self.replaced(msg):
            return
        if self.waiting or self.in_flight:
            self.held.append(msg)
            self.held_steps += isinstance(msg, Step)
            self.service_corrections()
            return
        self.take(msg)

    def replaced(self, msg) -> bool:
        """A step or pose the last revision replaced (a copy of one published before the
        correction came): dropped without a warning."""
        return self.superseded_until is not None and stamp_ns(msg) <= self.superseded_until

    def take(self, msg) -> None:
        """A step or a pose to the estimator, and what comes of it."""
        stamp = stamp_ns(msg)
        if isinstance(msg, Step):
            result = self.drift.push_step(stamp, msg.heading, msg.activity)
        else:
            p = msg.pose.pose.position
            cov = np.asarray(msg.pose.covariance, float).reshape(6, 6)[:3, :3]
            result = self.drift.push_pose(stamp, (p.x, p.y, p.z), cov)
        self.on_result(stamp, result)

    def in_other_frame(self, msg) -> bool:
        """A step or pose stamped in another frame than ``map_frame``: dropped, counted
        and warned of (throttled), as it belongs to another navigator."""
        if msg.header.frame_id == self.map_frame:
            return False
        self.other_frame += 1
        self.get_logger().warning(
            f"{self.other_frame} steps and poses dropped so far: stamped in frame "
            f"{msg.header.frame_id!r}, map_frame is {self.map_frame!r}",
            throttle_duration_sec=5.0)
        return True

    def on_result(self, stamp: int, result) -> None:
        self.report_problems()
        if result is None:
            return
        self.save()
        for landmark in result.landmarks:
            self.landmark_pub.publish(self.landmark_message(stamp, landmark))
            x, y, z = landmark.position
            self.get_logger().info(
                f"new landmark {landmark.id}: {LandmarkType(landmark.type).label} at ({x:.1f}, "
                f"{y:.1f}, {z:.1f}) m, floor {landmark.floor}")
        for estimate in result.drifts:
            self.drift_pub.publish(self.drift_message(stamp, estimate))
            self.get_logger().info(
                f"revisit of landmark {estimate.landmark_first}: deviation "
                f"{np.degrees(estimate.deviation):.2f} deg over {estimate.elapsed:.0f} s, drift "
                f"{np.degrees(estimate.drift):.4f} deg/s")
        for correction in result.corrections:
            fields = request_fields(correction)
            position = fields.pop("position", None)
            request = ApplyCorrection.Request(**fields, request_id=new_request_id())
            set_time(request.stamp, stamp)
            if position is not None:
                request.position.x, request.position.y, request.position.z = position
            self.waiting.append([request, 0])
            self.held_steps = self.delay_ticks = 0
        self.service_corrections()

    def service_corrections(self, tick: bool = False) -> None:
        """Send the next waiting correction when the service is there and none is in
        flight (after ``correction_delay_steps`` held steps), send again a call past the
        timeout (a pocket_pdr just started may be slow to answer), give up on a
        correction past ``max_retries`` tries, one counted at each retry period (``tick``:
        the timer's call; steps coming fast count none); when none is outstanding any
        more, take the messages held meanwhile (module docstring)."""
        now = self.get_clock().now().nanoseconds * 1e-9
        for item in list(self.in_flight):
            future, sent, request, tries = item
            if future.done():
                self.in_flight.remove(item)
                self.log_response(future)
            elif now - sent > self.timeout_s:
                self.in_flight.remove(item)
                future.cancel()
                self.resent += 1
                self.get_logger().warning(
                    f"correction {request.request_id} not answered within {self.timeout_s} s, "
                    f"sent again with the same id ({self.resent} resends so far)")
                self.waiting.insert(0, [request, tries + 1])
        if self.waiting and not self.in_flight and self.delay_done():
            item = self.waiting[0]
            if self.client.service_is_ready() and item[1] <= self.max_retries:
                self.waiting.pop(0)
                self.in_flight.append([self.client.call_async(item[0]), now, *item])
            elif tick:
                item[1] += 1
                if item[1] > self.max_retries:
                    self.waiting.pop(0)
                    self.get_logger().error(
                        f"{graph_name(topics.POCKET_APPLY_CORRECTION)} absent: correction "
                        f"dropped after {self.max_retries} retries")
        if not self.waiting and not self.in_flight and (self.held or self.revision):
            self.release()

    def delay_done(self) -> bool:
        """``correction_delay_steps`` held steps since the correction came (or as many
        retry periods without them: the end of a walk)."""
        return self.held_steps >= self.delay_steps or self.delay_ticks >= self.max_retries

    def on_timer(self) -> None:
        self.delay_ticks += 1
        self.service_corrections(tick=True)

    def release(self) -> None:
        """The last accepted answer's revised steps and poses, then the messages held
        meanwhile that they do not replace, to the estimator: until one of them brings
        a correction again, which holds the rest."""
        revision, self.revision = self.revision, None
        queue: list = []
        if revision is not None and revision.revised_poses:
            queue = [m for pair in zip(revision.revised_steps, revision.revised_poses,
                                       strict=True) for m in pair]
            self.superseded_until = stamp_ns(revision.revised_poses[-1])
        queue += [msg for msg in self.held if not self.replaced(msg)]
        self.held = []
        for i, msg in enumerate(queue):
            if self.waiting or self.in_flight:
                self.held = queue[i:]
                return
            self.take(msg)

    def log_response(self, future) -> None:
        try:
            response = future.result()
        except Exception as exc:   # a broken call must not stop the node
            self.get_logger().warning(f"correction call failed: {exc}")
            return
        if response.accepted:
            self.revision = response
            self.get_logger().info(f"correction accepted, {len(response.revised_steps)} steps "
                                   f"revised: {response.message}")
        else:
            self.get_logger().warning(f"correction refused: {response.message}")

    def landmark_message(self, stamp: int, landmark) -> Landmark:
        msg = Landmark()
        set_header(msg.header, stamp, self.map_frame)
        msg.id, msg.type, msg.floor = int(landmark.id), int(landmark.type), int(landmark.floor)
        msg.position.x, msg.position.y, msg.position.z = map(float, landmark.position)
        msg.position_covariance = [float(v) for v in np.asarray(landmark.covariance).ravel()]
        msg.yaw_before, msg.yaw_after = float(landmark.yaw_before), float(landmark.yaw_after)
        return msg

    def drift_message(self, stamp: int, estimate) -> DriftEstimate:
        msg = DriftEstimate()
        set_header(msg.header, stamp, self.map_frame)
        msg.landmark_first = estimate.landmark_first
        msg.landmark_revisit = estimate.landmark_revisit
        msg.deviation, msg.elapsed = float(estimate.deviation), float(estimate.elapsed)
        msg.drift, msg.drift_variance = float(estimate.drift), float(estimate.drift_variance)
        return msg

    def report_problems(self) -> None:
        for key, count in self.drift.counts.items():
            if key == "before_restart":
                if count and not self.reported.get(key):
                    self.get_logger().info("steps and poses from before the restart: known, "
                                           "dropped")
                    self.reported[key] = count
                continue
            if count > self.reported.get(key, 0):
                self.get_logger().warning(f"{count} messages dropped: {key}",
                                          throttle_duration_sec=5.0)
                self.reported[key] = count


def main(args: list[str] | None = None) -> None:
    spin_node("landmark_drift", LandmarkDriftNode, args)


if __name__ == "__main__":
    main()
