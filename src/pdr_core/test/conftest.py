"""Fixtures shared by the pdr_core tests."""
import numpy as np
import pytest

from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import IMU, POSE_STAMPED


def imu_batch(n: int, rate_hz: float = 200.0, seed: int = 0) -> MessageBatch:
    """n Imu messages with random rates and specific force, stamped at rate_hz from t=1 s."""
    rng = np.random.default_rng(seed)
    stamps = 1_000_000_000 + np.round(np.arange(n) * 1e9 / rate_hz).astype(np.int64)
    cov = np.zeros((n, 9))
    cov[:, 0] = -1.0
    return MessageBatch(IMU, stamps, "imu_link", {
        "orientation": np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)),
        "orientation_covariance": cov,
        "angular_velocity": rng.normal(size=(n, 3)),
        "angular_velocity_covariance": np.zeros((n, 9)),
        "linear_acceleration": rng.normal(size=(n, 3)) + np.array([0.0, 0.0, 9.81]),
        "linear_acceleration_covariance": np.zeros((n, 9)),
    })


def pose_batch(n: int, rate_hz: float = 200.0, seed: int = 1) -> MessageBatch:
    rng = np.random.default_rng(seed)
    stamps = 1_000_000_000 + np.round(np.arange(n) * 1e9 / rate_hz).astype(np.int64)
    quat = rng.normal(size=(n, 4))
    return MessageBatch(POSE_STAMPED, stamps, "map", {
        "pose.position": rng.normal(size=(n, 3)),
        "pose.orientation": quat / np.linalg.norm(quat, axis=1, keepdims=True)})


@pytest.fixture
def make_imu():
    return imu_batch


@pytest.fixture
def make_pose():
    return pose_batch


@pytest.fixture
def imu():
    return imu_batch(500)


@pytest.fixture
def pose():
    return pose_batch(500)
