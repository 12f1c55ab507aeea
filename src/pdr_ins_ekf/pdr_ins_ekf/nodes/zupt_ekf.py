"""Node ``zupt_ekf``: the foot navigator on ``imu/data``, live.

Subscribes ``imu/data`` (sensor_msgs/Imu) and publishes, per sample, ``pdr/foot/pose``
(PoseWithCovarianceStamped), ``pdr/foot/velocity`` (TwistWithCovarianceStamped),
``pdr/foot/odometry`` (nav_msgs/Odometry: the pose and its covariance, the velocity in
``base_frame``, for a fusion node), ``pdr/foot/stance`` (pdr_msgs/Stance) and the pose on
``/tf`` (pdr_core.ros.node_tf: ``map_frame → base_frame``, or ``map_frame → odom_frame``),
and at every stride (pdr_ins_ekf.strides: from one footfall to the next) ``pdr/foot/step``
(pdr_msgs/Step), ``pdr/foot/step_pose`` (PoseWithCovarianceStamped, at the stride's stamp)
and ``pdr/foot/path`` (one pose per stride). With
``smoothed_path`` true it also publishes ``pdr/foot/smoothed_path``: one Path per segment
of the segmented RTS smoother (Simón Colomar et al. 2012), with every sample's smoothed
pose, as soon as the segment ends (its lag and its memory are bounded by the segment).
Serves ``~/reset`` (std_srvs/Trigger) and ``pdr/foot/apply_correction``
(pdr_msgs/srv/ApplyCorrection), the drift corrections of ``landmark_drift`` run on the
foot's topics by remapping (docs/nodes.md): taken whole or not at all at the stride the
request's stamp names, the samples since filtered again (pdr_ins_ekf.correctable); the
strides run again go back in the answer and replace theirs in the path, published again;
a request whose ``request_id`` was answered before gets the first answer and changes
nothing (pdr_core.corrections.answered_requests).
A z gyro bias part needs the 15-state form and is refused with 9 states, saying so.

Parameters (docs/nodes.md): ``config`` (navigator YAML, see pdr_ins_ekf.config; default
the installed config/foot_ekf.yaml) or ``imu_profile`` (the shipped
config/foot_ekf_<profile>.yaml), ``map_frame`` (the frame of the poses and paths:
REP-105's map, pdr_core.frames), ``sensor_frame`` (the IMU's frame, placed on
``/tf_static`` at ``base_frame``), ``publish_tf`` (true), ``base_frame`` (base_link),
``odom_frame`` (empty), ``imu_durability`` (volatile or transient_local, to match the
publisher), ``smoothed_path`` (false). The start-up line names the resolved topics and
services.

Estimates lag the input by the detector's look-ahead (a few samples) and agree with
``pdr-ekf run`` on the same data. The node keeps up with input far faster than real
time: each callback takes the subscription's waiting messages as one block (up to
``MAX_BLOCK``; pdr_core.ros.backlog), runs the navigator once over the block, and decodes
and encodes the messages as raw CDR (pdr_core.io.cdr). ``pdr/foot/path`` is latched
(depth 1: its last message holds every step).

Bad samples (NaN/Inf, stamps going backwards) and malformed messages are dropped and
counted with a throttled warning; data in g or deg/s is refused at alignment with an
error, and nothing is navigated until ``~/reset``. The node's health, with those
counters, goes on ``/diagnostics`` once a second (pdr_core.ros.node_diagnostics: OK, WARN
when something was dropped since the last report, ERROR while not navigating).
"""
from __future__ import annotations

import dataclasses

import numpy as np
from geometry_msgs.msg import PoseWithCovarianceStamped, TwistWithCovarianceStamped
from nav_msgs.msg import Odometry
from nav_msgs.msg import Path as PathMsg
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from sensor_msgs.msg import Imu
from std_srvs.srv import Trigger

from pdr_core import topics
from pdr_core.corrections.answered_requests import AnsweredRequests
from pdr_core.corrections.correction import from_request
from pdr_core.corrections.replay import CorrectionResult
from pdr_core.frames import MAP_FRAME, SENSOR_FRAME
from pdr_core.io.cdr import encode
from pdr_core.io.headers import time_ns
from pdr_core.io.msgtypes import IMU
from pdr_core.maths.rotations import quaternion_from_orthonormal
from pdr_core.ros.backlog import decode_block, publish_acked, waiting_messages
from pdr_core.ros.diagnostics import Counters
from pdr_core.ros.node_diagnostics import NodeDiagnostics
from pdr_core.ros.node_main import spin_node
from pdr_core.ros.node_params import declare, refuse_removed
from pdr_core.ros.node_tf import TfBroadcaster
from pdr_core.ros.node_wiring import wiring
from pdr_core.topics import graph_name
from pdr_ins_ekf.config import load_run_config
from pdr_ins_ekf.offline import FootRun, output_batches, pose_path, step_path, stride_batches
from pdr_ins_ekf.streaming import StreamingNavigator
from pdr_ins_ekf.strides import Stride
from pdr_ins_ekf.zupt_ekf import SmoothedSegment
from pdr_msgs.msg import Stance, Step
from pdr_msgs.srv import ApplyCorrection

# messages taken from the subscription's queue per callback: 2 s at 200 Hz, so a backlog
# is worked off in large blocks while the ~/reset service still gets its turn
MAX_BLOCK = 400
# history of the estimate publishers (messages). Estimates go out in slices of at most
# half of it (the first block after alignment holds every sample since the rest it
# aligned on), each once the reliable subscribers have acknowledged the previous one (or
# ACK_TIMEOUT has passed): a subscriber slower than the node (a recorder behind a bag
# played at full speed) then slows the node down instead of losing what the history
# overwrote before it was delivered
HISTORY = 1000
ACK_TIMEOUT = Duration(seconds=1.0)


class ZuptEkfNode(Node):
    """Adapter from Imu messages to the streaming navigator and back to messages."""

    def __init__(self) -> None:
        super().__init__("zupt_ekf")
        refuse_removed(self, {"frame_id": "map_frame"})
        path = declare(self, "config", "", "navigator YAML (pdr_ins_ekf.config); empty: the "
                       "installed config/foot_ekf.yaml")
        profile = declare(self, "imu_profile", "", "use the shipped "
                          "config/foot_ekf_<profile>.yaml (xsens_mti, xsens_mtw, vn200, "
                          "consumer_phone)")
        self.map_frame = declare(self, "map_frame", MAP_FRAME,
                                 "frame of the poses, velocities and paths (ENU, REP-105)")
        sensor_frame = declare(self, "sensor_frame", SENSOR_FRAME,
                               "the IMU's frame (REP-145), at base_frame on /tf_static")
        self.tf = TfBroadcaster(self, self.map_frame, sensor_frame, HISTORY // 2,
                                ACK_TIMEOUT)
        durability = declare(self, "imu_durability", "volatile",
                             "durability of the IMU subscription, to match the publisher",
                             ("volatile", "transient_local"))
        config = load_run_config(path, profile)
        smoothing = declare(self, "smoothed_path", False,
                            "also publish pdr/foot/smoothed_path (segmented RTS smoother)")
        config = dataclasses.replace(config, smoother=dataclasses.replace(
            config.smoother, mode="segmented" if smoothing else "none"))
        self.navigator = StreamingNavigator(config)
        qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL
                         if durability == "transient_local" else DurabilityPolicy.VOLATILE)
        self.subscription = self.create_subscription(Imu, graph_name(topics.IMU_DATA),
                                                     self.on_imu, qos, raw=True)
        # transient local: a recorder that joins late still gets the last 1000 estimates
        out = QoSProfile(depth=HISTORY, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.estimate_pubs = {
            topic: self.create_publisher(kind, graph_name(topic), out)
            for topic, kind in ((topics.FOOT_POSE, PoseWithCovarianceStamped),
                                (topics.FOOT_VELOCITY, TwistWithCovarianceStamped),
                                (topics.FOOT_ODOMETRY, Odometry),
                                (topics.FOOT_STANCE, Stance))}
        self.stride_pubs = {
            topic: self.create_publisher(kind, graph_name(topic), out)
            for topic, kind in ((topics.FOOT_STEP, Step),
                                (topics.FOOT_STEP_POSE, PoseWithCovarianceStamped))}
        self.path_pub = self.create_publisher(PathMsg, graph_name(topics.FOOT_PATH), latched)
        self.smoothed_pub = self.create_publisher(PathMsg, graph_name(topics.FOOT_SMOOTHED_PATH),
                                                  out)
        self.create_service(Trigger, "~/reset", self.on_reset)
        self.create_service(ApplyCorrection, graph_name(topics.FOOT_APPLY_CORRECTION),
                            self.on_correction)
        self.answered = AnsweredRequests()
        self.strides: list[Stride] = []
        self.undecodable = 0
        self.reported: dict[str, int] = {}
        self.diagnostics = NodeDiagnostics(self, self.diagnostic_counters)
        self.get_logger().info(f"zupt_ekf: configuration {path or profile or 'default'}; "
                               f"map frame {self.map_frame}; {self.tf.describe()}; "
                               f"{wiring(self)}")

    def on_imu(self, raw: bytes) -> None:
        """One message from the executor, and the ones waiting behind it, as one block."""
        self.on_imu_block([raw, *waiting_messages(self.subscription, MAX_BLOCK - 1)])

    def on_imu_block(self, raws: list[bytes]) -> None:
        """Serialized Imu messages (CDR) in arrival order: navigate, publish, report."""
        imu, malformed = decode_block(IMU, raws)
        self.undecodable += malformed
        self.diagnostics.received(imu, malformed)
        run = self.navigator.push_many(imu.stamp_ns, imu["linear_acceleration"],
                                       imu["angular_velocity"])
        self.publish(run)
        for segment in self.navigator.take_smoothed():
            self.publish_smoothed(segment)
        self.report_problems()

    def report_problems(self) -> None:
        counts = {**self.navigator.counts, "malformed_cdr": self.undecodable}
        for key, count in counts.items():
            if count > self.reported.get(key, 0):
                self.get_logger().warning(f"imu/data: {count} samples with {key} so far",
                                          throttle_duration_sec=5.0)
                self.reported[key] = count
        if self.navigator.failed is not None:
            self.get_logger().error(f"not navigating: {self.navigator.failed}",
                                    throttle_duration_sec=5.0)

    def diagnostic_counters(self) -> Counters:
        """The counters of ``/diagnostics`` (pdr_core.ros.diagnostics, copies): the samples
        dropped by reason, the gaps and the malformed messages (the log's); the units
        refused; the poses not on /tf for want of an odom_frame transform at their stamp;
        the corrections refused, and the accepted and resent ones as tallies."""
        failed = self.navigator.failed
        corrections = self.navigator.corrections
        return Counters(self.diagnostics.samples_in,
                        {**self.navigator.counts, "malformed_cdr": self.undecodable,
                         "tf_no_odom": self.tf.no_odom,
                         "corrections_refused": corrections["refused"]},
                        {"corrections_accepted": corrections["accepted"],
                         "corrections_resent": self.answered.resent},
                        failed=None if failed is None else str(failed))

    def publish(self, run: FootRun) -> None:
        """Pose, velocity, odometry, stance and TF of every sample of the block (raw CDR; a
        large block in acknowledged slices, see HISTORY), and the strides ended in it with
        the path."""
        if not len(run.stamp_ns):
            return
        batches = output_batches(run, self.map_frame, self.tf.base_frame)
        publish_acked([(self.estimate_pubs[topic], batch) for topic, batch in batches.items()],
                      HISTORY // 2, ACK_TIMEOUT)
        self.tf.broadcast(run.stamp_ns, run.output.position,
                          quaternion_from_orthonormal(run.output.attitude))
        if run.strides:
            for topic, batch in stride_batches(run.strides, self.map_frame).items():
                for raw in encode(batch):
                    self.stride_pubs[topic].publish(raw)
            self.strides += run.strides
            self.publish_path()

    def publish_path(self) -> None:
        """``pdr/foot/path``: the pose at every stride, stamped with the last one."""
        self.path_pub.publish(step_path(self.strides, self.strides[-1].stamp_ns,
                                        self.map_frame))

    def on_correction(self, request, response):
        """pdr/foot/apply_correction: a request id answered before gets the first answer
        and changes nothing (pdr_core.corrections.answered_requests); logged."""
        return self.answered.answer(request.request_id,
                                    lambda: self.correction_answer(request, response),
                                    self.get_logger().info)

    def correction_answer(self, request, response):
        """A new correction: the navigator decides, at the request's stamp
        (pdr_ins_ekf.correctable); logged and counted. The strides run again go back in
        the response and replace theirs in the path, published again."""
        stamp = time_ns(request.stamp)
        try:
            result = self.navigator.apply_correction(from_request(request, stamp))
        except (ValueError, np.linalg.LinAlgError) as exc:
            result = CorrectionResult(False, f"correction not usable: {exc}")
        counts = self.navigator.corrections
        tally = f"({counts['accepted']} accepted, {counts['refused']} refused so far)"
        at = f" at stamp {stamp} ns" if stamp else " now"
        if result.accepted:    # one severity per call site: rclpy refuses a logger that changes it
            revised = [s for part in result.revised for s in part.strides]
            self.get_logger().info(f"correction accepted{at} {tally}, {len(revised)} "
                                   f"strides run again: {result.message}")
            if stamp:
                self.revise(stamp, revised, response)
        else:
            self.get_logger().warning(f"correction refused{at} {tally}: {result.message}")
        response.accepted, response.message = bool(result.accepted), result.message
        return response

    def revise(self, stamp: int, revised: list[Stride], response) -> None:
        """The strides run again after a correction stamped ``stamp`` [ns]: in the
        response (as published), and in place of theirs in the path, published again."""
        if revised:
            batches = stride_batches(revised, self.map_frame)
            response.revised_steps = [deserialize_message(raw, Step)
                                      for raw in encode(batches[topics.FOOT_STEP])]
            response.revised_poses = [deserialize_message(raw, PoseWithCovarianceStamped)
                                      for raw in encode(batches[topics.FOOT_STEP_POSE])]
        self.strides = [s for s in self.strides if s.stamp_ns <= stamp] + revised
        if self.strides:
            self.publish_path()

    def publish_smoothed(self, segment: SmoothedSegment) -> None:
        """One Path with every sample's smoothed pose, stamped at the segment's end."""
        self.smoothed_pub.publish(pose_path(segment.stamp_ns, segment.position,
                                            segment.attitude, int(segment.stamp_ns[-1]),
                                            self.map_frame))

    def on_reset(self, request: Trigger.Request, response: Trigger.Response):
        self.navigator.reset()
        self.strides = []
        response.success, response.message = True, "navigator reset"
        return response


def main(args: list[str] | None = None) -> None:
    spin_node("zupt_ekf", ZuptEkfNode, args)

if __name__ == "__main__":
    main()
