"""MessageBatch: the messages of one topic as NumPy arrays.

A batch holds N messages of one ROS type. Field arrays are keyed by their ROS field path
(``linear_acceleration``, ``pose.position``, ``orientation_covariance``). Messages whose
fields are all ``float64`` (Vector3, Point, Quaternion) become one ``(N, k)`` array in
their field order (x, y, z[, w]); fixed arrays such as covariances become ``(N, 9)``.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np


@dataclass
class MessageBatch:
    """N messages of type ``msgtype``.

    Attributes:
        msgtype: ROS type name, e.g. ``sensor_msgs/msg/Imu``.
        stamp_ns: (N,) int64, ``header.stamp`` in ns (from the data, never the wall clock).
        frame_id: (N,) str, ``header.frame_id``.
        fields: field path -> (N,) or (N, k) array, SI units as the message defines them.
    """

    msgtype: str
    stamp_ns: np.ndarray
    frame_id: np.ndarray
    fields: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.stamp_ns = np.asarray(self.stamp_ns, dtype=np.int64)
        n = len(self.stamp_ns)
        self.frame_id = np.broadcast_to(np.asarray(self.frame_id, dtype=str), (n,)).copy()
        for name, values in self.fields.items():
            if len(values) != n:
                raise ValueError(f"field {name!r} has {len(values)} rows, expected {n}")

    def __len__(self) -> int:
        return len(self.stamp_ns)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.fields[name]

    @property
    def t_s(self) -> np.ndarray:
        """(N,) float64 stamps in seconds."""
        return self.stamp_ns * 1e-9

    def take(self, index: np.ndarray | slice) -> MessageBatch:
        """The messages selected by ``index`` (a slice, mask or integer array)."""
        return MessageBatch(self.msgtype, self.stamp_ns[index], self.frame_id[index],
                            {k: v[index] for k, v in self.fields.items()})

    @classmethod
    def concatenate(cls, batches: list[MessageBatch]) -> MessageBatch:
        """One batch holding the messages of ``batches`` in order (all of one type)."""
        first = batches[0]
        return cls(first.msgtype,
                   np.concatenate([b.stamp_ns for b in batches]),
                   np.concatenate([b.frame_id for b in batches]),
                   {k: np.concatenate([b.fields[k] for b in batches]) for k in first.fields})


@dataclass
class LazyBatch:
    """N messages of type ``msgtype`` whose fields are built slice by slice, for writers
    that encode a block at a time (:meth:`pdr_core.io.bag.BagWriter.write_merged`): large
    outputs such as full-rate 6x6 covariances then never exist for the whole record.

    Attributes:
        msgtype, stamp_ns, frame_id: as in :class:`MessageBatch`.
        build: slice of the N messages -> their fields, as :attr:`MessageBatch.fields`.
    """

    msgtype: str
    stamp_ns: np.ndarray
    frame_id: np.ndarray
    build: Callable[[slice], dict[str, np.ndarray]]

    def __post_init__(self) -> None:
        self.stamp_ns = np.asarray(self.stamp_ns, dtype=np.int64)
        self.frame_id = np.broadcast_to(np.asarray(self.frame_id, dtype=str),
                                        self.stamp_ns.shape)

    def __len__(self) -> int:
        return len(self.stamp_ns)

    def take(self, index: slice) -> MessageBatch:
        """The messages of the slice ``index``, built."""
        return MessageBatch(self.msgtype, self.stamp_ns[index], self.frame_id[index],
                            self.build(index))


def stamp_ns_from_seconds(t_s: np.ndarray) -> np.ndarray:
    """(N,) int64 ns from float seconds, rounded to the nearest ns."""
    return np.rint(np.asarray(t_s, dtype=np.float64) * 1e9).astype(np.int64)
