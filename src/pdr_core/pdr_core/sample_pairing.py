"""A slow sensor's readings put on a fast sensor's samples, each reading once (issue 41).

The pocket navigator's time base is the IMU's samples; a sensor read more slowly (a
barometer at 25 Hz, pdr_pocket.sensor_inputs) gives each reading to the first IMU sample
stamped at or after it: 10 ms late at most at 100 Hz. Each reading lands once, so a
filter that takes it as a measurement counts it once, and the rule is the same offline
(pdr_pocket.inputs, the whole record) and live (pdr_pocket.streaming, sample blocks with
the stamp of the last sample before them), so both give the same samples. The
magnetometer, read at the IMU's rate and used at every sample, pairs otherwise
(pdr_core.magnetometer_pairing).

- :func:`readings_at_samples`: the readings on the samples, NaN where none lands.
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
