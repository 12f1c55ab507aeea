"""A sampled 3D trajectory of a body-mounted IMU: the simulator's ground truth.

Any placement (foot, thigh) is a *trajectory model* that produces a :class:`Trajectory`;
:mod:`pdr_sim.signals` turns any trajectory into sensor signals, so a new placement is a
new model, not a new simulator.

Frames and units: navigation frame ENU [m], body frame FLU, attitude C_b^n from Euler
angles (see :mod:`pdr_core.rotations`), time [s].
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core.rotations import body_rate_from_euler, rotation_from_euler


@dataclass(frozen=True)
class Trajectory:
    """Arrays over N samples.

    t: (N,) [s]; position, velocity, acceleration: (N, 3) ENU [m, m/s, m/s²];
    euler: (N, 3) roll, pitch, yaw [rad] (yaw unwrapped); euler_rate: (N, 3) [rad/s].
    """

    t: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    euler: np.ndarray
    euler_rate: np.ndarray

    @property
    def attitude(self) -> Rotation:
        """C_b^n for every sample."""
        return rotation_from_euler(*self.euler.T)

    @property
    def body_rate(self) -> np.ndarray:
        """ω_nb^b [rad/s], (N, 3), from the analytic Euler-angle rates."""
        return body_rate_from_euler(*self.euler.T, *self.euler_rate.T)


class TrajectoryModel(Protocol):
    """Anything that samples a trajectory at a given rate."""

    def sample(self, rate_hz: float) -> Trajectory: ...
