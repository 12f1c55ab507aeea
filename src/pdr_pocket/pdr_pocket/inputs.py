"""The pocket navigator's inputs from a bag, for every offline tool.

- :func:`pocket_inputs`: ``imu/data`` cleaned (NaN/Inf, values beyond any IMU's range
  and stamps that do not increase dropped and counted, units and rate checked) and
  ``imu/mag`` paired with it (:mod:`pdr_core.sensors.magnetometer_pairing`: the latest reading at
  most ``MAG_MAX_AGE_S`` old, else none), calibrated when a calibration is given, and
  the other sensors of pdr_pocket.sensor_inputs the bag has (``imu/pressure``), each
  reading on the first sample at or after it (pdr_core.sensors.sample_pairing);
- :func:`read_pocket_bag`: a bag's batches (``imu/data``, ``imu/mag``, the other sensors'
  and the truth topics it has) and those inputs.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.io.batch import MessageBatch
from pdr_core.sensors.imu_checks import (
    check_mag_units,
    check_sample_interval,
    check_units,
    clean_samples,
)
from pdr_core.sensors.magnetometer_pairing import paired_mag
from pdr_core.sensors.sample_pairing import readings_at_samples
from pdr_pocket.magnetometer import MagCalibration
from pdr_pocket.samples import Samples
from pdr_pocket.sensor_inputs import SENSOR_INPUTS


@dataclass
class PocketInputs:
    """Clean, paired inputs: stamps [ns], t [s from the first], gyro, accel [SI], mag [T]
    (NaN rows: none), the kept indices of imu/data and the counts of what was dropped,
    and the other sensors' readings on the samples by name (pdr_pocket.sensor_inputs;
    NaN: none on that sample), the sensors the bag has."""

    stamp_ns: np.ndarray
    t: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    mag: np.ndarray
    accel_covariance: np.ndarray
    counts: dict[str, int] = field(default_factory=dict)
    has_gyro: bool = True       # False: angular_velocity_covariance[0] = −1 (REP-145)
    readings: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def gyro_or_none(self) -> np.ndarray | None:
        return self.gyro if self.has_gyro else None

    @property
    def samples(self) -> Samples:
        """The navigator's inputs by name: no gyroscope or no magnetometer reading at all
        is None."""
        mag = self.mag if np.isfinite(self.mag).any() else None
        return Samples(self.t, self.accel, self.gyro_or_none, mag, **self.readings)


def pocket_inputs(imu: MessageBatch, mag: MessageBatch | None,
                  calibration: MagCalibration | None = None,
                  sensors: dict[str, MessageBatch] | None = None) -> PocketInputs:
    """The filter's inputs from the topics (see the module docstring); ``sensors``: the
    batches of pdr_pocket.sensor_inputs' topics there are, by topic."""
    keep, counts = clean_samples(imu)
    if len(keep) < 2:
        raise InputError(topics.IMU_DATA, f"{len(keep)} usable samples are too few")
    stamp_ns = imu.stamp_ns[keep]
    gyro = imu["angular_velocity"][keep]
    accel = imu["linear_acceleration"][keep]
    has_gyro = not bool(np.all(imu["angular_velocity_covariance"][keep, 0] == -1))
    check_sample_interval((stamp_ns - stamp_ns[0]) * 1e-9, topics.IMU_DATA)
    check_units(accel, gyro, t_s=(stamp_ns - stamp_ns[0]) * 1e-9)
    mag_values, counts["mag_non_finite"] = paired_mag(stamp_ns, mag)
    if np.isfinite(mag_values).any():
        check_mag_units(mag_values[np.isfinite(mag_values).all(axis=1)], topics.IMU_MAG)
        if calibration is not None:
            mag_values = calibration.apply(mag_values)
    counts["mag_missing"] = int((~np.isfinite(mag_values).all(axis=1)).sum())
    return PocketInputs(stamp_ns, (stamp_ns - stamp_ns[0]) * 1e-9, gyro, accel, mag_values,
                        imu["linear_acceleration_covariance"][keep], counts, has_gyro,
                        paired_readings(stamp_ns, sensors or {}, counts))


def paired_readings(stamp_ns: np.ndarray, sensors: dict[str, MessageBatch],
                    counts: dict[str, int]) -> dict[str, np.ndarray]:
    """The readings of each sensor of pdr_pocket.sensor_inputs with a batch in ``sensors``
    (by topic) on the IMU's samples stamped ``stamp_ns`` [ns]: non-finite readings dropped
    and counted (``<name>_non_finite``), the rest each on the first sample at or after it
    (pdr_core.sensors.sample_pairing). What a reading means is its user's to check (the height
    filter drops and counts what is no air pressure)."""
    out = {}
    for sensor in SENSOR_INPUTS:
        batch = sensors.get(sensor.topic)
        if batch is None or not len(batch):
            continue
        values = np.asarray(batch[sensor.field], float)
        finite = np.isfinite(values)
        counts[f"{sensor.name}_non_finite"] = int((~finite).sum())
        order = np.argsort(batch.stamp_ns[finite], kind="stable")
        out[sensor.name] = readings_at_samples(stamp_ns, batch.stamp_ns[finite][order],
                                               values[finite][order])
    return out


SENSOR_TOPICS = (topics.IMU_DATA, topics.IMU_MAG, *(s.topic for s in SENSOR_INPUTS))
TRUTH_TOPICS = (topics.GROUND_TRUTH_POSE, topics.GROUND_TRUTH_STEP,
                topics.GROUND_TRUTH_LANDMARKS)


def read_pocket_bag(bag, calibration_file=None, require=(), *, strict=False):
    """A bag's reader, its batches (imu/data, imu/mag and the truth topics it has) and
    the filter's inputs; ``require``: topics it must have besides imu/data; ``strict``:
    refuse a bag cut short (pdr_core.io.bag)."""
    from pdr_core.io.bag import BagReader

    reader = BagReader(bag, strict=strict)
    reader.require_topics([topics.IMU_DATA, *require])
    wanted = [t for t in (*SENSOR_TOPICS, *TRUTH_TOPICS) if t in reader.topics]
    batches = reader.read_batches(wanted)
    calibration = MagCalibration.load(calibration_file) if calibration_file else None
    inputs = pocket_inputs(batches[topics.IMU_DATA], batches.get(topics.IMU_MAG), calibration,
                           batches)
    return reader, batches, inputs
