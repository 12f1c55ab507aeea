"""Messages, bags and files: ROS messages as NumPy arrays, read from and written to
rosbag2 bags (MCAP) in bulk, and the logs of phones and datasets imported as them.

Modules:
    msgtypes      The rosbags typestore: ROS 2 Jazzy types plus pdr_msgs.
    batch         MessageBatch: a topic's messages as NumPy arrays.
    cdr           Vectorised CDR encoding and decoding of fixed-layout messages.
    mcap_bulk     Vectorised MCAP writes and indexed reads of fixed-size messages.
    bag           Reading and writing rosbag2 bags in MCAP storage.
    recording     A bag written as it is recorded: a crash loses at most the last second.
    headers       std_msgs/Header stamps to and from nanoseconds.
    nav_path      nav_msgs/Path to and from pose batches.
    odometry      A navigator's pose as nav_msgs/Odometry and /tf, /tf_static batches
                  (REP-105), for bags and topics alike.
    csv_table     A CSV table read as numbers: columns by name or index, bad cells refused.
    csv_rows      The rows of a CSV import checked: dead axes, unusable values, stamps.
    csv_import    A CSV IMU log as Imu and PoseStamped batches.
    csv_export    A bag's topics as a phone-style CSV log, each at its rows.
    phone_import  A phone's own export, one CSV per sensor, as batches.
    oxiod         A sequence of the Oxford Inertial Odometry Dataset (Chen et al. 2018) as
                  imu/data, imu/mag and ground_truth/pose batches.
"""
