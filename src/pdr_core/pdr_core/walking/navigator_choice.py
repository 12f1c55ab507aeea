"""Which navigator a recording is for, told from its IMU alone: the foot's (``pdr-ekf``),
the pocket's (``pdr-pocket``), or neither (``pdr-eval --navigator auto``).

- :func:`choose_navigator`: the :class:`NavigatorChoice` of a recording's samples (t [s],
  specific force [m/s²] and turn rate [rad/s], (N, 3), in the sensor's frame: only
  norms are used, so any mounting and either sign convention will do).

What tells them apart, while the wearer moves (the samples whose specific force varies
by more than :data:`MOTION_MIN_STD_MPS2` over :data:`MOTION_WINDOW_S`):

1. **A foot stands still at each stance.** Between two swings the shoe rests on the
   ground: |ω| < :data:`STANCE_MAX_RATE_RADPS` and |f| within
   :data:`STANCE_MAX_FORCE_DEV_MPS2` of g for at least :data:`STANCE_MIN_S` (a walking
   stance lasts 0.3-0.7 s, about 60 % of a gait cycle; Perry, *Gait Analysis*, 1992),
   with a swing (|ω| > :data:`SWING_MIN_RATE_RADPS`) within :data:`SWING_WITHIN_S` before
   and after. A foot walking has such a stance at every stride, 0.5-1 a second of motion;
   :data:`FOOT_MIN_STANCES_HZ` asks for one every eight seconds (a climb on a few stairs,
   with long pauses, has 0.17 a second). A hand-held phone is still enough but never
   swings between (0-0.06 a second on the shared hand-held exports); a thigh never stands
   still while walking: its turn rate passes through
   zero only at the ends of its swing, for less than 0.1 s, while the hip still moves it
   (|f| several m/s² off g).
2. **A foot that runs or walks fast** has a stance too short and too shaken to be still,
   but its swing turns faster than a thigh can: the median, over the moving samples, of
   the largest |ω| within :data:`GAIT_WINDOW_S` (about a gait cycle) above
   :data:`FOOT_SWING_PEAK_RADPS` (a shoe walking fast or running peaks at 10-13 rad/s;
   a thigh at 3-5 walking and 7 jogging, on the shared recordings).
3. **Otherwise the pocket navigator**, which judges itself where the phone rides (front
   pocket, back pocket, or not in a pocket: pdr_pocket.placement). A phone held in the
   hand has neither a foot's stances nor its swing, and comes here too, to be named
   not in a pocket. Without a gyroscope only the pocket navigator can run.
4. **No choice** with less than :data:`MIN_MOVING_S` of motion: nothing to tell from.

The thresholds were set on the shared recordings (9 foot, 9 pocket) and the simulator's
foot and pocket walks, with margins of 1.2-3 between the classes; docs/datasets.md gives
the figures.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import maximum_filter1d, minimum_filter1d, uniform_filter1d

from pdr_core.constants import STANDARD_GRAVITY_MPS2

MOTION_WINDOW_S = 2.0               # window of the specific force's spread [s]
MOTION_MIN_STD_MPS2 = 1.0           # spread above which the wearer moves [m/s²]
MIN_MOVING_S = 3.0                  # motion needed to tell anything [s]
GAIT_WINDOW_S = 1.5                 # about one gait cycle at a walk [s]
STANCE_MAX_RATE_RADPS = 0.6         # |ω| of a shoe at rest on the ground [rad/s]
STANCE_MAX_FORCE_DEV_MPS2 = 1.5     # ||f| − g| of a shoe at rest [m/s²]
STANCE_MIN_S = 0.15                 # the shortest still stance counted [s]
SWING_MIN_RATE_RADPS = 1.0          # |ω| of a swing on either side of a stance [rad/s]
SWING_WITHIN_S = 0.6                # how near that swing is to the stance [s]
FOOT_MIN_STANCES_HZ = 0.12          # still stances per second of motion of a foot [1/s]
FOOT_SWING_PEAK_RADPS = 8.5         # a swing turning faster is no thigh's [rad/s]


@dataclass(frozen=True)
class NavigatorChoice:
    """The navigator of a recording (``foot``, ``pocket``, or None: no choice), the reason
    in words, and the figures it was told from: seconds of motion, still stances per
    second of motion and the median swing peak [rad/s] (both None without a gyroscope or
    without motion)."""

    navigator: str | None
    why: str
    moving_s: float
    stances_hz: float | None = None
    swing_peak_radps: float | None = None

    def figures(self) -> str:
        """The figures in words, for a message."""
        text = f"{self.moving_s:.0f} s of motion"
        if self.stances_hz is None:
            return text
        return (f"{text}, {self.stances_hz:.2f} still stances/s (a foot's ≥ "
                f"{FOOT_MIN_STANCES_HZ:g}), swing peaks of {self.swing_peak_radps:.1f} rad/s "
                f"(a foot's ≥ {FOOT_SWING_PEAK_RADPS:g})")


def _samples(seconds: float, rate_hz: float) -> int:
    return max(1, round(seconds * rate_hz))


def _moving_spread(f: np.ndarray, n: int) -> np.ndarray:
    """The spread of the vectors ``f`` (N, 3) over a centred window of ``n`` samples:
    √(Σ_axes var) (N,)."""
    mean = uniform_filter1d(f, n, axis=0, mode="nearest")
    square = uniform_filter1d(f * f, n, axis=0, mode="nearest")
    return np.sqrt(np.maximum(square - mean * mean, 0.0).sum(axis=1))


def still_stances(rate: np.ndarray, force: np.ndarray, rate_hz: float) -> int:
    """The still stances between two swings (rule 1 of the module), from |ω| [rad/s]
    and |f| [m/s²] (N,)."""
    still = (rate < STANCE_MAX_RATE_RADPS) & \
        (np.abs(force - STANDARD_GRAVITY_MPS2) < STANCE_MAX_FORCE_DEV_MPS2)
    n = _samples(STANCE_MIN_S, rate_hz)
    long_still = maximum_filter1d(minimum_filter1d(still.astype(np.uint8), n), n)
    edges = np.flatnonzero(np.diff(np.concatenate(([0], long_still.astype(np.int8), [0]))))
    starts, ends = edges[::2], edges[1::2]
    swings = np.concatenate(([0], np.cumsum(rate > SWING_MIN_RATE_RADPS)))
    near = _samples(SWING_WITHIN_S, rate_hz)
    after = swings[np.minimum(ends + near, len(rate))] - swings[ends]
    before = swings[starts] - swings[np.maximum(starts - near, 0)]
    return int(np.count_nonzero((after > 0) & (before > 0)))


def choose_navigator(t_s: np.ndarray, accel: np.ndarray, gyro: np.ndarray | None
                     ) -> NavigatorChoice:
    """The navigator of samples at stamps ``t_s`` [s] (N,), increasing, of specific force
    ``accel`` [m/s²] and turn rate ``gyro`` [rad/s] (N, 3; None: no gyroscope), by the
    rules of the module."""
    t_s, accel = np.asarray(t_s, float), np.asarray(accel, float)
    rate_hz = (len(t_s) - 1) / (t_s[-1] - t_s[0]) if len(t_s) > 1 else 1.0
    moving = _moving_spread(accel, _samples(MOTION_WINDOW_S, rate_hz)) > MOTION_MIN_STD_MPS2
    moving_s = float(np.count_nonzero(moving) / rate_hz)
    if moving_s < MIN_MOVING_S:
        return NavigatorChoice(None, f"{moving_s:.1f} s of motion, less than "
                               f"{MIN_MOVING_S:g} s: too little to tell a foot from a "
                               "pocket", moving_s)
    if gyro is None:
        return NavigatorChoice("pocket", "no gyroscope: only the pocket navigator runs "
                               "without one", moving_s)
    turn = np.linalg.norm(gyro, axis=1)
    stances_hz = still_stances(turn, np.linalg.norm(accel, axis=1), rate_hz) / moving_s
    peak = float(np.median(maximum_filter1d(turn, _samples(GAIT_WINDOW_S, rate_hz))[moving]))
    if stances_hz >= FOOT_MIN_STANCES_HZ:
        why = "it stands still between swings, as a foot does at each stance"
    elif peak >= FOOT_SWING_PEAK_RADPS:
        why = "its swing turns faster than a thigh's, as a foot's does"
    else:
        return NavigatorChoice("pocket", "neither a foot's still stances nor its swing: "
                               "the pocket navigator judges where the phone rides",
                               moving_s, stances_hz, peak)
    return NavigatorChoice("foot", why, moving_s, stances_hz, peak)
