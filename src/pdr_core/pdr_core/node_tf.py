"""A navigator's pose on TF (REP-105; issue 42): ``map_frame → base_frame`` as a
tf2_msgs/TFMessage on ``/tf`` (rclpy imported inside the functions, as pdr_core's node
helpers do; ``tf2_msgs`` is the workspace's own when no other is installed,
docs/ros_install.md).

- :func:`tf_publisher`: the ``/tf`` publisher, with TF's QoS (reliable, volatile, depth 100,
  as tf2_ros' broadcaster);
- :func:`pose_transform`: the TFMessage of one pose.
"""
from __future__ import annotations

from pdr_core import topics
from pdr_core.headers import set_header

TF_DEPTH = 100


def tf_publisher(node):
    """A publisher of tf2_msgs/TFMessage on ``/tf`` for ``node``."""
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    from tf2_msgs.msg import TFMessage

    return node.create_publisher(TFMessage, topics.TF, QoSProfile(
        depth=TF_DEPTH, reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE))


def pose_transform(stamp_ns: int, parent: str, child: str, position, quaternion_xyzw):
    """The TFMessage of ``child``'s pose in ``parent`` at ``stamp_ns`` [ns]: the position
    [m] (3,) and the orientation, a unit quaternion (x, y, z, w)."""
    from geometry_msgs.msg import TransformStamped

    from tf2_msgs.msg import TFMessage

    transform = TransformStamped()
    set_header(transform.header, stamp_ns, parent)
    transform.child_frame_id = child
    t = transform.transform.translation
    t.x, t.y, t.z = map(float, position)
    r = transform.transform.rotation
    r.x, r.y, r.z, r.w = map(float, quaternion_xyzw)
    return TFMessage(transforms=[transform])
