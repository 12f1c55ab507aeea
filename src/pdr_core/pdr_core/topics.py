"""Topic names as stored in bags (absolute, without namespace).

On the ROS graph the same names are used relative to the node's namespace (``imu/data``),
so a namespace can prefix them; ``bag_play`` and ``bag_record`` map between the two.
See docs/nodes.md for the topics of each node.
"""
IMU_DATA = "/imu/data"
IMU_MAG = "/imu/mag"
GROUND_TRUTH_POSE = "/ground_truth/pose"
GROUND_TRUTH_STEP = "/ground_truth/step"            # pocket placement: one per true step
GROUND_TRUTH_LANDMARKS = "/ground_truth/landmarks"  # pocket placement: corners, flights
GROUND_TRUTH_STANCE = "/ground_truth/stance"        # foot placement: true zero velocity
CLOCK = "/clock"


def graph_name(bag_topic: str) -> str:
    """The relative graph name of a bag topic: ``/imu/data`` -> ``imu/data``.

    ``/clock`` stays absolute: it is global by ROS convention."""
    return bag_topic if bag_topic == CLOCK else bag_topic.lstrip("/")


def bag_name(graph_topic: str) -> str:
    """The bag name of a graph topic: ``imu/data`` -> ``/imu/data``."""
    return "/" + graph_topic.lstrip("/")
