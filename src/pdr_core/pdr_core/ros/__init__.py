"""What every node shares, duck-typed on rclpy or importing it inside a function.

Modules:
    node_main          The main() every node shares: init, spin, clean shutdown.
    node_params        Node parameters declared one way, with descriptors.
    node_wiring        The start-up log line: a node's resolved topic and service names.
    backlog            A subscription's backlog taken in one callback, and blocks
                       published as the reliable subscribers acknowledge them.
    ros_types          ROS type names to their rclpy message classes.
    message_yaml       A message as `ros2 topic echo` prints it: YAML or a CSV line
                       (rosidl_runtime_py's rules, no rclpy).
    message_fields     A message's fields set from a YAML mapping, as `ros2 service call`
                       fills a request (rosidl_runtime_py's rules, no rclpy).
    reception_rate     A topic's reception rate, intervals and window as `ros2 topic hz`
                       reports them (no rclpy).
    diagnostics        A navigator's health from its counters: OK, WARN or ERROR with the
                       reason (no rclpy).
    node_diagnostics   /diagnostics at 1 Hz for a node (diagnostic_msgs).
    node_tf            A navigator's pose on /tf (tf2_msgs, REP-105).
    transform_history  Transforms over time as a TF listener keeps them, and the
                       map → odom transform of REP-105 (plain NumPy and SciPy).
"""
