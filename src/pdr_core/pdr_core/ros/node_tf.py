"""A navigator's pose on TF (REP-105; issue 42), for both navigator nodes (rclpy imported
inside the functions, as pdr_core's node helpers do; ``tf2_msgs`` is the workspace's own
when no other is installed, docs/ros_install.md).

:class:`TfBroadcaster` declares the node's TF parameters and publishes, as raw CDR
(pdr_core.io.cdr, pdr_core.io.odometry):

- on ``/tf``, at each pose, ``map_frame → base_frame``; or, when ``odom_frame`` is given,
  ``map_frame → odom_frame`` from the ``odom_frame → base_frame`` transform another node
  (wheel or visual odometry) puts on ``/tf``, as robot_localization's map instance does
  (pdr_core.ros.transform_history). A pose waits until the odometry has reached its stamp
  (the ``/tf`` messages in the queue are read first), at most :data:`ODOM_WAIT_S` of pose
  time, so the topics may come in any order; a pose with no transform around its stamp
  publishes nothing and is counted (``tf_no_odom``);
- on ``/tf_static``, once, at the first pose's stamp, the identity ``base_frame →
  sensor_frame`` (pdr_core.io.odometry.static_batch).

The publishers have TF's QoS: reliable and volatile on ``/tf`` (deep enough for a block
of poses published in acknowledged slices), reliable and transient local, depth 1, on
``/tf_static``, as tf2_ros' broadcasters.
"""
from __future__ import annotations

import numpy as np

from pdr_core import topics
from pdr_core.frames import BASE_FRAME
from pdr_core.io import cdr
from pdr_core.io.odometry import static_batch, transform_batch
from pdr_core.ros.backlog import publish_acked, waiting_messages
from pdr_core.ros.node_params import declare
from pdr_core.ros.transform_history import TransformHistory, map_to_odom

# /tf history [messages]: a navigator's block of poses goes out in acknowledged slices of
# up to 500 (pdr_core.ros.backlog.publish_acked); tf2_ros' broadcaster keeps 100
TF_DEPTH = 1000
# odom → base transforms kept at most, not yet passed by a pose (10 min at 100 Hz)
ODOM_KEPT = 60_000
# how long a pose waits for the odometry to reach its stamp [s of pose time]: longer than
# a block of poses spans (400 samples, 4 s at 100 Hz: a bag played as fast as it goes
# brings whole blocks ahead of the odometry read so far); tf2's buffer keeps 10 s too
ODOM_WAIT_S = 10.0


class TfBroadcaster:
    """The TF of one navigator node: its parameters (``publish_tf``, ``base_frame``,
    ``odom_frame``), publishers and, with ``odom_frame``, the odometry it reads."""

    def __init__(self, node, map_frame: str, sensor_frame: str, slice_len: int,
                 ack_timeout) -> None:
        """``slice_len`` messages at most go out before the reliable subscribers have
        acknowledged them, waiting ``ack_timeout`` (an rclpy Duration) at most
        (pdr_core.ros.backlog.publish_acked)."""
        self.map_frame, self.sensor_frame = map_frame, sensor_frame
        self.slice_len, self.ack_timeout = slice_len, ack_timeout
        self.waiting: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
        self.enabled = declare(node, "publish_tf", True,
                               "broadcast map_frame -> base_frame (or -> odom_frame) on /tf")
        self.base_frame = declare(node, "base_frame", BASE_FRAME,
                                  "the frame whose pose the navigator estimates (REP-105)")
        self.odom_frame = declare(node, "odom_frame", "", "when given: publish map_frame -> "
                                  "odom_frame from the odom_frame -> base_frame on /tf")
        self.no_odom = 0
        self.static_sent = False
        self.odometry = TransformHistory(ODOM_KEPT)
        if not self.enabled:
            return
        from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

        from tf2_msgs.msg import TFMessage

        self.tf_pub = node.create_publisher(TFMessage, topics.TF, QoSProfile(
            depth=TF_DEPTH, reliability=ReliabilityPolicy.RELIABLE,
            durability=DurabilityPolicy.VOLATILE))
        self.static_pub = node.create_publisher(TFMessage, topics.TF_STATIC, QoSProfile(
            depth=1, reliability=ReliabilityPolicy.RELIABLE,
            durability=DurabilityPolicy.TRANSIENT_LOCAL))
        if self.odom_frame:
            # keep all: a transform overwritten before it was read leaves a gap the poses
            # would be interpolated across (the IMU subscriptions keep all too)
            self.odom_sub = node.create_subscription(TFMessage, topics.TF, self.on_tf, QoSProfile(
                history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                durability=DurabilityPolicy.VOLATILE))

    def describe(self) -> str:
        """The start-up line's part: what goes on /tf."""
        if not self.enabled:
            return "no /tf"
        if self.odom_frame:
            return (f"/tf {self.map_frame} -> {self.odom_frame} from {self.odom_frame} -> "
                    f"{self.base_frame}")
        return f"/tf {self.map_frame} -> {self.base_frame}"

    def on_tf(self, msg) -> None:
        """Keep the ``odom_frame → base_frame`` transforms of a /tf message, and publish
        the poses that waited for them."""
        for t in msg.transforms:
            if t.header.frame_id == self.odom_frame and t.child_frame_id == self.base_frame:
                p, q = t.transform.translation, t.transform.rotation
                self.odometry.add(t.header.stamp.sec * 1_000_000_000 + t.header.stamp.nanosec,
                                  np.array([p.x, p.y, p.z]), np.array([q.x, q.y, q.z, q.w]))
        self._publish_waiting()

    def broadcast(self, stamp_ns: np.ndarray, position: np.ndarray, quaternion_xyzw: np.ndarray
                  ) -> None:
        """The poses [m], (x, y, z, w) of ``base_frame`` in ``map_frame`` at ``stamp_ns``
        [ns, ascending]: on /tf (see the module)."""
        if not self.enabled or not len(stamp_ns):
            return
        if not self.static_sent:
            self.static_pub.publish(cdr.encode(static_batch(int(stamp_ns[0]), self.base_frame,
                                                            self.sensor_frame))[0])
            self.static_sent = True
        if not self.odom_frame:
            self._publish(stamp_ns, self.base_frame, position, quaternion_xyzw)
            return
        self.waiting.append((stamp_ns, position, quaternion_xyzw))
        while taken := waiting_messages(self.odom_sub, TF_DEPTH):  # read before these poses
            for msg in taken:
                self.on_tf(msg)
        self._publish_waiting()

    def _publish_waiting(self) -> None:
        """``map_frame → odom_frame`` at the waiting poses the odometry has reached; those
        that waited ``ODOM_WAIT_S`` of pose time in vain are counted (``tf_no_odom``)."""
        if not self.waiting:
            return
        stamps = np.concatenate([w[0] for w in self.waiting])
        position = np.concatenate([w[1] for w in self.waiting])
        quaternion = np.concatenate([w[2] for w in self.waiting])
        newest = self.odometry.newest_ns()
        reached = stamps <= newest if newest is not None else np.zeros(len(stamps), bool)
        expired = ~reached & (stamps < stamps[-1] - ODOM_WAIT_S * 1e9)
        self.no_odom += int(expired.sum())
        keep = ~reached & ~expired
        self.waiting = [(stamps[keep], position[keep], quaternion[keep])] if keep.any() else []
        odom_position, odom_quaternion, found = self.odometry.at(stamps[reached])
        self.no_odom += int(np.sum(~found))
        pose = np.flatnonzero(reached)[found]
        self._publish(stamps[pose], self.odom_frame, *map_to_odom(
            position[pose], quaternion[pose], odom_position, odom_quaternion))

    def _publish(self, stamp_ns: np.ndarray, child: str, position: np.ndarray,
                 quaternion_xyzw: np.ndarray) -> None:
        """``map_frame → child`` on /tf, in acknowledged slices."""
        if len(stamp_ns):
            publish_acked([(self.tf_pub, transform_batch(stamp_ns, self.map_frame, child,
                                                         position, quaternion_xyzw))],
                          self.slice_len, self.ack_timeout)
