"""Fitting raised-cosine step patterns to a recorded foot trajectory
(Zampella et al. 2011, section II-B, Eqs. (3)–(5)).

The recorded positions (N, 3) [m] in a z-up frame are treated as the paper describes:

1. detect stance and swing: the foot speed (5-sample median filter against marker
   glitches, 55 ms moving average) is below ``stance_speed_mps`` for at least
   ``min_stance_s`` in a stance;
2. rotate each swing in the x-y plane so that its displacement lies along +x;
3. translate it to the origin;
4. drop false steps: horizontal length, duration, height change or peak speed outside
   plausible bounds (:class:`StepFilter`).

Then one pattern f(t) per channel, Eq. (4) (half raised cosines) for the along-track
displacement and Eq. (3) for the height, minimises Eq. (5), the squared error over all
samples of all kept steps, with Levenberg–Marquardt (``scipy.optimize.least_squares``,
``method="lm"``). Pitch and roll are fitted when the recording has attitude; otherwise
the pattern carries the basic pitch of Eq. (2) written as a raised cosine
(A0 = −θ_max, f0 = 1/t_u, t0 = t_u/4) and no roll.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.ndimage import uniform_filter1d
from scipy.optimize import least_squares

from pdr_core.config_files import parse_yaml
from pdr_core.errors import InputError
from pdr_core.maths.rotations import about_vertical
from pdr_sim.step_pattern import FittedPattern, RaisedCosines


@dataclass(frozen=True)
class StepFilter:
    """Bounds of a plausible step."""

    stance_speed_mps: float = 0.15
    min_stance_s: float = 0.08
    length_m: tuple[float, float] = (0.3, 2.5)
    duration_s: tuple[float, float] = (0.3, 1.5)
    max_height_change_m: float = 0.1
    max_speed_mps: float = 10.0


@dataclass
class Steps:
    """Aligned steps: per step, time since swing start (M,) and positions (M, 3), plus the
    indices of the rejected swings and why."""

    t: list[np.ndarray] = field(default_factory=list)
    xyz: list[np.ndarray] = field(default_factory=list)
    rejected: list[str] = field(default_factory=list)


def foot_speed(t: np.ndarray, position: np.ndarray) -> np.ndarray:
    """Smoothed speed [m/s] of a recorded foot (median filter, then moving average)."""
    from scipy.signal import medfilt  # 0.3 s to import, for the few commands that fit steps

    clean = np.column_stack([medfilt(position[:, i], 5) for i in range(3)])
    speed = np.linalg.norm(np.gradient(clean, t, axis=0), axis=1)
    rate = (len(t) - 1) / (t[-1] - t[0])
    return uniform_filter1d(speed, max(1, round(0.055 * rate)))


def cut_steps(t: np.ndarray, position: np.ndarray, limits: StepFilter = StepFilter()) -> Steps:
    """Steps 1–4 of the paper's procedure (see the module docstring)."""
    rate = (len(t) - 1) / (t[-1] - t[0])
    speed = foot_speed(t, position)
    still = speed < limits.stance_speed_mps
    edges = np.flatnonzero(np.diff(still.astype(int))) + 1
    runs = np.split(np.arange(len(t)), edges)
    stances = [r for r in runs if still[r[0]] and len(r) >= limits.min_stance_s * rate]
    steps = Steps()
    for before, after in itertools.pairwise(stances):
        start, stop = before[-1], after[0]
        seg = position[start:stop + 1]
        disp = seg[-1] - seg[0]
        length, duration = np.hypot(disp[0], disp[1]), t[stop] - t[start]
        peak = np.max(np.linalg.norm(np.diff(seg, axis=0), axis=1)) * rate
        reason = ("length" if not limits.length_m[0] <= length <= limits.length_m[1] else
                  "duration" if not limits.duration_s[0] <= duration <= limits.duration_s[1] else
                  "height change" if abs(disp[2]) > limits.max_height_change_m else
                  "glitch" if peak > limits.max_speed_mps else "")
        if reason:
            steps.rejected.append(f"swing at {t[start]:.2f} s: {reason}")
            continue
        heading = np.arctan2(disp[1], disp[0])
        aligned = about_vertical(seg - seg[0], -heading)
        steps.t.append(t[start:stop + 1] - t[start])
        steps.xyz.append(aligned)
    return steps


def fit_channel(times: list[np.ndarray], values: list[np.ndarray], half: bool,
                guess: list[float]) -> RaisedCosines:
    """Eq. (5): one raised-cosine pair for all steps, by Levenberg–Marquardt."""
    t = np.concatenate(times)
    y = np.concatenate(values)

    def residual(p: np.ndarray) -> np.ndarray:
        return RaisedCosines(*p, half=half)(t).f - y

    fit = least_squares(residual, np.asarray(guess, float), method="lm")
    return RaisedCosines(*map(float, fit.x), half=half)


def fit_pattern(steps: Steps, pitch_max_rad: float = 0.55) -> FittedPattern:
    """The fitted pattern of the kept steps (at least 3)."""
    if len(steps.t) < 3:
        raise ValueError(f"only {len(steps.t)} valid steps to fit (need 3); rejected: "
                         + "; ".join(steps.rejected[:5]))
    swing = float(np.median([t[-1] for t in steps.t]))
    length = float(np.median([xyz[-1, 0] for xyz in steps.xyz]))
    height = float(np.median([xyz[:, 2].max() for xyz in steps.xyz]))
    along = fit_channel(steps.t, [xyz[:, 0] for xyz in steps.xyz], True,
                        [length / 4, length / 4, 1 / swing, 1 / swing, 0.0, 0.0])
    up = fit_channel(steps.t, [xyz[:, 2] for xyz in steps.xyz], False,
                     [height / 2, height / 4, 1 / swing, 2 / swing, 0.0, 0.0])
    pitch = RaisedCosines(-pitch_max_rad, 0.0, 1 / swing, 1 / swing, swing / 4, 0.0)
    roll = RaisedCosines(0.0, 0.0, 1 / swing, 1 / swing, 0.0, 0.0)
    return FittedPattern(swing, along, up, pitch, roll)


def pattern_to_dict(pattern: FittedPattern) -> dict:
    return {"swing_s": pattern.swing_s,
            **{name: getattr(pattern, name).as_list() for name in ("s", "z", "pitch", "roll")}}


def pattern_from_file(path: str | Path) -> FittedPattern:
    """A pattern written by ``pdr-sim fit-steps``; InputError names the file when it cannot
    be read or is not such a pattern."""
    try:
        data = parse_yaml(Path(path).read_text(), path)
        return FittedPattern(float(data["swing_s"]), RaisedCosines(*data["s"], half=True),
                             RaisedCosines(*data["z"]), RaisedCosines(*data["pitch"]),
                             RaisedCosines(*data["roll"]))
    except (OSError, KeyError, TypeError, ValueError) as exc:
        raise InputError(path, f"not a step pattern of pdr-sim fit-steps ({exc!r})") from exc


def rms_error(steps: Steps, pattern: FittedPattern) -> tuple[float, float]:
    """RMS residual [m] of the along-track and height fits over all kept steps."""
    t = np.concatenate(steps.t)
    xyz = np.concatenate(steps.xyz)
    return (float(np.sqrt(np.mean((pattern.s(t).f - xyz[:, 0]) ** 2))),
            float(np.sqrt(np.mean((pattern.z(t).f - xyz[:, 2]) ** 2))))
