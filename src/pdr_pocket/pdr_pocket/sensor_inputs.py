"""The pocket navigator's inputs besides ``imu/data`` and ``imu/mag``, by name (issue 41).

Each entry of :data:`SENSOR_INPUTS` is a sensor read more slowly than the IMU, one value
per reading: its name (the :class:`~pdr_pocket.samples.Samples` field it fills), its bag
topic and message type, and the message field that carries the value, in SI units.
Offline (pdr_pocket.inputs), live (pdr_pocket.streaming) and in the node
(pdr_pocket.nodes.pocket_pdr) each one is read, checked, paired with the IMU's samples
(pdr_core.sensors.sample_pairing) and held for in the same way, so adding a sensor is a line
here, a field of Samples, a topic name (and a message type's), the docs that list the
inputs and the code that uses it (docs/extending.md, "Adding a sensor input").
"""
from __future__ import annotations

from dataclasses import dataclass

from pdr_core import topics
from pdr_core.io.msgtypes import FLUID_PRESSURE


@dataclass(frozen=True)
class SensorInput:
    """A sensor by name: the Samples field ``name``, the bag ``topic`` (pdr_core.topics),
    its message type ``msgtype`` (pdr_core.io.msgtypes, e.g. "sensor_msgs/msg/FluidPressure")
    and the message ``field`` that holds the value in ``unit``."""

    name: str
    topic: str
    msgtype: str
    field: str
    unit: str


SENSOR_INPUTS = (
    SensorInput("pressure", topics.IMU_PRESSURE, FLUID_PRESSURE, "fluid_pressure", "Pa"),
)
