"""The pocket navigator sample by sample, for the live node (no rclpy here).

:class:`StreamingPocket` takes ``imu/data`` and ``imu/mag`` messages as plain values and
returns what to publish: :class:`Processed` chunks, the stamps of the samples the
navigator took and its output for them (attitude per sample, steps with their poses).
It applies the offline rules one message at a time, so the node and ``pdr-pocket run``
(and ``attitude``) give the same estimates on the same bag (the navigator gives the same
result whatever the chunks, pdr_pocket.navigator):

- an IMU sample with NaN/Inf, beyond any IMU's range (pdr_core.sensors.imu_checks.plausible), or
  with a stamp that does not increase, is dropped and counted;
- each IMU sample pairs with the latest magnetometer reading stamped at or before it and
  at most :data:`~pdr_core.sensors.magnetometer_pairing.MAG_MAX_AGE_S` older, as offline. The two
  topics travel separately, so a reading may arrive after IMU samples stamped later than
  it: a sample is held until a reading stamped at or after it arrives (at once when the
  magnetometer keeps pace) or until ``mag_wait_s`` of IMU data has come after it. A
  magnetometer quiet for longer than that holds nothing (no latency without one,
  :attr:`mag_stale`) and only pauses the magnetic updates: samples processed without a
  reading for ``mag_wait_s`` of IMU data (:attr:`mag_paused`, what the node reports);
- the other sensors' readings (pdr_pocket.sensor_inputs: ``imu/pressure``) land each on
  the first sample stamped at or after them, as offline (pdr_core.sensors.sample_pairing): once a
  sensor's reading has come, a sample is held, as for the magnetometer, until a reading
  stamped at or after it has come or ``mag_wait_s`` of IMU data has passed since the
  sensor's last; a reading that is not finite, or stamped at or before the last kept
  one, is dropped and counted. A sensor that never reads makes nothing wait;
- the units are checked on the first :data:`UNIT_CHECK_SAMPLES` samples: data in g or
  deg/s is refused (nothing is navigated until :meth:`reset`), a magnetometer in µT or
  gauss is switched off (:attr:`mag_error`);
- gaps longer than ``max_gap_s`` are propagated over and counted by the filter;
- a correction (:meth:`StreamingPocket.apply_correction`, the node's service) names
  the step it belongs to by its stamp: the navigator goes back to its state at that
  instant, right after the step's sample, takes the correction there and runs the
  samples since again (robot_localization's ``revertTo``), so the steps after it do not
  depend on when the call came. ``pdr-pocket run --drift online`` applies it at that same
  point (pdr_pocket.drift_loop), so the two agree at any replay speed. The navigator's
  state is kept at most every :data:`CHECKPOINT_EVERY_S` with the inputs processed since
  (pdr_core.corrections.checkpoints), for ``correction_window_s`` of IMU data; the corrections taken
  are inputs too, so one that reaches further back runs them again in their place. A
  stamp older than the window, or later than the last sample processed, is refused by
  name; a zero stamp applies the correction now, to the current state. The steps run
  again come back with the answer (pdr_core.corrections.replay.CorrectionResult, their
  :class:`Revised`): they replace the ones given out before the call came. The replay
  is pdr_core.corrections.replay's, the foot's too.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from pdr_core.corrections.correction import Correction
from pdr_core.corrections.replay import CorrectionResult, Replay, TakenCorrection
from pdr_core.errors import InputError
from pdr_core.sensors.imu_checks import check_mag_units, check_units, plausible
from pdr_core.sensors.magnetometer_pairing import latest_readings
from pdr_core.sensors.sample_pairing import readings_at_samples
from pdr_pocket.arrivals import MAG, Arrivals
from pdr_pocket.compiled_orientation_data import ATT_ROWS
from pdr_pocket.config import PocketConfig, StairsConfig
from pdr_pocket.magnetometer import MagCalibration
from pdr_pocket.navigator import PocketNavigator, TakenLines
from pdr_pocket.orientation import AttitudeEstimate
from pdr_pocket.placement import Placement, walk_placement
from pdr_pocket.records import NavigatorOutput, StepRecord
from pdr_pocket.samples import Samples
from pdr_pocket.step_length import StepLengthConfig

UNIT_CHECK_SAMPLES = 50
MAG_BEFORE_IMU_NS = 60_000_000_000   # readings kept before the first IMU sample [ns]
MAG_WAIT_S = 1.0
"""Default wait for a late magnetometer reading [s of IMU data]: playback at full speed
acknowledges every 100 messages, so the topics drift at most that far apart."""
CORRECTION_WINDOW_S = 60.0
"""How far back a stamped correction may reach [s of IMU data]: ``landmark_drift``'s
answer comes within a step live, but a bag played as fast as acknowledged runs the
navigator ahead of it, and a correction held back 20 steps on purpose (its
``correction_delay_steps``, 25 s of walking) came 32 s of data late in one run. A
minute costs 60 checkpoints of the navigator's state and a minute of samples."""
CHECKPOINT_EVERY_S = 1.0
"""The navigator's state is kept at most this often [s of IMU data]: a correction runs
again at most this much besides the samples since its step."""
BLOCK_S = 0.25
"""The node's default ``block_s`` [s of IMU data]: a call of the navigator costs about
450 µs besides about 37 µs a sample, so live at 100 Hz, a message at a time, a sample
costs 489 µs processed at once, 76 µs in blocks of 0.1 s, 47 µs in blocks of 0.25 s and
41 µs in blocks of 0.5 s (test/benchmarks/bench_pocket_live.py; issue 56 asks at most
50 µs). The price is latency: a sample's attitude goes out up to 0.25 s later; a step is
confirmed a few tenths of a second after its pitch maximum anyway. ``block_s`` 0 gives
each sample's attitude at once."""
ATTITUDE_KEPT_S = 30.0
"""How long the orientation filter's output is kept [s of IMU data]: a step is confirmed
after its sample, the first one, once the thigh frame is learnt, up to seconds after and
in a later chunk; its pose takes the attitude of its own sample, as offline."""


@dataclass(frozen=True)
class Processed:
    """Samples the navigator took: their stamps [ns], its output for them, the stamp of
    its time 0 [ns], and for each of its steps the attitude C_b^n (3, 3) and its
    covariance (3, 3) [rad²] at the sample that confirmed it (:class:`AttitudeTail`)."""

    stamp_ns: np.ndarray
    output: NavigatorOutput
    t0_ns: int
    step_attitude: list[tuple[np.ndarray, np.ndarray]]

    def stamp_of(self, t_s: float) -> int:
        """The stamp [ns] of the navigator time ``t_s`` (a step's confirmation)."""
        return stamp_of(self.t0_ns, t_s)


def latest_before(stamps: np.ndarray, usable: np.ndarray, start: int) -> np.ndarray:
    """For each of ``stamps`` [ns], the latest usable stamp before it, or ``start`` (the
    last one kept before the block) when none is later."""
    return np.maximum.accumulate(np.concatenate(([start], np.where(usable, stamps, start))))[:-1]


def stamp_of(t0_ns: int, t_s: float) -> int:
    """The stamp [ns] of the navigator time ``t_s`` [s], its time 0 stamped ``t0_ns``."""
    return t0_ns + round(t_s * 1e9)


class AttitudeTail:
    """The orientation filter's attitude C_b^n and its covariance (the attitude rows,
    [rad²]) at the samples of the last ``kept_s`` seconds [s of navigator time], the
    latest run of each sample (a correction's run again replaces the first).

    The samples live in arrays grown by doubling and cut at the front by an index, so a
    sample kept costs the same whether the chunks hold one sample (live at the IMU's
    rate) or thousands."""

    def __init__(self, kept_s: float) -> None:
        self.kept_s = kept_s
        self._t = np.zeros(0)
        self._attitude = np.zeros((0, 3, 3))
        self._covariance = np.zeros((0, 3, 3))
        self._start = self._end = 0

    @property
    def t(self) -> np.ndarray:
        """The samples' times [s of navigator time], ascending."""
        return self._t[self._start:self._end]

    def extend(self, estimate: AttitudeEstimate) -> None:
        """Keep the estimate's samples, in place of any at or after its first."""
        n = len(estimate.t)
        if not n:
            return
        cut = self._start + int(np.searchsorted(self.t, estimate.t[0]))
        if cut + n > len(self._t):
            self._make_room(cut, n)
            cut = self._end
        end = cut + n
        self._t[cut:end] = estimate.t
        self._attitude[cut:end] = estimate.attitude
        self._covariance[cut:end] = estimate.covariance[:, ATT_ROWS, ATT_ROWS]
        self._end = end
        self._start += int(np.searchsorted(self.t, self._t[end - 1] - self.kept_s))

    def _make_room(self, cut: int, n: int) -> None:
        """Move the samples before ``cut`` to the front of arrays with room for ``n``
        more (twice what is needed, so the moves are rare)."""
        kept = slice(self._start, cut)
        capacity = 2 * (cut - self._start + n)
        for name in ("_t", "_attitude", "_covariance"):
            old = getattr(self, name)
            new = np.empty((capacity, *old.shape[1:]))
            new[:cut - self._start] = old[kept]
            setattr(self, name, new)
        self._start, self._end = 0, cut - self._start

    def at(self, step: StepRecord) -> tuple[np.ndarray, np.ndarray]:
        """C_b^n (3, 3) and its covariance (3, 3) at the step's confirmation (the first
        sample at or after it, as pdr_pocket.messages.step_batches takes it)."""
        i = self._start + min(int(np.searchsorted(self.t, step.t_confirm)),
                              self._end - self._start - 1)
        return self._attitude[i].copy(), self._covariance[i].copy()


@dataclass(frozen=True)
class Revised:
    """A step run again with a correction: its stamp [ns], the step and C_b^n (3, 3) at
    its confirmation."""

    stamp_ns: int
    step: StepRecord
    attitude: np.ndarray


@dataclass
class Readings:
    """A sensor's readings (pdr_pocket.sensor_inputs) not yet on a sample: stamps [ns]
    ascending and values, and the newest stamp kept [ns] (−1: none yet)."""

    stamps: np.ndarray = field(default_factory=lambda: np.empty(0, np.int64))
    values: np.ndarray = field(default_factory=lambda: np.empty(0))
    newest_ns: int = -1

    def add(self, stamps: np.ndarray, values: np.ndarray) -> None:
        if len(stamps):
            self.stamps = np.concatenate((self.stamps, stamps))
            self.values = np.concatenate((self.values, values))
            self.newest_ns = int(stamps[-1])

    def take(self, stamps: np.ndarray, previous_ns: int | None) -> np.ndarray:
        """The readings on the samples stamped ``stamps`` [ns], the next to be processed
        after the one stamped ``previous_ns`` (pdr_core.sensors.sample_pairing); those put on them
        are let go."""
        out = readings_at_samples(stamps, self.stamps, self.values, previous_ns)
        used = int(np.searchsorted(self.stamps, stamps[-1], side="right"))
        self.stamps, self.values = self.stamps[used:], self.values[used:]
        return out


@dataclass
class StreamingPocket:
    """Live navigator: :meth:`push_imu` and :meth:`push_mag` return the
    :class:`Processed` chunks of the samples they let the navigator process. ``block_s``
    [s of IMU data]: how long a sample may wait for the ones after it, to be processed
    with them in one block (0: at once; the node's default is :data:`BLOCK_S`)."""

    config: PocketConfig
    calibration: MagCalibration | None = None
    mag_wait_s: float = MAG_WAIT_S
    correction_window_s: float = CORRECTION_WINDOW_S
    block_s: float = 0.0
    counts: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        self.navigator = PocketNavigator(self.config)
        # the navigator's state at past instants [s] and the inputs taken since
        self.replay: Replay[PocketNavigator, Samples] = Replay(
            PocketNavigator.copy_state, self.correction_window_s)
        self.corrections = {"accepted": 0, "refused": 0}
        self.last_stamp_ns: int | None = None
        # the readings a sample not yet processed may pair with: from the last one at or
        # before the last processed sample on (stamps [ns] ascending, values [T])
        self.mag_stamps = np.empty(0, np.int64)
        self.mag_values = np.empty((0, 3))
        self.held: list[tuple[int, np.ndarray, np.ndarray]] = []
        self.tail = AttitudeTail(ATTITUDE_KEPT_S)
        self.checked = self.mag_checked = False
        self.failed: str | None = None
        self.mag_error: str | None = None
        self.t0_ns: int | None = None
        self.processed_ns: int | None = None    # the last sample processed ...
        self.paired_ns: int | None = None       # ... and the last with a reading
        self.readings: dict[str, Readings] = {}     # the other sensors', once they read
        self.arrivals = Arrivals()                  # pushes held for a block (block_s)
        self.counts = {"non_finite": 0, "implausible": 0, "stamp_not_increasing": 0,
                       "mag_non_finite": 0,
                       "mag_missing": 0}

    # --- what the navigator says of itself ------------------------------------------
    @property
    def gyro_noise_var(self) -> float:
        """The orientation filter's σ_ν² [rad²/s²] per sample (its attitude messages')."""
        return self.navigator.gyro_noise_var

    def bound_warning(self) -> str | None:
        """Strides cut to what a person walks, said (None: none)."""
        return self.navigator.bound_warning()

    def speed_warning(self) -> str | None:
        """A walk faster than a person walks, said (None: it is not)."""
        return self.navigator.speed_warning()

    def placement(self) -> Placement:
        """Where the phone rides, its stride model and why (pdr_pocket.placement)."""
        return walk_placement(self.navigator)

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
        NaN/Inf is counted and dropped, one stamped before the last kept one dropped. With
        ``block_s``, held until the IMU's block (pdr_pocket.arrivals)."""
        stamps = np.array(stamp_ns, np.int64).reshape(-1)
        values = np.array(field_t, float).reshape(-1, 3)
        if self.block_s > 0:
            self.arrivals.add_readings(MAG, stamps, values)
            return []
        return self._take_mags(stamps, values)

    def _take_mags(self, stamps: np.ndarray, values: np.ndarray) -> list[Processed]:
        finite = np.isfinite(values).all(axis=1)
        self.counts["mag_non_finite"] += int((~finite).sum())
        if self.mag_error is not None:
            return []
        if self.calibration is not None and finite.any():
            values[finite] = self.calibration.apply(values[finite])
        start = self.mag_stamps[-1] if len(self.mag_stamps) else np.iinfo(np.int64).min
        before = latest_before(stamps, finite, start)
        kept = finite & (stamps >= before)
        self.mag_stamps = np.concatenate((self.mag_stamps, stamps[kept]))
        self.mag_values = np.vstack([self.mag_values, values[kept]])
        if self.last_stamp_ns is None and len(self.mag_stamps):   # no IMU yet: the last minute
            first = np.searchsorted(self.mag_stamps, self.mag_stamps[-1] - MAG_BEFORE_IMU_NS)
            self.mag_stamps, self.mag_values = self.mag_stamps[first:], self.mag_values[first:]
        if not self.checked:
            return []
        self._check_mag_units()
        return self._process(self._ready())

    def push_readings(self, name: str, stamp_ns: np.ndarray, values) -> list[Processed]:
        """Readings (N,) of the sensor ``name`` of pdr_pocket.sensor_inputs (SI units) in
        arrival order, as one block: one not finite, or stamped at or before the last kept
        one, is dropped and counted (``<name>_non_finite``, ``<name>_out_of_order``). With
        ``block_s``, held until the IMU's block (pdr_pocket.arrivals)."""
        stamps = np.array(stamp_ns, np.int64).reshape(-1)
        values = np.array(values, float).reshape(-1)
        if self.block_s > 0:
            self.arrivals.add_readings(name, stamps, values)
            return []
        return self._take_readings(name, stamps, values)

    def _take_readings(self, name: str, stamps: np.ndarray, values: np.ndarray
                       ) -> list[Processed]:
        readings = self.readings.setdefault(name, Readings())
        finite = np.isfinite(values)
        before = latest_before(stamps, finite, readings.newest_ns)
        kept = finite & (stamps > before)
        for what, count in (("non_finite", ~finite), ("out_of_order", finite & ~kept)):
            key = f"{name}_{what}"
            self.counts[key] = self.counts.get(key, 0) + int(count.sum())
        readings.add(stamps[kept], values[kept])
        if not kept.any() or not self.checked:
            return []
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
        time would be (the module docstring), one chunk for the whole block. With
        ``block_s``, held until ``block_s`` of them have come, then taken as one block
        after the other topics' readings that came meanwhile (pdr_pocket.arrivals)."""
        stamps = np.array(stamp_ns, np.int64).reshape(-1)
        a = np.array(accel, float).reshape(-1, 3)
        w = None if gyro is None else np.array(gyro, float).reshape(-1, 3)
        if self.block_s <= 0:
            return self._take_imus(stamps, a, w)
        self.arrivals.add_imus(stamps, a, w)
        return self._release() if self.arrivals.due(self.block_s) else []

    def _release(self) -> list[Processed]:
        """The pushes held (pdr_pocket.arrivals) taken: the readings, then the IMU's."""
        arrivals, self.arrivals = self.arrivals, Arrivals()
        out = []
        for name, stamps, values in arrivals.readings_blocks():
            out += self._take_mags(stamps, values) if name == MAG else \
                self._take_readings(name, stamps, values)
        for stamps, a, w in arrivals.imu_blocks():
            out += self._take_imus(stamps, a, w)
        return out

    def _take_imus(self, stamps: np.ndarray, a: np.ndarray, gyro: np.ndarray | None
                   ) -> list[Processed]:
        w = np.full_like(a, np.nan) if gyro is None else gyro
        checked = np.zeros_like(a) if gyro is None else w
        finite = np.isfinite(a).all(axis=1) & np.isfinite(checked).all(axis=1)
        valid = finite & plausible(a, checked)
        self.counts["non_finite"] += int((~finite).sum())
        self.counts["implausible"] += int((finite & ~valid).sum())
        start = np.iinfo(np.int64).min if self.last_stamp_ns is None else self.last_stamp_ns
        before = latest_before(stamps, valid, start)
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

    def release(self) -> list[Processed]:
        """Process what waits only for its block (``block_s``): the samples held for it and
        the readings that came with them, as the other sensors let them go (the IMU went
        quiet, or a correction comes that applies now: the node's idle timer and service)."""
        released = self._release()
        if not self.checked or self.failed is not None:
            return released
        return released + self._process(self._covered())

    def flush(self) -> list[Processed]:
        """Process every held sample (the end of a stream)."""
        released = self._release()
        if self.held and not self.checked and self.failed is None:
            self._check_units()
        return released + ([] if self.failed is not None else self._process(len(self.held)))

    def _check_units(self) -> None:
        self.checked = True
        try:
            check_units(np.array([h[1] for h in self.held]), np.array([h[2] for h in self.held]),
                        t_s=(np.array([h[0] for h in self.held]) - self.held[0][0]) * 1e-9)
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
        """How many held samples can be processed (:meth:`_covered`), none before the
        first has waited ``block_s`` of IMU data: the samples go to the navigator in
        blocks, whose call costs far less per sample than one call each."""
        if self.held and self.last_stamp_ns - self.held[0][0] < self.block_s * 1e9:
            return 0
        return self._covered()

    def _covered(self) -> int:
        """How many held samples the other sensors let go: those a reading stamped at or
        after them has come for, or ``mag_wait_s`` of IMU data has passed since, or all
        when the magnetometer is off or has been quiet that long."""
        covered = []
        if self.mag_error is None and not self.mag_stale:
            covered.append(self.mag_stamps[-1] if len(self.mag_stamps) else -1)
        covered += [r.newest_ns for r in self.readings.values() if r.newest_ns >= 0 and
                    self.last_stamp_ns - r.newest_ns <= self.mag_wait_s * 1e9]
        if not covered:
            return len(self.held)
        waited = self.last_stamp_ns - self.mag_wait_s * 1e9
        return int(np.searchsorted([h[0] for h in self.held], max(min(covered), waited),
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
        readings = {name: r.take(stamps, self.processed_ns) for name, r in self.readings.items()}
        missing = np.isnan(mag).any(axis=1)
        self.counts["mag_missing"] += int(missing.sum())
        self.processed_ns = int(stamps[-1])
        if not missing.all():
            self.paired_ns = int(stamps[~missing][-1])
        gyro = np.array([h[2] for h in held])
        samples = Samples(self._time_s(stamps), np.array([h[1] for h in held]),
                          None if np.isnan(gyro).all() else gyro, mag, **readings)
        out = self._run_kept(self.navigator, samples)
        return [Processed(stamps, out, self.t0_ns, [self.tail.at(s) for s in out.steps])]

    def _run_kept(self, navigator: PocketNavigator, samples: Samples) -> NavigatorOutput:
        """``navigator`` on a chunk of samples, kept in the history: the chunk in parts
        with a checkpoint before each, :data:`CHECKPOINT_EVERY_S` apart at least."""
        t, outputs, start = samples.t, [], 0
        while start < len(t):
            latest = self.replay.history.latest_s
            if latest is None or t[start] - latest >= CHECKPOINT_EVERY_S:
                latest = float(t[start])
                self.replay.history.remember(latest, navigator)
            end = int(np.searchsorted(t, latest + CHECKPOINT_EVERY_S, side="left"))
            end = max(end, start + 1)
            part = samples.part(start, end)
            outputs.append(navigator.process(part))
            self.tail.extend(outputs[-1].attitude)
            self.replay.history.record(part, float(t[end - 1]))
            start = end
        return outputs[0] if len(outputs) == 1 else NavigatorOutput.concatenate(outputs)

    # --- corrections at their step's stamp ------------------------------------------
    def apply_correction(self, correction: Correction) -> CorrectionResult:
        """:meth:`PocketNavigator.apply_correction` as of the sample stamped with the
        correction's ``stamp_ns`` [ns], the samples since run again; now when the stamp is
        0 (the module docstring): after the last sample processed, so with ``block_s``
        call :meth:`release` first for the samples that came before it."""
        stamp_ns = correction.stamp_ns
        if stamp_ns == 0:
            accepted, message = self.navigator.apply_correction(correction)
            if accepted and self.processed_ns is not None:
                t_now = self._time_s(self.processed_ns)
                self.replay.history.record(TakenCorrection(t_now, correction), t_now)
            return self._counted(CorrectionResult(accepted, message))
        problem = self._stamp_problem(stamp_ns)
        if problem is not None:
            return self._counted(CorrectionResult(False, f"nothing applied: {problem}"))
        return self._counted(self.replay.correct(self, correction, self._time_s(stamp_ns)))

    # --- the person's lines (pdr_pocket.line_calibration, the node stride_calibrator) --
    def take_lines(self, step_length: StepLengthConfig, stairs: StairsConfig) -> None:
        """The person's level line (``step_length``) and stairs lines (``stairs``) for
        the steps of the samples processed from now on (pdr_pocket.navigator.PocketNavigator
        .take_lines); the steps of the samples processed before keep theirs, also when a
        correction runs them again (the lines are an input of the replay's history,
        :class:`~pdr_pocket.navigator.TakenLines`). With ``block_s``, call :meth:`release`
        first for the samples that came before. A :meth:`reset` keeps them."""
        self.config = replace(self.config, step_length=step_length, stairs=stairs)
        self.navigator.take_lines(step_length, stairs)
        if self.processed_ns is not None:
            t_now = self._time_s(self.processed_ns)
            self.replay.history.record(TakenLines(t_now, step_length, stairs), t_now)

    # --- the replay's side (pdr_core.corrections.replay.Replayable) -------------------------------
    @staticmethod
    def worker(state: PocketNavigator) -> PocketNavigator:
        """The navigator kept at a past instant (the replay's copy) runs the inputs again
        itself."""
        return state

    def adopt(self, worker: PocketNavigator) -> None:
        self.navigator = worker

    def take(self, item: Samples | TakenCorrection | TakenLines) -> list[Revised]:
        """An input taken again and kept: the steps a chunk gives, run again."""
        if isinstance(item, TakenCorrection | TakenLines):
            self.navigator.rerun(item)
            self.replay.history.record(item, item.t_s)
            return []
        out = self._run_kept(self.navigator, item)
        return [Revised(stamp_of(self.t0_ns, s.t_confirm), s, self.tail.at(s)[0])
                for s in out.steps]

    def _stamp_problem(self, stamp_ns: int) -> str | None:
        """Why no kept state serves a correction stamped ``stamp_ns`` [ns] (None: one
        does)."""
        if self.processed_ns is None:
            return "the navigator has not started (no IMU sample processed yet)"
        if stamp_ns > self.processed_ns:
            return (f"stamp {stamp_ns} ns is after the last sample processed "
                    f"({self.processed_ns} ns): no step of this navigator")
        instants = self.replay.history.instants
        if not self.replay.serves(self._time_s(stamp_ns)):
            oldest = "nothing kept" if not instants else \
                f"kept back to {stamp_of(self.t0_ns, instants[0])} ns"
            return (f"stamp {stamp_ns} ns is older than the correction window "
                    f"(correction_window_s {self.correction_window_s:g} s of IMU data, "
                    f"{oldest}; the last sample processed {self.processed_ns} ns)")
        return None

    def _time_s(self, stamp_ns):
        """The navigator's time [s] of stamps [ns], one or an array (:func:`stamp_of`'s
        inverse)."""
        return (stamp_ns - self.t0_ns) * 1e-9

    def _counted(self, result: CorrectionResult) -> CorrectionResult:
        self.corrections["accepted" if result.accepted else "refused"] += 1
        return result
