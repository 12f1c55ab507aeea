"""A sampled 3D trajectory of a body-mounted IMU: the simulator's ground truth.

Any placement (foot, thigh) is a *trajectory model* that produces a :class:`Trajectory`;
:mod:`pdr_sim.signals` turns any trajectory into sensor signals, so a new placement is a
new model, not a new simulator.

Frames and units: navigation frame ENU [m], body frame FLU, attitude C_b^n from Euler
angles (see :mod:`pdr_core.rotations`), time [s].
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
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

    @classmethod
    def concatenate(cls, parts: list[Trajectory]) -> Trajectory:
        """One trajectory from consecutive pieces (keeping attitudes already computed)."""
        out = cls(*(np.concatenate([getattr(p, f) for p in parts])
                    for f in ("t", "position", "velocity", "acceleration", "euler",
                              "euler_rate")))
        if all("attitude" in p.__dict__ for p in parts):
            out.__dict__["attitude"] = Rotation.concatenate([p.attitude for p in parts])
        return out

    @cached_property
    def attitude(self) -> Rotation:
        """C_b^n for every sample (computed once)."""
        return rotation_from_euler(*self.euler.T)

    @cached_property
    def matrix(self) -> np.ndarray:
        """C_b^n as (N, 3, 3) matrices."""
        return self.attitude.as_matrix()

    def to_body(self, v_n: np.ndarray) -> np.ndarray:
        """C_b^nᵀ·v for navigation-frame vectors (N, 3) or one vector (3,): (N, 3)."""
        v_n = np.broadcast_to(v_n, (len(self.t), 3))
        return np.einsum("nji,nj->ni", self.matrix, v_n)

    @property
    def body_rate(self) -> np.ndarray:
        """ω_nb^b [rad/s], (N, 3), from the analytic Euler-angle rates."""
        return body_rate_from_euler(*self.euler.T, *self.euler_rate.T)


class TrajectoryModel(Protocol):
    """Anything that gives a trajectory at any times within its duration."""

    @property
    def duration_s(self) -> float: ...

    def at(self, t: np.ndarray) -> Trajectory: ...
