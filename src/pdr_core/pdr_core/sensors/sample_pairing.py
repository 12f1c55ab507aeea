"""A slow sensor's readings put on a fast sensor's samples, each reading once (issue 41).

The pocket navigator's time base is the IMU's samples; a sensor read more slowly (a
barometer at 25 Hz, pdr_pocket.sensor_inputs) gives each reading to the first IMU sample
stamped at or after it: 10 ms late at most at 100 Hz. Each reading lands once, so a
filter that takes it as a measurement counts it once, and the rule is the same offline
(pdr_pocket.inputs, the whole record) and live (pdr_pocket.streaming, sample blocks with
the stamp of the last sample before them), so both give the same samples. The
magnetometer, read at the IMU's rate and used at every sample, pairs otherwise
(pdr_core.sensors.magnetometer_pairing).

A phone's accelerometer and gyroscope, each in its own file at its own rate (a Sensor
Logger export: 100 Hz and 500 Hz), become one ``sensor_msgs/Imu`` stream at the slower
sensor's stamps (pdr_core.io.phone_import): each of its samples takes the mean of the faster
sensor's readings within the sample's own interval, from half the gap to the sample before
to half the gap to the one after. Nothing is interpolated or held: a mean over the
interval is what an integrator of the rate over that interval needs (the attitude
increment of a strapdown, to first order), it keeps no lag (the window is centred on the
sample), and a sample whose interval holds no reading (a gap of the faster sensor) gets
none. Two sensors at one rate and one stamp pair one to one.

- :func:`readings_at_samples`: the readings on the samples, NaN where none lands;
- :func:`interval_means`: the mean of the readings within each sample's interval, NaN
  where none is.
"""
from __future__ import annotations

import numpy as np


def readings_at_samples(sample_ns: np.ndarray, reading_ns: np.ndarray, values: np.ndarray,
                        previous_ns: int | None = None) -> np.ndarray:
    """Readings (M,) stamped ``reading_ns`` [ns] (ascending) on the samples stamped
    ``sample_ns`` [ns] (N,): each sample takes the latest reading stamped after the sample
    before it (``previous_ns`` before the first; None: any) and at or before itself, NaN
    where none is (the module docstring)."""
    sample_ns = np.asarray(sample_ns, np.int64)
    out = np.full(len(sample_ns), np.nan)
    if not len(reading_ns) or not len(sample_ns):
        return out
    latest = np.searchsorted(reading_ns, sample_ns, side="right") - 1
    before = np.concatenate(([np.iinfo(np.int64).min if previous_ns is None
                              else previous_ns], sample_ns[:-1]))
    ok = latest >= 0
    ok[ok] = np.asarray(reading_ns)[latest[ok]] > before[ok]
    out[ok] = np.asarray(values, float)[latest[ok]]
    return out


def interval_bounds(sample_ns: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The interval (start, end] [ns] of each sample stamped ``sample_ns`` (N,), ascending:
    from half the gap to the sample before to half the gap to the one after, so that the
    intervals tile the time axis (the first and the last sample take their one
    neighbour's half gap on their open side)."""
    sample_ns = np.asarray(sample_ns, np.int64)
    if len(sample_ns) < 2:
        return sample_ns - 1, sample_ns
    gap = np.diff(sample_ns)
    between = sample_ns[:-1] + gap // 2
    start = np.concatenate(([sample_ns[0] - gap[0] // 2], between))
    end = np.concatenate((between, [sample_ns[-1] + gap[-1] // 2]))
    return start, end


def interval_means(sample_ns: np.ndarray, reading_ns: np.ndarray, values: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
    """The mean (N, M) of the readings ``values`` (K, M) stamped ``reading_ns`` [ns]
    (ascending) within each sample's interval (:func:`interval_bounds` of ``sample_ns``,
    (N,) ascending), NaN where the interval holds none, and the count of readings in each
    (N,) int (the module docstring)."""
    values = np.asarray(values, float)
    values = values[:, None] if values.ndim == 1 else values
    start, end = interval_bounds(sample_ns)
    first = np.searchsorted(reading_ns, start, side="right")
    last = np.searchsorted(reading_ns, end, side="right")
    count = last - first
    sums = np.vstack([np.zeros((1, values.shape[1])), np.cumsum(values, axis=0)])
    with np.errstate(invalid="ignore", divide="ignore"):
        means = (sums[last] - sums[first]) / count[:, None]
    return means, count
