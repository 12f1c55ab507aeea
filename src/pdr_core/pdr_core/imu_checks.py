"""Checks every navigator runs on IMU data before using it.

- :func:`clean_samples`, :func:`usable_samples`: drop (and count) samples with NaN/Inf,
  beyond any IMU's range, or stamps that do not increase.
- :func:`check_units`: refuse an accelerometer in g or a gyroscope in deg/s.
- :func:`check_mag_units`: refuse a magnetometer in µT or gauss (ROS wants tesla).
- :func:`plausible`: samples within any IMU's reach (a garbage reading of 1e150 rad/s is
  finite but no measurement).
"""
from __future__ import annotations

import numpy as np

from pdr_core.batch import MessageBatch
from pdr_core.errors import InputError

# |B| of the Earth's field is 25-65 µT; a disturbed indoor field rarely exceeds 1 mT
MAX_FIELD_T = 1e-3
# Beyond any MEMS or tactical IMU's range (±400 g, ±20,000 °/s): not a measurement
MAX_PLAUSIBLE_ACCEL_MPS2 = 4000.0
MAX_PLAUSIBLE_RATE_RADPS = 350.0


def plausible(accel: np.ndarray, gyro: np.ndarray) -> np.ndarray:
    """Per sample (or for one sample): finite and within :data:`MAX_PLAUSIBLE_ACCEL_MPS2`
    and :data:`MAX_PLAUSIBLE_RATE_RADPS` on every axis."""
    accel, gyro = np.asarray(accel, float), np.asarray(gyro, float)
    with np.errstate(invalid="ignore"):
        return ((np.abs(accel) <= MAX_PLAUSIBLE_ACCEL_MPS2).all(axis=-1)
                & (np.abs(gyro) <= MAX_PLAUSIBLE_RATE_RADPS).all(axis=-1))


def clean_samples(imu: MessageBatch) -> tuple[np.ndarray, dict[str, int]]:
    """Indices of the usable samples of a record and the counts of the dropped ones
    (:func:`usable_samples`)."""
    keep, counts = usable_samples(imu.stamp_ns, imu["linear_acceleration"],
                                  imu["angular_velocity"])
    return np.flatnonzero(keep), counts


def usable_samples(stamp_ns: np.ndarray, accel: np.ndarray, gyro: np.ndarray,
                   after_ns: int | None = None) -> tuple[np.ndarray, dict[str, int]]:
    """Mask of the usable samples (N,) and the counts of the dropped ones: NaN/Inf, beyond
    any IMU's range (:func:`plausible`), then stamps [ns] not later than every usable one
    before (and than ``after_ns``, the last kept before these), in that order, as the
    live nodes drop them one sample at a time."""
    finite = np.isfinite(accel).all(axis=1) & np.isfinite(gyro).all(axis=1)
    sane = finite & plausible(accel, gyro)
    stamps = np.where(sane, np.asarray(stamp_ns, np.int64), np.iinfo(np.int64).min)
    before = np.maximum.accumulate(stamps)[:-1]
    if after_ns is None:
        later = np.concatenate(([True], stamps[1:] > before))
    else:
        later = stamps > np.maximum(np.concatenate(([after_ns], before)), after_ns)
    keep = sane & later
    return keep, {"non_finite": int((~finite).sum()),
                  "implausible": int((finite & ~sane).sum()),
                  "stamp_not_increasing": int((sane & ~later).sum())}


def check_units(accel: np.ndarray, gyro: np.ndarray) -> None:
    """Refuse data in the wrong units. The median |f| of any walk or rest is near g; a
    foot turns at up to about 35 rad/s (2000 °/s): a median |f| near 1 gives away data
    in g, a 99th percentile of |ω| above 50 data in deg/s."""
    f = float(np.median(np.linalg.norm(accel, axis=1)))
    if 0.5 < f < 2.0:
        raise InputError("imu/data", f"median specific force is {f:.3f}: the accelerometer "
                                     "looks like it is in g, not m/s²")
    w = float(np.percentile(np.linalg.norm(gyro, axis=1), 99))
    if w > 50.0:
        raise InputError("imu/data", f"99th percentile of the angular rate is {w:.1f}: the "
                                     "gyroscope looks like it is in deg/s, not rad/s")


def check_mag_units(mag: np.ndarray, topic: str = "imu/mag") -> None:
    """Refuse magnetometer data that is not in tesla: a median |B| above 1 mT is µT
    (25-65 for the Earth's field) or gauss (0.25-0.65) data."""
    b = float(np.median(np.linalg.norm(mag, axis=1)))
    if b > MAX_FIELD_T:
        unit = "µT" if b > 1.0 else "gauss"
        raise InputError(topic, f"median field is {b:.4g}: the magnetometer looks like it "
                                f"is in {unit}, not tesla")
