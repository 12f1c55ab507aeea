"""The foot's strides, one per footfall, from the filter's estimates (``pdr/foot/step``).

A stride ends at a stance onset: the first sample the detector calls stance after a swing,
where the foot has just landed and the filter's position is the footfall's. It runs from
the previous stride's end (the aligned start, for the first) and gives what
pdr_msgs/Step carries, so the drift estimator (pdr_drift) reads the foot as it reads the
pocket:

- ``length_m``: the horizontal distance between the two footfalls [m];
- ``vertical_m``: the height gained [m], ENU up;
- ``heading_rad``: the direction of travel, atan2 of the horizontal displacement (ENU yaw:
  0 east, counter-clockwise positive). It is not the foot's yaw, which differs by the
  person's toe-out angle; a yaw correction turns both alike;
- ``pitch_max_rad``, ``pitch_min_rad``: the foot's extreme pitches over the stride (the
  ZYX Euler pitch of pdr_core.maths.rotations.rotation_from_euler);
- ``activity``: :class:`~pdr_core.vocabulary.Activity` UPSTAIRS or DOWNSTAIRS when the
  height changed by at least one riser (:data:`pdr_core.walking.stair_geometry.RISER_MIN_M`;
  a level stride's height error is centimetres), WALKING otherwise.

A footfall less than :data:`pdr_core.walking.gait.FOOT_STRIDE_MIN_M` from the last stride's end
(stepping in place, a turn on the spot) has no direction of travel: it ends no stride,
and the next stride runs from the last one's end.

:class:`StrideTracker` takes the estimates block by block, in any blocks (the live node's,
or a whole record at once), with the same strides; it is a small value, copied into the
foot navigator's checkpoints (pdr_ins_ekf.streaming).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.vocabulary import Activity
from pdr_core.walking.gait import FOOT_STRIDE_MIN_M
from pdr_core.walking.stair_geometry import RISER_MIN_M
from pdr_ins_ekf.kernel_data import ATTITUDE, AXES
from pdr_ins_ekf.zupt_ekf import FilterOutput


@dataclass(frozen=True)
class Stride:
    """One stride (module docstring), stamped ``stamp_ns`` at the footfall that ends it,
    with the filter's position (3,) [m] and its covariance (3, 3) [m²], attitude C_b^n
    (3, 3) and the variances of its attitude error δθ (3,) [rad²] there; ``index`` counts
    from 0."""

    index: int
    stamp_ns: int
    length_m: float
    vertical_m: float
    heading_rad: float
    pitch_max_rad: float
    pitch_min_rad: float
    duration_s: float
    activity: int
    position_m: np.ndarray
    covariance_m2: np.ndarray
    attitude: np.ndarray
    attitude_variance_rad2: np.ndarray


def foot_pitch(attitude: np.ndarray) -> np.ndarray:
    """The ZYX Euler pitch [rad] of attitudes C_b^n (N, 3, 3): C₃₁ = −sin θ."""
    return np.arcsin(np.clip(-attitude[:, 2, 0], -1.0, 1.0))


def stride_activity(vertical_m: float) -> int:
    """UPSTAIRS, DOWNSTAIRS or WALKING from a stride's height change [m]."""
    if vertical_m >= RISER_MIN_M:
        return int(Activity.UPSTAIRS)
    if vertical_m <= -RISER_MIN_M:
        return int(Activity.DOWNSTAIRS)
    return int(Activity.WALKING)


@dataclass
class StrideTracker:
    """Strides from blocks of the filter's estimates (module docstring). The first block
    starts at the aligned start, at rest: the foot is in stance there."""

    index: int = 0
    in_stance: bool = True
    start_stamp_ns: int | None = None
    start_position_m: np.ndarray = field(default_factory=lambda: np.zeros(3))
    pitch_max_rad: float = -np.inf
    pitch_min_rad: float = np.inf

    def copy(self) -> StrideTracker:
        return StrideTracker(self.index, self.in_stance, self.start_stamp_ns,
                             self.start_position_m.copy(), self.pitch_max_rad,
                             self.pitch_min_rad)

    def onsets(self, stance: np.ndarray) -> np.ndarray:
        """The block's stance onsets, indices into ``stance`` (N,) bool."""
        before = np.concatenate(([self.in_stance], stance[:-1]))
        return np.flatnonzero(stance & ~before)

    def push(self, stamp_ns: np.ndarray, stance: np.ndarray, output: FilterOutput
             ) -> list[Stride]:
        """The strides ended in a block: stamps (N,) [ns], stance (N,) and the filter's
        estimates there."""
        if not len(stamp_ns):
            return []
        position = output.position
        if self.start_stamp_ns is None:
            self.start_stamp_ns = int(stamp_ns[0])
            self.start_position_m = position[0].copy()
        pitch = foot_pitch(output.attitude)
        strides, first = [], 0
        for onset in self.onsets(stance).tolist():
            self._extremes(pitch[first:onset + 1])
            first = onset + 1
            stride = self._ended(int(stamp_ns[onset]), output, onset)
            if stride is not None:
                strides.append(stride)
        self._extremes(pitch[first:])
        self.in_stance = bool(stance[-1])
        return strides

    def _extremes(self, pitch: np.ndarray) -> None:
        if len(pitch):
            self.pitch_max_rad = max(self.pitch_max_rad, float(pitch.max()))
            self.pitch_min_rad = min(self.pitch_min_rad, float(pitch.min()))

    def _ended(self, stamp_ns: int, output: FilterOutput, k: int) -> Stride | None:
        """The stride the footfall at sample ``k`` of ``output`` ends, or None when it is
        too short to have a direction."""
        position = output.position[k]
        dx, dy, dz = position - self.start_position_m
        length = float(np.hypot(dx, dy))
        if length < FOOT_STRIDE_MIN_M:
            return None
        stride = Stride(self.index, stamp_ns, length, float(dz), float(np.arctan2(dy, dx)),
                        self.pitch_max_rad, self.pitch_min_rad,
                        (stamp_ns - self.start_stamp_ns) * 1e-9, stride_activity(float(dz)),
                        position.copy(), output.position_cov[k].copy(),
                        output.attitude[k].copy(),
                        output.variance[k, ATTITUDE:ATTITUDE + AXES].copy())
        self.index += 1
        self.start_stamp_ns, self.start_position_m = stamp_ns, position.copy()
        self.pitch_max_rad, self.pitch_min_rad = -np.inf, np.inf
        return stride
