"""Where the phone rides, from its pitch swing, and the stride model that holds there.

A thigh's pitch swing grows with its stride, s = a_H·Δθ + b_H (Muñoz Díaz 2016, Eq.
(4.2)), and the stride with the cadence, s = c_H·f + d_H (Eq. (4.3)). At a gait cycle of
f [Hz] a thigh therefore swings about

    Δθ_thigh(f) = (c_H·f + d_H − b_H) / a_H   [deg]

(with the configured lines: the population's, or the person's once calibrated). A phone in
a back pocket rides on the buttock, whose soft tissue follows the thigh's flexion only in
part, so its swing is a fraction of that: the pitch line would shorten every stride (by
39 % on the simulated back-pocket walk), while the cadence says how far a person walks.

The swing ratio ρ = median Δθ / Δθ_thigh(median f), over the last
:data:`~pdr_core.gait.PLACEMENT_WINDOW_STEPS` level gait cycles, names the placement:

- ρ ≥ :data:`~pdr_core.gait.THIGH_SWING_MIN_RATIO`: a thigh's swing, the **front pocket**,
  where the pitch line holds;
- below it: not a thigh's swing, the **back pocket**: strides from the cadence-and-height
  line (Eq. (4.3), scaled by ``person.height_m`` as every uncalibrated line is);
- fewer level cycles than the window: **unknown**, the pitch line (the thesis').

It is judged only at a cadence of at least :data:`~pdr_core.gait.PLACEMENT_MIN_CADENCE_HZ`
(90 steps/min): slower, the cadence line does not hold and a slow thigh swings as little
as a back pocket, so the placement stays as it was judged last (unknown at first).

With ``step_length.model: auto`` (the default) the stride model follows the placement;
any other model is used throughout and the placement is only named. A limit: a thigh at a
run swings less than the walking lines say (the shared jog, ρ ≈ 0.57), and is named a back
pocket; its strides then come from the cadence, which for a run is the better guess.
"""
from __future__ import annotations

from collections import Counter, deque
from dataclasses import dataclass
from statistics import median

import numpy as np

from pdr_core.gait import (
    PLACEMENT_MIN_CADENCE_HZ,
    PLACEMENT_WINDOW_STEPS,
    THIGH_SWING_MIN_RATIO,
)
from pdr_pocket.config import StepLengthConfig
from pdr_pocket.step_length import AUTO_MODEL, StrideInputs

FRONT_POCKET, BACK_POCKET, UNKNOWN = "front pocket", "back pocket", "unknown"
MODEL_AT = {FRONT_POCKET: "pitch", BACK_POCKET: "frequency", UNKNOWN: "pitch"}


@dataclass(frozen=True)
class Placement:
    """Where the phone rides, the stride model used for it, and why."""

    placement: str
    model: str
    swing_ratio: float          # ρ (module docstring), NaN while unknown
    why: str


def thigh_swing_deg(config: StepLengthConfig, cycle_hz: float) -> float:
    """Δθ_thigh(f) [deg]: the pitch swing the pitch and cadence lines agree on at a gait
    cycle of ``cycle_hz`` (module docstring)."""
    return (config.c_h_m_per_hz * cycle_hz + config.d_h_m - config.b_h_m) \
        / config.a_h_m_per_deg


def stride_choice(config: StepLengthConfig) -> str:
    """How the strides are chosen, in words (the node's start-up log)."""
    if config.model != AUTO_MODEL:
        return f"the {config.model} model, as configured, whatever the placement"
    return (f"auto: the {MODEL_AT[FRONT_POCKET]} line on a thigh's swing (front pocket), "
            f"the {MODEL_AT[BACK_POCKET]} (cadence and height) line on a smaller one (back "
            f"pocket), judged over the last {PLACEMENT_WINDOW_STEPS} level gait cycles; the "
            f"{MODEL_AT[UNKNOWN]} line until then")


class PlacementClassifier:
    """The placement of each level gait cycle from the last ones (module docstring)."""

    def __init__(self, config: StepLengthConfig) -> None:
        self.config = config
        self.window: deque[tuple[float, float]] = deque(maxlen=PLACEMENT_WINDOW_STEPS)
        self.judged: Placement | None = None      # the last placement judged by the swing
        self.current = self._decide()
        self.counts: Counter[str] = Counter()     # level cycles per placement
        self.models: Counter[str] = Counter()     # level cycles per stride model
        self.last: dict[str, Placement] = {}      # the last decision of each placement

    def add(self, x: StrideInputs) -> Placement:
        """The placement with this level cycle in the window."""
        self.window.append((x.amplitude_deg, x.duration_s))
        self.current = self._decide()
        self.counts[self.current.placement] += 1
        self.models[self.current.model] += 1
        self.last[self.current.placement] = self.current
        return self.current

    def _decide(self) -> Placement:
        configured = self.config.model
        if len(self.window) < PLACEMENT_WINDOW_STEPS:
            return Placement(UNKNOWN, MODEL_AT[UNKNOWN] if configured == AUTO_MODEL else configured,
                             float("nan"), f"fewer than {PLACEMENT_WINDOW_STEPS} level gait "
                                           "cycles so far")
        # the medians of a handful of cycles: the standard library's, in a tenth of
        # NumPy's time on so few values, and the same numbers
        amplitude = median(a for a, _ in self.window)
        duration = median(d for _, d in self.window)
        cycle_hz = 1.0 / duration
        if cycle_hz < PLACEMENT_MIN_CADENCE_HZ:
            return self._kept(cycle_hz)
        ratio = float(amplitude / thigh_swing_deg(self.config, cycle_hz))
        placement = FRONT_POCKET if ratio >= THIGH_SWING_MIN_RATIO else BACK_POCKET
        model = MODEL_AT[placement] if configured == AUTO_MODEL else configured
        side = "at least" if placement == FRONT_POCKET else "below"
        self.judged = Placement(placement, model, ratio, (
            f"the pitch swing is {100 * ratio:.0f} % of a thigh's at {cycle_hz:.2f} cycles/s "
            f"({side} {100 * THIGH_SWING_MIN_RATIO:.0f} %)"))
        return self.judged

    def _kept(self, cycle_hz: float) -> Placement:
        """The last judged placement, at a cadence too slow to judge it."""
        slow = (f"{cycle_hz:.2f} cycles/s is too slow to judge the swing by (under "
                f"{PLACEMENT_MIN_CADENCE_HZ:g})")
        last = self.judged
        if last is None:
            return Placement(UNKNOWN, self.current.model, float("nan"), slow)
        return Placement(last.placement, last.model, last.swing_ratio, f"{last.why}; now {slow}")

    def summary(self) -> dict:
        """report.json's ``placement``: the placement of most judged level cycles (unknown
        when fewer than a window's were judged) with its last swing ratio and reason, the
        stride model of most cycles, and the cycles per placement and per model."""
        decided = Counter({k: n for k, n in self.counts.items() if k != UNKNOWN})
        placement = decided.most_common(1)[0][0] \
            if decided.total() >= PLACEMENT_WINDOW_STEPS else UNKNOWN
        last = self.last.get(placement, self.current)
        return {"placement": placement,
                "stride_model": self.models.most_common(1)[0][0] if self.models
                else last.model,
                "configured_model": self.config.model,
                "swing_ratio": None if np.isnan(last.swing_ratio) else round(last.swing_ratio, 3),
                "why": last.why,
                "cycles": dict(self.counts), "cycles_by_model": dict(self.models)}
