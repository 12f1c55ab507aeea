"""Checks every navigator runs on IMU data before using it, and the importer's checks of
a CSV log's units.

- :func:`clean_samples`, :func:`usable_samples`: drop (and count) samples with NaN/Inf,
  beyond any IMU's range, or stamps that do not increase.
- :func:`check_units`: refuse an accelerometer in g or a gyroscope in deg/s.
- :func:`check_mag_units`: refuse a magnetometer not in tesla (µT, gauss, or tesla read
  as µT).
- :func:`check_sample_interval`: refuse stamps 1000 times too far apart or too close (a
  time column in ms imported as s).
- :func:`plausible`: samples within any IMU's reach (a garbage reading of 1e150 rad/s is
  finite but no measurement).
- :class:`PlausibleRange` and its instances :data:`SPECIFIC_FORCE_RANGE`,
  :data:`ANGULAR_RATE_RANGE`, :data:`FIELD_RANGE`, :data:`SAMPLE_INTERVAL_RANGE`: where a
  statistic of any walk's or rest's data lies, and which unit would bring data there
  (the fix a refusal names). The statistics: :func:`median_specific_force_mps2`,
  :func:`angular_rate_p99_radps`, :func:`median_field_t`, :func:`median_interval_s`.
- :func:`gravity_removed`: an accelerometer with gravity taken out (a phone app's "linear
  acceleration" or "user acceleration"), from :func:`slow_part_median_norm`.

Gravity-removed accelerometers. With gravity, the slow part of the specific force (its
moving mean over :data:`SLOW_PART_WINDOW_S`) is gravity seen from the turning sensor:
its norm stays near g whatever the motion, so its median is about the median |f| (0.88 to
1.13 times it in every shared recording, a foot's run at 2.2 g included: the run raises
|f| but averages out of the mean). Without gravity, walking's accelerations average out
over a stride: the slow part keeps only what the app's gravity estimate got wrong, and
its median norm falls to 0.19-0.43 times the median |f| (Sensor Logger's two exports).
Both are ratios of the same data, so the test holds in whatever unit the data were read:
data in g read as m/s² keep a ratio of 1 and get the unit hint, gravity-removed data
never do.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.io.batch import MessageBatch
from pdr_core.topics import IMU_DATA, IMU_MAG, graph_name
from pdr_core.units import (
    ACC_UNITS_MPS2,
    GYRO_UNITS_RADPS,
    MAG_UNITS_T,
    TIME_UNITS_S,
    UNIT_SYMBOLS,
)

# |B| of the Earth's field is 25-65 µT; a disturbed indoor field rarely exceeds 1 mT, nor
# falls below 1 µT
MAX_FIELD_T = 1e-3
MIN_FIELD_T = 1e-6
# Beyond any MEMS or tactical IMU's range (±400 g, ±20,000 °/s): not a measurement
MAX_PLAUSIBLE_ACCEL_MPS2 = 4000.0
MAX_PLAUSIBLE_RATE_RADPS = 350.0
# A foot turns at up to about 35 rad/s (2000 °/s): a 99th percentile of |ω| above this is
# a gyroscope in deg/s
MAX_WALK_RATE_RADPS = 50.0
# The median |f| of data in g (about 1) read as m/s² falls between these [m/s²]
G_LIKE_MEDIAN_MPS2 = (0.5, 2.0)
# The slow part of a specific force: its moving mean over this window [s], a stride or two
SLOW_PART_WINDOW_S = 1.0
# Below this ratio of the slow part's median norm to the median |f|, gravity is missing:
# with gravity 0.88-1.13, without 0.19-0.43 (module docstring)
GRAVITY_REMOVED_SLOW_RATIO = 0.5


@dataclass(frozen=True)
class PlausibleRange:
    """Where one statistic of a sensor's data lies for any walk or rest, in SI units."""

    statistic: str      # what is measured, e.g. "median |f|"
    si_unit: str        # the symbol of its SI unit, e.g. "m/s²"
    low_si: float       # the least plausible value
    high_si: float      # the largest plausible value
    typical_si: float   # of the units that make data plausible, the one nearest is proposed
    expected: str       # the range as a reader reads it, e.g. "1-1000 µT"

    def contains(self, value_si: float) -> bool:
        return self.low_si <= value_si <= self.high_si

    def excludes(self, value_si: float) -> bool:
        """Below or above the range; NaN (no data, e.g. an IMU without gyroscope) is not."""
        return value_si < self.low_si or value_si > self.high_si

    def unit_fix(self, value_si: float, units: dict[str, float],
                 read_in: float = 1.0) -> str | None:
        """The name of the unit of ``units`` (name -> SI factor) that makes the data
        plausible, had they been read with the SI factor ``read_in`` and had the
        statistic ``value_si``: of those that do, the one whose value is nearest (in
        ratio) the typical one; None when no unit does."""
        raw = value_si / read_in
        fits = [(abs(math.log(raw * factor / self.typical_si)), name)
                for name, factor in units.items()
                if raw * factor > 0 and self.contains(raw * factor)]
        return min(fits, key=lambda fit: fit[0])[1] if fits else None


# A walk's or a rest's median |f| is about g; a foot-mounted IMU's in a run reaches 2.2 g
SPECIFIC_FORCE_RANGE = PlausibleRange("median |f|", "m/s²", 0.5 * STANDARD_GRAVITY_MPS2,
                                      5.0 * STANDARD_GRAVITY_MPS2, STANDARD_GRAVITY_MPS2,
                                      "0.5-5 g, 4.9-49 m/s²")
ANGULAR_RATE_RANGE = PlausibleRange("99th percentile of |ω|", "rad/s", 0.0,
                                    MAX_WALK_RATE_RADPS, 3.0, "at most 50 rad/s")
FIELD_RANGE = PlausibleRange("median |B|", "T", MIN_FIELD_T, MAX_FIELD_T, 50e-6, "1-1000 µT")
# An IMU log is sampled at 5 Hz to 10 kHz
SAMPLE_INTERVAL_RANGE = PlausibleRange("median sample interval", "s", 1e-4, 0.2, 0.01,
                                       "0.1 ms-0.2 s, 5-10000 Hz")


def median_specific_force_mps2(accel: np.ndarray) -> float:
    """Median |f| [m/s²] of (N, 3) specific forces [m/s²]: about g for any walk or rest."""
    return float(np.median(np.linalg.norm(accel, axis=1)))


def slow_part_median_norm(t_s: np.ndarray, accel: np.ndarray) -> float:
    """Median norm of the slow part of (N, 3) specific forces ``accel`` (any unit; the
    result is in it) sampled at the increasing stamps ``t_s`` [s] (N,): their moving mean
    over :data:`SLOW_PART_WINDOW_S` (a window of round(window / median interval) samples,
    whole windows only). NaN when the data do not fill one window."""
    if len(t_s) < 2:
        return float("nan")
    interval = median_interval_s(t_s)
    window = max(1, round(SLOW_PART_WINDOW_S / interval)) if interval > 0 else len(t_s) + 1
    if window > len(accel):
        return float("nan")
    sums = np.cumsum(np.vstack([np.zeros((1, 3)), accel]), axis=0)
    slow = (sums[window:] - sums[:-window]) / window
    return float(np.median(np.linalg.norm(slow, axis=1)))


def gravity_removed(t_s: np.ndarray, accel: np.ndarray) -> bool:
    """Whether the (N, 3) accelerometer readings ``accel`` (any unit) at the stamps ``t_s``
    [s] look gravity-removed: the median norm of their slow part
    (:func:`slow_part_median_norm`) below :data:`GRAVITY_REMOVED_SLOW_RATIO` times their
    median |f| (module docstring). False when the data do not fill one window."""
    slow = slow_part_median_norm(t_s, accel)
    return bool(slow < GRAVITY_REMOVED_SLOW_RATIO * median_specific_force_mps2(accel))


def angular_rate_p99_radps(gyro: np.ndarray) -> float:
    """99th percentile of |ω| [rad/s] of (N, 3) angular rates [rad/s]."""
    return float(np.percentile(np.linalg.norm(gyro, axis=1), 99))


def median_field_t(mag: np.ndarray) -> float:
    """Median |B| [T] of (N, 3) magnetic field readings [T]."""
    return float(np.median(np.linalg.norm(mag, axis=1)))


def median_interval_s(t_s: np.ndarray) -> float:
    """Median interval [s] between the increasing stamps ``t_s`` [s] (N >= 2)."""
    return float(np.median(np.diff(t_s)))


def plausible(accel: np.ndarray, gyro: np.ndarray) -> np.ndarray:
    """Per sample (or for one sample): finite and within :data:`MAX_PLAUSIBLE_ACCEL_MPS2`
    and :data:`MAX_PLAUSIBLE_RATE_RADPS` on every axis."""
    accel, gyro = np.asarray(accel, float), np.asarray(gyro, float)
    with np.errstate(invalid="ignore"):
        return ((np.abs(accel) <= MAX_PLAUSIBLE_ACCEL_MPS2).all(axis=-1)
                & (np.abs(gyro) <= MAX_PLAUSIBLE_RATE_RADPS).all(axis=-1))


def clean_samples(imu: MessageBatch) -> tuple[np.ndarray, dict[str, int]]:
    """Indices of the usable samples of a record and the counts of the dropped ones
    (:func:`usable_samples`)."""
    keep, counts = usable_samples(imu.stamp_ns, imu["linear_acceleration"],
                                  imu["angular_velocity"])
    return np.flatnonzero(keep), counts


def usable_samples(stamp_ns: np.ndarray, accel: np.ndarray, gyro: np.ndarray,
                   after_ns: int | None = None) -> tuple[np.ndarray, dict[str, int]]:
    """Mask of the usable samples (N,) and the counts of the dropped ones: NaN/Inf, beyond
    any IMU's range (:func:`plausible`), then stamps [ns] not later than every usable one
    before (and than ``after_ns``, the last kept before these), in that order, as the
    live nodes drop them one sample at a time."""
    finite = np.isfinite(accel).all(axis=1) & np.isfinite(gyro).all(axis=1)
    sane = finite & plausible(accel, gyro)
    stamps = np.where(sane, np.asarray(stamp_ns, np.int64), np.iinfo(np.int64).min)
    before = np.maximum.accumulate(stamps)[:-1]
    if after_ns is None:
        later = np.concatenate(([True], stamps[1:] > before))
    else:
        later = stamps > np.maximum(np.concatenate(([after_ns], before)), after_ns)
    keep = sane & later
    return keep, {"non_finite": int((~finite).sum()),
                  "implausible": int((finite & ~sane).sum()),
                  "stamp_not_increasing": int((sane & ~later).sum())}


def check_units(accel: np.ndarray, gyro: np.ndarray, topic: str = graph_name(IMU_DATA),
                t_s: np.ndarray | None = None) -> None:
    """Refuse data in the wrong units, naming ``topic``, the value and the fix. The median
    |f| of any walk or rest is near g: one between :data:`G_LIKE_MEDIAN_MPS2` gives away
    data in g, unless, with their stamps ``t_s`` [s], they look gravity-removed
    (:func:`gravity_removed`: a phone's linear acceleration, about 0.1-0.3 g while it
    moves), which no unit fixes (pdr_core.walking.walk_plausibility names it); a 99th percentile
    of |ω| above :data:`MAX_WALK_RATE_RADPS` gives away data in deg/s."""
    f = median_specific_force_mps2(accel)
    if G_LIKE_MEDIAN_MPS2[0] < f < G_LIKE_MEDIAN_MPS2[1] and (
            t_s is None or not gravity_removed(np.asarray(t_s, float), accel)):
        raise InputError(topic, _wrong_unit(SPECIFIC_FORCE_RANGE, f, "the accelerometer", "m/s²",
                                            ACC_UNITS_MPS2, "--acc-unit"))
    w = angular_rate_p99_radps(gyro)
    if ANGULAR_RATE_RANGE.excludes(w):
        raise InputError(topic, _wrong_unit(ANGULAR_RATE_RANGE, w, "the gyroscope", "rad/s",
                                            GYRO_UNITS_RADPS, "--gyro-unit"))


def check_mag_units(mag: np.ndarray, topic: str = graph_name(IMU_MAG)) -> None:
    """Refuse magnetometer data that is not in tesla, naming ``topic``, the value and the
    fix: a median |B| above :data:`MAX_FIELD_T` is µT (25-65 for the Earth's field) or
    gauss (0.25-0.65) data, one below :data:`MIN_FIELD_T` tesla data imported as µT."""
    b = median_field_t(mag)
    if FIELD_RANGE.excludes(b):
        raise InputError(topic, _wrong_unit(FIELD_RANGE, b, "the magnetometer", "tesla",
                                            MAG_UNITS_T, "--mag-unit", default="ut"))


def check_sample_interval(t_s: np.ndarray, topic: str = graph_name(IMU_DATA)) -> None:
    """Refuse stamps [s] whose median interval lies beyond :data:`SAMPLE_INTERVAL_RANGE`
    (5-10000 Hz), naming ``topic``, the interval and the fix; fewer than two pass."""
    if len(t_s) < 2:
        return
    interval = median_interval_s(t_s)
    if SAMPLE_INTERVAL_RANGE.excludes(interval):
        raise InputError(topic, _wrong_unit(SAMPLE_INTERVAL_RANGE, interval, "the time column",
                                            "s", TIME_UNITS_S, "--time-unit"))


def _wrong_unit(plausible_range: PlausibleRange, value_si: float, sensor: str,
                si_name: str, units: dict[str, float], flag: str,
                default: str | None = None) -> str:
    """Why a topic's data look like they are in another unit, and the fix: the import
    unit that makes them plausible, whether the topic holds the file's numbers as they
    were (imported in SI) or scaled by the importer's ``default`` unit."""
    problem = (f"{plausible_range.statistic} {value_si:.4g} {plausible_range.si_unit} "
               f"(expected {plausible_range.expected})")
    fix = plausible_range.unit_fix(value_si, units)
    if fix is not None:
        return (f"{problem}: {sensor} looks like it is in {UNIT_SYMBOLS[fix]}, not "
                f"{si_name}; re-import with pdr-sim import-csv {flag} {fix}")
    fix = None if default is None else \
        plausible_range.unit_fix(value_si, units, read_in=units[default])
    if fix is not None:
        return (f"{problem}: {sensor} looks like a column in {UNIT_SYMBOLS[fix]} imported "
                f"as {UNIT_SYMBOLS[default]}; re-import with pdr-sim import-csv {flag} {fix}")
    return (f"{problem}: {sensor} is not in {si_name}, nor in any unit of pdr-sim "
            f"import-csv {flag}; check the columns it was imported from")
