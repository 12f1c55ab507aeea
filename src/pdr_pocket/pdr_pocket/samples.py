"""The pocket navigator's inputs by name (issue 41): :class:`Samples`, a chunk of
time-ordered samples in which each sensor is a field of its own and a sensor the phone
does not have is ``None``, never zeros.

robot_localization turns every input into one measurement type in one time-ordered queue;
VQF takes each sensor through its own entry point. Here the IMU's samples set the time
base (the orientation filter runs at their rate, Muñoz Díaz 2016, chapter 3), and every
other sensor is paired with them by stamp before it comes in (pdr_core.sensors.magnetometer_pairing
offline, pdr_pocket.streaming live): a chunk is one named stream, cut and joined as one.

A new sensor read more slowly than the IMU is a new field here, a line of
pdr_pocket.sensor_inputs (which pairs it) and its use where the navigator reads it
(docs/extending.md, "Adding a sensor input").
"""
from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np


@dataclass(frozen=True)
class Samples:
    """A chunk of samples, time-ordered, the body frame's axes:

    - ``t`` (N,) [s], increasing;
    - ``accel`` (N, 3) [m/s²], the specific force;
    - ``gyro`` (N, 3) [rad/s], or None: the IMU has no gyroscope (REP-145);
    - ``mag`` (N, 3) [T], or None: no magnetometer; a NaN row: no reading paired with
      that sample;
    - ``pressure`` (N,) [Pa], or None: no barometer; each reading on the first sample
      stamped at or after it (pdr_core.sensors.barometry.readings_at_samples), NaN elsewhere.
    """

    t: np.ndarray
    accel: np.ndarray
    gyro: np.ndarray | None = None
    mag: np.ndarray | None = None
    pressure: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.t)

    def __getitem__(self, index) -> Samples:
        """The samples at ``index`` (a slice, indices or a mask) of every sensor there is."""
        return replace(self, **{f.name: getattr(self, f.name)[index]
                                for f in fields(self) if getattr(self, f.name) is not None})

    def part(self, start: int, stop: int) -> Samples:
        """Samples ``start`` to ``stop`` (exclusive)."""
        return self[start:stop]

    def split(self, t_s: float) -> tuple[Samples, Samples]:
        """The samples at or before ``t_s`` [s] and those after it."""
        cut = int(np.searchsorted(self.t, t_s, side="right"))
        return self.part(0, cut), self.part(cut, len(self))

    @property
    def end_s(self) -> float:
        """The last sample's time [s]."""
        return float(self.t[-1])
