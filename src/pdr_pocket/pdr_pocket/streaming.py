"""The pocket navigator sample by sample, for the live node (no rclpy here).

:class:`StreamingPocket` takes ``imu/data`` and ``imu/mag`` messages as plain values and
returns what to publish. It applies the offline rules one message at a time, so the node
and ``pdr-pocket attitude`` give the same estimates on the same bag:

- an IMU sample with NaN/Inf, or a stamp that does not increase, is dropped and counted;
- each IMU sample pairs with the latest magnetometer reading stamped at or before it and
  at most :data:`~pdr_pocket.attitude_offline.MAG_MAX_AGE_S` older, as offline. A reading
  stamped like its IMU sample may arrive after it, so a sample is processed when the next
  one arrives or a reading stamped at or after it does (one sample of latency). A
  magnetometer that stops publishing only pauses the magnetic updates (:attr:`mag_stale`);
- the units are checked on the first :data:`UNIT_CHECK_SAMPLES` samples: data in g or
  deg/s is refused (nothing is navigated until :meth:`reset`), a magnetometer in µT or
  gauss is switched off (:attr:`mag_error`);
- gaps longer than ``max_gap_s`` are propagated over and counted by the filter.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

import numpy as np

from pdr_core.errors import InputError
from pdr_core.imu_checks import check_mag_units, check_units
from pdr_pocket.attitude_offline import MAG_MAX_AGE_S
from pdr_pocket.config import OrientationConfig
from pdr_pocket.magnetometer import MagCalibration
from pdr_pocket.orientation import AttitudeEstimate, OrientationFilter

UNIT_CHECK_SAMPLES = 50
MAG_HISTORY = 256


@dataclass
class StreamingPocket:
    """Live orientation filter: :meth:`push_imu` and :meth:`push_mag` return the
    (stamp [ns], estimate) of every sample they let the filter process."""

    config: OrientationConfig
    calibration: MagCalibration | None = None
    counts: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        self.filter = OrientationFilter(self.config)
        self.last_stamp_ns: int | None = None
        self.mags: deque = deque(maxlen=MAG_HISTORY)
        self.held: list[tuple[int, np.ndarray, np.ndarray]] = []
        self.checked = False
        self.failed: str | None = None
        self.mag_error: str | None = None
        self.t0_ns: int | None = None
        self.counts = {"non_finite": 0, "stamp_not_increasing": 0, "mag_non_finite": 0,
                       "mag_missing": 0}

    @property
    def mag_stale(self) -> bool:
        """No reading within MAG_MAX_AGE_S of the last IMU sample."""
        return not self.mags or (self.last_stamp_ns is not None and
                                 self.last_stamp_ns - self.mags[-1][0] > MAG_MAX_AGE_S * 1e9)

    def push_mag(self, stamp_ns: int, field_t) -> list[tuple[int, AttitudeEstimate]]:
        """A magnetometer reading [T] (body frame)."""
        value = np.asarray(field_t, float)
        if not np.isfinite(value).all():
            self.counts["mag_non_finite"] += 1
            return []
        if self.calibration is not None:
            value = self.calibration.apply(value.reshape(1, 3))[0]
        if self.mags and stamp_ns < self.mags[-1][0]:
            return []
        self.mags.append((int(stamp_ns), value))
        if self.checked and self.held and self.held[-1][0] <= stamp_ns:
            return self._process(len(self.held))
        return []

    def push_imu(self, stamp_ns: int, accel, gyro) -> list[tuple[int, AttitudeEstimate]]:
        """An IMU sample [m/s², rad/s]."""
        a, w = np.asarray(accel, float), np.asarray(gyro, float)
        if not (np.isfinite(a).all() and np.isfinite(w).all()):
            self.counts["non_finite"] += 1
            return []
        if self.last_stamp_ns is not None and stamp_ns <= self.last_stamp_ns:
            self.counts["stamp_not_increasing"] += 1
            return []
        self.last_stamp_ns = int(stamp_ns)
        if self.failed is not None:
            return []
        self.held.append((int(stamp_ns), a, w))
        if not self.checked:
            if len(self.held) < UNIT_CHECK_SAMPLES:
                return []
            self._check_units()
            if self.failed is not None:
                return []
        return self._process(len(self.held) - 1)

    def flush(self) -> list[tuple[int, AttitudeEstimate]]:
        """Process every held sample (the end of a stream)."""
        if self.held and not self.checked and self.failed is None:
            self._check_units()
        return [] if self.failed is not None else self._process(len(self.held))

    def _check_units(self) -> None:
        self.checked = True
        try:
            check_units(np.array([h[1] for h in self.held]), np.array([h[2] for h in self.held]))
        except InputError as exc:
            self.failed = str(exc)
            self.held = []
            return
        if self.mags:
            try:
                check_mag_units(np.array([m[1] for m in self.mags]))
            except InputError as exc:
                self.mag_error = str(exc)

    def _mag_for(self, stamp_ns: int) -> np.ndarray | None:
        if self.mag_error is not None:
            return None
        for m_stamp, value in reversed(self.mags):
            if m_stamp <= stamp_ns:
                return value if stamp_ns - m_stamp <= MAG_MAX_AGE_S * 1e9 else None
        return None

    def _process(self, count: int) -> list[tuple[int, AttitudeEstimate]]:
        out = []
        for stamp_ns, accel, gyro in self.held[:count]:
            if self.t0_ns is None:
                self.t0_ns = stamp_ns
            mag = self._mag_for(stamp_ns)
            if mag is None:
                self.counts["mag_missing"] += 1
            out.append((stamp_ns, self.filter.push((stamp_ns - self.t0_ns) * 1e-9, gyro, accel,
                                                   mag)))
        self.held = self.held[count:]
        return out
