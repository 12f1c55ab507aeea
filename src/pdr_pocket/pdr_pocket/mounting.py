"""The thigh's frame in the sensor's, estimated from the data (the phone's mounting in the
pocket is unknown).

- :func:`up_axis`: the thigh's long axis, pointing up, from the specific force at rest
  (standing: the thigh is vertical, Muñoz Díaz 2016, Section 4.1.3);
- :func:`flexion_axis`: the dominant rotation axis while walking (the leg swings about
  it), signed so that the thigh pitch it gives has the thesis' asymmetry (θ_max, the
  forward swing, well beyond |θ_min|, Fig. 4.1);
- :func:`thigh_pitch`: the opening angle θ of the leg from the filter's attitude: the
  angle of the long axis from the vertical, positive with the knee ahead.

These work on a whole record (a reference for the tests on real recordings); the
navigator learns the same axes causally, sample by sample (pdr_pocket.compiled_gait).

All axes are unit vectors in the sensor frame; angles in rad.
"""
from __future__ import annotations

import numpy as np


def up_axis(accel_at_rest: np.ndarray) -> np.ndarray:
    """Unit vector (3,) of the mean specific force of samples at rest (N, 3)."""
    mean = np.asarray(accel_at_rest, float).mean(axis=0)
    return mean / np.linalg.norm(mean)


def flexion_axis(gyro: np.ndarray, up: np.ndarray) -> np.ndarray:
    """The principal axis of the turn rate (N, 3) [rad/s], made orthogonal to ``up``
    (sign not yet chosen; see :func:`signed_flexion_axis`)."""
    w = np.asarray(gyro, float)
    _, vectors = np.linalg.eigh(w.T @ w)
    axis = vectors[:, -1] - (vectors[:, -1] @ up) * up
    return axis / np.linalg.norm(axis)


def thigh_pitch(attitude: np.ndarray, up: np.ndarray, flexion: np.ndarray) -> np.ndarray:
    """θ [rad], (N,), for attitudes C_b^n (N, 3, 3): the tilt of the long axis ``up``
    (sensor frame) from the vertical in the plane the leg swings in, positive with the
    knee ahead of the hip along the horizontal direction of ``flexion`` × ``up`` (the
    bulk twin of pdr_pocket.compiled_gait.thigh_angles)."""
    long_n = attitude @ up                      # (N, 3) the thigh's long axis, ENU
    forward_n = attitude @ np.cross(flexion, up)
    horizontal = forward_n[:, :2] / np.linalg.norm(forward_n[:, :2], axis=1, keepdims=True)
    return np.arctan2(-np.einsum("ni,ni->n", long_n[:, :2], horizontal), long_n[:, 2])


def signed_flexion_axis(attitude: np.ndarray, up: np.ndarray, flexion: np.ndarray) -> np.ndarray:
    """``flexion`` or its opposite, whichever makes the forward swing the larger extreme
    (95th percentile of θ beyond the magnitude of the 5th)."""
    pitch = thigh_pitch(attitude, up, flexion)
    high, low = np.percentile(pitch, [95, 5])
    return flexion if high >= -low else -flexion
