"""Shared pure-Python core of the PDR stack (no rclpy import).

Modules:
    errors      InputError and the CLI error convention (one line naming file and problem).
    msgtypes    The rosbags typestore: ROS 2 Jazzy types plus pdr_msgs.
    batch       MessageBatch: a topic's messages as NumPy arrays.
    cdr         Vectorised CDR encoding and decoding of fixed-layout stamped messages.
    bag         Reading and writing rosbag2 bags in MCAP storage.
    csv_import  Turning a CSV IMU log into Imu and PoseStamped batches.
"""
