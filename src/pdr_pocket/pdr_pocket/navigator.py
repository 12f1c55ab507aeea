"""The pocket navigator: from IMU samples to steps and a 3D position (Muñoz Díaz 2016,
chapters 3, 4 and 6).

:class:`PocketNavigator` composes, per chunk of :class:`~pdr_pocket.samples.Samples`
(one sample live, a whole record offline, the same result either way), three parts, each
in the module named for it:

1. the sensors and the pitch source (:mod:`pdr_pocket.pitch_source`): the orientation
   filter, or without a gyroscope the gravity direction's tilt; the thigh frame and
   pitch;
2. the steps (:mod:`pdr_pocket.step_assembly`): the step detector, and per step the
   activity, stride, vertical displacement, heading and position; with a barometer the
   height, floors and lift rides from the height filter (:mod:`pdr_pocket.height_filter`);
3. the corrections (:mod:`pdr_pocket.corrections`, Eqs. (6.2)-(6.3)): a
   :class:`~pdr_core.corrections.correction.Correction` through
   :meth:`PocketNavigator.apply_correction`.

The first chunk says which sensors there are: without a gyroscope the footfalls count
the steps and every step is level.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, fields, is_dataclass, replace

import numpy as np

from pdr_core.corrections.correction import Correction
from pdr_core.corrections.replay import TakenCorrection
from pdr_pocket.config import PocketConfig, StairsConfig
from pdr_pocket.corrections import CorrectionTaker
from pdr_pocket.height_records import BarometerStatus
from pdr_pocket.pitch_source import PitchSource
from pdr_pocket.records import NavigatorOutput
from pdr_pocket.samples import Samples
from pdr_pocket.step_assembly import StepAssembly
from pdr_pocket.step_length import StepLengthConfig


def frozen_records(config: PocketConfig) -> dict[int, object]:
    """The frozen dataclasses reachable from ``config`` (itself included), by ``id``: as
    :func:`copy.deepcopy`'s memo, a copy shares them instead of copying what never
    changes."""
    records: dict[int, object] = {}
    todo: list[object] = [config]
    while todo:
        item = todo.pop()
        if (is_dataclass(item) and not isinstance(item, type) and id(item) not in records
                and item.__dataclass_params__.frozen):
            records[id(item)] = item
            todo.extend(getattr(item, f.name) for f in fields(item))
    return records


@dataclass(frozen=True)
class TakenLines:
    """The person's lines taken at instant ``t_s`` [s of the navigator's time]
    (:meth:`PocketNavigator.take_lines`): an input of a replay's history
    (pdr_core.corrections.replay), taken again in its place when a correction reaches back
    before it, so the steps before it keep the lines they had."""

    t_s: float
    step_length: StepLengthConfig
    stairs: StairsConfig

    @property
    def end_s(self) -> float:
        return self.t_s

    def __len__(self) -> int:
        return 1

    def split(self, t_s: float) -> tuple[tuple, TakenLines]:
        """An instant: all of it after ``t_s`` (the replay splits only what ends after)."""
        return (), self


class PocketNavigator:
    def __init__(self, config: PocketConfig) -> None:
        self.config = config
        self.shared = frozen_records(config)    # what a copy shares (copy_state)
        self.reset()

    def reset(self) -> None:
        self.pitch_source = PitchSource(self.config)
        self.assembly = StepAssembly(self.config)
        self.taker = CorrectionTaker(self.pitch_source.orientation, self.assembly)
        self.gyroscope: bool | None = None      # known from the first samples

    def copy_state(self) -> PocketNavigator:
        """A copy to run on from here (a correction taken as of an earlier sample): its
        state deep-copied, its list of steps a new list of the same frozen records (a deep
        copy of them at every step would grow with the walk), its configuration the same
        frozen records (:func:`frozen_records`; copying them was 40 % of the copy's time)."""
        steps, self.assembly.steps = self.assembly.steps, []
        try:
            duplicate = copy.deepcopy(self, dict(self.shared))
        finally:
            self.assembly.steps = steps
        duplicate.assembly.steps = list(steps)
        return duplicate

    # --- what the parts hold ----------------------------------------------------------
    @property
    def orientation(self):
        """The orientation filter (pdr_pocket.orientation)."""
        return self.pitch_source.orientation

    @property
    def gyro_noise_var(self) -> float:
        """The orientation filter's σ_ν² [rad²/s²] per sample (its attitude messages')."""
        return self.orientation.gyro_noise_var

    @property
    def mounting(self):
        """The thigh frame's state (pdr_pocket.compiled_mounting)."""
        return self.pitch_source.mounting

    @property
    def steps(self):
        """Every step so far (pdr_pocket.records.StepRecord)."""
        return self.assembly.steps

    @property
    def position(self):
        """The position filter (pdr_pocket.position)."""
        return self.assembly.position

    @property
    def staircases(self):
        """The staircases and the floor (pdr_pocket.stairs)."""
        return self.assembly.staircases

    @property
    def placement(self):
        """Where the phone rides (pdr_pocket.placement)."""
        return self.assembly.placement

    @property
    def bounded_steps(self) -> int:
        """Strides cut to what a person walks at their cadence."""
        return self.assembly.bounded_steps

    @property
    def footfalls(self) -> int:
        """Footfalls of both feet so far."""
        return self.assembly.footfalls

    @property
    def moving_s(self) -> float:
        """Time moving so far [s] (pdr_pocket.pitch_source)."""
        return self.pitch_source.moving_s

    @property
    def corrections(self) -> dict[str, int]:
        """The corrections accepted and refused so far."""
        return self.taker.counts

    # --- processing -----------------------------------------------------------------
    def process(self, samples: Samples) -> NavigatorOutput:
        """A chunk of samples (:class:`~pdr_pocket.samples.Samples`: t [s], accel [m/s²],
        gyro [rad/s] or None, mag [T] or None)."""
        samples = replace(samples, t=np.asarray(samples.t, float))
        if self.gyroscope is None and len(samples):
            self.gyroscope = samples.gyro is not None
            self.assembly.use_sensors(self.gyroscope)
        chunk = self.pitch_source.run(samples)
        a = self.assembly
        a.sense_height(samples, chunk)
        before = (a.last_confirm, a.last_activity)
        steps = a.add(chunk)
        return NavigatorOutput(chunk.attitude, chunk.pitch, chunk.heading,
                               a.activity(samples.t, chunk.tilt, steps, before), steps)

    def apply_correction(self, correction: Correction) -> tuple[bool, str]:
        """Take ``correction`` whole or not at all (pdr_pocket.corrections): (accepted,
        what was done or why not). Its stamp is the caller's (pdr_pocket.streaming)."""
        return self.taker.take(correction)

    def take_lines(self, step_length: StepLengthConfig, stairs: StairsConfig) -> None:
        """The person's level and stairs lines (pdr_pocket.line_calibration) for the
        steps confirmed from now on (pdr_pocket.step_assembly.StepAssembly.take_lines);
        the steps before keep theirs."""
        self.config = replace(self.config, step_length=step_length, stairs=stairs)
        self.shared = frozen_records(self.config)
        self.assembly.take_lines(step_length, stairs)

    def rerun(self, item: Samples | TakenCorrection | TakenLines) -> None:
        """A kept input again, on a replay (pdr_core.corrections.replay.Worker): a chunk of samples,
        a correction taken before (gated again) or lines taken before."""
        if isinstance(item, TakenCorrection):
            self.apply_correction(item.correction)
        elif isinstance(item, TakenLines):
            self.take_lines(item.step_length, item.stairs)
        else:
            self.process(item)

    # --- what the result says ---------------------------------------------------------
    def detection(self) -> dict:
        """What counted the steps and what named their activities, and why (the report
        and the node's log say it)."""
        a = self.assembly
        if self.gyroscope is None:
            return {"step_detector": a.detector.name, "pitch_from": "no sample yet",
                    "activities": a.classifier.name}
        pitch_from = "the orientation filter (gyroscope and accelerometer)" \
            if self.gyroscope else "the gravity direction alone (no gyroscope: the " \
            "accelerometer's low-passed specific force)"
        activities = a.classifier.name if self.gyroscope else \
            "level only (no gyroscope: the gravity direction's pitch holds no stairs evidence)"
        return {"step_detector": a.detector.name, "pitch_from": pitch_from,
                "activities": activities}

    def barometer(self) -> dict | None:
        """What the barometer did (the report's ``barometer``; None without one): whether
        it was fused, the lift and escalator rides, the changes judged by kind, the
        offset jumps let in, the readings dropped and the steps whose climb came late."""
        if not self.assembly.barometer:
            return None
        h = self.assembly.height
        kinds = [c.kind.label for c in h.changes]
        return {"fused": h.fused,
                "rides": [{"kind": r.kind.label, "start_s": r.start_s, "end_s": r.end_s,
                           "height_m": r.height_m, "floors": r.floors} for r in h.rides],
                "changes": {kind: kinds.count(kind) for kind in sorted(set(kinds))},
                "offset_jumps": h.jumps, "dropped": dict(h.dropped),
                "late_steps": h.late_steps}

    def barometer_status(self) -> BarometerStatus:
        """Whether the barometer goes into the height, and why not (the report's
        ``inputs``, the node's /diagnostics; pdr_pocket.height_filter)."""
        return self.assembly.height.status()

    def no_step_reason(self) -> str | None:
        """Why no step was found, when none was (None otherwise)."""
        return self.pitch_source.no_step_reason(bool(self.steps))

    def bound_warning(self) -> str | None:
        """What to say when strides needed the bound (None otherwise)."""
        return self.assembly.bound_warning()

    def speed_warning(self) -> str | None:
        """What to say when the level steps walk faster than a person walks."""
        return self.assembly.speed_warning()

    def warnings(self) -> list[str]:
        """What is implausible or missing in the result so far (the report's and the
        log's warnings, the plot's title)."""
        return [w for w in (self.no_step_reason(), self.bound_warning(), self.speed_warning())
                if w is not None]
