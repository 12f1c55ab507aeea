"""The frame names messages are stamped with by default (REP-105, REP-145), defined once.

- :data:`MAP_FRAME`: the ENU navigation frame of poses, paths, steps, landmarks and drift
  estimates (REP-105's ``map``). Two people in one graph each get their own
  (``-p map_frame:=alice_map``).
- :data:`BASE_FRAME`: the frame a navigator's pose places on TF (REP-105's
  ``base_link``): the IMU's body, whose attitude the pose's orientation is; two people in
  one graph each get their own (``-p base_frame:=alice/base_link``).
- :data:`TRUTH_FRAME`: the true pose of the IMU on ``/tf`` in a simulated or imported
  recording (``map → ground_truth``), apart from the estimates' ``base_link``.
- :data:`SENSOR_FRAME`: the IMU's own frame (REP-145), the frame of a sensor_msgs/Imu's
  rates and specific force, and of the gyro biases.
"""
from __future__ import annotations

MAP_FRAME = "map"
SENSOR_FRAME = "imu_link"
BASE_FRAME = "base_link"
TRUTH_FRAME = "ground_truth"
