"""A person's own stride and riser lines, learned from a foot INS walking with the pocket.

Muñoz Díaz 2016, Section 7.3: every sensor on one pedestrian moves by the same horizontal
and vertical displacement, so a foot-mounted INS (pdr_ins_ekf, ``pdr/foot/step``) can
calibrate the pocket's displacement lines while the person walks:

- Eq. (4.2), level: s = a_H·Δθ_H + b_H, s the stride (one gait cycle) [m], Δθ_H the thigh's
  pitch swing [deg], a_H [m/deg], b_H [m];
- Eqs. (4.4)-(4.5), stairs: v_U = a_U·Δθ_U + b_U and v_D = a_D·Δθ_D + b_D, v the vertical
  displacement of one gait cycle (two risers) [cm], a [cm/deg], b [cm].

One pocket step is one gait cycle of the sensor leg and pairs with one foot stride (no
factor 2). The thesis gives no algorithm; the pairing, the estimator and the refusals are
ours (desk study of issue 57):

- :class:`LineFit`: one line y = a·x + b by recursive least squares with exponential
  forgetting λ, its prior the configured (population) line with P₀ = diag(σ_a², σ_b²),
  and P clipped so that it never exceeds P₀ (a direction the walk does not excite, the
  slope at one speed, falls back to the prior instead of winding up);
- :class:`StrideCalibrator`: pairs the pocket's steps (:class:`PocketStep`) with the foot's
  strides (:class:`FootStride`) by their stamps alone, so that any interleaving of the two
  streams, live or offline, gives the same pairs and fit, refuses what is not one cycle of
  one line walked by both (:data:`REASONS`, each counted) and feeds the three lines;
- the saved fit, the YAML ``calibrate-step --foot`` writes: :mod:`pdr_pocket.saved_lines`.
"""
from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterable
from dataclasses import dataclass, field, fields

import numpy as np

from pdr_core.io.batch import MessageBatch
from pdr_core.maths.angles import circular_mean, wrap_angle
from pdr_core.vocabulary import Activity
from pdr_core.walking.gait import FOOT_STRIDE_MIN_M, stride_bound_m
from pdr_pocket.config import PositionConfig, StairsConfig, StepsConfig
from pdr_pocket.step_length import StepLengthConfig

LEVEL, UP, DOWN = "level", "up", "down"
LINES = (LEVEL, UP, DOWN)
"""The three lines, in the order of Eqs. (4.2), (4.4), (4.5)."""
LINE_OF_ACTIVITY = {Activity.WALKING: LEVEL, Activity.UPSTAIRS: UP, Activity.DOWNSTAIRS: DOWN}
CM_PER_M = 100.0

REASONS = ("lag", "count", "rest", "turn", "activity", "cadence", "implausible", "outlier")
"""Why a pocket step is not paired, in the order they are tried: ``lag`` the lag phase is
still being learned; ``count`` not exactly one footfall in the step's window; ``rest`` the
first or last step of a walking bout, or a cycle longer than a step period; ``turn`` the
heading turned by more than ``turn_max_deg`` over the step or the stride; ``activity`` the
pocket's and the foot's activities differ (or are not one of the three lines'); ``cadence``
the stride's and the step's durations differ; ``implausible`` the foot stride is no
person's (shorter than FOOT_STRIDE_MIN_M, longer than stride_bound_m, or climbing the other
way); ``outlier`` more than ``outlier_sigma_factor`` σ off the line fitted so far."""


@dataclass(frozen=True)
class PocketStep:
    """One pocket step: ``stamp_s`` [s] at the thigh's pitch maximum, ``duration_s`` [s] of
    its cycle, ``amplitude_deg`` Δθ [deg] (``pdr_msgs/Step.pitch_amplitude`` is in rad),
    ``activity`` (:class:`Activity`), ``heading_change_deg`` [deg] over the step (NaN:
    unknown)."""

    stamp_s: float
    duration_s: float
    amplitude_deg: float
    activity: int
    heading_change_deg: float = math.nan


@dataclass(frozen=True)
class FootStride:
    """One foot stride (``pdr/foot/step``): ``stamp_s`` [s] at its footfall, ``length_m``
    [m] horizontal, ``vertical_m`` [m] its height change (up +), ``duration_s`` [s],
    ``activity`` (:class:`Activity`), ``heading_change_deg`` [deg] from the stride before
    (NaN: unknown)."""

    stamp_s: float
    length_m: float
    vertical_m: float
    duration_s: float
    activity: int
    heading_change_deg: float = math.nan


@dataclass(frozen=True)
class CalibrationSettings:
    """The calibrator's constants (desk study of issue 57, Section 3).

    Prior: σ_a = ``slope_sigma_fraction`` of the configured level slope (the slopes are
    "very similar" among people, Section 4.2.3: a walk at several speeds still shows a
    person's own) and ``stairs_slope_sigma_fraction`` of each stairs slope: the stairs of a
    building are standardised (Section 4.3), so a walk sees a stairs line at one Δθ only,
    where its slope cannot be told from its offset; at 2 % the slope takes about 5 % of a
    correction at 17 cm risers ((0.02·a·Δθ)² against σ_b²) and the person's difference goes
    to the offset, as the thesis' calibration of b_H alone. Level σ_b = PositionConfig's
    ``stride_offset_sigma_m`` (people lie up to 14 cm per stride off the population line, as
    2σ); stairs σ_b ``stairs_offset_sigma_cm`` (an assumption: no data). Noise R of one
    pair: level (cv·s)² + σ_foot² + (a·σ_Δθ)², with ``stride_cv`` a person's stride
    variation about their own line (Gabell & Nayak 1984 bound it by 6 %; 2.5 % taken),
    ``foot_length_sigma_m`` a foot INS's stride end (pdr_core.walking.gait: about a
    centimetre) and ``level_amplitude_sigma_deg``; stairs σ_foot,v² + (a·σ_Δθ)² in cm.
    """

    forgetting: float = 0.999                   # λ: a memory of about 1/(1 − λ) pairs
    slope_sigma_fraction: float = 0.10
    stairs_slope_sigma_fraction: float = 0.02
    level_offset_sigma_m: float = PositionConfig.stride_offset_sigma_m
    stairs_offset_sigma_cm: float = 4.0
    stride_cv: float = 0.025
    foot_length_sigma_m: float = 0.01
    foot_vertical_sigma_cm: float = 1.5
    level_amplitude_sigma_deg: float = 0.5
    stairs_amplitude_sigma_deg: float = 0.3
    lag_steps: int = 10                         # steady pairs the lag phase is learned from
    lag_spread_max_cycles: float = 0.1          # ... whose phases agree within this
    turn_max_deg: float = 20.0
    cadence_ratio_min: float = 0.85             # T_foot / T_pocket
    cadence_ratio_max: float = 1.18
    outlier_sigma_factor: float = 3.0
    outlier_min_pairs: int = 20                 # a line's pairs before outliers are refused
    max_cycle_s: float = StepsConfig.max_step_period_s   # a longer gap ends a walking bout
    height_m: float | None = None               # the person's, for stride_bound_m

    def __post_init__(self) -> None:
        if not 0.0 < self.forgetting <= 1.0:
            raise ValueError(f"forgetting must be within (0, 1], got {self.forgetting}")
        if not self.cadence_ratio_max > self.cadence_ratio_min > 0.0:
            raise ValueError("cadence_ratio_max must be above cadence_ratio_min > 0")


class LineFit:
    """One line y = a·x + b by recursive least squares with forgetting λ.

    State θ = [a, b], regressor φ = [x, 1]. Per pair (x, y) of noise variance R:
    e = y − φᵀθ, S = λR + φᵀPφ, K = Pφ/S, θ += K·e, P = (P − KφᵀP)/λ; then P is clipped to
    P₀ (P₀ − P ⪰ 0: eigenvalues of P₀^-½·P·P₀^-½ at most 1). Without the clip this is the
    minimiser of λᴺ·(θ − θ₀)ᵀP₀⁻¹(θ − θ₀) + Σᵢ λᴺ⁻ⁱ·eᵢ²/Rᵢ (with λ = 1 the weighted least
    squares with the prior as pseudo-observations). Units are the caller's: level x in deg
    and y in m (Eq. (4.2)), stairs y in cm (Eqs. (4.4)-(4.5)).

    Also kept, with the same forgetting: the normalised residual scale, the mean of e²/S
    (1 when R is right), and the residual σ, the root mean e² [y's unit].
    """

    def __init__(self, slope: float, offset: float, slope_sigma: float, offset_sigma: float,
                 forgetting: float = 1.0) -> None:
        self.theta = np.array([slope, offset], float)
        self.sigma0 = np.array([slope_sigma, offset_sigma], float)
        self.p0 = np.diag(self.sigma0 ** 2)
        self.p = self.p0.copy()
        self.forgetting = forgetting
        self.pairs = 0
        self._weight = 0.0
        self._squares = 0.0
        self._normalised = 0.0

    @property
    def slope(self) -> float:
        return float(self.theta[0])

    @property
    def offset(self) -> float:
        return float(self.theta[1])

    def innovation(self, x: float, y: float, r: float) -> tuple[float, float]:
        """e = y − φᵀθ and its variance S = λR + φᵀPφ."""
        phi = np.array([x, 1.0])
        return float(y - phi @ self.theta), float(self.forgetting * r + phi @ self.p @ phi)

    def update(self, x: float, y: float, r: float) -> float:
        """Take one pair (x, y) of noise variance ``r`` [y's unit²]; returns e."""
        lam = self.forgetting
        phi = np.array([x, 1.0])
        e, s = self.innovation(x, y, r)
        gain = self.p @ phi / s
        self.theta = self.theta + gain * e
        self.p = self._clipped((self.p - np.outer(gain, phi @ self.p)) / lam)
        self.pairs += 1
        self._weight = lam * self._weight + 1.0
        self._squares = lam * self._squares + e * e
        self._normalised = lam * self._normalised + e * e / s
        return e

    def _clipped(self, p: np.ndarray) -> np.ndarray:
        scaled = p / np.outer(self.sigma0, self.sigma0)
        values, vectors = np.linalg.eigh(0.5 * (scaled + scaled.T))
        scaled = (vectors * np.minimum(values, 1.0)) @ vectors.T
        return scaled * np.outer(self.sigma0, self.sigma0)

    @property
    def residual_scale(self) -> float:
        """The mean of e²/S (1 before any pair)."""
        return self._normalised / self._weight if self._weight else 1.0

    @property
    def residual_sigma(self) -> float:
        """The root mean e² [y's unit] (NaN before any pair)."""
        return math.sqrt(self._squares / self._weight) if self._weight else math.nan

    @property
    def covariance(self) -> np.ndarray:
        """P times the residual scale: the published covariance of [a, b], honest when R
        is not."""
        return self.p * self.residual_scale


@dataclass(frozen=True)
class Decision:
    """What became of one pocket step: paired to ``line`` (``reason`` None) with
    ``amplitude_deg`` and the foot's ``measured`` (m level, cm stairs), or refused for
    ``reason`` (:data:`REASONS`), ``detail`` saying by how much."""

    stamp_s: float
    reason: str | None
    detail: str = ""
    line: str | None = None
    amplitude_deg: float = math.nan
    measured: float = math.nan


@dataclass
class _Lag:
    """The lag phase of the paired footfall after the pitch maximum, in cycles [0, 1):
    about 0.14 for a foot on the pocket's leg, 0.64 on the other."""

    steps: int
    spread_max: float
    phase: float | None = None
    candidates: deque = field(default_factory=deque)

    def add(self, phase: float) -> None:
        """One steady pair's phase; learned once the last ``steps`` agree."""
        self.candidates.append(phase % 1.0)
        if len(self.candidates) > self.steps:
            self.candidates.popleft()
        if len(self.candidates) < self.steps:
            return
        p = np.array(self.candidates)
        centre = circular_mean(2.0 * np.pi * p) / (2.0 * np.pi)
        offsets = (p - centre + 0.5) % 1.0 - 0.5
        if offsets.max() - offsets.min() < self.spread_max:
            self.phase = float((centre + np.median(offsets)) % 1.0)


class StrideCalibrator:
    """The pocket's three lines from pairs of pocket steps and foot strides, by stamps.

    Pocket step k (stamp t_k at its pitch maximum, cycle T_k) pairs with the footfall in
    (t_k + (φ̂ − ½)·T_k, t_k + (φ̂ + ½)·T_k], φ̂ the learned lag phase (:class:`_Lag`; while
    it is learned, the window is (t_k, t_k + T_k] and the steps are refused as ``lag``).
    Step k is decided once step k+1 has come (a bout's last step is refused) and a foot
    stride stamped after the window's end; so the decisions depend on the stamps alone,
    not on how the two streams interleave (each stream in stamp order). A tail never
    decided stays :attr:`pending`.

    The level line's measure is the foot's length [m]; the stairs lines' is
    100·|v − g·L| [cm], v and L the stride's height change and length and g the mean grade
    Σv/ΣL of the paired level strides (a foot INS's height drifts by a lift per stride,
    docs/foot_ins.md, that would bias the risers).
    """

    def __init__(self, step_length: StepLengthConfig | None = None,
                 stairs: StairsConfig | None = None,
                 settings: CalibrationSettings | None = None) -> None:
        """The priors are the configured lines (the shipped population's by default)."""
        step_length = step_length or StepLengthConfig()
        stairs = stairs or StairsConfig()
        s = self.settings = settings or CalibrationSettings()
        lines = {LEVEL: (step_length.a_h_m_per_deg, step_length.b_h_m,
                         s.slope_sigma_fraction, s.level_offset_sigma_m),
                 UP: (stairs.a_u_cm_per_deg, stairs.b_u_cm, s.stairs_slope_sigma_fraction,
                      s.stairs_offset_sigma_cm),
                 DOWN: (stairs.a_d_cm_per_deg, stairs.b_d_cm, s.stairs_slope_sigma_fraction,
                        s.stairs_offset_sigma_cm)}
        self.prior = {name: (a, b) for name, (a, b, _, _) in lines.items()}
        self.fits = {name: LineFit(a, b, fraction * abs(a), sigma_b, s.forgetting)
                     for name, (a, b, fraction, sigma_b) in lines.items()}
        self.refused = dict.fromkeys(REASONS, 0)
        self.lag = _Lag(s.lag_steps, s.lag_spread_max_cycles)
        self._pocket: deque[PocketStep] = deque()
        self._foot: deque[FootStride] = deque()
        self._foot_horizon = -math.inf
        self._previous_stamp: float | None = None
        self._rise_m = 0.0
        self._run_m = 0.0

    @property
    def pending(self) -> int:
        """Pocket steps not decided yet."""
        return len(self._pocket)

    @property
    def grade(self) -> float:
        """Σv/ΣL over the paired level strides (0 before any)."""
        return self._rise_m / self._run_m if self._run_m else 0.0

    def push_pocket(self, steps: Iterable[PocketStep]) -> list[Decision]:
        """Pocket steps in stamp order; returns the decisions they allowed."""
        for step in steps:
            last = self._pocket[-1].stamp_s if self._pocket else self._previous_stamp
            _check_order(last, step.stamp_s, "pocket steps")
            self._pocket.append(step)
        return self._decide_ready()

    def push_foot(self, strides: Iterable[FootStride]) -> list[Decision]:
        """Foot strides in stamp order; returns the decisions they allowed."""
        for stride in strides:
            _check_order(self._foot_horizon, stride.stamp_s, "foot strides")
            self._foot.append(stride)
            self._foot_horizon = stride.stamp_s
        return self._decide_ready()

    def _window(self, step: PocketStep) -> tuple[float, float]:
        if self.lag.phase is None:
            return step.stamp_s, step.stamp_s + step.duration_s
        return (step.stamp_s + (self.lag.phase - 0.5) * step.duration_s,
                step.stamp_s + (self.lag.phase + 0.5) * step.duration_s)

    def _decide_ready(self) -> list[Decision]:
        out = []
        while len(self._pocket) >= 2 and self._foot_horizon > self._window(self._pocket[0])[1]:
            step = self._pocket.popleft()
            out.append(self._decide(step, self._pocket[0].stamp_s))
            self._previous_stamp = step.stamp_s
            # a later window starts after t − max_cycle_s (longer cycles are refused as rest)
            while self._foot and self._foot[0].stamp_s <= step.stamp_s - self.settings.max_cycle_s:
                self._foot.popleft()
        return out

    def _decide(self, step: PocketStep, next_stamp_s: float) -> Decision:
        start, end = self._window(step)
        feet = [f for f in self._foot if start < f.stamp_s <= end]
        problem = (self._rest(step, next_stamp_s)
                   or (None if len(feet) == 1 else ("count", f"{len(feet)} footfalls"))
                   or _mismatch(step, feet[0], self.settings))
        if problem is None and self.lag.phase is None:
            self.lag.add((feet[0].stamp_s - step.stamp_s) / step.duration_s)
            problem = ("lag", "learning the lag phase")
        if problem is None:
            return self._pair(step, feet[0])
        return self._refuse(step, *problem)

    def _rest(self, step: PocketStep, next_stamp_s: float) -> tuple[str, str] | None:
        limit = self.settings.max_cycle_s
        if self._previous_stamp is None or step.stamp_s - self._previous_stamp > limit:
            return "rest", "a bout's first step"
        if next_stamp_s - step.stamp_s > limit:
            return "rest", "a bout's last step"
        if step.duration_s > limit:
            return "rest", f"a cycle of {step.duration_s:.1f} s"
        return None

    def _refuse(self, step: PocketStep, reason: str, detail: str) -> Decision:
        self.refused[reason] += 1
        return Decision(step.stamp_s, reason, detail)

    def _pair(self, step: PocketStep, foot: FootStride) -> Decision:
        line = LINE_OF_ACTIVITY[Activity(step.activity)]
        fit = self.fits[line]
        x = step.amplitude_deg
        y, r = self._measure(line, x, foot)
        if y <= 0.0:
            return self._refuse(step, "implausible", f"climbs {foot.vertical_m:+.2f} m")
        e, s = fit.innovation(x, y, r)
        gate = self.settings.outlier_sigma_factor * math.sqrt(s * fit.residual_scale)
        if fit.pairs >= self.settings.outlier_min_pairs and abs(e) > gate:
            return self._refuse(step, "outlier", f"{e:+.3g} off the line (gate {gate:.3g})")
        fit.update(x, y, r)
        if line == LEVEL:
            self._rise_m += foot.vertical_m
            self._run_m += foot.length_m
        return Decision(step.stamp_s, None, "", line, x, y)

    def _measure(self, line: str, x: float, foot: FootStride) -> tuple[float, float]:
        """The foot's measure of ``line`` (m level, cm stairs) and its noise variance R,
        from the configured line's prediction at ``x`` (a fixed weight: no bias from
        weighting by the measurement)."""
        s = self.settings
        a, b = self.prior[line]
        if line == LEVEL:
            r = ((s.stride_cv * (a * x + b)) ** 2 + s.foot_length_sigma_m ** 2
                 + (a * s.level_amplitude_sigma_deg) ** 2)
            return foot.length_m, r
        r = s.foot_vertical_sigma_cm ** 2 + (a * s.stairs_amplitude_sigma_deg) ** 2
        climb_cm = CM_PER_M * (foot.vertical_m - self.grade * foot.length_m)
        return (climb_cm if line == UP else -climb_cm), r

def unusable(item: PocketStep | FootStride) -> str | None:
    """Why :class:`StrideCalibrator` cannot take a step or a stride (a live node drops and
    counts it): ``non_finite``, a value not finite (the heading change aside: NaN is
    unknown), or ``unknown_activity``, none of :class:`Activity`; None: it can."""
    if not all(math.isfinite(getattr(item, f.name)) for f in fields(item)
               if f.name != "heading_change_deg"):
        return "non_finite"
    if item.activity not in set(Activity):
        return "unknown_activity"
    return None


def heading_changes_deg(heading_rad: np.ndarray, previous_rad: float = math.nan) -> np.ndarray:
    """Each step's heading change [deg] from the one before (``previous_rad`` before the
    first; NaN: unknown), wrapped to (−180, 180]."""
    heading = np.asarray(heading_rad, float)
    before = np.concatenate([[previous_rad], heading[:-1]])
    return np.degrees(wrap_angle(heading - before))


def pocket_steps(step: MessageBatch, previous_heading_rad: float = math.nan
                 ) -> list[PocketStep]:
    """The pocket's ``pdr/pocket/step`` messages (pdr_msgs/Step) as :class:`PocketStep`,
    stamped at ``header.stamp`` (s since the epoch), Δθ = ``pitch_amplitude`` in deg."""
    turns = heading_changes_deg(step["heading"], previous_heading_rad)
    return [PocketStep(float(t), float(d), float(np.degrees(a)), int(k), float(h))
            for t, d, a, k, h in zip(step.stamp_ns * 1e-9, step["duration"],
                                     step["pitch_amplitude"], step["activity"], turns,
                                     strict=True)]


def foot_strides(stride: MessageBatch, previous_heading_rad: float = math.nan
                 ) -> list[FootStride]:
    """The foot INS's ``pdr/foot/step`` messages (pdr_msgs/Step) as :class:`FootStride`."""
    turns = heading_changes_deg(stride["heading"], previous_heading_rad)
    return [FootStride(float(t), float(n), float(v), float(d), int(k), float(h))
            for t, n, v, d, k, h in zip(stride.stamp_ns * 1e-9, stride["length"],
                                        stride["vertical_displacement"], stride["duration"],
                                        stride["activity"], turns, strict=True)]


def calibrated(pocket: MessageBatch, foot: MessageBatch,
               calibrator: StrideCalibrator | None = None) -> StrideCalibrator:
    """A calibrator fed a whole walk's pocket steps and foot strides (the offline mode;
    the node pushes the same messages one by one and, the decisions depending on the
    stamps alone, ends with the same fit)."""
    calibrator = calibrator or StrideCalibrator()
    calibrator.push_pocket(pocket_steps(pocket))
    calibrator.push_foot(foot_strides(foot))
    return calibrator


def _check_order(last: float | None, stamp_s: float, what: str) -> None:
    if not math.isfinite(stamp_s) or (last is not None and stamp_s <= last):
        raise ValueError(f"{what} must come in increasing stamp order: {stamp_s} after {last}")


def _mismatch(step: PocketStep, foot: FootStride, s: CalibrationSettings
              ) -> tuple[str, str] | None:
    """activity, turn, cadence or implausible: why the step and the stride are not one
    cycle of one line (None: they are)."""
    pocket_line = LINE_OF_ACTIVITY.get(step.activity)
    if pocket_line is None or pocket_line != LINE_OF_ACTIVITY.get(foot.activity):
        return "activity", (f"pocket {Activity(step.activity).label}, "
                            f"foot {Activity(foot.activity).label}")
    turn = max(abs(step.heading_change_deg), abs(foot.heading_change_deg))
    if turn > s.turn_max_deg:                       # NaN (unknown) compares False
        return "turn", f"turn {turn:.0f}°"
    ratio = foot.duration_s / step.duration_s
    if not s.cadence_ratio_min <= ratio <= s.cadence_ratio_max:
        return "cadence", f"stride/step duration {ratio:.2f}"
    bound = stride_bound_m(foot.duration_s, s.height_m)
    if not FOOT_STRIDE_MIN_M <= foot.length_m <= bound:
        return "implausible", f"stride {foot.length_m:.2f} m (bound {bound:.2f} m)"
    return None
