"""Shared pure-Python core of the PDR stack (no rclpy import).

Modules:
    errors                    InputError and the CLI error convention (one line naming
                              file and problem).
    msgtypes                  The rosbags typestore: ROS 2 Jazzy types plus pdr_msgs.
    topics                    Topic names in bags and on the graph.
    batch                     MessageBatch: a topic's messages as NumPy arrays.
    cdr                       Vectorised CDR encoding and decoding of fixed-layout messages.
    bag                       Reading and writing rosbag2 bags in MCAP storage.
    nav_path                  nav_msgs/Path to and from pose batches.
    csv_import                Turning a CSV IMU log into Imu and PoseStamped batches.
    units                     Conversions at the edges (°/√h, µg/√Hz, mg, ...).
    rotations                 Attitude conventions (ENU/FLU, ZYX Euler) and conversions.
    imu_errors                Sensor error models applied to whole signals and runs.
    imu_profiles              Named IMU profiles and their configuration keys.
    allan                     Overlapping Allan deviation and the noise parameters on it.
    magnetic_field            Homogeneous and cylinder-perturbed fields, iron distortion.
    magnetometer_calibration  Hard/soft-iron calibration by ellipsoid fitting.
"""
