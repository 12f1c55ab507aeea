"""The height filter's records (pdr_pocket.height_filter): its configuration in SI units
per epoch (:class:`HeightCoefficients`), what it says of a change (:class:`HeightChange`),
of the barometer (:class:`BarometerStatus`) and to a step (:class:`StepHeight`), and what it
keeps: the readings not yet processed (:class:`PendingReadings`), the processed epochs the
change detector looks back on (:class:`Epochs`, :func:`epoch_means`), a change in progress
(:class:`ChangeInProgress`) and a step's climb (:class:`Climb`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal, NamedTuple

import numpy as np

from pdr_core.maths.chi2 import chi2_quantile
from pdr_core.sensors.barometry import PA_PER_HPA, RIDE_KINDS, HeightChangeKind
from pdr_pocket.config import BarometerConfig

EPOCH_COLUMNS = ("start_s", "z", "n", "force", "still", "h")
SECONDS_PER_HOUR = 3600.0


class HeightCoefficients(NamedTuple):
    """What :class:`~pdr_pocket.config.BarometerConfig` means in SI units, per epoch, at
    the first reading's dh/dp [m/Pa]."""

    epoch_s: float
    reading_var_m2: float       # a 25 Hz reading's variance: (σ_p² + q²/12)·(dh/dp)²
    correlated_var_m2: float    # what an epoch's mean keeps: σ_c²·(dh/dp)²
    offset_walk_var_m2: float   # var(w_b) per epoch
    drift_var_m2ps2: float      # σ_w², the drift rate's stationary variance
    drift_decay: float          # φ = exp(−Δt/τ_w) per epoch
    jump_var_m2: float          # σ_j²
    gate_nis: float             # the χ² gate of the innovation (1 dof)
    motion_epochs: int          # W: the backward difference's span
    settle_epochs: int          # A: the level held before and after
    max_change_epochs: int

    @classmethod
    def from_config(cls, c: BarometerConfig, metres_per_pa: float) -> HeightCoefficients:
        m_per_hpa = abs(metres_per_pa) * PA_PER_HPA
        drift = c.weather_drift_hpa_per_h * m_per_hpa / SECONDS_PER_HOUR
        walk = c.offset_walk_hpa_per_sqrt_h * m_per_hpa / np.sqrt(SECONDS_PER_HOUR)
        return cls(
            c.epoch_s,
            (c.pressure_noise_hpa**2 + c.pressure_resolution_hpa**2 / 12.0) * m_per_hpa**2,
            (c.correlated_noise_hpa * m_per_hpa) ** 2, walk**2 * c.epoch_s, drift**2,
            float(np.exp(-c.epoch_s / c.weather_drift_time_s)),
            (c.offset_jump_sigma_hpa * m_per_hpa) ** 2,
            chi2_quantile(c.offset_jump_gate_probability, 1),
            epoch_count(c.motion_window_s, c.epoch_s), epoch_count(c.settle_s, c.epoch_s),
            epoch_count(c.max_change_s, c.epoch_s))


def epoch_count(seconds: float, epoch_s: float) -> int:
    return max(1, round(seconds / epoch_s))


@dataclass(frozen=True)
class HeightChange:
    """A change of the barometric height, judged (the module docstring): its kind, when
    it passed 10 % and 90 % [s], its height D [m] (+ up), the floors the filter's height
    moved by over it, and the vertical force's double integral over it [m] (NaN when
    there was none or the person was not still)."""

    kind: HeightChangeKind
    start_s: float
    end_s: float
    height_m: float
    floors: int
    accel_height_m: float

    @property
    def ride(self) -> bool:
        """A lift or escalator ride: its height went to h."""
        return self.kind in RIDE_KINDS


@dataclass(frozen=True)
class BarometerStatus:
    """Whether the barometer goes into the height: ``status`` "fused", "not fused" (turned
    off, not trusted, or its readings not yet processed) or "absent" (no reading); ``why``
    in words ("" when fused); the offset jumps let in so far; the readings' rate [Hz]
    (0 with fewer than two)."""

    status: Literal["fused", "not fused", "absent"]
    why: str
    offset_jumps: int
    rate_hz: float

    def as_dict(self) -> dict:
        return {"status": self.status, "why": self.why, "offset_jumps": self.offset_jumps,
                "rate_hz": round(self.rate_hz, 2)}


class StepHeight(NamedTuple):
    """A step's height above the start [m] and its σ [m], its floor, and the rides that
    ended since the step before (the module docstring)."""

    height_m: float
    sigma_m: float
    floor: int
    rides: tuple[HeightChange, ...]


@dataclass
class PendingReadings:
    """Readings given but not yet processed: stamps [s], values, and the last stamp."""

    t: list = field(default_factory=list)
    values: list = field(default_factory=list)
    last_t: float = -np.inf
    columns: int = 0            # the values' columns (0: one value per reading)

    def add(self, t: np.ndarray, values: np.ndarray) -> None:
        if len(t):
            self.t.append(t)
            self.values.append(values)
            self.last_t = float(t[-1])

    def take(self, first_epoch: int, end_epoch: int, epoch_s: float):
        """The readings of epochs [first_epoch, end_epoch): their epoch's offset from
        ``first_epoch`` and values; later ones stay, earlier ones are dropped."""
        if not self.t:
            return np.empty(0, np.int64), np.empty((0, self.columns) if self.columns else 0)
        t, values = np.concatenate(self.t), np.concatenate(self.values)
        epoch = np.floor(t / epoch_s).astype(np.int64)
        later = epoch >= end_epoch
        self.t, self.values = ([t[later]], [values[later]]) if later.any() else ([], [])
        now = (epoch >= first_epoch) & ~later
        return epoch[now] - first_epoch, values[now]


def epoch_means(offsets: np.ndarray, values: np.ndarray, count: int):
    """Per epoch of ``count``: the readings' number, mean and σ (NaN without readings).
    bincount adds each epoch's readings one after the other in order, so an epoch's
    figures do not depend on how its readings were chunked."""
    n = np.bincount(offsets, minlength=count)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.bincount(offsets, weights=values, minlength=count) / n
        spread = np.sqrt(np.bincount(offsets, weights=(values - mean[offsets]) ** 2,
                                     minlength=count) / n)
    return n, mean, spread


class Epochs:
    """The processed epochs the change detector looks back on, a column per
    :data:`EPOCH_COLUMNS`: per epoch its start [s], mean barometric height [m] and
    readings, mean f_up [m/s²] and whether the person stood still, and h after it [m].
    Epochs are indexed from the first processed; ``first`` is the oldest kept."""

    def __init__(self) -> None:
        self.first = 0
        self.columns: dict[str, list] = {name: [] for name in EPOCH_COLUMNS}

    def __len__(self) -> int:
        return self.first + len(self.columns["z"])

    def append(self, **values) -> None:
        for name, column in self.columns.items():
            column.append(values[name])

    def array(self, name: str, lo: int, hi: int) -> np.ndarray:
        """Epochs [lo, hi) of a column."""
        return np.asarray(self.columns[name][lo - self.first:hi - self.first], float)

    def value(self, name: str, index: int) -> float:
        return self.columns[name][index - self.first]

    def shift_h(self, lo: int, dh: float) -> None:
        """Add ``dh`` [m] to h from epoch ``lo`` on (a ride's height moved into h)."""
        h = self.columns["h"]
        for index in range(max(lo - self.first, 0), len(h)):
            h[index] += dh

    def forget_before(self, index: int) -> None:
        cut = index - self.first
        if cut > 0:
            for column in self.columns.values():
                del column[:cut]
            self.first = index


@dataclass
class ChangeInProgress:
    """A change of the barometric height in progress: the epoch it was first seen moving,
    the last one moving, and how many have been still since."""

    first: int
    last: int
    still_epochs: int = 0


@dataclass
class Climb:
    """A step's v [m] and variance [m²] climbed evenly from ``start`` to ``end`` [s], of
    which the share ``applied`` is in h."""

    start: float
    end: float
    v: float
    var: float
    applied: float = 0.0

    def share(self, t_s: float) -> float:
        """The share of the climb done by ``t_s``."""
        if t_s >= self.end:
            return 1.0
        if t_s <= self.start:
            return 0.0
        return (t_s - self.start) / (self.end - self.start)
