"""Transforms over time, as a TF listener keeps them, and the ``map → odom`` transform of
REP-105 (plain NumPy and SciPy; pdr_core.ros.node_tf reads ``/tf`` into it).

- :class:`TransformHistory`: one frame's pose in another at a window of stamps, looked
  up at any stamp inside it (translation linear, rotation spherical-linear between the
  two neighbours, as tf2 interpolates; no extrapolation, as tf2 refuses it);
- :func:`map_to_odom`: T_map←odom = T_map←base · (T_odom←base)⁻¹, robot_localization's
  map instance's output.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

_NS = 1e-9


class TransformHistory:
    """The poses (position [m], quaternion x y z w) of a child frame in a parent frame at
    their stamps [ns], kept until a lookup has passed them: a pose is forgotten once a
    lookup was made at a later stamp than its successor's, so a source that runs ahead of
    the lookups (a bag played as fast as it goes) loses nothing; at most ``max_kept``
    are kept (the oldest go first)."""

    def __init__(self, max_kept: int) -> None:
        self.max_kept = max_kept
        self.stamp_ns = np.zeros(0, np.int64)
        self.position = np.zeros((0, 3))
        self.quaternion = np.zeros((0, 4))
        self._new: list[tuple[int, np.ndarray, np.ndarray]] = []

    def add(self, stamp_ns: int, position: np.ndarray, quaternion_xyzw: np.ndarray) -> None:
        """Keep one pose (merged at the next lookup; a later one of an equal stamp wins)."""
        self._new.append((int(stamp_ns), np.asarray(position, float),
                          np.asarray(quaternion_xyzw, float)))

    def _merge(self) -> None:
        if not self._new:
            return
        stamps = np.concatenate([self.stamp_ns, [s for s, _, _ in self._new]])
        position = np.vstack([self.position, [p for _, p, _ in self._new]])
        quaternion = np.vstack([self.quaternion, [q for _, _, q in self._new]])
        self._new = []
        # the last of each stamp: unique over the reversed order keeps the latest added
        _, last = np.unique(stamps[::-1], return_index=True)
        keep = (len(stamps) - 1 - last)[-self.max_kept:]
        self.stamp_ns, self.position, self.quaternion = (
            stamps[keep], position[keep], quaternion[keep])

    def newest_ns(self) -> int | None:
        """The latest stamp kept [ns] (None: none)."""
        self._merge()
        return int(self.stamp_ns[-1]) if len(self.stamp_ns) else None

    def at(self, stamp_ns: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The poses at ``stamp_ns`` (N,) [ns, ascending] inside the kept span: positions
        (K, 3), quaternions (K, 4) and which of the N stamps had one (N,) bool, K of
        them. The poses before the last stamp's neighbour are then forgotten."""
        self._merge()
        stamp_ns = np.asarray(stamp_ns, np.int64)
        if not len(self.stamp_ns):
            return np.zeros((0, 3)), np.zeros((0, 4)), np.zeros(len(stamp_ns), bool)
        found = (stamp_ns >= self.stamp_ns[0]) & (stamp_ns <= self.stamp_ns[-1])
        wanted = stamp_ns[found]
        if len(self.stamp_ns) == 1:
            position = np.repeat(self.position, len(wanted), axis=0)
            quaternion = np.repeat(self.quaternion, len(wanted), axis=0)
        else:
            t = (self.stamp_ns - self.stamp_ns[0]) * _NS
            query = (wanted - self.stamp_ns[0]) * _NS
            position = np.stack([np.interp(query, t, self.position[:, k]) for k in range(3)],
                                axis=1)
            quaternion = Slerp(t, Rotation.from_quat(self.quaternion))(query).as_quat()
        if len(stamp_ns):
            self._forget_before(int(stamp_ns[-1]))
        return position, quaternion.reshape(-1, 4), found

    def _forget_before(self, stamp_ns: int) -> None:
        """Forget the poses no lookup at ``stamp_ns`` or later needs."""
        first = max(int(np.searchsorted(self.stamp_ns, stamp_ns, side="right")) - 1, 0)
        self.stamp_ns, self.position, self.quaternion = (
            self.stamp_ns[first:], self.position[first:], self.quaternion[first:])


def map_to_odom(map_position: np.ndarray, map_quaternion: np.ndarray,
                odom_position: np.ndarray, odom_quaternion: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:
    """``odom``'s pose in ``map`` (N, 3) [m], (N, 4) x y z w, from ``base``'s pose in
    ``map`` and in ``odom`` at the same stamps: R_mo = R_mb·R_obᵀ, p_mo = p_mb − R_mo·p_ob."""
    if not len(map_position):
        return np.zeros((0, 3)), np.zeros((0, 4))
    r_mo = Rotation.from_quat(map_quaternion) * Rotation.from_quat(odom_quaternion).inv()
    return map_position - r_mo.apply(odom_position), r_mo.as_quat().reshape(-1, 4)
