"""Node ``pocket_pdr``: the pocket navigator on ``imu/data`` and ``imu/mag``, live.

Subscribes ``imu/data`` (sensor_msgs/Imu, REP-145) and ``imu/mag``
(sensor_msgs/MagneticField, tesla) and publishes, per sample, ``pdr/pocket/attitude``
(sensor_msgs/Imu with the orientation and its covariance, REP-145) and
``pdr/pocket/gyro_bias`` (geometry_msgs/Vector3Stamped); per step, ``pdr/pocket/step``
(pdr_msgs/Step), ``pdr/pocket/pose`` (geometry_msgs/PoseWithCovarianceStamped) and
``pdr/pocket/path`` (nav_msgs/Path, every step so far), stamped with the IMU sample that
confirmed the step. Serves ``~/reset`` (std_srvs/Trigger) and
``pdr/pocket/apply_correction`` (pdr_msgs/srv/ApplyCorrection: yaw and z gyro bias added
as Kalman updates, Eq. (6.2), and the position fix, Eq. (6.3); refused with
``accepted=false`` and the reason when a variance is negative or not finite or a χ² gate
fails; a part whose value and variance are both 0 is not applied).

Parameters: ``config`` (the navigator YAML, pdr_pocket.config; default the installed
config/pocket_pdr.yaml), ``mag_calibration`` (YAML of pdr-pocket calibrate-mag; overrides
the configuration's), ``frame_id`` ("imu_link"), ``imu_durability`` (volatile or
transient_local, to match the publisher), ``mag_wait_s`` (1.0: how long a sample waits for
a late magnetometer reading, in seconds of IMU data).

A sample goes out once the magnetometer reading for it has come (at once when the two
topics keep pace), so the estimates equal ``pdr-pocket attitude``'s on the same bag. Bad samples are
dropped and counted with a throttled warning (pdr_pocket.streaming); data in g or deg/s is
refused with an error until ``~/reset``; a magnetometer that stops publishing pauses the
magnetic updates with a warning.
"""
from __future__ import annotations

from collections import deque

import numpy as np
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped, Vector3Stamped
from nav_msgs.msg import Path
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Imu, MagneticField
from std_srvs.srv import Trigger

from pdr_core.headers import set_header, stamp_ns
from pdr_core.node_main import spin_node
from pdr_core.rotations import quaternion_from_orthonormal
from pdr_msgs.msg import Step
from pdr_msgs.srv import ApplyCorrection
from pdr_pocket.config import load_pocket_config
from pdr_pocket.magnetometer import MagCalibration
from pdr_pocket.pocket_offline import MAP_FRAME, pose_fields, step_fields
from pdr_pocket.streaming import MAG_WAIT_S, StreamingPocket

NO_GAIT_WARN_S = 10.0   # moving this long without a step: the warning, once


class PocketPdrNode(Node):
    """Adapter from Imu and MagneticField messages to the streaming navigator."""

    def __init__(self) -> None:
        super().__init__("pocket_pdr")
        path = self.declare_parameter("config", "").value
        calibration_path = self.declare_parameter("mag_calibration", "").value
        self.frame_id = self.declare_parameter("frame_id", "imu_link").value
        durability = self.declare_parameter("imu_durability", "volatile").value
        mag_wait_s = float(self.declare_parameter("mag_wait_s", MAG_WAIT_S).value)
        config = load_pocket_config(path or None)
        calibration_path = calibration_path or config.magnetometer_calibration
        calibration = MagCalibration.load(calibration_path) if calibration_path else None
        self.navigator = StreamingPocket(config, calibration, mag_wait_s)
        self.gyro_noise_var = self.navigator.navigator.orientation.params.gyro_noise_var
        qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL
                         if durability == "transient_local" else DurabilityPolicy.VOLATILE)
        self.create_subscription(Imu, "imu/data", self.on_imu, qos)
        self.create_subscription(MagneticField, "imu/mag", self.on_mag, qos)
        out = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.attitude_pub = self.create_publisher(Imu, "pdr/pocket/attitude", out)
        self.bias_pub = self.create_publisher(Vector3Stamped, "pdr/pocket/gyro_bias", out)
        self.step_pub = self.create_publisher(Step, "pdr/pocket/step", out)
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, "pdr/pocket/pose", out)
        self.path_pub = self.create_publisher(Path, "pdr/pocket/path", out)
        self.path = Path()
        self.path.header.frame_id = MAP_FRAME
        self.create_service(Trigger, "~/reset", self.on_reset)
        self.create_service(ApplyCorrection, "pdr/pocket/apply_correction", self.on_correction)
        self.inputs: deque[tuple[int, Imu]] = deque()
        self.reported: dict[str, int] = {}
        self.mag_was_stale = False
        self.detection_told = self.no_gait_told = False
        self.get_logger().info(f"pocket_pdr: configuration {path or 'default'}")

    def on_imu(self, msg: Imu) -> None:
        stamp = stamp_ns(msg)
        a, w = msg.linear_acceleration, msg.angular_velocity
        gyro = None if msg.angular_velocity_covariance[0] == -1 else (w.x, w.y, w.z)
        self.inputs.append((stamp, msg))
        self.publish(self.navigator.push_imu(stamp, (a.x, a.y, a.z), gyro))
        if self.navigator.failed is not None:
            self.inputs.clear()
        self.report_problems()

    def on_mag(self, msg: MagneticField) -> None:
        m = msg.magnetic_field
        self.publish(self.navigator.push_mag(stamp_ns(msg), (m.x, m.y, m.z)))

    def publish(self, chunks) -> None:
        for chunk in chunks:
            out = chunk.output
            for i, stamp in enumerate(chunk.stamp_ns.tolist()):
                self.publish_one(stamp, self.source_of(stamp), out.attitude, i)
            for step in out.steps:
                self.publish_step(chunk.stamp_of(step.t_confirm), step,
                                  out.attitude.attitude[
                                      min(np.searchsorted(out.attitude.t, step.t_confirm),
                                          len(out.attitude.t) - 1)])

    def source_of(self, stamp: int) -> Imu:
        """The message of an estimate; the ones before it are samples the navigator
        dropped."""
        while True:
            source_stamp, source = self.inputs.popleft()
            if source_stamp == stamp:
                return source

    def publish_one(self, stamp: int, source: Imu, e, i: int) -> None:
        att = Imu()
        set_header(att.header, stamp, self.frame_id)
        q = quaternion_from_orthonormal(e.attitude[i])
        o = att.orientation
        o.x, o.y, o.z, o.w = map(float, q)
        cov = e.covariance[i]
        att.orientation_covariance = [float(v) for v in cov[:3, :3].ravel()]
        bias = e.bias[i]
        w = source.angular_velocity
        att.angular_velocity.x = w.x - float(bias[0])
        att.angular_velocity.y = w.y - float(bias[1])
        att.angular_velocity.z = w.z - float(bias[2])
        att.angular_velocity_covariance = [
            float(v) for v in (cov[3:, 3:] + np.eye(3) * self.gyro_noise_var).ravel()]
        att.linear_acceleration = source.linear_acceleration
        att.linear_acceleration_covariance = source.linear_acceleration_covariance
        self.attitude_pub.publish(att)
        out = Vector3Stamped()
        out.header = att.header
        out.vector.x, out.vector.y, out.vector.z = map(float, bias)
        self.bias_pub.publish(out)

    def publish_step(self, stamp: int, step, attitude: np.ndarray) -> None:
        """Step, pose and path of one step (fields packed as pdr-pocket run packs them)."""
        fields = {k: v[0] for k, v in step_fields([step]).items()}
        msg = Step()
        set_header(msg.header, stamp, MAP_FRAME)
        msg.index = int(fields.pop("index"))
        msg.activity = int(fields.pop("activity"))
        for key, value in fields.items():
            setattr(msg, key, float(value))
        self.step_pub.publish(msg)
        pose_values = {k: v[0] for k, v in pose_fields([step], attitude[None]).items()}
        pose = PoseWithCovarianceStamped()
        set_header(pose.header, stamp, MAP_FRAME)
        p = pose.pose.pose.position
        p.x, p.y, p.z = map(float, pose_values["pose.pose.position"])
        q = pose.pose.pose.orientation
        q.x, q.y, q.z, q.w = map(float, pose_values["pose.pose.orientation"])
        pose.pose.covariance = [float(v) for v in pose_values["pose.covariance"]]
        self.pose_pub.publish(pose)
        stamped = PoseStamped()
        stamped.header = pose.header
        stamped.pose.position = pose.pose.pose.position
        stamped.pose.orientation.z = float(np.sin(step.heading / 2))
        stamped.pose.orientation.w = float(np.cos(step.heading / 2))
        self.path.header.stamp = pose.header.stamp
        self.path.poses.append(stamped)
        self.path_pub.publish(self.path)

    def on_correction(self, request, response):
        """pdr/pocket/apply_correction: the navigator decides; logged and counted."""
        position = (request.position.x, request.position.y, request.position.z) \
            if request.has_position else None
        covariance = list(request.position_covariance) if request.has_position else None
        try:
            accepted, message = self.navigator.apply_correction(
                request.yaw, request.yaw_variance, request.gyro_bias_z,
                request.gyro_bias_z_variance, position, covariance)
        except (ValueError, np.linalg.LinAlgError) as exc:
            accepted, message = False, f"correction not usable: {exc}"
            self.navigator.navigator.corrections["refused"] += 1
        counts = self.navigator.navigator.corrections
        tally = f"({counts['accepted']} accepted, {counts['refused']} refused so far)"
        if accepted:    # one severity per call site: rclpy refuses a logger that changes it
            self.get_logger().info(f"correction accepted {tally}: {message}")
        else:
            self.get_logger().warning(f"correction refused {tally}: {message}")
        response.accepted, response.message = bool(accepted), message
        return response

    def report_problems(self) -> None:
        nav = self.navigator
        for key, count in nav.counts.items():
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
        stale = nav.mag_stale
        if stale and not self.mag_was_stale and nav.last_stamp_ns is not None:
            self.get_logger().warning("imu/mag: no recent reading, magnetic updates paused",
                                      throttle_duration_sec=10.0)
        self.mag_was_stale = stale

    def on_reset(self, request: Trigger.Request, response: Trigger.Response):
        self.navigator.reset()
        self.detection_told = self.no_gait_told = False
        self.inputs.clear()
        self.path.poses = []
        response.success, response.message = True, "navigator reset"
        return response


def main(args: list[str] | None = None) -> None:
    spin_node("pocket_pdr", PocketPdrNode, args)

if __name__ == "__main__":
    main()
