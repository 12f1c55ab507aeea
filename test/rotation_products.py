"""Chained rotations for the tests that integrate a gyroscope against a truth
(src/pdr_sim/test/test_pocket_model.py, test_foot_gaits.py): the prefix products of a
sequence of rotations, vectorised over the sequence in NumPy."""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation


def hamilton(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """p ⊗ q of quaternions (N, 4), scalar last as scipy's: the rotation q, then p."""
    px, py, pz, pw = p.T
    qx, qy, qz, qw = q.T
    return np.stack([pw * qx + px * qw + py * qz - pz * qy,
                     pw * qy - px * qz + py * qw + pz * qx,
                     pw * qz + px * qy - py * qx + pz * qw,
                     pw * qw - px * qx - py * qy - pz * qz], axis=1)


def prefix_products(steps: Rotation) -> Rotation:
    """R₁, R₁R₂, R₁R₂R₃, ... by doubling (log₂ N vectorised products)."""
    q = steps.as_quat()
    k = 1
    while k < len(q):
        q = np.concatenate([q[:k], hamilton(q[:-k], q[k:])])
        k *= 2
    return Rotation.from_quat(q)
