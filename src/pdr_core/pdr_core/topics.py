"""Topic and service names, defined once, as stored in bags (absolute, without namespace).

On the ROS graph the same names are used relative to the node's namespace (``imu/data``,
:func:`graph_name`), so a namespace can prefix them; ``bag_play`` and ``bag_record`` map
between the two. Nodes, bag writers, readers and command lines all take the names from
here. See docs/nodes.md for the topics of each node.
"""
IMU_DATA = "/imu/data"
IMU_MAG = "/imu/mag"
IMU_PRESSURE = "/imu/pressure"                      # sensor_msgs/FluidPressure [Pa]
GROUND_TRUTH_POSE = "/ground_truth/pose"
GROUND_TRUTH_STEP = "/ground_truth/step"            # pocket placement: one per true step
GROUND_TRUTH_LANDMARKS = "/ground_truth/landmarks"  # pocket placement: corners, flights
GROUND_TRUTH_STANCE = "/ground_truth/stance"        # foot placement: true zero velocity
CLOCK = "/clock"
DIAGNOSTICS = "/diagnostics"                        # diagnostic_msgs/DiagnosticArray, absolute
TF = "/tf"                                          # tf2_msgs/TFMessage, absolute (REP-105)
TF_STATIC = "/tf_static"                            # tf2_msgs/TFMessage, absolute, latched

# a foot IMU beside the pocket's on one walk (pdr-sim generate --with-foot): its topics
# under this namespace, /foot/imu/data and so on (issue 57)
FOOT_NAMESPACE = "/foot"

# the foot navigator (zupt_ekf, pdr-ekf run)
FOOT_POSE = "/pdr/foot/pose"
FOOT_VELOCITY = "/pdr/foot/velocity"
FOOT_STANCE = "/pdr/foot/stance"
FOOT_ODOMETRY = "/pdr/foot/odometry"                # nav_msgs/Odometry, for a fusion node
FOOT_PATH = "/pdr/foot/path"
FOOT_SMOOTHED_PATH = "/pdr/foot/smoothed_path"
FOOT_STEP = "/pdr/foot/step"                        # pdr_msgs/Step, one per stride
FOOT_STEP_POSE = "/pdr/foot/step_pose"              # the pose at each stride, for pdr_drift
FOOT_APPLY_CORRECTION = "/pdr/foot/apply_correction"    # the service zupt_ekf offers

# the pocket navigator (pocket_pdr, pdr-pocket run)
POCKET_ATTITUDE = "/pdr/pocket/attitude"
POCKET_GYRO_BIAS = "/pdr/pocket/gyro_bias"
POCKET_STEP = "/pdr/pocket/step"
POCKET_POSE = "/pdr/pocket/pose"
POCKET_ODOMETRY = "/pdr/pocket/odometry"            # nav_msgs/Odometry, for a fusion node
POCKET_PATH = "/pdr/pocket/path"
POCKET_CORRECTED_PATH = "/pdr/pocket/corrected_path"   # pdr-drift run's offline correction
POCKET_APPLY_CORRECTION = "/pdr/pocket/apply_correction"   # the service pocket_pdr offers

# the stride calibrator (stride_calibrator): the foot INS calibrates the pocket's lines
POCKET_STRIDE_LINES = "/pdr/pocket/stride_lines"    # pdr_msgs/StrideLines, the fitted lines

# the landmark drift estimator (landmark_drift, pdr-drift run)
LANDMARKS = "/pdr/landmarks"
DRIFT = "/pdr/drift"


def graph_name(bag_topic: str) -> str:
    """The relative graph name of a bag topic: ``/imu/data`` -> ``imu/data``.

    ``/clock`` stays absolute: it is global by ROS convention."""
    return bag_topic if bag_topic == CLOCK else bag_topic.lstrip("/")


def bag_name(graph_topic: str) -> str:
    """The bag name of a graph topic: ``imu/data`` -> ``/imu/data``."""
    return "/" + graph_topic.lstrip("/")
