"""The message typestore used for (de)serialisation outside the ROS graph.

``rosbags`` ships the standard ROS 2 Jazzy types; the ``pdr_msgs`` definitions are read
from the installed package's ``share/pdr_msgs/msg/*.msg`` so that they exist in one place.
"""
from __future__ import annotations

import functools
from pathlib import Path

from ament_index_python.packages import PackageNotFoundError, get_package_share_directory
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

IMU = "sensor_msgs/msg/Imu"
MAGNETIC_FIELD = "sensor_msgs/msg/MagneticField"
FLUID_PRESSURE = "sensor_msgs/msg/FluidPressure"   # fluid_pressure [Pa], variance [Pa²]
POSE_STAMPED = "geometry_msgs/msg/PoseStamped"
POSE_WITH_COVARIANCE_STAMPED = "geometry_msgs/msg/PoseWithCovarianceStamped"
TWIST_WITH_COVARIANCE_STAMPED = "geometry_msgs/msg/TwistWithCovarianceStamped"
VECTOR3_STAMPED = "geometry_msgs/msg/Vector3Stamped"
PATH = "nav_msgs/msg/Path"
ODOMETRY = "nav_msgs/msg/Odometry"      # child_frame_id after the header: pdr_core.io.cdr
TF_MESSAGE = "tf2_msgs/msg/TFMessage"   # one transform per message: pdr_core.io.cdr
CLOCK = "rosgraph_msgs/msg/Clock"
STEP = "pdr_msgs/msg/Step"
LANDMARK = "pdr_msgs/msg/Landmark"
DRIFT_ESTIMATE = "pdr_msgs/msg/DriftEstimate"
# Fields appended to our own messages since bags were first written with them: a message
# of an older bag, without them, reads them as 0 (pdr_core.io.cdr). Only ever append.
APPENDED_FIELDS = {STEP: ("ride", "ride_height")}      # issue 41: the lift rides


def pdr_msgs_dir() -> Path:
    """The installed ``pdr_msgs`` share directory (holds ``msg/*.msg``)."""
    try:
        return Path(get_package_share_directory("pdr_msgs"))
    except PackageNotFoundError as exc:
        raise RuntimeError(
            "pdr_msgs is not installed: build the workspace (make build) and run through ./ws"
        ) from exc


@functools.cache
def typestore() -> Typestore:
    """ROS 2 Jazzy types plus ``pdr_msgs/msg/*``, built once per process."""
    store = get_typestore(Stores.ROS2_JAZZY)
    types = {}
    for path in sorted((pdr_msgs_dir() / "msg").glob("*.msg")):
        types.update(get_types_from_msg(path.read_text(), f"pdr_msgs/msg/{path.stem}"))
    store.register(types)
    return store
