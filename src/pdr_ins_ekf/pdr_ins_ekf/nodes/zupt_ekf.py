"""Node ``zupt_ekf``: the foot navigator on ``imu/data``, live.

Subscribes ``imu/data`` (sensor_msgs/Imu) and publishes, per sample, ``pdr/foot/pose``
(PoseWithCovarianceStamped), ``pdr/foot/velocity`` (TwistWithCovarianceStamped) and
``pdr/foot/stance`` (pdr_msgs/Stance), and at the end of every step ``pdr/foot/path``
(one pose per step). With ``smoothed_path`` true it also publishes
``pdr/foot/smoothed_path``: one Path per segment of the segmented RTS smoother
(001_5b5dbf275b14cf0a.txt), with every sample's smoothed pose, as soon as the segment
ends (its lag and its memory are bounded by the segment). Serves ``~/reset``
(std_srvs/Trigger).

Parameters: ``config`` (navigator YAML, see pdr_ins_ekf.config; default the installed
config/foot_ekf.yaml) or ``imu_profile`` (the shipped config/foot_ekf_<profile>.yaml),
``frame_id`` ("map"), ``imu_durability`` (volatile or
transient_local, to match the publisher), ``smoothed_path`` (false).

Estimates lag the input by the detector's look-ahead (a few samples) and agree with
``pdr-ekf run`` on the same data. Bad samples (NaN/Inf, stamps going backwards) are
dropped and counted with a throttled warning; data in g or deg/s is refused at alignment
with an error, and nothing is navigated until ``~/reset``.
"""
from __future__ import annotations

import dataclasses

from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped, TwistWithCovarianceStamped
from nav_msgs.msg import Path as PathMsg
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Imu
from std_srvs.srv import Trigger

from pdr_core.headers import NS_PER_S, set_header, stamp_ns
from pdr_core.node_main import spin_node
from pdr_core.rotations import quaternion_from_orthonormal
from pdr_ins_ekf.config import load_run_config
from pdr_ins_ekf.offline import UNKNOWN_VARIANCE
from pdr_ins_ekf.streaming import Estimate, StreamingNavigator
from pdr_ins_ekf.zupt_ekf import SmoothedSegment
from pdr_msgs.msg import Stance


class ZuptEkfNode(Node):
    """Adapter from Imu messages to the streaming navigator and back to messages."""

    def __init__(self) -> None:
        super().__init__("zupt_ekf")
        path = self.declare_parameter("config", "").value
        profile = self.declare_parameter("imu_profile", "").value
        self.frame_id = self.declare_parameter("frame_id", "map").value
        durability = self.declare_parameter("imu_durability", "volatile").value
        config = load_run_config(path, profile)
        smoothing = self.declare_parameter("smoothed_path", False).value
        config = dataclasses.replace(config, smoother=dataclasses.replace(
            config.smoother, mode="segmented" if smoothing else "none"))
        self.navigator = StreamingNavigator(config)
        qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL
                         if durability == "transient_local" else DurabilityPolicy.VOLATILE)
        self.create_subscription(Imu, "imu/data", self.on_imu, qos)
        # transient local: a recorder that joins late still gets the last 1000 estimates
        out = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, "pdr/foot/pose", out)
        self.velocity_pub = self.create_publisher(TwistWithCovarianceStamped,
                                                  "pdr/foot/velocity", out)
        self.stance_pub = self.create_publisher(Stance, "pdr/foot/stance", out)
        self.path_pub = self.create_publisher(PathMsg, "pdr/foot/path", out)
        self.smoothed_pub = self.create_publisher(PathMsg, "pdr/foot/smoothed_path", out)
        self.create_service(Trigger, "~/reset", self.on_reset)
        self.path = PathMsg()
        self.path.header.frame_id = self.frame_id
        self.previous_stance = False
        self.reported: dict[str, int] = {}
        self.get_logger().info(f"zupt_ekf: configuration {path or profile or 'default'}")

    def on_imu(self, msg: Imu) -> None:
        a, w = msg.linear_acceleration, msg.angular_velocity
        stamp = stamp_ns(msg)
        estimates = self.navigator.push(stamp, (a.x, a.y, a.z), (w.x, w.y, w.z))
        for estimate in estimates:
            self.publish(estimate)
        for segment in self.navigator.take_smoothed():
            self.publish_smoothed(segment)
        self.report_problems()

    def report_problems(self) -> None:
        for key, count in self.navigator.counts.items():
            if count > self.reported.get(key, 0):
                self.get_logger().warning(f"imu/data: {count} samples with {key} so far",
                                          throttle_duration_sec=5.0)
                self.reported[key] = count
        if self.navigator.failed is not None:
            self.get_logger().error(f"not navigating: {self.navigator.failed}",
                                    throttle_duration_sec=5.0)

    def publish(self, e: Estimate) -> None:
        sec, nanosec = divmod(e.stamp_ns, NS_PER_S)
        q = quaternion_from_orthonormal(e.attitude)
        pose = PoseWithCovarianceStamped()
        pose.header.stamp.sec, pose.header.stamp.nanosec = sec, nanosec
        pose.header.frame_id = self.frame_id
        p = pose.pose.pose
        p.position.x, p.position.y, p.position.z = map(float, e.position)
        p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = map(float, q)
        cov = [0.0] * 36
        for i in range(3):
            for j in range(3):
                cov[6 * i + j] = float(e.covariance[i, j])
            cov[7 * (i + 3)] = float(e.covariance[6 + i, 6 + i])
        pose.pose.covariance = cov
        self.pose_pub.publish(pose)
        twist = TwistWithCovarianceStamped()
        twist.header = pose.header
        v = twist.twist.twist.linear
        v.x, v.y, v.z = map(float, e.velocity)
        tcov = [0.0] * 36
        for i in range(3):
            for j in range(3):
                tcov[6 * i + j] = float(e.covariance[3 + i, 3 + j])
            tcov[7 * (i + 3)] = UNKNOWN_VARIANCE
        twist.twist.covariance = tcov
        self.velocity_pub.publish(twist)
        stance = Stance(stationary=e.stance, statistic=e.statistic, detector=e.detector)
        stance.header.stamp = pose.header.stamp
        stance.header.frame_id = "imu_link"
        self.stance_pub.publish(stance)
        if e.stance and not self.previous_stance:
            step = PoseStamped(header=pose.header, pose=p)
            self.path.poses.append(step)
            self.path.header.stamp = pose.header.stamp
            self.path_pub.publish(self.path)
        self.previous_stance = e.stance

    def publish_smoothed(self, segment: SmoothedSegment) -> None:
        """One Path with every sample's smoothed pose, stamped at the segment's end."""
        path = PathMsg()
        path.header.frame_id = self.frame_id
        quats = quaternion_from_orthonormal(segment.attitude)
        for stamp, p, q in zip(segment.stamp_ns.tolist(), segment.position.tolist(),
                               quats.tolist(), strict=True):
            pose = PoseStamped()
            set_header(pose.header, stamp, self.frame_id)
            position, orientation = pose.pose.position, pose.pose.orientation
            position.x, position.y, position.z = p
            orientation.x, orientation.y, orientation.z, orientation.w = q
            path.poses.append(pose)
        path.header.stamp = path.poses[-1].header.stamp
        self.smoothed_pub.publish(path)

    def on_reset(self, request: Trigger.Request, response: Trigger.Response):
        self.navigator.reset()
        self.path.poses = []
        self.previous_stance = False
        response.success, response.message = True, "navigator reset"
        return response


def main(args: list[str] | None = None) -> None:
    spin_node("zupt_ekf", ZuptEkfNode, args)

if __name__ == "__main__":
    main()
