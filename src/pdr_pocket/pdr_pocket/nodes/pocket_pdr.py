"""Node ``pocket_pdr``: the pocket navigator on ``imu/data``, ``imu/mag`` and
``imu/pressure``, live.

Subscribes ``imu/data`` (sensor_msgs/Imu, REP-145), ``imu/mag``
(sensor_msgs/MagneticField, tesla) and, optionally, ``imu/pressure``
(sensor_msgs/FluidPressure, Pa: the height, floors and lift rides then come from the
barometer fused with the steps, pdr_pocket.height_filter) and publishes, per sample,
``pdr/pocket/attitude`` (sensor_msgs/Imu with the orientation and its covariance, REP-145) and
``pdr/pocket/gyro_bias`` (geometry_msgs/Vector3Stamped); per step, ``pdr/pocket/step``
(pdr_msgs/Step), ``pdr/pocket/pose`` (geometry_msgs/PoseWithCovarianceStamped),
``pdr/pocket/odometry`` (nav_msgs/Odometry: the pose with the position's and the
attitude's covariance, for a fusion node; pdr_pocket.messages), the pose on ``/tf``
(pdr_core.ros.node_tf: ``map_frame → base_frame``, or ``map_frame → odom_frame``) and
``pdr/pocket/path`` (nav_msgs/Path, every step so far), stamped with the IMU sample that
confirmed the step. Serves ``~/reset`` (std_srvs/Trigger) and
``pdr/pocket/apply_correction`` (pdr_msgs/srv/ApplyCorrection: yaw and z gyro bias added
as Kalman updates, Eq. (6.2), and the position fix, Eq. (6.3); all or nothing, every part
gated against the covariance before any is applied, a refusal naming each failing part:
pdr_pocket.navigator.PocketNavigator.apply_correction). A correction is taken at its
stamp, the step it belongs to, the samples since run again (pdr_pocket.streaming); the
steps run again go back in the response and replace theirs in ``pdr/pocket/path``,
published again. A request whose ``request_id`` was answered before (sent again after a
timeout) gets the first answer and changes nothing (pdr_core.corrections.answered_requests).

Parameters (docs/nodes.md): ``config`` (the navigator YAML, pdr_pocket.config; default
the installed config/pocket_pdr.yaml), ``mag_calibration`` (YAML of pdr-pocket
calibrate-mag; overrides the configuration's), ``map_frame`` (the frame of the steps,
poses and path: REP-105's map, pdr_core.frames), ``sensor_frame`` (the frame of the
attitude's rates and of the gyro bias: the IMU's), ``imu_durability`` (volatile or
transient_local, to match the publisher), ``correction_window_s`` (60.0: how far back a
stamped correction may reach, in seconds of IMU data), ``mag_wait_s`` (1.0: how long a
sample waits for a late magnetometer reading, in seconds of IMU data), ``block_s`` (0.25:
how long a sample may wait to be processed with the ones after it, in seconds of IMU data;
a call of the navigator costs far more than a sample in it, pdr_pocket.streaming.BLOCK_S;
0: each sample's attitude at once; the samples waiting for their block go out once no IMU
message has come for ``block_s`` of the node's clock, and before a correction is taken),
``step_calibration`` (the saved fit of ``pdr-pocket calibrate-step --foot``,
pdr_pocket.saved_lines.applied: its walked lines replace the configuration's, as
``pdr-pocket run --step-calibration``; empty: the configuration's ``step_calibration``)
and the person's lines ``step_length.a_h_m_per_deg``, ``step_length.b_h_m``,
``stairs.a_u_cm_per_deg``, ``stairs.b_u_cm``, ``stairs.a_d_cm_per_deg``,
``stairs.b_d_cm`` (defaults: the configuration's, with the saved fit's). Set while the
node runs (``stride_calibrator`` does, through the standard
``set_parameters_atomically`` service, issue 57), the lines set together are checked
together (finite, slopes above 0; a refusal says why) and taken for the steps confirmed
from then on (pdr_pocket.streaming.StreamingPocket.take_lines, after the samples waiting
for their block), each logged. The start-up line names the resolved topics and services.

A sample goes out once the magnetometer reading for it has come (at once when the two
topics keep pace), so the estimates equal ``pdr-pocket run``'s on the same bag, byte for
byte for the attitude. Each callback takes its subscription's waiting messages as one
block (up to :data:`MAX_BLOCK`, pdr_core.ros.backlog), decoded and encoded as raw CDR, so a
backlog (a bag played as fast as it is acknowledged) is worked off far faster than real
time. Bad samples and malformed messages are dropped and counted with a throttled
warning (pdr_pocket.streaming); data in g or deg/s is
refused with an error until ``~/reset``; when the configuration has magnetic updates, a
magnetometer quiet for ``mag_wait_s`` of IMU data pauses them with a warning naming its
topic, and its next reading resumes them (logged too). The node's health, with those
counters and the corrections', goes on ``/diagnostics`` once a second
(pdr_core.ros.node_diagnostics: OK, WARN when something was dropped or a correction refused
since the last report, while the magnetometer is paused or once the barometer is no
longer trusted, ERROR while not navigating), with the inputs fused: ``barometer``
("fused", "not fused: why", "absent: why"), ``barometer_offset_jumps`` and
``magnetometer`` (its magnetic updates, the first reading's heading only, paused or off).
A barometer whose offset jumps more than pdr_core.sensors.barometry.OFFSET_JUMPS_MAX_PER_MIN times
a minute is no longer fused (pdr_pocket.height_filter): a throttled warning says so.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped, Vector3Stamped
from nav_msgs.msg import Odometry, Path
from rcl_interfaces.msg import SetParametersResult
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Imu, MagneticField
from std_srvs.srv import Trigger

from pdr_core import topics
from pdr_core.corrections.answered_requests import AnsweredRequests
from pdr_core.corrections.correction import from_request
from pdr_core.corrections.replay import CorrectionResult
from pdr_core.errors import InputError
from pdr_core.frames import MAP_FRAME, SENSOR_FRAME
from pdr_core.io import cdr
from pdr_core.io.batch import MessageBatch
from pdr_core.io.headers import set_header, stamp_ns, time_ns
from pdr_core.io.msgtypes import IMU, MAGNETIC_FIELD, ODOMETRY
from pdr_core.ros.backlog import decode_block, publish_acked, waiting_messages
from pdr_core.ros.diagnostics import Counters
from pdr_core.ros.node_diagnostics import NodeDiagnostics
from pdr_core.ros.node_main import spin_node
from pdr_core.ros.node_params import declare, refuse_removed
from pdr_core.ros.node_tf import TfBroadcaster
from pdr_core.ros.node_wiring import wiring
from pdr_core.ros.ros_types import message_class
from pdr_core.topics import graph_name
from pdr_msgs.msg import Step
from pdr_msgs.srv import ApplyCorrection
from pdr_pocket.config import load_pocket_config
from pdr_pocket.inputs import PocketInputs
from pdr_pocket.magnetometer import MagCalibration
from pdr_pocket.messages import (
    attitude_batches,
    odometry_step_fields,
    pose_fields,
    step_fields,
)
from pdr_pocket.placement import UNKNOWN, stride_choice
from pdr_pocket.saved_lines import LINE_PARAMETERS, applied, lines_text, read_fit, taken_lines
from pdr_pocket.sensor_inputs import SENSOR_INPUTS
from pdr_pocket.streaming import BLOCK_S, CORRECTION_WINDOW_S, MAG_WAIT_S, StreamingPocket

NO_GAIT_WARN_S = 10.0   # moving this long without a step: the warning, once
IMPLAUSIBLE_WARN_S = 30.0   # implausible strides or speed: said at most this often
DURABILITIES = ("volatile", "transient_local")
# messages taken from a subscription's queue per callback (pdr_core.ros.backlog): 4 s at
# 100 Hz, so a backlog is worked off in large blocks while the services get their turn
MAX_BLOCK = 400
# history of the publishers (messages); the attitude goes out in acknowledged slices of
# half of it (pdr_core.ros.backlog.publish_acked), as zupt_ekf's estimates do
HISTORY = 1000
ACK_TIMEOUT = Duration(seconds=1.0)


class PocketPdrNode(Node):
    """Adapter from Imu and MagneticField messages to the streaming navigator."""

    def __init__(self) -> None:
        super().__init__("pocket_pdr")
        refuse_removed(self, {"frame_id": "map_frame (steps, poses, path) or sensor_frame "
                                          "(attitude, gyro bias)"})
        path = declare(self, "config", "", "navigator YAML (pdr_pocket.config); empty: the "
                       "installed config/pocket_pdr.yaml")
        calibration_path = declare(self, "mag_calibration", "", "YAML of pdr-pocket "
                                   "calibrate-mag; overrides the configuration's")
        self.map_frame = declare(self, "map_frame", MAP_FRAME,
                                 "frame of the steps, poses and path (ENU, REP-105)")
        self.sensor_frame = declare(self, "sensor_frame", SENSOR_FRAME,
                                    "frame of the attitude's rates and the gyro bias (the IMU)")
        self.tf = TfBroadcaster(self, self.map_frame, self.sensor_frame, HISTORY // 2,
                                ACK_TIMEOUT)
        durability = declare(self, "imu_durability", "volatile",
                             "durability of the IMU subscriptions, to match the publisher",
                             DURABILITIES)
        mag_wait_s = declare(self, "mag_wait_s", MAG_WAIT_S, "how long a sample waits for a "
                             "late magnetometer reading [s of IMU data]")
        window_s = declare(self, "correction_window_s", CORRECTION_WINDOW_S, "how far back a "
                           "stamped correction may reach [s of IMU data]")
        block_s = declare(self, "block_s", BLOCK_S, "how long a sample may wait to be "
                          "processed with the ones after it, in one block [s of IMU data]; "
                          "0: each at once")
        step_calibration = declare(self, "step_calibration", "", "saved fit YAML of pdr-pocket "
                                   "calibrate-step --foot; its walked lines replace the "
                                   "configuration's; empty: the configuration's "
                                   "step_calibration")
        config = load_pocket_config(path or None)
        step_calibration = step_calibration or config.step_calibration or ""
        config = person_lines(self, config, step_calibration)
        self.mag_updates = config.orientation.magnetic
        calibration_path = calibration_path or config.magnetometer_calibration
        calibration = MagCalibration.load(calibration_path) if calibration_path else None
        self.navigator = StreamingPocket(config, calibration, mag_wait_s, window_s, block_s)
        self.gyro_noise_var = self.navigator.gyro_noise_var
        qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL
                         if durability == "transient_local" else DurabilityPolicy.VOLATILE)
        self.imu_sub = self.create_subscription(Imu, graph_name(topics.IMU_DATA), self.on_imu,
                                                qos, raw=True)
        self.mag_sub = self.create_subscription(MagneticField, graph_name(topics.IMU_MAG),
                                                self.on_mag, qos, raw=True)
        self.mag_topic = self.mag_sub.topic_name
        # the other sensors (pdr_pocket.sensor_inputs), each on its topic
        self.sensor_subs = {sensor.name: (sensor, self.create_subscription(
            message_class(sensor.msgtype), graph_name(sensor.topic),
            lambda raw, name=sensor.name: self.on_readings(name, [raw]), qos, raw=True))
            for sensor in SENSOR_INPUTS}
        out = QoSProfile(depth=HISTORY, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.attitude_pub = self.create_publisher(Imu, graph_name(topics.POCKET_ATTITUDE), out)
        self.bias_pub = self.create_publisher(Vector3Stamped, graph_name(topics.POCKET_GYRO_BIAS),
                                             out)
        self.step_pub = self.create_publisher(Step, graph_name(topics.POCKET_STEP), out)
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped,
                                              graph_name(topics.POCKET_POSE), out)
        self.odometry_pub = self.create_publisher(Odometry, graph_name(topics.POCKET_ODOMETRY),
                                                  out)
        self.path_pub = self.create_publisher(Path, graph_name(topics.POCKET_PATH), out)
        self.path = Path()
        self.path.header.frame_id = self.map_frame
        self.create_service(Trigger, "~/reset", self.on_reset)
        self.create_service(ApplyCorrection, graph_name(topics.POCKET_APPLY_CORRECTION),
                            self.on_correction)
        self.answered = AnsweredRequests()
        # the samples that wait for their block go out when the IMU goes quiet
        self.quiet_since_ns = self.get_clock().now().nanoseconds
        if block_s > 0:
            self.create_timer(block_s, self.on_quiet)
        self.sources = _Sources()
        self.undecodable = 0
        self.reported: dict[str, int] = {}
        self.mag_was_paused = False
        self.detection_told = self.no_gait_told = False
        self.placement_told = UNKNOWN
        self.diagnostics = NodeDiagnostics(self, self.diagnostic_counters)
        self.add_on_set_parameters_callback(self.on_set_parameters)
        if step_calibration:
            said = lines_text(config.step_length, config.stairs)
            self.get_logger().info(f"pocket_pdr: took the person's lines from "
                                   f"{step_calibration}: {said}")
        magnetometer = "magnetic updates" if self.mag_updates else \
            "the first reading's heading only (no magnetic update configured)"
        self.get_logger().info(
            f"pocket_pdr: configuration {path or 'default'}; map frame {self.map_frame}, "
            f"sensor frame {self.sensor_frame}; {self.tf.describe()}; "
            f"{self.mag_topic}: {magnetometer}; "
            f"strides: {stride_choice(self.navigator.config.step_length)}; "
            f"{wiring(self)}")

    def on_set_parameters(self, parameters) -> SetParametersResult:
        """The person's lines set while the node runs (``stride_calibrator``): checked
        (pdr_pocket.saved_lines.taken_lines), then taken for the steps confirmed from now
        on, after the samples waiting for their block; logged. Other parameters are
        accepted as before (read at the start only)."""
        values = {p.name: p.value for p in parameters if p.name in LINE_NAMES}
        if not values:
            return SetParametersResult(successful=True)
        nav = self.navigator
        try:
            step_length, stairs = taken_lines(nav.config.step_length, nav.config.stairs,
                                              values)
        except (TypeError, ValueError) as exc:
            self.get_logger().warning(f"pocket_pdr: the person's lines refused: {exc}")
            return SetParametersResult(successful=False, reason=str(exc))
        self.publish(nav.release())
        nav.take_lines(step_length, stairs)
        self.get_logger().info(f"pocket_pdr: took the person's lines from a parameter "
                               f"update: {lines_text(step_length, stairs)}")
        return SetParametersResult(successful=True)

    def on_quiet(self) -> None:
        """The samples that wait for their block (``block_s``) processed and published once
        no IMU message has come for ``block_s`` (of the node's clock): the end of a bag, or
        a sensor that stalled. Data time alone decides otherwise."""
        quiet_ns = self.get_clock().now().nanoseconds - self.quiet_since_ns
        if quiet_ns >= self.navigator.block_s * 1e9:
            self.publish(self.navigator.release())

    def on_imu(self, raw: bytes) -> None:
        """One message from the executor, and the ones waiting behind it, as one block,
        given to the navigator in parts of at most half ``mag_wait_s`` each after the
        magnetometer readings that have come: a sample waits for its reading ``mag_wait_s``
        of IMU data, and a whole block at once would let that time pass unseen."""
        self.quiet_since_ns = self.get_clock().now().nanoseconds
        imu, malformed = decode_block(IMU, [raw, *waiting_messages(self.imu_sub,
                                                                   MAX_BLOCK - 1)])
        self.undecodable += malformed
        self.diagnostics.received(imu, malformed)
        self.sources.add(imu)
        no_gyro = len(imu) and bool(np.all(imu["angular_velocity_covariance"][:, 0] == -1))
        span_ns = self.navigator.mag_wait_s * 0.5e9
        start = 0
        while start < len(imu):
            end = int(np.searchsorted(imu.stamp_ns, imu.stamp_ns[start] + span_ns,
                                      side="right"))
            self.on_mag_block([])
            for name in self.sensor_subs:
                self.on_readings(name, [])
            part = imu.take(slice(start, end))
            self.publish(self.navigator.push_imus(
                part.stamp_ns, part["linear_acceleration"],
                None if no_gyro else part["angular_velocity"]))
            start = end
        if self.navigator.failed is not None:
            self.sources = _Sources()
        self.report_problems()

    def on_mag(self, raw: bytes) -> None:
        self.on_mag_block([raw])

    def on_mag_block(self, raws: list[bytes]) -> None:
        """These magnetometer messages and the ones waiting behind them, as one block."""
        mag, malformed = decode_block(MAGNETIC_FIELD, [*raws, *waiting_messages(
            self.mag_sub, MAX_BLOCK - len(raws))])
        self.undecodable += malformed
        if len(mag):
            self.publish(self.navigator.push_mags(mag.stamp_ns, mag["magnetic_field"]))

    def on_readings(self, name: str, raws: list[bytes]) -> None:
        """These messages of the sensor ``name`` (pdr_pocket.sensor_inputs) and the ones
        waiting behind them, as one block."""
        sensor, subscription = self.sensor_subs[name]
        block, malformed = decode_block(sensor.msgtype, [*raws, *waiting_messages(
            subscription, MAX_BLOCK - len(raws))])
        self.undecodable += malformed
        if len(block):
            self.publish(self.navigator.push_readings(name, block.stamp_ns,
                                                      block[sensor.field]))

    def publish(self, chunks) -> None:
        """Attitude and gyro bias of every sample the navigator took (raw CDR, as
        ``pdr-pocket run`` writes them, in acknowledged slices), then each step."""
        for chunk in chunks:
            out = chunk.output
            inputs = self.sources.take(chunk.stamp_ns)
            batches = attitude_batches(inputs, out.attitude, self.gyro_noise_var,
                                       self.sensor_frame)
            publish_acked([(self.attitude_pub, batches[topics.POCKET_ATTITUDE]),
                           (self.bias_pub, batches[topics.POCKET_GYRO_BIAS])], HISTORY // 2,
                          ACK_TIMEOUT)
            for step, (attitude, covariance) in zip(out.steps, chunk.step_attitude,
                                                    strict=True):
                self.publish_step(chunk.stamp_of(step.t_confirm), step, attitude, covariance)

    def publish_step(self, stamp: int, step, attitude: np.ndarray,
                     attitude_covariance: np.ndarray) -> None:
        """Step, pose, odometry, TF and path of one step (fields packed as pdr-pocket run
        packs them): C_b^n (3, 3) and its covariance (3, 3) [rad²] at the step."""
        msg, pose = self.step_messages(stamp, step, attitude)
        self.step_pub.publish(msg)
        self.pose_pub.publish(pose)
        odometry = MessageBatch(ODOMETRY, np.array([stamp]), self.map_frame, odometry_step_fields(
            [step], attitude[None], attitude_covariance[None], self.tf.base_frame))
        self.odometry_pub.publish(cdr.encode(odometry)[0])
        self.tf.broadcast(odometry.stamp_ns, odometry["pose.pose.position"],
                          odometry["pose.pose.orientation"])
        self.path.poses.append(path_pose(pose, step.heading))
        self.path.header.stamp = pose.header.stamp
        self.path_pub.publish(self.path)

    def step_messages(self, stamp: int, step, attitude: np.ndarray
                      ) -> tuple[Step, PoseWithCovarianceStamped]:
        """The Step and the pose of one step, stamped ``stamp`` [ns] in the map frame."""
        fields = {k: v[0] for k, v in step_fields([step]).items()}
        msg = Step()
        set_header(msg.header, stamp, self.map_frame)
        msg.index = int(fields.pop("index"))
        msg.activity = int(fields.pop("activity"))
        msg.ride = int(fields.pop("ride"))
        for key, value in fields.items():
            setattr(msg, key, float(value))
        pose_values = {k: v[0] for k, v in pose_fields([step], attitude[None]).items()}
        pose = PoseWithCovarianceStamped()
        set_header(pose.header, stamp, self.map_frame)
        p = pose.pose.pose.position
        p.x, p.y, p.z = map(float, pose_values["pose.pose.position"])
        q = pose.pose.pose.orientation
        q.x, q.y, q.z, q.w = map(float, pose_values["pose.pose.orientation"])
        pose.pose.covariance = [float(v) for v in pose_values["pose.covariance"]]
        return msg, pose

    def on_correction(self, request, response):
        """pdr/pocket/apply_correction: a request id answered before gets the first answer
        and changes nothing (pdr_core.corrections.answered_requests); logged."""
        return self.answered.answer(request.request_id,
                                    lambda: self.correction_answer(request, response),
                                    self.get_logger().info)

    def correction_answer(self, request, response):
        """A new correction: the navigator decides, at the request's stamp
        (pdr_pocket.streaming); logged and counted. The steps it ran again go back in the
        response and replace theirs in the path, published again."""
        stamp = time_ns(request.stamp)
        self.publish(self.navigator.release())      # the samples before the call first
        try:
            result = self.navigator.apply_correction(from_request(request, stamp))
        except (ValueError, np.linalg.LinAlgError) as exc:
            result = CorrectionResult(False, f"correction not usable: {exc}")
            self.navigator.corrections["refused"] += 1
        counts = self.navigator.corrections
        tally = f"({counts['accepted']} accepted, {counts['refused']} refused so far)"
        at = f" at stamp {stamp} ns" if stamp else " now"
        if result.accepted:    # one severity per call site: rclpy refuses a logger that changes it
            self.get_logger().info(f"correction accepted{at} {tally}, {len(result.revised)} "
                                   f"steps run again: {result.message}")
            self.revise(stamp, result.revised, response)
        else:
            self.get_logger().warning(f"correction refused{at} {tally}: {result.message}")
        response.accepted, response.message = bool(result.accepted), result.message
        return response

    def revise(self, stamp: int, revised, response) -> None:
        """The steps run again after a correction stamped ``stamp`` [ns]: in the response,
        and in place of theirs in the path, published again."""
        for item in revised:
            msg, pose = self.step_messages(item.stamp_ns, item.step, item.attitude)
            response.revised_steps.append(msg)
            response.revised_poses.append(pose)
        if not self.path.poses:
            return
        stamps = [stamp_ns(p) for p in self.path.poses]
        keep = int(np.searchsorted(stamps, stamp, side="right")) if stamp else len(stamps)
        self.path.poses = self.path.poses[:keep] + [
            path_pose(pose, item.step.heading)
            for item, pose in zip(revised, response.revised_poses, strict=True)]
        self.path_pub.publish(self.path)

    def report_problems(self) -> None:
        nav = self.navigator
        for key, count in {**nav.counts, "malformed_cdr": self.undecodable}.items():
            if key != "mag_missing" and count > self.reported.get(key, 0):
                self.get_logger().warning(f"{count} samples with {key} so far",
                                          throttle_duration_sec=5.0)
                self.reported[key] = count
        if nav.failed is not None:
            self.get_logger().error(f"not navigating: {nav.failed}", throttle_duration_sec=5.0)
        if nav.mag_error is not None:
            self.get_logger().error(f"magnetometer off: {nav.mag_error}",
                                    throttle_duration_sec=10.0)
        navigator = nav.navigator
        if navigator.gyroscope is not None and not self.detection_told:
            told = navigator.detection()
            self.get_logger().info(f"steps by {told['step_detector']}, the pitch from "
                                   f"{told['pitch_from']}; activities: {told['activities']}")
            self.detection_told = True
        if not self.no_gait_told and navigator.moving_s >= NO_GAIT_WARN_S and \
                navigator.no_step_reason() is not None:
            self.get_logger().warning(navigator.no_step_reason())
            self.no_gait_told = True
        self.report_strides()
        self.report_magnetometer()
        barometer = navigator.barometer_status()
        if navigator.assembly.height.distrusted_s is not None:
            self.get_logger().warning(f"{topics.IMU_PRESSURE}: {barometer.why}",
                                      throttle_duration_sec=IMPLAUSIBLE_WARN_S)

    def report_strides(self) -> None:
        """The placement found, once each time it changes, with its stride model and why;
        strides cut to the bound and a walk faster than a person's (throttled: each says
        its count so far)."""
        bound, speed = self.navigator.bound_warning(), self.navigator.speed_warning()
        if bound is not None:
            self.get_logger().warning(bound, throttle_duration_sec=IMPLAUSIBLE_WARN_S)
        if speed is not None:
            self.get_logger().warning(speed, throttle_duration_sec=IMPLAUSIBLE_WARN_S)
        found = self.navigator.placement()
        if found.placement != self.placement_told:
            self.get_logger().info(f"placement: {found.placement} ({found.why}); strides "
                                   f"from the {found.model} model")
            self.placement_told = found.placement

    def report_magnetometer(self) -> None:
        """With magnetic updates configured: the magnetometer going quiet (paused) and
        coming back (resumed), once each time."""
        paused = self.navigator.mag_paused
        if self.mag_updates and paused != self.mag_was_paused:
            wait = self.navigator.mag_wait_s
            if paused:
                self.get_logger().warning(f"{self.mag_topic}: no reading for {wait:g} s of "
                                          "IMU data, magnetic updates paused")
            else:
                self.get_logger().info(f"{self.mag_topic}: readings again, magnetic updates "
                                       "resumed")
        self.mag_was_paused = paused

    def diagnostic_counters(self) -> Counters:
        """The counters of ``/diagnostics`` (pdr_core.ros.diagnostics, copies): the samples
        and readings dropped by reason and the malformed messages (the log's), the gaps
        the orientation filter propagated over, the refused corrections; the accepted and
        resent ones and the samples without a magnetometer reading as tallies; the magnetometer off
        (units) or, with magnetic updates configured, paused; the units refused; the poses
        not on /tf for want of an odom_frame transform at their stamp."""
        nav = self.navigator
        corrections = nav.corrections
        problems = {key: count for key, count in nav.counts.items() if key != "mag_missing"}
        problems.update(malformed_cdr=self.undecodable, gaps=filter_gaps(nav.navigator),
                        corrections_refused=corrections["refused"], tf_no_odom=self.tf.no_odom)
        conditions = {"mag_off": nav.mag_error}
        if self.mag_updates:
            conditions["mag_paused"] = (
                f"no reading on {self.mag_topic} for {nav.mag_wait_s:g} s of IMU data, "
                "magnetic updates paused") if nav.mag_paused and nav.mag_error is None else None
        barometer = nav.navigator.barometer_status()
        conditions["barometer_distrusted"] = barometer.why \
            if nav.navigator.assembly.height.distrusted_s is not None else None
        return Counters(self.diagnostics.samples_in, problems,
                        {"corrections_accepted": corrections["accepted"],
                         "corrections_resent": self.answered.resent,
                         "mag_missing": nav.counts["mag_missing"]}, conditions, nav.failed,
                        {"barometer": _said(barometer.status, barometer.why),
                         "barometer_offset_jumps": str(barometer.offset_jumps),
                         "magnetometer": self.magnetometer_use()})

    def magnetometer_use(self) -> str:
        """What the navigator does with the magnetometer, for ``/diagnostics``."""
        nav = self.navigator
        if nav.mag_error is not None:
            return _said("not fused", nav.mag_error)
        if not self.mag_updates:
            return _said("not fused", "the first reading's heading only (no magnetic "
                                      "update configured)")
        if nav.mag_paused:
            return _said("not fused", f"no reading on {self.mag_topic} for "
                                      f"{nav.mag_wait_s:g} s of IMU data (paused)")
        return "fused"

    def on_reset(self, request: Trigger.Request, response: Trigger.Response):
        self.navigator.reset()
        self.detection_told = self.no_gait_told = self.mag_was_paused = False
        self.sources = _Sources()
        self.path.poses = []
        response.success, response.message = True, "navigator reset"
        return response


LINE_NAMES = tuple(name for pair in LINE_PARAMETERS.values() for name in pair)
LINE_DESCRIPTIONS = {
    "step_length.a_h_m_per_deg": "the person's level stride line s = a_H·Δθ + b_H: a_H "
                                 "[m/deg] (Muñoz Díaz 2016 Eq. (4.2))",
    "step_length.b_h_m": "the level stride line's offset b_H [m]",
    "stairs.a_u_cm_per_deg": "the climb of a gait cycle upstairs v = a_U·Δθ + b_U: a_U "
                             "[cm/deg] (Eq. (4.4))",
    "stairs.b_u_cm": "the upstairs line's offset b_U [cm]",
    "stairs.a_d_cm_per_deg": "the descent of a gait cycle downstairs v = a_D·Δθ + b_D: a_D "
                             "[cm/deg] (Eq. (4.5))",
    "stairs.b_d_cm": "the downstairs line's offset b_D [cm]"}


def person_lines(node: Node, config, step_calibration: str):
    """``config`` (pdr_pocket.config.PocketConfig) with the walked lines of the saved fit
    ``step_calibration`` (when given; pdr_pocket.saved_lines.applied, as ``pdr-pocket run
    --step-calibration``), then the line parameters, declared with those as defaults (a
    value given with ``-p`` replaces its default): InputError naming the file or the
    parameter for one that cannot be used."""
    if step_calibration:
        config = applied(config, read_fit(step_calibration), step_calibration)
    sections = {"step_length": config.step_length, "stairs": config.stairs}
    values = {}
    for name in LINE_NAMES:
        section, key = name.split(".")
        values[name] = declare(node, name, float(getattr(sections[section], key)),
                               LINE_DESCRIPTIONS[name])
    try:
        step_length, stairs = taken_lines(config.step_length, config.stairs, values)
    except ValueError as exc:
        name, _, problem = str(exc).partition(": ")
        raise InputError(f"parameter {name}", problem) from None
    return replace(config, step_length=step_length, stairs=stairs)


def _said(state: str, why: str) -> str:
    """An input's state with its reason: "fused", "not fused: turned off"."""
    return f"{state}: {why}" if why else state


def filter_gaps(navigator) -> int:
    """Gaps longer than ``max_gap_s`` the orientation filter of ``navigator``
    (pdr_pocket.navigator.PocketNavigator) propagated over so far (0 before its first
    sample)."""
    return navigator.orientation.gaps


def path_pose(pose: PoseWithCovarianceStamped, heading: float) -> PoseStamped:
    """A step's entry of ``pdr/pocket/path``: its pose's header and position, oriented by
    the step's heading [rad] (ENU yaw)."""
    stamped = PoseStamped()
    stamped.header = pose.header
    stamped.pose.position = pose.pose.pose.position
    stamped.pose.orientation.z = float(np.sin(heading / 2))
    stamped.pose.orientation.w = float(np.cos(heading / 2))
    return stamped


class _Sources:
    """The IMU samples received and not yet estimated: the fields the attitude messages
    carry over from them (the measured rates and specific force, with its covariance)."""

    def __init__(self) -> None:
        self.batch: MessageBatch | None = None

    def add(self, imu: MessageBatch) -> None:
        self.batch = imu if self.batch is None else MessageBatch.concatenate([self.batch, imu])

    def take(self, stamp_ns: np.ndarray) -> PocketInputs:
        """The samples of these stamps (ascending, each received) as the navigator's
        inputs; they and every sample before them are forgotten (the navigator dropped
        those)."""
        b = self.batch
        index = np.searchsorted(b.stamp_ns, stamp_ns)
        rows = b.take(index)
        self.batch = b.take(slice(int(index[-1]) + 1, None))
        return PocketInputs(rows.stamp_ns, (rows.stamp_ns - rows.stamp_ns[0]) * 1e-9,
                            rows["angular_velocity"], rows["linear_acceleration"],
                            np.full((len(rows), 3), np.nan),
                            rows["linear_acceleration_covariance"])


def main(args: list[str] | None = None) -> None:
    spin_node("pocket_pdr", PocketPdrNode, args)

if __name__ == "__main__":
    main()
