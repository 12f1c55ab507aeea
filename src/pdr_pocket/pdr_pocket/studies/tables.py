"""The thesis' comparison tables on simulated bags (Muñoz Díaz 2016, Tables 4.1 and 4.4),
and the stride calibration of ``pdr-pocket calibrate-step``.

- :func:`detector_rows`: per bag and detector of Table 4.1, the undetected (US) and false
  (FD) steps in % of the true ones. Footfall detectors (‖α‖ peaks) are matched against
  the true footfalls (the cycle's end and its middle), each within a quarter cycle, the
  others against the cycles.
- :func:`stride_rows`: per bag, the distance error % (total estimated over total true
  strides, Table 4.4) of the pitch line and of the frequency and Weinberg models, the
  latter two calibrated on the first bag (their one free factor fitted so that its
  distance comes out right; the thesis personalises both the same way).
- :func:`level_amplitudes`: the level steps' Δθ [deg] of a bag, for calibrate-step.
"""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.vocabulary import Activity
from pdr_pocket.config import PocketConfig
from pdr_pocket.inputs import read_pocket_bag
from pdr_pocket.navigator import PocketNavigator
from pdr_pocket.records import NavigatorOutput, StepRecord
from pdr_pocket.run_report import match_steps
from pdr_pocket.step_length import StrideInputs, stride_model
from pdr_pocket.steps import table_4_1_detectors


def navigate(bag: Path, config: PocketConfig, need_truth: bool = False):
    """The navigator's output on a bag, the inputs, and its ground_truth/step (or None)."""
    _, batches, inputs = read_pocket_bag(
        bag, require=[topics.GROUND_TRUTH_STEP] if need_truth else [])
    out = PocketNavigator(config).process(inputs.samples)
    return out, inputs, batches.get(topics.GROUND_TRUTH_STEP)


def _true_times(truth, t0_ns: int) -> tuple[np.ndarray, np.ndarray]:
    return (truth.stamp_ns - t0_ns) * 1e-9, np.asarray(truth["duration"], float)


def _rates(found_t: np.ndarray, ends: np.ndarray, durations: np.ndarray) -> tuple[float, float]:
    match = match_steps(found_t, ends, durations)
    missed = 100 * float((match < 0).mean())
    false = 100 * (len(found_t) - int((match >= 0).sum())) / len(ends)
    return missed, false


def detector_rows(bags: list[Path], config: PocketConfig) -> list[dict]:
    """Table 4.1 (module docstring)."""
    rows = []
    for bag in bags:
        out, inputs, truth = navigate(bag, config, need_truth=True)
        ends, durations = _true_times(truth, int(inputs.stamp_ns[0]))
        quarter = float(np.median(durations)) / 4
        footfalls = np.sort(np.r_[ends, ends - durations / 2]) + quarter   # window ends
        half = np.full(len(footfalls), 2 * quarter)
        for detector in table_4_1_detectors(config.steps):
            found = detector.detect(inputs.t, out.pitch, inputs.accel)
            missed, false = (_rates(found.t, footfalls, half) if found.per_cycle == 2
                             else _rates(found.t, ends, durations))
            rows.append({"bag": bag.name, "detector": detector.name, "undetected_pct": missed,
                         "false_pct": false})
    return rows


def stride_inputs(step: StepRecord) -> StrideInputs:
    return StrideInputs(float(np.degrees(step.pitch_amplitude)), step.duration,
                        step.vertical_force_range)


def walked(out: NavigatorOutput, model, factor: float = 1.0) -> float:
    """The distance [m] of the steps with the level strides by ``model`` times ``factor``
    (stairs steps keep theirs)."""
    return sum(factor * model.length(stride_inputs(s)) if s.activity == Activity.WALKING
               else s.length for s in out.steps)


def stride_rows(bags: list[Path], config: PocketConfig) -> list[dict]:
    """Table 4.4 (module docstring)."""
    runs = [navigate(bag, config, need_truth=True) for bag in bags]
    models = {name: stride_model(replace(config.step_length, model=name))
              for name in ("pitch", "frequency", "weinberg")}
    first_out, _, first_truth = runs[0]
    factors = {name: 1.0 if name == "pitch" else
               float(first_truth["length"].sum()) / walked(first_out, model)
               for name, model in models.items()}
    rows = []
    for bag, (out, _, truth) in zip(bags, runs, strict=True):
        true = float(truth["length"].sum())
        rows.append({"bag": bag.name, **{
            f"{name}_error_pct": 100 * (walked(out, model, factors[name]) / true - 1)
            for name, model in models.items()}})
    return rows


def level_amplitudes(bag: Path, config: PocketConfig) -> np.ndarray:
    """Δθ [deg] of the level steps of a walk (calibrate-step)."""
    out, _, _ = navigate(bag, config)
    amplitudes = np.array([np.degrees(s.pitch_amplitude) for s in out.steps
                           if s.activity == Activity.WALKING])
    if not len(amplitudes):
        raise InputError(bag, "no level steps found: is this a walk with the phone in the "
                              "trouser pocket?")
    return amplitudes
