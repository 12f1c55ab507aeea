"""Step detection for a phone in the trouser pocket (Muñoz Díaz 2016, Section 4.1).

A *step* is one gait cycle of the sensor leg: two footfalls. Every detector here takes
the same inputs, t [s] (N,), the thigh pitch θ [rad] (N,) and the specific force α
[m/s²] (N, 3) in the sensor frame, and returns :class:`DetectedSteps`:

- :class:`PitchMaximumDetector`: the thesis' detector, one maximum of θ per cycle
  (Section 4.1.1; hysteresis and plausibility rules in :mod:`pdr_pocket.compiled_peaks`).
  It also runs one sample at a time (:meth:`~PitchMaximumDetector.push`) with the same
  state, which the navigator uses live.
- :class:`FootfallDetector`, beyond the thesis, for an IMU without gyroscope: footfalls as
  peaks of ‖α‖ low-passed at ``footfall_cutoff_hz`` (the textbook step counter, Table
  4.1's "LPF ‖α‖" with a prominence and a minimum interval instead of a fixed threshold;
  scipy.signal.find_peaks' rules, causally), every second one closing a gait cycle. It
  needs no pitch, which the gravity direction alone gives only roughly.
- The baselines of Table 4.1: :class:`AccelerationPeakDetector` (peaks of ‖α‖, and with
  ``lowpass_samples=15`` of ‖α‖ through a 15-sample moving average: footfalls, two per
  cycle) and :class:`PitchZeroCrossingDetector` (θ crossing zero upwards, once per
  cycle; no crossing when θ_min > 0, as downstairs, Fig. 4.6).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.walking.gait import GAIT_MIN_FOOTFALLS
from pdr_pocket.compiled_biquads import sos_filter
from pdr_pocket.compiled_peaks import (
    EV_MAX,
    EV_MIN,
    EV_T_MAX,
    EV_T_MIN,
    N_EVENT_COLUMNS,
    PeakParams,
    footfall_loop,
    new_footfall_state,
    new_peak_state,
    peak_loop,
)
from pdr_pocket.config import StepsConfig
from pdr_pocket.lowpass_design import butterworth_sections, steady_state_delays

# The baselines' fixed thresholds, "adapted to a comfortable walking speed" as in Table 4.1:
# just below the weaker footfall's peak of ‖α‖ at 3.5 km/h (12.3 m/s² raw and low-passed,
# 5th percentile, on the simulated H1 walk with the Xsens MTw profile).
ACC_PEAK_THRESHOLD_MPS2 = STANDARD_GRAVITY_MPS2 + 2.3
ACC_PEAK_MIN_INTERVAL_S = 0.35                          # between two footfalls
LOWPASS_PEAK_THRESHOLD_MPS2 = STANDARD_GRAVITY_MPS2 + 2.3
ZERO_CROSSING_HYSTERESIS_DEG = 1.0


@dataclass(frozen=True)
class DetectedSteps:
    """Detections: ``t`` [s] the instant of each (the pitch maximum, a footfall's peak or
    the zero crossing); ``per_cycle`` 1 when each detection is a gait cycle (a step), 2
    when it is a footfall. θ_max, θ_min [rad] for the pitch maximum, else NaN."""

    t: np.ndarray
    per_cycle: int
    pitch_max: np.ndarray
    pitch_min: np.ndarray
    t_min: np.ndarray


def peak_params(config: StepsConfig) -> PeakParams:
    return PeakParams(np.radians(config.drop_min_deg), config.drop_fraction,
                      np.radians(config.rise_min_deg), config.rise_fraction,
                      np.radians(config.min_amplitude_deg),
                      np.radians(config.max_amplitude_deg), config.max_rise_s,
                      config.max_hold_s, config.min_step_period_s, config.max_step_period_s)


class PitchMaximumDetector:
    """One step per maximum of the thigh pitch (Muñoz Díaz 2016, Section 4.1.1)."""

    name = "pitch maximum"

    def __init__(self, config: StepsConfig | None = None) -> None:
        self.config = config or StepsConfig()
        self.params = peak_params(self.config)
        self.state = new_peak_state()

    def restart(self) -> None:
        """Seek a minimum afresh, with no amplitude or step remembered."""
        self.state = new_peak_state()

    def push(self, t: np.ndarray, pitch: np.ndarray, force: np.ndarray | None = None
             ) -> np.ndarray:
        """Samples in order; the confirmed maxima, rows of compiled_peaks.EV_* columns
        (``force``, the specific force's norm, is not used)."""
        t = np.ascontiguousarray(t, dtype=float)
        # a footfall per sample at most, and the waiting ones of a run released with one
        events = np.empty(((len(t) + GAIT_MIN_FOOTFALLS) // 2 + 1, N_EVENT_COLUMNS))
        count = peak_loop(self.state, self.params, t,
                          np.ascontiguousarray(pitch, dtype=float), events)
        return events[:count]

    def detect(self, t: np.ndarray, pitch: np.ndarray, accel: np.ndarray) -> DetectedSteps:
        """A whole record, from a fresh state (this detector's is left alone)."""
        rows = PitchMaximumDetector(self.config).push(t, pitch)
        return DetectedSteps(rows[:, EV_T_MAX], 1, rows[:, EV_MAX], rows[:, EV_MIN],
                             rows[:, EV_T_MIN])


RATE_SAMPLES = 10       # the sample rate is read off the first intervals


class FootfallDetector:
    """Gait cycles from the footfalls in the specific force's norm (module docstring).
    The low-pass is a fourth-order Butterworth at the rate of the first
    :data:`RATE_SAMPLES` intervals (the samples wait for them), carried across calls."""

    name = "footfalls in the specific force's norm"

    def __init__(self, config: StepsConfig | None = None) -> None:
        self.config = config or StepsConfig()
        self.state = new_footfall_state()
        self.sos: np.ndarray | None = None
        self.zi: np.ndarray | None = None
        self.waiting: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    @property
    def footfalls(self) -> int:
        return int(self.state.scalars[0].footfalls)

    def restart(self) -> None:
        """Nothing: the footfalls do not depend on how the phone sits."""

    def push(self, t: np.ndarray, pitch: np.ndarray, force: np.ndarray) -> np.ndarray:
        """Samples in order: times [s], the pitch [rad] (NaN: unknown) and the specific
        force's norm [m/s²]; the cycles closed, rows of compiled_peaks.EV_* columns."""
        t, pitch, force = (np.ascontiguousarray(x, dtype=float) for x in (t, pitch, force))
        if not len(t):          # (the navigator's stretch between two mounting changes)
            return np.empty((0, N_EVENT_COLUMNS))
        if self.sos is None:
            if self.waiting is not None:
                t, pitch, force = (np.concatenate(pair) for pair in
                                   zip(self.waiting, (t, pitch, force), strict=True))
            if len(t) <= RATE_SAMPLES:
                self.waiting = (t, pitch, force)
                return np.empty((0, N_EVENT_COLUMNS))
            self.waiting = None
            self._design(float(np.median(np.diff(t[:RATE_SAMPLES + 1]))), force[0])
        low = sos_filter(self.sos, force, self.zi)
        # a footfall per sample at most, and the waiting ones of a run released with one
        events = np.empty(((len(t) + GAIT_MIN_FOOTFALLS) // 2 + 1, N_EVENT_COLUMNS))
        c = self.config
        count = footfall_loop(self.state, c.footfall_prominence_mps2, c.footfall_min_interval_s,
                              0.5 * c.max_step_period_s, t, np.ascontiguousarray(low), pitch,
                              events)
        return events[:count]

    def _design(self, period_s: float, first: float) -> None:
        nyquist = 0.5 / period_s
        cutoff = min(self.config.footfall_cutoff_hz, 0.8 * nyquist)
        self.sos = butterworth_sections(4, cutoff / nyquist)
        self.zi = steady_state_delays(self.sos) * first

    def detect(self, t: np.ndarray, pitch: np.ndarray, accel: np.ndarray) -> DetectedSteps:
        """A whole record, from a fresh state: the cycles."""
        rows = FootfallDetector(self.config).push(t, pitch, np.linalg.norm(accel, axis=1))
        return DetectedSteps(rows[:, EV_T_MAX], 1, rows[:, EV_MAX], rows[:, EV_MIN],
                             rows[:, EV_T_MIN])


def _no_pitch(t: np.ndarray, per_cycle: int) -> DetectedSteps:
    nan = np.full(len(t), np.nan)
    return DetectedSteps(np.asarray(t, float), per_cycle, nan, nan, nan)


class AccelerationPeakDetector:
    """Footfalls as peaks of ‖α‖ above a fixed threshold, at least
    :data:`ACC_PEAK_MIN_INTERVAL_S` apart; ``lowpass_samples`` > 1 averages ‖α‖ over that
    many samples first (Table 4.1, "LPF ‖α‖")."""

    def __init__(self, lowpass_samples: int = 1) -> None:
        self.lowpass_samples = lowpass_samples
        self.threshold = (LOWPASS_PEAK_THRESHOLD_MPS2 if lowpass_samples > 1
                          else ACC_PEAK_THRESHOLD_MPS2)
        self.name = f"LPF({lowpass_samples}) |acc| peaks" if lowpass_samples > 1 \
            else "|acc| peaks"

    def detect(self, t: np.ndarray, pitch: np.ndarray, accel: np.ndarray) -> DetectedSteps:
        norm = np.linalg.norm(accel, axis=1)
        if self.lowpass_samples > 1:
            kernel = np.ones(self.lowpass_samples) / self.lowpass_samples
            norm = np.convolve(norm, kernel, mode="full")[:len(norm)]   # causal average
        above = norm > self.threshold
        starts = np.flatnonzero(above & ~np.r_[False, above[:-1]])
        ends = np.flatnonzero(above & ~np.r_[above[1:], False])
        peaks = [a + int(np.argmax(norm[a:b + 1])) for a, b in zip(starts, ends, strict=True)]
        kept: list[int] = []
        for p in peaks:
            if not kept or t[p] - t[kept[-1]] >= ACC_PEAK_MIN_INTERVAL_S:
                kept.append(p)
        return _no_pitch(np.asarray(t)[kept], 2)


class PitchZeroCrossingDetector:
    """One step per upward zero crossing of θ (Table 4.1, "Pitch z-c"): armed once θ is
    below −:data:`ZERO_CROSSING_HYSTERESIS_DEG`, so that noise about zero while standing
    is not a step."""

    name = "pitch zero crossing"

    def __init__(self) -> None:
        self.hysteresis = np.radians(ZERO_CROSSING_HYSTERESIS_DEG)

    def detect(self, t: np.ndarray, pitch: np.ndarray, accel: np.ndarray) -> DetectedSteps:
        p = np.asarray(pitch, float)
        armed, out = False, []
        for k in np.flatnonzero(np.isfinite(p)):
            if p[k] < -self.hysteresis:
                armed = True
            elif armed and p[k] >= 0.0:
                out.append(t[k])
                armed = False
        return _no_pitch(np.asarray(out), 1)


def table_4_1_detectors(config: StepsConfig | None = None) -> list:
    """The four detectors of Muñoz Díaz 2016, Table 4.1, in its order."""
    return [AccelerationPeakDetector(1), AccelerationPeakDetector(15),
            PitchZeroCrossingDetector(), PitchMaximumDetector(config)]
