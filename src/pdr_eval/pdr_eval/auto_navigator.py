"""``--navigator auto``: the navigator of a bag, told from its ``imu/data``
(pdr_core.walking.navigator_choice: a foot's still stances, a pocket's tilt swing)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.io.bag import BagReader
from pdr_core.sensors.imu_checks import clean_samples
from pdr_core.walking.navigator_choice import NavigatorChoice, choose_navigator


def bag_navigator(bag: Path) -> NavigatorChoice:
    """The :class:`~pdr_core.walking.navigator_choice.NavigatorChoice` of ``bag``'s usable
    ``imu/data`` samples (no gyroscope: REP-145's angular velocity covariance −1)."""
    imu = BagReader(bag).read_batches([topics.IMU_DATA])[topics.IMU_DATA]
    keep, _ = clean_samples(imu)
    if len(keep) < 2:
        raise InputError(bag, f"{len(keep)} usable {topics.IMU_DATA} samples: nothing to "
                              "choose a navigator from")
    has_gyro = not bool(np.all(imu["angular_velocity_covariance"][keep, 0] == -1))
    return choose_navigator((imu.stamp_ns[keep] - imu.stamp_ns[keep[0]]) * 1e-9,
                            imu["linear_acceleration"][keep],
                            imu["angular_velocity"][keep] if has_gyro else None)


def refusal(choice: NavigatorChoice) -> str:
    """What ``auto`` says when it cannot choose."""
    return (f"--navigator auto: {choice.why} ({choice.figures()}): pass --navigator foot "
            "(a foot-mounted IMU) or --navigator pocket (a phone in a trouser pocket)")
