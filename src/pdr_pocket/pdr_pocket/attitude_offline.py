"""The orientation filter on a whole bag: inputs, outputs and the report of
``pdr-pocket attitude``.

- :func:`pocket_inputs`: ``imu/data`` cleaned (NaN/Inf, values beyond any IMU's range
  and stamps that do not increase dropped and counted, units and rate checked) and ``imu/mag``
  paired with it (pdr_core.magnetometer_pairing: the latest reading at most
  :data:`MAG_MAX_AGE_S` old, else none), calibrated when a calibration is given;
- :func:`read_pocket_bag`: a bag's batches and those inputs, for every offline tool;
- :func:`attitude_batches`: ``pdr/pocket/attitude`` (sensor_msgs/Imu with orientation and
  its covariance, REP-145) and ``pdr/pocket/gyro_bias`` (geometry_msgs/Vector3Stamped);
- :func:`attitude_report`: roll, pitch and yaw RMSE against ``ground_truth/pose``, the
  final gyro bias errors against the simulation's true biases, and the share of samples
  each update ran.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core import topics
from pdr_core.batch import MessageBatch
from pdr_core.errors import InputError
from pdr_core.frames import SENSOR_FRAME
from pdr_core.imu_checks import (
    check_mag_units,
    check_sample_interval,
    check_units,
    clean_samples,
)
from pdr_core.magnetometer_pairing import MAG_MAX_AGE_S as MAG_MAX_AGE_S
from pdr_core.magnetometer_pairing import latest_readings as latest_readings
from pdr_core.magnetometer_pairing import paired_mag
from pdr_core.msgtypes import IMU, VECTOR3_STAMPED
from pdr_core.rotations import quaternion_from_orthonormal
from pdr_pocket.magnetometer import MagCalibration
from pdr_pocket.orientation import AttitudeEstimate

ATTITUDE_TOPIC = "/pdr/pocket/attitude"
GYRO_BIAS_TOPIC = "/pdr/pocket/gyro_bias"


@dataclass
class PocketInputs:
    """Clean, paired inputs: stamps [ns], t [s from the first], gyro, accel [SI], mag [T]
    (NaN rows: none), the kept indices of imu/data and the counts of what was dropped."""

    stamp_ns: np.ndarray
    t: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    mag: np.ndarray
    accel_covariance: np.ndarray
    counts: dict[str, int] = field(default_factory=dict)
    has_gyro: bool = True       # False: angular_velocity_covariance[0] = −1 (REP-145)

    @property
    def gyro_or_none(self) -> np.ndarray | None:
        return self.gyro if self.has_gyro else None


def pocket_inputs(imu: MessageBatch, mag: MessageBatch | None,
                  calibration: MagCalibration | None = None) -> PocketInputs:
    """The filter's inputs from the two topics (see the module docstring)."""
    keep, counts = clean_samples(imu)
    if len(keep) < 2:
        raise InputError(topics.IMU_DATA, f"{len(keep)} usable samples are too few")
    stamp_ns = imu.stamp_ns[keep]
    gyro = imu["angular_velocity"][keep]
    accel = imu["linear_acceleration"][keep]
    has_gyro = not bool(np.all(imu["angular_velocity_covariance"][keep, 0] == -1))
    check_sample_interval((stamp_ns - stamp_ns[0]) * 1e-9, topics.IMU_DATA)
    check_units(accel, gyro)
    mag_values, counts["mag_non_finite"] = paired_mag(stamp_ns, mag)
    if np.isfinite(mag_values).any():
        check_mag_units(mag_values[np.isfinite(mag_values).all(axis=1)], topics.IMU_MAG)
        if calibration is not None:
            mag_values = calibration.apply(mag_values)
    counts["mag_missing"] = int((~np.isfinite(mag_values).all(axis=1)).sum())
    return PocketInputs(stamp_ns, (stamp_ns - stamp_ns[0]) * 1e-9, gyro, accel, mag_values,
                        imu["linear_acceleration_covariance"][keep], counts, has_gyro)


TRUTH_TOPICS = (topics.GROUND_TRUTH_POSE, topics.GROUND_TRUTH_STEP,
                topics.GROUND_TRUTH_LANDMARKS)


def read_pocket_bag(bag, calibration_file=None, require=(), *, strict=False):
    """A bag's reader, its batches (imu/data, imu/mag and the truth topics it has) and
    the filter's inputs; ``require``: topics it must have besides imu/data; ``strict``:
    refuse a bag cut short (pdr_core.bag)."""
    from pdr_core.bag import BagReader

    reader = BagReader(bag, strict=strict)
    reader.require_topics([topics.IMU_DATA, *require])
    wanted = [t for t in (topics.IMU_DATA, topics.IMU_MAG, *TRUTH_TOPICS)
              if t in reader.topics]
    batches = reader.read_batches(wanted)
    calibration = MagCalibration.load(calibration_file) if calibration_file else None
    inputs = pocket_inputs(batches[topics.IMU_DATA], batches.get(topics.IMU_MAG), calibration)
    return reader, batches, inputs


def attitude_batches(inputs: PocketInputs, estimate: AttitudeEstimate,
                     gyro_noise_var: float, frame: str = SENSOR_FRAME
                     ) -> dict[str, MessageBatch]:
    """``pdr/pocket/attitude`` and ``pdr/pocket/gyro_bias`` at every sample, stamped in the
    sensor's ``frame``."""
    n = len(inputs.t)
    cov = estimate.covariance
    rate_cov = cov[:, 3:, 3:] + np.eye(3) * gyro_noise_var
    attitude = MessageBatch(IMU, inputs.stamp_ns, frame, {
        "orientation": quaternion_from_orthonormal(estimate.attitude),
        "orientation_covariance": cov[:, :3, :3].reshape(n, 9),
        "angular_velocity": inputs.gyro - estimate.bias,
        "angular_velocity_covariance": rate_cov.reshape(n, 9),
        "linear_acceleration": inputs.accel,
        "linear_acceleration_covariance": inputs.accel_covariance})
    bias = MessageBatch(VECTOR3_STAMPED, inputs.stamp_ns, frame,
                        {"vector": estimate.bias})
    return {ATTITUDE_TOPIC: attitude, GYRO_BIAS_TOPIC: bias}


def attitude_errors(estimate: AttitudeEstimate, truth_quat: np.ndarray) -> np.ndarray:
    """Roll, pitch, yaw of the estimate minus the truth's [rad], wrapped, (N, 3)."""
    from scipy.spatial.transform import Rotation

    truth = Rotation.from_quat(truth_quat).as_euler("ZYX")[:, ::-1]
    return np.angle(np.exp(1j * (estimate.euler - truth)))


def attitude_report(inputs: PocketInputs, estimate: AttitudeEstimate,
                    truth_quat: np.ndarray | None,
                    true_bias_radps: np.ndarray | None) -> dict:
    """The report of ``pdr-pocket attitude`` (angles in degrees, biases in °/s)."""
    report: dict = {"samples": len(inputs.t), "duration_s": float(inputs.t[-1]),
                    "dropped": inputs.counts,
                    "update_fraction": estimate.fraction_ran(),
                    "saturated_fraction": float(estimate.detected[:, 3].mean()),
                    "final_bias_deg_per_s": np.degrees(estimate.bias[-1]).tolist(),
                    "final_bias_sigma_deg_per_s": np.degrees(estimate.bias_sigma[-1]).tolist()}
    if truth_quat is not None:
        err = np.degrees(attitude_errors(estimate, truth_quat))
        report["rmse_deg"] = dict(zip(("roll", "pitch", "yaw"),
                                      np.sqrt(np.mean(err**2, axis=0)).tolist(), strict=True))
        report["final_error_deg"] = dict(zip(("roll", "pitch", "yaw"), err[-1].tolist(),
                                             strict=True))
    if true_bias_radps is not None:
        report["final_bias_error_deg_per_s"] = np.degrees(
            estimate.bias[-1] - np.asarray(true_bias_radps)).tolist()
    return report
