"""Pushes to the streaming pocket navigator held for a block (pdr_pocket.streaming,
``block_s``): live at the IMU's rate a message comes at a time, and a call of the navigator
costs far more than a sample in it, so the IMU's samples wait until ``block_s`` of them
have come, with the other topics' readings that came meanwhile, and are then taken as one
block: each other topic's readings first, in their order of arrival, then the IMU's.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

MAX_WAITING = 1000
"""At most this many IMU samples wait, whatever their stamps say (a stamp far in the past
would otherwise hold every sample after it)."""
MAG = "magnetometer"
"""The name the magnetometer's readings are held under (the other sensors go by their
pdr_pocket.sensor_inputs names)."""


@dataclass
class Arrivals:
    """The pushes held: the IMU's parts (stamps [ns], accel [m/s²], gyro [rad/s] or None),
    and each other topic's readings (stamps [ns], values) by name."""

    imu: list[tuple[np.ndarray, np.ndarray, np.ndarray | None]] = field(default_factory=list)
    readings: dict[str, list[tuple[np.ndarray, np.ndarray]]] = field(default_factory=dict)
    samples: int = 0
    first_ns: int = 0
    newest_ns: int = 0

    def add_imus(self, stamps: np.ndarray, accel: np.ndarray, gyro: np.ndarray | None) -> None:
        if not len(stamps):
            return
        if not self.samples:
            self.first_ns = self.newest_ns = int(stamps[0])
        self.imu.append((stamps, accel, gyro))
        self.samples += len(stamps)
        self.newest_ns = max(self.newest_ns, int(stamps.max()))

    def add_readings(self, name: str, stamps: np.ndarray, values: np.ndarray) -> None:
        self.readings.setdefault(name, []).append((stamps, values))

    def due(self, block_s: float) -> bool:
        """``block_s`` [s] of IMU data, or :data:`MAX_WAITING` samples, have come."""
        return (self.newest_ns - self.first_ns >= block_s * 1e9
                or self.samples >= MAX_WAITING)

    def readings_blocks(self) -> list[tuple[str, np.ndarray, np.ndarray]]:
        """Each topic's readings as one block: (name, stamps, values)."""
        return [(name, np.concatenate([s for s, _ in parts]),
                 np.concatenate([v for _, v in parts])) for name, parts in self.readings.items()]

    def imu_blocks(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray | None]]:
        """The IMU's parts joined into blocks, one for each run of parts with a gyroscope,
        or without one."""
        blocks: list[tuple[np.ndarray, np.ndarray, np.ndarray | None]] = []
        start = 0
        for end in range(1, len(self.imu) + 1):
            if end == len(self.imu) or (self.imu[end][2] is None) != (self.imu[start][2] is None):
                run = self.imu[start:end]
                gyro = None if run[0][2] is None else np.concatenate([p[2] for p in run])
                blocks.append((np.concatenate([p[0] for p in run]),
                               np.concatenate([p[1] for p in run]), gyro))
                start = end
        return blocks
