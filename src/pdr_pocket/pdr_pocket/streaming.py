"""The pocket navigator sample by sample, for the live node (no rclpy here).

:class:`StreamingPocket` takes ``imu/data`` and ``imu/mag`` messages as plain values and
returns what to publish: :class:`Processed` chunks, the stamps of the samples the
navigator took and its output for them (attitude per sample, steps with their poses).
It applies the offline rules one message at a time, so the node and ``pdr-pocket run``
(and ``attitude``) give the same estimates on the same bag (the navigator gives the same
result whatever the chunks, pdr_pocket.navigator):

- an IMU sample with NaN/Inf, beyond any IMU's range (pdr_core.imu_checks.plausible), or
  with a stamp that does not increase, is dropped and counted;
- each IMU sample pairs with the latest magnetometer reading stamped at or before it and
  at most :data:`~pdr_core.magnetometer_pairing.MAG_MAX_AGE_S` older, as offline. The two
  topics travel separately, so a reading may arrive after IMU samples stamped later than
  it: a sample is held until a reading stamped at or after it arrives (at once when the
  magnetometer keeps pace) or until ``mag_wait_s`` of IMU data has come after it. A
  magnetometer quiet for longer than that holds nothing (no latency without one,
  :attr:`mag_stale`) and only pauses the magnetic updates: samples processed without a
  reading for ``mag_wait_s`` of IMU data (:attr:`mag_paused`, what the node reports);
- the units are checked on the first :data:`UNIT_CHECK_SAMPLES` samples: data in g or
  deg/s is refused (nothing is navigated until :meth:`reset`), a magnetometer in µT or
  gauss is switched off (:attr:`mag_error`);
- gaps longer than ``max_gap_s`` are propagated over and counted by the filter;
- a correction (:meth:`StreamingPocket.apply_correction`, the node's service) counts from
  the last step, the one whose landmark it comes from: the navigator as it was right
  after that step's sample takes it, and the samples since are run again. The service
  call comes some samples after the step, more or fewer by how busy the graph is, and
  an update of the orientation filter in between (a mean gravity window closing) turns
  out differently with the yaw corrected or not: 2.3 m at the end of a two-lap walk
  without magnetometer updates between 0 and 2 samples late. ``pdr-pocket run --drift
  online`` applies it at that same point (pdr_pocket.drift_loop), so the two agree. The
  state right after the last step and the samples since are a checkpoint
  (pdr_core.checkpoints, which also says how a correction later than it is expressed).
  After more than ``replay_max_s`` without a step the correction applies from now.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.checkpoints import Checkpoints
from pdr_core.errors import InputError
from pdr_core.imu_checks import check_mag_units, check_units, plausible
from pdr_core.magnetometer_pairing import latest_readings
from pdr_pocket.config import PocketConfig
from pdr_pocket.magnetometer import MagCalibration
from pdr_pocket.navigator import NavigatorOutput, PocketNavigator

UNIT_CHECK_SAMPLES = 50
MAG_BEFORE_IMU_NS = 60_000_000_000   # readings kept before the first IMU sample [ns]
MAG_WAIT_S = 1.0
"""Default wait for a late magnetometer reading [s of IMU data]: playback at full speed
acknowledges every 100 messages, so the topics drift at most that far apart."""
REPLAY_MAX_S = 5.0
"""A correction counts from the last step when it comes within this of the step [s of
IMU data]: two gait cycles at the slowest walk."""


@dataclass(frozen=True)
class Processed:
    """Samples the navigator took: their stamps [ns], its output for them and the stamp
    of its time 0 [ns]."""

    stamp_ns: np.ndarray
    output: NavigatorOutput
    t0_ns: int

    def stamp_of(self, t_s: float) -> int:
        """The stamp [ns] of the navigator time ``t_s`` (a step's confirmation)."""
        return self.t0_ns + round(t_s * 1e9)


@dataclass
class StreamingPocket:
    """Live navigator: :meth:`push_imu` and :meth:`push_mag` return the
    :class:`Processed` chunks of the samples they let the navigator process."""

    config: PocketConfig
    calibration: MagCalibration | None = None
    mag_wait_s: float = MAG_WAIT_S
    replay_max_s: float = REPLAY_MAX_S
    counts: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        self.navigator = PocketNavigator(self.config)
        # right after the last step (its confirmation [s]) and the inputs processed since
        self.at_step: Checkpoints[PocketNavigator, tuple] = Checkpoints(
            PocketNavigator.copy_state, self.replay_max_s, capacity=1)
        self.last_stamp_ns: int | None = None
        # the readings a sample not yet processed may pair with: from the last one at or
        # before the last processed sample on (stamps [ns] ascending, values [T])
        self.mag_stamps = np.empty(0, np.int64)
        self.mag_values = np.empty((0, 3))
        self.held: list[tuple[int, np.ndarray, np.ndarray]] = []
        self.checked = self.mag_checked = False
        self.failed: str | None = None
        self.mag_error: str | None = None
        self.t0_ns: int | None = None
        self.processed_ns: int | None = None    # the last sample processed ...
        self.paired_ns: int | None = None       # ... and the last with a reading
        self.counts = {"non_finite": 0, "implausible": 0, "stamp_not_increasing": 0,
                       "mag_non_finite": 0,
                       "mag_missing": 0}

    @property
    def mag_stale(self) -> bool:
        """The magnetometer quiet for more than ``mag_wait_s`` of IMU data: since its last
        reading, or since the first IMU sample when none has come."""
        if self.last_stamp_ns is None:
            return False
        quiet_since = self.mag_stamps[-1] if len(self.mag_stamps) else self.t0_ns
        return self.last_stamp_ns - quiet_since > self.mag_wait_s * 1e9

    @property
    def mag_paused(self) -> bool:
        """The samples processed for the last ``mag_wait_s`` of IMU data had no
        magnetometer reading (since the last that had one, or since the first sample)."""
        if self.processed_ns is None:
            return False
        since = self.paired_ns if self.paired_ns is not None else self.t0_ns
        return self.processed_ns - since > self.mag_wait_s * 1e9

    def push_mag(self, stamp_ns: int, field_t) -> list[Processed]:
        """A magnetometer reading [T] (body frame)."""
        return self.push_mags(np.array([stamp_ns], np.int64),
                              np.asarray(field_t, float).reshape(1, 3))

    def push_mags(self, stamp_ns: np.ndarray, field_t: np.ndarray) -> list[Processed]:
        """Magnetometer readings [T] (N, 3) in arrival order, as one block: a reading with
        NaN/Inf is counted and dropped, one stamped before the last kept one dropped."""
        values = np.asarray(field_t, float).reshape(-1, 3)
        finite = np.isfinite(values).all(axis=1)
        self.counts["mag_non_finite"] += int((~finite).sum())
        if self.mag_error is not None:
            return []
        if self.calibration is not None and finite.any():
            values[finite] = self.calibration.apply(values[finite])
        stamps = np.asarray(stamp_ns, np.int64)
        start = self.mag_stamps[-1] if len(self.mag_stamps) else np.iinfo(np.int64).min
        before = np.maximum.accumulate(np.r_[start, np.where(finite, stamps, start)])[:-1]
        kept = finite & (stamps >= before)
        self.mag_stamps = np.r_[self.mag_stamps, stamps[kept]]
        self.mag_values = np.vstack([self.mag_values, values[kept]])
        if self.last_stamp_ns is None and len(self.mag_stamps):   # no IMU yet: the last minute
            first = np.searchsorted(self.mag_stamps, self.mag_stamps[-1] - MAG_BEFORE_IMU_NS)
            self.mag_stamps, self.mag_values = self.mag_stamps[first:], self.mag_values[first:]
        if not self.checked:
            return []
        self._check_mag_units()
        return self._process(self._ready())

    def push_imu(self, stamp_ns: int, accel, gyro) -> list[Processed]:
        """An IMU sample [m/s², rad/s]; ``gyro`` None when the IMU has no gyroscope
        (REP-145: angular_velocity_covariance[0] = −1), for which the navigator takes the
        pitch from the gravity direction alone."""
        return self.push_imus(np.array([stamp_ns], np.int64),
                              np.asarray(accel, float).reshape(1, 3),
                              None if gyro is None else np.asarray(gyro, float).reshape(1, 3))

    def push_imus(self, stamp_ns: np.ndarray, accel: np.ndarray, gyro: np.ndarray | None
                  ) -> list[Processed]:
        """IMU samples (N,) [ns], (N, 3) [m/s², rad/s; gyro None: no gyroscope] in arrival
        order, as one block: the same samples kept, counted and processed as one at a
        time would be (the module docstring), one chunk for the whole block."""
        stamps = np.asarray(stamp_ns, np.int64)
        a = np.asarray(accel, float).reshape(-1, 3)
        w = np.full_like(a, np.nan) if gyro is None else np.asarray(gyro, float).reshape(-1, 3)
        checked = np.zeros_like(a) if gyro is None else w
        finite = np.isfinite(a).all(axis=1) & np.isfinite(checked).all(axis=1)
        valid = finite & plausible(a, checked)
        self.counts["non_finite"] += int((~finite).sum())
        self.counts["implausible"] += int((finite & ~valid).sum())
        start = np.iinfo(np.int64).min if self.last_stamp_ns is None else self.last_stamp_ns
        before = np.maximum.accumulate(np.r_[start, np.where(valid, stamps, start)])[:-1]
        kept = valid & (stamps > before)
        self.counts["stamp_not_increasing"] += int((valid & ~kept).sum())
        if not kept.any():
            return []
        self.last_stamp_ns = int(stamps[kept][-1])
        if self.t0_ns is None:
            self.t0_ns = int(stamps[kept][0])
        if self.failed is not None:
            return []
        self.held.extend(zip(stamps[kept].tolist(), a[kept], w[kept], strict=True))
        if not self.checked:
            if len(self.held) < UNIT_CHECK_SAMPLES:
                return []
            self._check_units()
            if self.failed is not None:
                return []
        return self._process(self._ready())

    def flush(self) -> list[Processed]:
        """Process every held sample (the end of a stream)."""
        if self.held and not self.checked and self.failed is None:
            self._check_units()
        return [] if self.failed is not None else self._process(len(self.held))

    def _check_units(self) -> None:
        self.checked = True
        try:
            check_units(np.array([h[1] for h in self.held]), np.array([h[2] for h in self.held]))
        except InputError as exc:
            self.failed = str(exc)
            self.held = []
            return
        self._check_mag_units()

    def _check_mag_units(self) -> None:
        """On the readings there are when the IMU check is made, or on the first one
        after it."""
        if not len(self.mag_stamps) or self.mag_checked:
            return
        self.mag_checked = True
        try:
            check_mag_units(self.mag_values)
        except InputError as exc:
            self.mag_error = str(exc)

    def _ready(self) -> int:
        """How many held samples can be processed: those a reading stamped at or after
        them has come for, or ``mag_wait_s`` of IMU data has passed since, or all when
        the magnetometer is off or has been quiet that long."""
        if self.mag_error is not None or self.mag_stale:
            return len(self.held)
        covered = self.mag_stamps[-1] if len(self.mag_stamps) else -1
        waited = self.last_stamp_ns - self.mag_wait_s * 1e9
        return int(np.searchsorted([h[0] for h in self.held], max(covered, waited),
                                   side="right"))

    def _process(self, count: int) -> list[Processed]:
        """The first ``count`` held samples as one chunk."""
        if count == 0:
            return []
        held, self.held = self.held[:count], self.held[count:]
        stamps = np.array([h[0] for h in held], dtype=np.int64)
        mag = np.full((count, 3), np.nan)
        if self.mag_error is None:
            mag = latest_readings(stamps, self.mag_stamps, self.mag_values)
            first = max(int(np.searchsorted(self.mag_stamps, stamps[-1], side="right")) - 1, 0)
            self.mag_stamps, self.mag_values = self.mag_stamps[first:], self.mag_values[first:]
        missing = np.isnan(mag).any(axis=1)
        self.counts["mag_missing"] += int(missing.sum())
        self.processed_ns = int(stamps[-1])
        if not missing.all():
            self.paired_ns = int(stamps[~missing][-1])
        gyro = np.array([h[2] for h in held])
        inputs = ((stamps - self.t0_ns) * 1e-9, None if np.isnan(gyro).all() else gyro,
                  np.array([h[1] for h in held]), mag)
        before = self.navigator.copy_state() if count > 1 else None
        out = self.navigator.process(*inputs)
        self._remember(inputs, out, before)
        return [Processed(stamps, out, self.t0_ns)]

    # --- corrections from the last step --------------------------------------------
    def apply_correction(self, *correction) -> tuple[bool, str]:
        """:meth:`PocketNavigator.apply_correction` as of right after the last step (the
        module docstring), the samples since run again; from now when there is none."""
        reverted = self.at_step.revert_to()
        if reverted is None:
            return self.navigator.apply_correction(*correction)
        navigator = reverted.state
        result = navigator.apply_correction(*correction)
        self.at_step.remember(reverted.t_s, navigator)
        for inputs in reverted.inputs:
            navigator.process(*inputs)
            self.at_step.record(inputs, inputs[0][-1])
        navigator.steps = self.navigator.steps
        self.navigator = navigator
        return result

    def _remember(self, inputs: tuple, out: NavigatorOutput, before) -> None:
        """Keep the state right after the last step and the inputs since (the module
        docstring)."""
        t = inputs[0]
        if not out.steps:       # the samples since the step, while within replay_max_s
            self.at_step.record(inputs, t[-1])
            return
        confirm = out.steps[-1].t_confirm
        cut = max(int(np.searchsorted(t, confirm, side="right")), 1)
        if cut >= len(t):
            self.at_step.remember(confirm, self.navigator)
            return
        # the chunk went on past the step: run it again from before, up to the step
        steps = self.navigator.steps
        before.process(*(x[:cut] for x in inputs))
        self.at_step.remember(confirm, before)
        since = tuple(x[cut:] for x in inputs)
        before.process(*since)
        before.steps = steps
        self.navigator = before
        self.at_step.record(since, t[-1])

