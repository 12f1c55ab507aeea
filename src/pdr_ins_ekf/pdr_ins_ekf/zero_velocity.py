"""Zero-velocity (stance) detectors behind one interface, vectorised over samples.

Every detector is a frozen dataclass with its parameters and a method
``detect(accel, gyro, rate_hz) -> Stance`` taking specific force (N, 3) [m/s²] and angular
rate (N, 3) [rad/s] in the body frame, and returning a boolean stance mask and the test
statistic per sample. The detectors of the papers count their windows in samples, as
the papers do; the adaptive ones in seconds (``window_s``, ``span_s``), so that one
configuration serves 100 Hz to 1 kHz: ``rate_hz`` turns them into samples
(:func:`samples_of`), and :func:`sample_rate_hz` gives the rate one way, offline and live.
Time is axis 0 and components the last
axis: ``accel`` and ``gyro`` of shape (N, R, 3) (R Monte-Carlo runs) give masks (N, R),
each column exactly the decision on that run alone.

- :class:`ConditionVoteDetector`: Zampella et al. 2011, Eqs. (15)–(19): acceleration
  magnitude band (C1), angular-rate threshold (C2), standard deviation of |a| over the
  last W1+1 samples (C3), their product filtered by a median over the last W2+1 samples.
  ``variant="limited"`` multiplies the median by the current conditions (the limited
  window); ``variant="retarded"`` uses W1 = W2 = W centred on the sample (the retarded
  window, a delay of W/2 samples for a causal implementation).
- :class:`ShoeDetector`: the stance hypothesis optimal detector (GLRT) of
  Wang et al. 2020, section II (Skog et al. 2010):
  T = 1/W·Σ (‖y_a − g·ȳ_a/‖ȳ_a‖‖²/σ_a² + ‖y_ω‖²/σ_ω²) < γ.
- :class:`AdaptiveShoeDetector`: SHOE with a threshold that follows the gait, beyond the
  papers: γ_k = clip(κ·min_{|j−k|≤L/2} T_j, γ_min, γ_max). The floor of the statistic
  over about one stride rises from walking to running (the foot never rests as well), so
  one setting serves both; one fixed γ does not (Wang et al. 2020, section IV; the pyshoe
  anchor). Where the statistic's valley over the span is shallow, max T / min T below
  ρ, the span holds no stance, only a swing longer than it (a slow high step), and the
  threshold falls back to γ_min (docs/foot_ins.md, "The foot on real stairs").
- :class:`MovingVarianceDetector` (1/(σ_a²W)·Σ‖y_a − ȳ_a‖²), :class:`MagnitudeDetector`
  (1/(σ_a²W)·Σ(‖y_a‖ − g)²) and :class:`AngularRateEnergyDetector` (1/(σ_ω²W)·Σ‖y_ω‖²),
  Skog et al. 2010, for comparison; all over centred windows of W samples.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
from scipy.ndimage import maximum_filter1d, minimum_filter1d, uniform_filter1d

from pdr_core.constants import STANDARD_GRAVITY_MPS2

# pdr_msgs/Stance detector identifiers
DETECTOR_IDS = {"original": 0, "limited": 1, "retarded": 2, "shoe": 3, "moving_variance": 4,
                "magnitude": 5, "angular_rate_energy": 6, "adaptive_shoe": 7}


@dataclass(frozen=True)
class Stance:
    """Per-sample stance decision (N,) bool, the detector's statistic (N,), and the
    pdr_msgs/Stance detector identifier."""

    mask: np.ndarray
    statistic: np.ndarray
    detector: int


# the sample intervals the rate is taken from: the first ones of a record, so that the
# live node knows it as soon as the offline run does
RATE_PROBE_INTERVALS = 200


def sample_rate_hz(stamp_ns: np.ndarray) -> float:
    """The IMU's rate [Hz]: one over the median interval of a record's first
    RATE_PROBE_INTERVALS intervals (``stamp_ns`` increasing, at least two). The same for
    the offline run and the live node, which waits for those samples before it decides
    any (or takes what there is at the end of a shorter record)."""
    first = np.asarray(stamp_ns[:RATE_PROBE_INTERVALS + 1], np.int64)
    return 1e9 / float(np.median(np.diff(first)))


def samples_of(seconds: float, rate_hz: float) -> int:
    """A centred window of at least ``seconds`` at ``rate_hz``, in samples: the smallest
    odd count (an even one is not centred: it shifts the decisions by half a sample, which
    costs a simulated walk at 100 Hz 40 % of its ARMSE)."""
    at_least = int(np.ceil(seconds * rate_hz - 1e-9))
    return at_least + 1 - at_least % 2


class StanceDetector(Protocol):
    """What the filter needs of a detector: the vectorised decision, and how many samples
    before and after a sample its decision depends on at ``rate_hz`` (for causal, buffered
    use)."""

    def detect(self, accel: np.ndarray, gyro: np.ndarray, rate_hz: float) -> Stance: ...

    def context(self, rate_hz: float) -> tuple[int, int]: ...


class _CentredWindow:
    """Context of a detector with one centred window of ``window_samples`` samples."""

    window_samples: int

    def context(self, rate_hz: float) -> tuple[int, int]:
        return self.window_samples // 2, (self.window_samples - 1) // 2


def trailing_mean(x: np.ndarray, samples: int) -> np.ndarray:
    """Mean over the last ``samples`` samples (k − samples + 1 .. k), along axis 0."""
    return uniform_filter1d(np.asarray(x, float), samples, axis=0, mode="nearest",
                            origin=(samples - 1) // 2)


def centred_mean(x: np.ndarray, samples: int) -> np.ndarray:
    """Mean over ``samples`` samples centred on k, along axis 0."""
    return uniform_filter1d(np.asarray(x, float), samples, axis=0, mode="nearest")


def _squared_norm(x: np.ndarray) -> np.ndarray:
    """‖x‖² over the last axis."""
    return np.einsum("...i,...i->...", x, x)


def _check_window(name: str, value: int) -> None:
    if value < 1:
        raise ValueError(f"{name} must be >= 1 sample, got {value}")


@dataclass(frozen=True)
class ConditionVoteDetector:
    """Three threshold conditions and a majority vote over a window: Zampella et al. 2011,
    Eqs. (15)–(19), and its limited / retarded windows (see the module docstring).

    Thresholds: |a| in (acc_low_mps2, acc_high_mps2), |ω| < rate_max_radps, std of |a|
    over W1+1 samples < acc_std_max_mps2; median over W2+1 samples (W1, W2: ``w1_samples``,
    ``w2_samples``). The paper gives no values; the defaults suit 100 Hz walking data: with
    them the limited and the retarded windows end a noiseless 100-step walk within 1 cm along
    track (Zampella et al. 2011, section IV-A).
    """

    acc_low_mps2: float = 9.0
    acc_high_mps2: float = 11.0
    rate_max_radps: float = 0.5
    acc_std_max_mps2: float = 0.5
    w1_samples: int = 15
    w2_samples: int = 11
    variant: str = "original"

    def __post_init__(self) -> None:
        if self.variant not in ("original", "limited", "retarded"):
            raise ValueError(f"variant must be original, limited or retarded, got "
                             f"{self.variant!r}")
        _check_window("w1_samples", self.w1_samples)
        _check_window("w2_samples", self.w2_samples)

    def context(self, rate_hz: float) -> tuple[int, int]:
        if self.variant == "retarded":
            window = max(self.w1_samples, self.w2_samples) + 1
            return 2 * (window // 2), 2 * ((window - 1) // 2)
        return self.w1_samples + self.w2_samples, 0

    def detect(self, accel: np.ndarray, gyro: np.ndarray, rate_hz: float) -> Stance:
        norm_a = np.linalg.norm(accel, axis=-1)
        c1 = (self.acc_low_mps2 < norm_a) & (norm_a < self.acc_high_mps2)
        c2 = np.linalg.norm(gyro, axis=-1) < self.rate_max_radps
        if self.variant == "retarded":
            window = max(self.w1_samples, self.w2_samples) + 1
            mean, mean_sq = centred_mean(norm_a, window), centred_mean(norm_a**2, window)
        else:
            window = self.w1_samples + 1
            mean, mean_sq = trailing_mean(norm_a, window), trailing_mean(norm_a**2, window)
        std = np.sqrt(np.maximum(mean_sq - mean**2, 0.0))
        conditions = c1 & c2 & (std < self.acc_std_max_mps2)
        if self.variant == "retarded":
            votes = centred_mean(conditions, max(self.w1_samples, self.w2_samples) + 1)
        else:
            votes = trailing_mean(conditions, self.w2_samples + 1)
        mask = votes > 0.5
        if self.variant == "limited":
            mask &= conditions
        return Stance(mask, votes, DETECTOR_IDS[self.variant])


@dataclass(frozen=True)
class ShoeDetector(_CentredWindow):
    """SHOE / GLRT (Wang et al. 2020, section II): σ_a [m/s²], σ_ω [rad/s], window W
    [samples], threshold γ.

    With the default σ, γ = 1e5 admits |ω| up to 0.55 rad/s or an acceleration residual of
    3 m/s² over the window; γ scales with 1/σ², so change σ and γ together.
    """

    sigma_acc_mps2: float = 0.01
    sigma_rate_radps: float = 0.1 * np.pi / 180
    window_samples: int = 5
    threshold: float = 1.0e5
    gravity_mps2: float = STANDARD_GRAVITY_MPS2

    def __post_init__(self) -> None:
        _check_window("window_samples", self.window_samples)

    def detect(self, accel: np.ndarray, gyro: np.ndarray, rate_hz: float) -> Stance:
        w = self.window_samples
        mean_a = centred_mean(accel, w)
        # 1/W·Σ‖y − g·u‖² = mean‖y‖² − 2g·u·mean(y) + g², with u = mean(y)/‖mean(y)‖ fixed
        # over the window, so u·mean(y) = ‖mean(y)‖ (0 for a window of zero mean force)
        acc_term = (centred_mean(_squared_norm(accel), w)
                    - 2 * self.gravity_mps2 * np.sqrt(_squared_norm(mean_a))
                    + self.gravity_mps2**2)
        rate_term = centred_mean(_squared_norm(gyro), w)
        statistic = acc_term / self.sigma_acc_mps2**2 + rate_term / self.sigma_rate_radps**2
        return Stance(statistic < self.threshold, statistic, DETECTOR_IDS["shoe"])


@dataclass(frozen=True)
class AdaptiveShoeDetector:
    """SHOE (Wang et al. 2020, section II) against a threshold that adapts to the gait.

    γ_k = clip(threshold_factor · min T_j over the ``span_s`` centred on k, threshold_min,
    threshold_max): stance is where the statistic is within a factor of its lowest value
    over about one stride. ``span_s`` should cover a stride and a half; the live node then
    lags the input by half of it. The SHOE sum runs over ``window_s``.

    A span that holds no stance (a swing longer than it: a slow, high step) has a floor
    too, the swing's slowest moment, and the factor would call it stance, a ZUPT on a foot
    still moving. So the adaptive threshold holds only where the valley is deep, max T_j
    ≥ ``depth_min`` · min T_j over the span; elsewhere γ_k = threshold_min. A foot at rest
    in a stride lowers the statistic by 10³–10⁴ from its swing (walking; about 10² running),
    a slow swing's own minimum only by 30–60 (the pyshoe trial that climbs, docs/foot_ins.md).

    The defaults are the single setting used on all eight pyshoe VICON trials
    (docs/foot_ins.md), which mix slow walking, fast walking, running and slow high steps
    at 200 Hz (7 and 241 samples there; 5 and 121 at 100 Hz).
    """

    sigma_acc_mps2: float = 0.01
    sigma_rate_radps: float = 0.1 * np.pi / 180
    window_s: float = 0.035
    span_s: float = 1.2
    threshold_factor: float = 1.5
    threshold_min: float = 3.0e3
    threshold_max: float = 1.0e8
    depth_min: float = 70.0
    gravity_mps2: float = STANDARD_GRAVITY_MPS2

    def __post_init__(self) -> None:
        if self.depth_min < 1:
            raise ValueError(f"depth_min must be >= 1, got {self.depth_min}")
        if not (self.window_s > 0 and self.span_s > 0):
            raise ValueError(f"window_s and span_s must be > 0 s, got {self.window_s} and "
                             f"{self.span_s}")
        if self.threshold_factor < 1:
            raise ValueError(f"threshold_factor must be >= 1, got {self.threshold_factor}")
        if not 0 < self.threshold_min <= self.threshold_max:
            raise ValueError("need 0 < threshold_min <= threshold_max, got "
                             f"{self.threshold_min} and {self.threshold_max}")

    def context(self, rate_hz: float) -> tuple[int, int]:
        window, span = samples_of(self.window_s, rate_hz), samples_of(self.span_s, rate_hz)
        return span // 2 + window // 2, (span - 1) // 2 + (window - 1) // 2

    def detect(self, accel: np.ndarray, gyro: np.ndarray, rate_hz: float) -> Stance:
        shoe = ShoeDetector(self.sigma_acc_mps2, self.sigma_rate_radps,
                            samples_of(self.window_s, rate_hz), 1.0, self.gravity_mps2)
        statistic = shoe.detect(accel, gyro, rate_hz).statistic
        span = samples_of(self.span_s, rate_hz)
        floor = minimum_filter1d(statistic, span, axis=0, mode="nearest")
        peak = maximum_filter1d(statistic, span, axis=0, mode="nearest")
        threshold = np.where(peak >= self.depth_min * floor,
                             np.clip(self.threshold_factor * floor, self.threshold_min,
                                     self.threshold_max), self.threshold_min)
        return Stance(statistic < threshold, statistic, DETECTOR_IDS["adaptive_shoe"])


@dataclass(frozen=True)
class MovingVarianceDetector(_CentredWindow):
    """Acceleration moving variance (Skog et al. 2010)."""

    sigma_acc_mps2: float = 0.01
    window_samples: int = 5
    threshold: float = 1.0e2

    def detect(self, accel: np.ndarray, gyro: np.ndarray, rate_hz: float) -> Stance:
        mean_a = centred_mean(accel, self.window_samples)
        variance = (centred_mean(np.sum(accel**2, axis=-1), self.window_samples)
                    - np.sum(mean_a**2, axis=-1))
        statistic = np.maximum(variance, 0.0) / self.sigma_acc_mps2**2
        return Stance(statistic < self.threshold, statistic, DETECTOR_IDS["moving_variance"])


@dataclass(frozen=True)
class MagnitudeDetector(_CentredWindow):
    """Acceleration magnitude (Skog et al. 2010)."""

    sigma_acc_mps2: float = 0.01
    window_samples: int = 5
    threshold: float = 5.0e3
    gravity_mps2: float = STANDARD_GRAVITY_MPS2

    def detect(self, accel: np.ndarray, gyro: np.ndarray, rate_hz: float) -> Stance:
        deviation = (np.linalg.norm(accel, axis=-1) - self.gravity_mps2) ** 2
        statistic = centred_mean(deviation, self.window_samples) / self.sigma_acc_mps2**2
        return Stance(statistic < self.threshold, statistic, DETECTOR_IDS["magnitude"])


@dataclass(frozen=True)
class AngularRateEnergyDetector(_CentredWindow):
    """Angular-rate energy (Skog et al. 2010)."""

    sigma_rate_radps: float = 0.1 * np.pi / 180
    window_samples: int = 5
    threshold: float = 1.0e4

    def detect(self, accel: np.ndarray, gyro: np.ndarray, rate_hz: float) -> Stance:
        statistic = (centred_mean(np.sum(gyro**2, axis=-1), self.window_samples)
                     / self.sigma_rate_radps**2)
        return Stance(statistic < self.threshold, statistic,
                      DETECTOR_IDS["angular_rate_energy"])
