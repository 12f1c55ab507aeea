"""A sampled 3D trajectory of a body-mounted IMU: the simulator's ground truth.

Any placement (foot, thigh) is a *trajectory model* that produces a :class:`Trajectory`;
:mod:`pdr_sim.signals` turns any trajectory into sensor signals, so a new placement is a
new model, not a new simulator.

Frames and units: navigation frame ENU [m], body frame FLU, attitude C_b^n from Euler
angles (see :mod:`pdr_core.maths.rotations`), time [s].
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Protocol

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core.maths.rotations import body_rate_from_euler, rotation_from_euler


@dataclass(frozen=True)
class Trajectory:
    """Arrays over N samples.

    t: (N,) [s]; position, velocity, acceleration: (N, 3) ENU [m, m/s, m/s²];
    attitude: C_b^n of every sample; body_rate: ω_nb^b (N, 3) [rad/s], exact (from the
    model's analytic derivatives); ``euler``: (N, 3) roll, pitch, yaw of C_b^n [rad] (yaw
    unwrapped), for plots and tests: the model's own angles when it is built from Euler
    angles (``euler_known``), else computed from the attitude when first asked for.
    """

    t: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    attitude: Rotation
    body_rate: np.ndarray
    euler_known: np.ndarray | None = None

    @cached_property
    def euler(self) -> np.ndarray:
        if self.euler_known is not None:
            return self.euler_known
        euler = self.attitude.as_euler("ZYX")[:, ::-1].copy()
        euler[:, 2] = np.unwrap(euler[:, 2])
        return euler

    @classmethod
    def from_euler(cls, t: np.ndarray, position: np.ndarray, velocity: np.ndarray,
                   acceleration: np.ndarray, euler: np.ndarray,
                   euler_rate: np.ndarray) -> Trajectory:
        """A trajectory whose attitude is given as Euler angles and their rates [rad, rad/s]
        (:mod:`pdr_core.maths.rotations` conventions)."""
        return cls(t, position, velocity, acceleration, rotation_from_euler(*euler.T),
                   body_rate_from_euler(*euler.T, *euler_rate.T), euler)

    @classmethod
    def concatenate(cls, parts: list[Trajectory]) -> Trajectory:
        """One trajectory from consecutive pieces."""
        arrays = {f: np.concatenate([getattr(p, f) for p in parts])
                  for f in ("t", "position", "velocity", "acceleration", "body_rate")}
        known = [p.euler_known for p in parts]
        euler = None if any(e is None for e in known) else np.concatenate(known)
        return cls(attitude=Rotation.concatenate([p.attitude for p in parts]),
                   euler_known=euler, **arrays)

    @cached_property
    def matrix(self) -> np.ndarray:
        """C_b^n as (N, 3, 3) matrices."""
        return self.attitude.as_matrix()

    def to_body(self, v_n: np.ndarray) -> np.ndarray:
        """C_b^nᵀ·v for navigation-frame vectors (N, 3) or one vector (3,): (N, 3)."""
        v_n = np.broadcast_to(v_n, (len(self.t), 3))
        return np.einsum("nji,nj->ni", self.matrix, v_n)


class TrajectoryModel(Protocol):
    """Anything that gives a trajectory at any times within its duration."""

    @property
    def duration_s(self) -> float: ...

    def at(self, t: np.ndarray) -> Trajectory: ...
