"""The foot navigator as samples arrive, one at a time or in blocks, for the live node,
with the same numbers as the offline :func:`pdr_ins_ekf.offline.navigate`.

Each stance decision needs ``detector.context(rate)`` samples before and after the
sample, so decisions, and the filter behind them, run that many samples behind the
input. The rate is the offline run's (:func:`pdr_ins_ekf.zero_velocity.sample_rate_hz`,
from the record's first intervals): nothing is decided before those samples are in. The
detector runs once per block, over the newly decidable samples and their context
(starting at the first sample near the start of the record, as offline); the filter is
aligned on the same first stationary period, and its block steps are the offline loop's
kernels (:meth:`ZuptEkf.run_block`), so the estimates agree with the offline run to
rounding. A block costs one detector call and one compiled loop, so a node that takes its
subscription's backlog in blocks keeps up with input rates far above its per-message
overhead.

Input hygiene as offline: samples with NaN/Inf or beyond any IMU's range
(pdr_core.sensors.imu_checks.plausible) and stamps that do not increase are dropped and counted;
gaps longer than ``max_gap_s`` are counted (the filter propagates over them).
Data in g or deg/s is refused at alignment (:class:`UnitsError`), after which nothing is
navigated until :meth:`reset`.

The filter runs with its recent past kept (pdr_ins_ekf.correctable): it gives the
strides (``FootRun.strides``) and takes a drift correction at the stride it names
(:meth:`StreamingNavigator.apply_correction`), the samples since filtered again; not with
the segmented smoother, which cannot go back.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.corrections.correction import Correction
from pdr_core.corrections.replay import CorrectionResult
from pdr_core.errors import InputError
from pdr_core.sensors.imu_checks import check_units, usable_samples
from pdr_ins_ekf.config import RunConfig
from pdr_ins_ekf.correctable import CORRECTION_WINDOW_S, CorrectableFilter, FilterBlock
from pdr_ins_ekf.offline import FootRun, check_rest
from pdr_ins_ekf.zero_velocity import RATE_PROBE_INTERVALS, sample_rate_hz
from pdr_ins_ekf.zupt_ekf import FilterOutput, SegmentSmoother, SmoothedSegment, ZuptEkf


class UnitsError(InputError):
    """The data at rest is not 1 g of specific force and near-zero rate."""


class _Rows:
    """(n, 3) samples appended at the back and dropped from the front, kept in one array
    (slices are views; no list of arrays to stack at every decision)."""

    def __init__(self, capacity: int = 1024) -> None:
        self._data = np.empty((capacity, 3))
        self._start = self._end = 0

    def __len__(self) -> int:
        return self._end - self._start

    def extend(self, rows: np.ndarray) -> None:
        """Append rows (n, 3); when the array is full, the kept rows move to its front
        (into one twice the size while they would fill more than half of it)."""
        if self._end + len(rows) > len(self._data):
            kept = self._data[self._start:self._end].copy()
            capacity = len(self._data)
            while 2 * (len(kept) + len(rows)) > capacity:
                capacity *= 2
            if capacity > len(self._data):
                self._data = np.empty((capacity, 3))
            self._data[:len(kept)] = kept
            self._start, self._end = 0, len(kept)
        self._data[self._end:self._end + len(rows)] = rows
        self._end += len(rows)

    def __getitem__(self, index):
        if isinstance(index, slice):
            a, b, _ = index.indices(len(self))
            return self._data[self._start + a:self._start + max(a, b)]
        return self._data[self._start + index]

    def __delitem__(self, index: slice) -> None:
        self._start += index.indices(len(self))[1]


@dataclass
class StreamingNavigator:
    """Push samples in stamp order; get the estimates that became available.

    Samples are kept from the oldest one still needed (by the detector's context or the
    alignment search), so memory is bounded once the filter runs.

    With ``config.smoother.mode`` "segmented", a :class:`SegmentSmoother` runs beside the
    filter from the same aligned start; its finished segments wait in :attr:`smoothed`
    (take them with :meth:`take_smoothed`), the last one at :meth:`flush`. "full" needs
    the whole record and is refused.
    """

    config: RunConfig
    correction_window_s: float = CORRECTION_WINDOW_S
    counts: dict[str, int] = field(default_factory=lambda: {
        "non_finite": 0, "implausible": 0, "stamp_not_increasing": 0, "gaps": 0})

    def __post_init__(self) -> None:
        if self.config.smoother.mode == "full":
            raise InputError("smoother.mode", "full smoothing needs the whole record: use "
                                              "segmented live, or pdr-ekf run --smoother full")
        self.reset()

    def reset(self) -> None:
        """Forget everything (the ``~/reset`` service)."""
        self.stamps: list[int] = []      # record indices [offset, offset + len)
        self.accel = _Rows()
        self.gyro = _Rows()
        self.stance: list[bool] = []     # record indices [offset, offset + len)
        self.statistic: list[float] = []
        self.offset = 0
        self.first_stamp = 0
        self.ekf: ZuptEkf | None = None
        self.filter: CorrectableFilter | None = None
        self.corrections = {"accepted": 0, "refused": 0}
        self.smoother: SegmentSmoother | None = None
        self.smoothed: list[SmoothedSegment] = []
        self.filter_start = 0
        self.next_filtered = 0
        self.failed: UnitsError | None = None
        self.detector_id = 0
        self.rate_hz: float | None = None
        self.units_checked = False
        for key in self.counts:
            self.counts[key] = 0

    @property
    def received(self) -> int:
        """Record index after the last kept sample."""
        return self.offset + len(self.stamps)

    def push(self, stamp_ns: int, accel, gyro) -> FootRun:
        """Add one sample (:meth:`push_many`)."""
        return self.push_many([stamp_ns], np.reshape(accel, (1, 3)), np.reshape(gyro, (1, 3)))

    def push_many(self, stamp_ns, accel, gyro) -> FootRun:
        """Add samples: stamps (N,) [ns], specific force [m/s²] and rate [rad/s] (N, 3) in
        the IMU frame. Returns the estimates of the samples now decided (none, or the
        same as :meth:`push` one at a time would give, in one block)."""
        stamp_ns = np.asarray(stamp_ns, np.int64)
        accel, gyro = np.asarray(accel, float), np.asarray(gyro, float)
        keep, dropped = usable_samples(stamp_ns, accel, gyro,
                                       self.stamps[-1] if self.stamps else None)
        for key, count in dropped.items():
            self.counts[key] += count
        stamp_ns = stamp_ns[keep]
        if len(stamp_ns):
            if not self.stamps and self.offset == 0:
                self.first_stamp = int(stamp_ns[0])
            previous = np.concatenate((self.stamps[-1:], stamp_ns))
            self.counts["gaps"] += int((np.diff(previous) * 1e-9 > self.config.max_gap_s).sum())
            self.stamps.extend(stamp_ns.tolist())
            self.accel.extend(accel[keep])
            self.gyro.extend(gyro[keep])
        if self.rate_hz is None and self.received > RATE_PROBE_INTERVALS:
            self.rate_hz = sample_rate_hz(np.array(self.stamps, np.int64))
        if self.rate_hz is None:
            return self._none_filtered()
        _, right = self.config.detector.context(self.rate_hz)
        return self._advance(self.received - 1 - right, final=False)

    def flush(self) -> FootRun:
        """At the end of the input: decide and filter the remaining samples."""
        if self.rate_hz is None:
            if self.received < 2:
                return self._none_filtered()
            self.rate_hz = sample_rate_hz(np.array(self.stamps, np.int64))
        out = self._advance(self.received - 1, final=True)
        if self.smoother is not None:
            last = self.smoother.finish()
            if last is not None:
                self.smoothed.append(last)
        return out

    def take_smoothed(self) -> list[SmoothedSegment]:
        """The smoothed segments finished since the last call."""
        out, self.smoothed = self.smoothed, []
        return out

    def _advance(self, last: int, final: bool) -> FootRun:
        if self.offset + len(self.stance) <= last:
            self._decide(self.offset + len(self.stance), last)
        if self.ekf is None and self.failed is None:
            self._check_units(final)
        if self.ekf is None and self.failed is None:
            self._try_align(final)
        out = self._filter(self.next_filtered, last)
        if self.ekf is not None:
            self._trim()
        return out

    def _decide(self, first: int, last: int) -> None:
        """The stance decisions of record samples first..last, each from its context (one
        detector call over the block's samples and their context)."""
        left, right = self.config.detector.context(self.rate_hz)
        start, stop = max(0, first - left), min(last + right, self.received - 1)
        a = self.accel[start - self.offset:stop + 1 - self.offset]
        w = self.gyro[start - self.offset:stop + 1 - self.offset]
        result = self.config.detector.detect(a, w, self.rate_hz)
        decided = slice(first - start, last + 1 - start)
        self.stance.extend(result.mask[decided].tolist())
        self.statistic.extend(result.statistic[decided].tolist())
        self.detector_id = result.detector

    def _t(self, k: int) -> float:
        return (self.stamps[k - self.offset] - self.first_stamp) * 1e-9

    def _check_units(self, final: bool) -> None:
        """Before alignment, once ``alignment_min_s`` of data is in: refuse g and deg/s
        (as offline does on the whole record), so that a detector that never fires on
        such data cannot leave the node waiting silently."""
        if self.units_checked or not self.stamps or (
                not final and self._t(self.received - 1) < self.config.alignment_min_s):
            return
        self.units_checked = True
        try:
            check_units(self.accel[:], self.gyro[:])
        except InputError as exc:
            self.failed = UnitsError(exc.source, exc.problem)

    def _try_align(self, final: bool) -> None:
        """Align on the first stationary run lasting alignment_min_s, once it has ended
        (as :func:`pdr_ins_ekf.offline.alignment_window` does on the whole record)."""
        mask = np.array(self.stance, bool)
        edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(int), [0]))))
        for start, stop in zip(edges[::2], edges[1::2], strict=True):
            if stop == len(mask) and not final:
                return
            if self._t(stop - 1) - self._t(start) >= self.config.alignment_min_s:
                a, w = self.accel[start:stop].copy(), self.gyro[start:stop].copy()
                try:
                    check_rest(a, w)
                except InputError as exc:
                    self.failed = UnitsError(exc.source, exc.problem)
                    return
                self.ekf = ZuptEkf.aligned(self.config.filter, a, w,
                                           np.radians(self.config.initial_yaw_deg))
                self.filter = CorrectableFilter(self.ekf, self.correction_window_s)
                if self.config.smoother.mode == "segmented":
                    self.smoother = SegmentSmoother(self.config.filter, self.config.smoother,
                                                    self.ekf)
                self.filter_start = self.next_filtered = int(start)
                return

    def _filter(self, first: int, last: int) -> FootRun:
        """Filter record samples first..last (none if last < first) in one block."""
        if self.ekf is None or last < first:
            return self._none_filtered()
        kept = slice(first - self.offset, last + 1 - self.offset)
        stamps = np.array(self.stamps[kept], np.int64)
        if first > self.filter_start:
            dt = np.diff((np.array(self.stamps[kept.start - 1:kept.stop], np.int64)
                          - self.first_stamp) * 1e-9)
        else:
            dt = np.concatenate(([0.0], np.diff((stamps - self.first_stamp) * 1e-9)))
        stance = np.array(self.stance[kept], bool)
        accel, gyro = self.accel[kept], self.gyro[kept]
        filtered = self.filter.run(FilterBlock(stamps, self._times_s(stamps), dt, accel.copy(),
                                               gyro.copy(), stance))
        if self.smoother is not None:
            for i, stamp in enumerate(stamps.tolist()):
                segment = self.smoother.step(stamp, accel[i], gyro[i], dt[i], stance[i])
                if segment is not None:
                    self.smoothed.append(segment)
        self.next_filtered = last + 1
        return FootRun(stamps, stance, np.array(self.statistic[kept], float),
                       self.detector_id, filtered.output, strides=filtered.strides)

    def _times_s(self, stamp_ns) -> np.ndarray:
        """Stamps [ns] as seconds from the first sample: the instants of the history."""
        return (np.asarray(stamp_ns, np.int64) - self.first_stamp) * 1e-9

    def apply_correction(self, correction: Correction) -> CorrectionResult:
        """Take a drift correction at the sample stamped ``correction.stamp_ns`` (0: now),
        the samples since filtered again (pdr_ins_ekf.correctable); refused by name before
        alignment and with the segmented smoother. Counted in :attr:`corrections`."""
        if self.filter is None:
            result = CorrectionResult(False, "nothing applied: the navigator has not aligned "
                                             "yet (no stationary start)")
        elif self.smoother is not None:
            result = CorrectionResult(False, "nothing applied: the segmented smoother runs "
                                             "beside the filter and cannot go back")
        else:
            t_s = (None if correction.stamp_ns == 0
                   else float(self._times_s(correction.stamp_ns)))
            result = self.filter.apply_correction(correction, t_s)
        self.corrections["accepted" if result.accepted else "refused"] += 1
        return result

    def _none_filtered(self) -> FootRun:
        """An empty block of estimates."""
        n = self.config.filter.states
        empty = FilterOutput(np.empty((0, 3)), np.empty((0, 3)), np.empty((0, 3, 3)),
                             np.empty((0, 6)), np.empty((0, n)), np.empty((0, 3, 3)),
                             np.empty((0, 3, 3)), np.empty(0))
        return FootRun(np.empty(0, np.int64), np.empty(0, bool), np.empty(0),
                       self.detector_id, empty)

    def _trim(self) -> None:
        """Drop the samples no decision or filter step will need again."""
        left, _ = self.config.detector.context(self.rate_hz)
        keep_from = min(self.offset + len(self.stance) - left, self.next_filtered - 1)
        drop = max(0, keep_from - self.offset)
        if drop:
            for buffer in (self.stamps, self.accel, self.gyro, self.stance, self.statistic):
                del buffer[:drop]
            self.offset += drop
