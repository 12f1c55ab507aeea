"""rclpy nodes of pdr_ins_ekf: thin adapters over the streaming navigator.

- :mod:`zupt_ekf`: the foot navigator on ``imu/data``, live (:mod:`pdr_ins_ekf.streaming`).
"""
