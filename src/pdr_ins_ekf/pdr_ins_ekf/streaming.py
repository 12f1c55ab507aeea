"""The foot navigator sample by sample, for the live node, with the same numbers as the
offline :func:`pdr_ins_ekf.offline.navigate`.

Each stance decision needs ``detector.context`` samples before and after the sample, so
decisions, and the filter behind them, run that many samples behind the input. The
detector is evaluated on exactly the samples its decision depends on (starting at the
first sample near the start of the record, as offline), the filter is aligned on the
same first stationary period, and the filter steps are the offline ones
(:meth:`ZuptEkf.step`), so the estimates agree with the offline run to rounding.

Input hygiene as offline: samples with NaN/Inf or beyond any IMU's range
(pdr_core.imu_checks.plausible) and stamps that do not increase are dropped and counted;
gaps longer than ``max_gap_s`` are counted (the filter propagates over them).
Data in g or deg/s is refused at alignment (:class:`UnitsError`), after which nothing is
navigated until :meth:`reset`.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.errors import InputError
from pdr_core.imu_checks import check_units, plausible
from pdr_ins_ekf.config import RunConfig
from pdr_ins_ekf.offline import check_rest
from pdr_ins_ekf.zupt_ekf import SegmentSmoother, SmoothedSegment, ZuptEkf


class UnitsError(InputError):
    """The data at rest is not 1 g of specific force and near-zero rate."""


@dataclass
class Estimate:
    """The filter's state after one sample (ENU, SI)."""

    stamp_ns: int
    position: np.ndarray
    velocity: np.ndarray
    attitude: np.ndarray
    covariance: np.ndarray
    stance: bool
    statistic: float
    detector: int


class _Rows:
    """(n, 3) samples appended one at a time and dropped from the front, kept in one
    array (slices are views; no list of arrays to stack at every decision)."""

    def __init__(self, capacity: int = 1024) -> None:
        self._data = np.empty((capacity, 3))
        self._start = self._end = 0

    def __len__(self) -> int:
        return self._end - self._start

    def append(self, row: np.ndarray) -> None:
        if self._end == len(self._data):
            kept = self._data[self._start:self._end]
            if 2 * len(kept) > len(self._data):
                self._data = np.empty((2 * len(self._data), 3))
            self._data[:len(kept)] = kept.copy()
            self._start, self._end = 0, len(kept)
        self._data[self._end] = row
        self._end += 1

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
        self.smoother: SegmentSmoother | None = None
        self.smoothed: list[SmoothedSegment] = []
        self.filter_start = 0
        self.next_filtered = 0
        self.failed: UnitsError | None = None
        self.detector_id = 0
        self.units_checked = False
        for key in self.counts:
            self.counts[key] = 0

    @property
    def received(self) -> int:
        """Record index after the last kept sample."""
        return self.offset + len(self.stamps)

    def push(self, stamp_ns: int, accel, gyro) -> list[Estimate]:
        """Add one sample; returns the estimates of the samples now decided."""
        accel, gyro = np.asarray(accel, float), np.asarray(gyro, float)
        if not (np.isfinite(accel).all() and np.isfinite(gyro).all()):
            self.counts["non_finite"] += 1
            return []
        if not plausible(accel, gyro):
            self.counts["implausible"] += 1
            return []
        if self.stamps and stamp_ns <= self.stamps[-1]:
            self.counts["stamp_not_increasing"] += 1
            return []
        if not self.stamps and self.offset == 0:
            self.first_stamp = int(stamp_ns)
        elif (stamp_ns - self.stamps[-1]) * 1e-9 > self.config.max_gap_s:
            self.counts["gaps"] += 1
        self.stamps.append(int(stamp_ns))
        self.accel.append(accel)
        self.gyro.append(gyro)
        _, right = self.config.detector.context
        return self._advance(self.received - 1 - right, final=False)

    def flush(self) -> list[Estimate]:
        """At the end of the input: decide and filter the remaining samples."""
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

    def _advance(self, last: int, final: bool) -> list[Estimate]:
        while self.offset + len(self.stance) <= last:
            self._decide(self.offset + len(self.stance))
        if self.ekf is None and self.failed is None:
            self._check_units(final)
        if self.ekf is None and self.failed is None:
            self._try_align(final)
        if self.ekf is None:
            return []
        out = [self._filter(k) for k in range(self.next_filtered, last + 1)]
        self._trim()
        return out

    def _decide(self, k: int) -> None:
        """The stance decision of record sample k, from exactly its context."""
        left, right = self.config.detector.context
        start, stop = max(0, k - left), min(k + right, self.received - 1)
        a = self.accel[start - self.offset:stop + 1 - self.offset]
        w = self.gyro[start - self.offset:stop + 1 - self.offset]
        result = self.config.detector.detect(a, w, 0.0)
        self.stance.append(bool(result.mask[k - start]))
        self.statistic.append(float(result.statistic[k - start]))
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
                if self.config.smoother.mode == "segmented":
                    self.smoother = SegmentSmoother(self.config.filter, self.config.smoother,
                                                    self.ekf)
                self.filter_start = self.next_filtered = int(start)
                return

    def _filter(self, k: int) -> Estimate:
        i = k - self.offset
        dt = self._t(k) - self._t(k - 1) if k > self.filter_start else 0.0
        self.ekf.step(self.accel[i], self.gyro[i], dt, self.stance[i])
        if self.smoother is not None:
            segment = self.smoother.step(self.stamps[i], self.accel[i], self.gyro[i], dt,
                                         self.stance[i])
            if segment is not None:
                self.smoothed.append(segment)
        self.next_filtered = k + 1
        return Estimate(self.stamps[i], self.ekf.p.copy(), self.ekf.v.copy(),
                        self.ekf.C.copy(), self.ekf.P.copy(), self.stance[i],
                        self.statistic[i], self.detector_id)

    def _trim(self) -> None:
        """Drop the samples no decision or filter step will need again."""
        left, _ = self.config.detector.context
        keep_from = min(self.offset + len(self.stance) - left, self.next_filtered - 1)
        drop = max(0, keep_from - self.offset)
        if drop:
            for buffer in (self.stamps, self.accel, self.gyro, self.stance, self.statistic):
                del buffer[:drop]
            self.offset += drop
