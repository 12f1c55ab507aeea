"""Mapping ROS type names (``sensor_msgs/msg/Imu``) to rclpy message classes."""
from __future__ import annotations

import importlib
from typing import Any


def message_class(msgtype: str) -> Any:
    """The generated Python class of ``pkg/msg/Name``; ImportError if not installed."""
    package, kind, name = msgtype.split("/")
    return getattr(importlib.import_module(f"{package}.{kind}"), name)
