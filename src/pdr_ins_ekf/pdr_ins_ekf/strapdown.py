"""Strapdown mechanization (pure INS): attitude, velocity and position from IMU samples.

Attitude: C_n = C_{n−1}·exp(Ω·T_s) by one of :data:`~pdr_ins_ekf.attitude_update.METHODS`
(Zampella et al. 2011, Eqs. (9), (11), (12); Simón Colomar et al. 2012, Eqs. (1)–(2)).
Velocity and position in ENU, with g = [0, 0, g] and local gravity g a parameter:

- ``integration="rectangular"``: Simón Colomar et al. 2012, Eqs. (3)–(5) as written:
  Ω from ω_n, a_n = C_n·f_n − g, p_n = p_{n−1} + v_{n−1}·T_s + a_n·T_s²/2,
  v_n = v_{n−1} + a_n·T_s. Each sample is held over the interval before it, so with
  instantaneous samples the error is first order in T_s: the attitude lags by ω·T_s/2
  inside every swing and misprojects gravity.
- ``integration="trapezoidal"`` (default): Ω from (ω_{n−1} + ω_n)/2,
  v_n = v_{n−1} + (a_{n−1} + a_n)·T_s/2, p_n = p_{n−1} + (v_{n−1} + v_n)·T_s/2, second order.

Frames and units: navigation ENU [m, m/s], body FLU; gyro [rad/s] and specific force
[m/s²] are (N, 3); C_b^n (N, 3, 3). The first sample sets the initial state; sample n
(n ≥ 1) propagates it over T_s.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_ins_ekf.attitude_update import METHODS, increments


@dataclass(frozen=True)
class NavigationSolution:
    """Pure-INS solution over N samples: attitude C_b^n (N, 3, 3), velocity and position
    (N, 3) ENU."""

    attitude: np.ndarray
    velocity: np.ndarray
    position: np.ndarray


INTEGRATIONS = ("trapezoidal", "rectangular")


def interval_rates(gyro: np.ndarray, integration: str) -> np.ndarray:
    """The rate held over each interval n−1 → n, (N−1, 3)."""
    if integration == "rectangular":
        return gyro[1:]
    if integration == "trapezoidal":
        return (gyro[:-1] + gyro[1:]) / 2
    raise ValueError(f"unknown integration '{integration}' (known: {', '.join(INTEGRATIONS)})")


def propagate_attitude(initial: np.ndarray, gyro: np.ndarray, dt: float, method: str,
                       integration: str = "trapezoidal") -> np.ndarray:
    """C_b^n at every sample, (N, 3, 3), from C_0 = ``initial`` and the gyro samples."""
    if method not in METHODS:
        raise ValueError(f"unknown attitude method '{method}' (known: {', '.join(METHODS)})")
    n = len(gyro)
    steps = increments(method, interval_rates(gyro, integration), dt)
    if method == "quaternion":
        q = np.empty((n, 4))
        q[0] = Rotation.from_matrix(initial).as_quat()
        for k in range(1, n):
            q[k] = steps[k - 1] @ q[k - 1]
        return Rotation.from_quat(q).as_matrix()
    out = np.empty((n, 3, 3))
    out[0] = initial
    for k in range(1, n):
        out[k] = out[k - 1] @ steps[k - 1]
    return out


def mechanize(gyro: np.ndarray, accel: np.ndarray, rate_hz: float, initial_attitude: np.ndarray,
              initial_velocity=(0.0, 0.0, 0.0), initial_position=(0.0, 0.0, 0.0),
              method: str = "closed_form", integration: str = "trapezoidal",
              gravity_mps2: float = STANDARD_GRAVITY_MPS2) -> NavigationSolution:
    """Pure INS over all samples (see the module docstring)."""
    dt = 1.0 / rate_hz
    attitude = propagate_attitude(np.asarray(initial_attitude, float), gyro, dt, method,
                                  integration)
    acc_n = np.einsum("nij,nj->ni", attitude, accel) - np.array([0.0, 0.0, gravity_mps2])
    v0, p0 = np.asarray(initial_velocity, float), np.asarray(initial_position, float)
    rectangular = integration == "rectangular"
    dv = acc_n[1:] * dt if rectangular else (acc_n[:-1] + acc_n[1:]) / 2 * dt
    velocity = v0 + np.vstack([np.zeros(3), np.cumsum(dv, axis=0)])
    dp = (velocity[:-1] * dt + acc_n[1:] * dt**2 / 2 if rectangular
          else (velocity[:-1] + velocity[1:]) / 2 * dt)
    position = p0 + np.vstack([np.zeros(3), np.cumsum(dp, axis=0)])
    return NavigationSolution(attitude, velocity, position)
