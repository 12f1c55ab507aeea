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
:data:`~pdr_core.walking.gait.PLACEMENT_WINDOW_STEPS` level gait cycles, names the placement:

- ρ ≥ :data:`~pdr_core.walking.gait.THIGH_SWING_MIN_RATIO`: a thigh's swing, the **front pocket**,
  where the pitch line holds;
- below it: not a thigh's swing, the **back pocket**: strides from the cadence-and-height
  line (Eq. (4.3), scaled by ``person.height_m`` as every uncalibrated line is);
- fewer level cycles than the window: **unknown**, the pitch line (the thesis').

A phone that rides on no leg (held in the hand, in a bag) is **not in a pocket**: the
accelerometer hears the footfalls (pdr_pocket.steps.FootfallDetector on |f|, run beside
the pitch maximum with a gyroscope, pdr_pocket.pitch_source), two per gait cycle, but
the pitch does not swing once per cycle. A thigh's pitch swings through a cycle every two
footfalls (1.92-2.04 footfalls per cycle on every shared pocket walk, the simulated front
and back pockets and the stairs); phones held in the hand give 3.2-27 (the two shared
Sensor Logger walks, two OxIOD handheld sequences; 588 and none on the simulated hand).
With at least :data:`NOT_A_THIGH_MIN_FOOTFALLS` footfalls heard and more than
:data:`THIGH_FOOTFALLS_PER_CYCLE_MAX` per cycle of the pitch, the walk is not a pocket
walk: ``pdr-pocket run`` writes no step. A limit: a phone swung in the hand like a
pendulum swings once per cycle too (OxIOD's multi_users_user2_seq4: 2.0 footfalls per
cycle, a swing of 0.7 of a thigh's) and is taken for a back pocket.

It is judged only at a cadence of at least :data:`~pdr_core.walking.gait.PLACEMENT_MIN_CADENCE_HZ`
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

from pdr_core.walking.gait import (
    PLACEMENT_MIN_CADENCE_HZ,
    PLACEMENT_WINDOW_STEPS,
    THIGH_SWING_MIN_RATIO,
)
from pdr_pocket.config import StepLengthConfig
from pdr_pocket.step_length import AUTO_MODEL, StrideInputs

FRONT_POCKET, BACK_POCKET, UNKNOWN = "front pocket", "back pocket", "unknown"
NOT_IN_POCKET = "not in a pocket"
MODEL_AT = {FRONT_POCKET: "pitch", BACK_POCKET: "frequency", UNKNOWN: "pitch"}
NO_STRIDES = "none"     # the model of a walk not in a pocket: it gets no stride
# a thigh's gait: two footfalls per swing of the pitch; above this many, the pitch misses
# a third of the cycles the accelerometer hears (the module docstring's evidence)
THIGH_FOOTFALLS_PER_CYCLE_MAX = 3.0
# the fewest footfalls heard to judge by: a placement window's gait cycles
NOT_A_THIGH_MIN_FOOTFALLS = 2 * PLACEMENT_WINDOW_STEPS


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
        self.last: dict[str, Placement] = {}      # the last judgement of each placement

    def add(self, x: StrideInputs) -> Placement:
        """The placement with this level cycle in the window."""
        self.window.append((x.amplitude_deg, x.duration_s))
        self.current = self._decide()
        self.counts[self.current.placement] += 1
        self.models[self.current.model] += 1
        if self.current is self.judged:
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

    def verdict(self, cycles: int = 0, heard_footfalls: int | None = None) -> Placement:
        """The walk's placement so far, worded for the walk as a whole (the final report's
        and the live node's, the same): not in a pocket when the ``heard_footfalls`` (the
        accelerometer's, None: not counted apart) outnumber the pitch's gait ``cycles``
        (module docstring); else the placement of most judged level cycles, with its last
        swing ratio and reason; unknown when none was judged, and why."""
        if heard_footfalls is not None and heard_footfalls >= NOT_A_THIGH_MIN_FOOTFALLS \
                and heard_footfalls > THIGH_FOOTFALLS_PER_CYCLE_MAX * cycles:
            return Placement(NOT_IN_POCKET, NO_STRIDES, self._last_ratio(),
                             self._no_thigh_gait(cycles, heard_footfalls))
        decided = Counter({k: n for k, n in self.counts.items() if k != UNKNOWN})
        if decided:
            return self.last[decided.most_common(1)[0][0]]
        level = self.counts.total()
        if level < PLACEMENT_WINDOW_STEPS:
            return Placement(UNKNOWN, self.current.model, float("nan"),
                             f"{level} level gait cycles, fewer than the "
                             f"{PLACEMENT_WINDOW_STEPS} the placement is judged over")
        return self.current

    def _last_ratio(self) -> float:
        return float("nan") if self.judged is None else self.judged.swing_ratio

    def _no_thigh_gait(self, cycles: int, heard: int) -> str:
        """Why the phone is not in a pocket: the footfalls against the pitch's cycles,
        and the swing when it was judged."""
        why = (f"the accelerometer heard {heard} footfalls but the pitch swung through "
               f"{cycles} gait cycles; a thigh's swings once every two footfalls (at most "
               f"{THIGH_FOOTFALLS_PER_CYCLE_MAX:g}): these steps are no thigh's gait")
        if self.judged is not None:
            why += f", and the pitch swing is {100 * self.judged.swing_ratio:.0f} % of a thigh's"
        return why + " (held in the hand? in a bag?)"

    def summary(self, cycles: int = 0, heard_footfalls: int | None = None) -> dict:
        """report.json's ``placement``: the :meth:`verdict` with its swing ratio and
        reason, the stride model of most level cycles, the footfalls heard apart, and the
        level cycles per placement and per model."""
        verdict = self.verdict(cycles, heard_footfalls)
        ratio = verdict.swing_ratio
        return {"placement": verdict.placement,
                "stride_model": self.models.most_common(1)[0][0] if self.models
                else verdict.model,
                "configured_model": self.config.model,
                "swing_ratio": None if np.isnan(ratio) else round(ratio, 3),
                "why": verdict.why, "gait_cycles": cycles, "footfalls_heard": heard_footfalls,
                "cycles": dict(self.counts), "cycles_by_model": dict(self.models)}


def walk_placement(navigator) -> Placement:
    """The :meth:`PlacementClassifier.verdict` of a
    :class:`~pdr_pocket.navigator.PocketNavigator` so far: what ``pdr-pocket run``
    reports at the end and the live node says as it changes."""
    return navigator.placement.verdict(len(navigator.steps),
                                       navigator.pitch_source.heard_footfalls)


def placement_summary(navigator) -> dict:
    """:meth:`PlacementClassifier.summary` of a navigator (as :func:`walk_placement`)."""
    return navigator.placement.summary(len(navigator.steps),
                                       navigator.pitch_source.heard_footfalls)
