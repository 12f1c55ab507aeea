"""Each IMU sample paired with a magnetometer reading: the latest one stamped at or before
it and at most :data:`MAG_MAX_AGE_S` old, else none (a NaN row). One rule for every tool
that pairs the two topics: the pocket navigator offline (pdr_pocket.inputs) and
live (pdr_pocket.streaming), and ``pdr-sim export-csv`` (pdr_core.io.csv_export).

- :func:`paired_mag`: a ``sensor_msgs/MagneticField`` batch paired with IMU stamps;
- :func:`latest_readings`: the rule on plain arrays.
"""
from __future__ import annotations

import numpy as np

from pdr_core.io.batch import MessageBatch

MAG_MAX_AGE_S = 0.05


def paired_mag(imu_stamps: np.ndarray, mag: MessageBatch | None) -> tuple[np.ndarray, int]:
    """For each IMU stamp [ns] (N,) the latest finite magnetometer reading [T] (N, 3) at
    most :data:`MAG_MAX_AGE_S` old (NaN rows otherwise), and the count of non-finite
    readings."""
    if mag is None or len(mag) == 0:
        return np.full((len(imu_stamps), 3), np.nan), 0
    values = mag["magnetic_field"]
    finite = np.isfinite(values).all(axis=1)
    stamps, values = mag.stamp_ns[finite], values[finite]
    order = np.argsort(stamps, kind="stable")
    return latest_readings(imu_stamps, stamps[order], values[order]), int((~finite).sum())


def latest_readings(imu_stamps: np.ndarray, mag_stamps: np.ndarray, values: np.ndarray
                    ) -> np.ndarray:
    """For each IMU stamp [ns] the latest reading (N, 3) stamped at or before it and at
    most :data:`MAG_MAX_AGE_S` old, NaN rows otherwise; ``mag_stamps`` ascending."""
    out = np.full((len(imu_stamps), 3), np.nan)
    latest = np.searchsorted(mag_stamps, imu_stamps, side="right") - 1
    ok = latest >= 0
    fresh = np.zeros(len(imu_stamps), dtype=bool)
    fresh[ok] = imu_stamps[ok] - mag_stamps[latest[ok]] <= MAG_MAX_AGE_S * 1e9
    out[fresh] = values[latest[fresh]]
    return out
