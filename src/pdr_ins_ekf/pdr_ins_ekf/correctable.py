"""The foot filter with its recent past kept, to give strides and take drift corrections
at the stride they belong to (``zupt_ekf``'s ``pdr/foot/apply_correction``, ``pdr-ekf run
--drift online``), as the pocket navigator takes them (pdr_pocket.streaming).

:class:`CorrectableFilter` runs the filter (pdr_ins_ekf.zupt_ekf.ZuptEkf) over blocks of
decided samples and finds the strides in them (pdr_ins_ekf.strides). Each block is cut
right after every stance onset, so a stride ends a piece; after each stride the filter's
state and the stride tracker are kept as a checkpoint at the stride's instant, with the
pieces filtered since (pdr_core.corrections.checkpoints), for ``window_s`` of data.

A correction names its stride by stamp (pdr_msgs/srv/ApplyCorrection). The filter goes
back to the checkpoint at or before it, runs the pieces up to the stamp, gates the
correction there (pdr_ins_ekf.corrections) and, when every part passes, applies it and
runs the pieces since again: the estimates and strides after the stamp come back with the
answer (pdr_core.corrections.replay.CorrectionResult, the :class:`Filtered` parts run again) to
replace those given out before the call came; the replay is pdr_core.corrections.replay's, the
pocket navigator's too. A refused correction changes nothing. The corrections taken are inputs
too, so one that reaches further back takes them again in their place. A zero stamp
applies the correction to the state now. A stamp later than the last sample filtered, or
older than the window, is refused by name.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np

from pdr_core.corrections.correction import Correction
from pdr_core.corrections.replay import CorrectionResult, Replay, TakenCorrection
from pdr_ins_ekf import corrections
from pdr_ins_ekf.kernel_data import NavState
from pdr_ins_ekf.strides import Stride, StrideTracker
from pdr_ins_ekf.zupt_ekf import FilterOutput, ZuptEkf

CORRECTION_WINDOW_S = 60.0
"""How far back a stamped correction may reach [s of IMU data], as the pocket navigator's
(pdr_pocket.streaming.CORRECTION_WINDOW_S): a minute of samples and one checkpoint per
stride."""


@dataclass(frozen=True)
class FilterBlock:
    """Consecutive decided samples: stamps (N,) [ns], their time t (N,) [s] from the
    first sample, the intervals dt (N,) [s], specific force and rate (N, 3) [m/s², rad/s],
    body frame, and the stance decisions (N,)."""

    stamp_ns: np.ndarray
    t_s: np.ndarray
    dt: np.ndarray
    accel: np.ndarray
    gyro: np.ndarray
    stance: np.ndarray

    def __len__(self) -> int:
        return len(self.stamp_ns)

    def part(self, start: int, stop: int) -> FilterBlock:
        return FilterBlock(*(getattr(self, f.name)[start:stop] for f in fields(self)))

    def split(self, t_s: float) -> tuple[FilterBlock, FilterBlock]:
        """The samples at or before instant ``t_s`` [s] and those after it."""
        cut = int(np.searchsorted(self.t_s, t_s, side="right"))
        return self.part(0, cut), self.part(cut, len(self))

    @property
    def end_s(self) -> float:
        return float(self.t_s[-1])


@dataclass
class FilterState:
    """What a checkpoint keeps: the filter's state and the stride tracker."""

    nav: NavState
    started: bool
    strides: StrideTracker

    def copy(self) -> FilterState:
        return FilterState(NavState(*(a.copy() for a in self.nav)), self.started,
                           self.strides.copy())


@dataclass(frozen=True)
class Filtered:
    """A block's estimates and the strides it ended."""

    block: FilterBlock
    output: FilterOutput
    strides: list[Stride] = field(default_factory=list)


def concatenated(parts: list[Filtered]) -> Filtered:
    """Consecutive :class:`Filtered` parts as one."""
    if len(parts) == 1:
        return parts[0]
    return Filtered(
        FilterBlock(*(np.concatenate([getattr(p.block, f.name) for p in parts])
                      for f in fields(FilterBlock))),
        FilterOutput.concatenate([p.output for p in parts]),
        [s for p in parts for s in p.strides])


class CorrectableFilter:
    """The filter ``ekf`` (aligned) with strides, checkpoints and corrections (module
    docstring)."""

    def __init__(self, ekf: ZuptEkf, window_s: float = CORRECTION_WINDOW_S) -> None:
        self.ekf = ekf
        self.strides = StrideTracker()
        self.replay: Replay[FilterState, FilterBlock] = Replay(FilterState.copy, window_s)
        self.last_s: float | None = None

    def state(self) -> FilterState:
        """The state now (not a copy)."""
        return FilterState(self.ekf.state, self.ekf.started, self.strides)

    def _restore(self, state: FilterState) -> None:
        self.ekf.state, self.ekf.started, self.strides = state.nav, state.started, state.strides

    def run(self, block: FilterBlock) -> Filtered:
        """Filter a block, cut after each stance onset; a checkpoint after each stride."""
        cuts = [*(self.strides.onsets(block.stance) + 1).tolist(), len(block.stamp_ns)]
        parts, start = [], 0
        for stop in cuts:
            if stop > start:
                parts.append(self._run_piece(block.part(start, stop)))
            start = stop
        self.last_s = block.end_s
        return concatenated(parts)

    def _run_piece(self, piece: FilterBlock) -> Filtered:
        output = self.ekf.run_block(piece.accel, piece.gyro, piece.dt, piece.stance)
        strides = self.strides.push(piece.stamp_ns, piece.stance, output)
        self.replay.history.record(piece, piece.end_s)
        for stride in strides:
            self.replay.history.remember(self._instant(piece, stride.stamp_ns), self.state())
        return Filtered(piece, output, strides)

    @staticmethod
    def _instant(piece: FilterBlock, stamp_ns: int) -> float:
        return float(piece.t_s[np.searchsorted(piece.stamp_ns, stamp_ns)])

    def apply_correction(self, correction: Correction, t_s: float | None
                         ) -> CorrectionResult:
        """Take ``correction`` as of instant ``t_s`` [s] (its stamp's; None: now), the
        samples since filtered again (module docstring)."""
        problem = corrections.refusal(correction, self.ekf.state.P.shape[0])
        if problem is None and t_s is not None:
            problem = self._instant_problem(t_s)
        if problem is not None:
            return CorrectionResult(False, f"nothing applied: {problem}")
        if t_s is None:
            return self._apply_now(correction)
        return self.replay.correct(self, correction, t_s)

    # --- the replay's side (pdr_core.corrections.replay.Replayable) -------------------------------
    def worker(self, state: FilterState) -> Scratch:
        """A filter at ``state`` (the replay's copy), outside the history."""
        scratch = CorrectableFilter(ZuptEkf(self.ekf.config, self.ekf.C))
        scratch._restore(state)
        return Scratch(scratch)

    def adopt(self, worker: Scratch) -> None:
        self._restore(worker.filter.state())

    def take(self, item: FilterBlock | TakenCorrection) -> list[Filtered]:
        """A kept input again, in the history: a block's estimates and strides."""
        filtered = self._take(item)
        return [] if filtered is None else [filtered]

    def gated(self, correction: Correction) -> tuple[bool, str]:
        """Gate ``correction`` against the state now and apply it, whole or not at all
        (pdr_ins_ekf.corrections): (accepted, what was done or why not)."""
        problem, nis = corrections.gate(correction, self.ekf.state)
        if problem is not None:
            return False, f"nothing applied: {problem}"
        corrections.apply(correction, self.ekf.state)
        return True, _applied(nis)

    def _take(self, item: FilterBlock | TakenCorrection) -> Filtered | None:
        """An input again: a block filtered (kept in the history when this is the
        navigator's filter), a correction applied."""
        if isinstance(item, TakenCorrection):
            corrections.apply(item.correction, self.ekf.state)
            self.replay.history.record(item, item.end_s)
            return None
        return self._run_piece(item)

    def _apply_now(self, correction: Correction) -> CorrectionResult:
        accepted, message = self.gated(correction)
        if accepted and self.last_s is not None:
            self.replay.history.record(TakenCorrection(self.last_s, correction), self.last_s)
        return CorrectionResult(accepted, message)

    def _instant_problem(self, t_s: float) -> str | None:
        """Why no kept state serves instant ``t_s`` [s] (None: one does)."""
        if self.last_s is None or t_s > self.last_s:
            return (f"the stamp is {t_s - (self.last_s or 0.0):.3f} s after the last sample "
                    "filtered")
        if not self.replay.serves(t_s):
            oldest = self.replay.history.instants[0] if len(self.replay.history) else None
            reach = ("no stride kept yet" if oldest is None
                     else f"the oldest kept stride is {self.last_s - oldest:.1f} s back")
            return (f"the stamp is {self.last_s - t_s:.1f} s back, beyond the correction "
                    f"window of {self.replay.history.window_s:g} s of IMU data ({reach})")
        return None


@dataclass
class Scratch:
    """A filter at a kept state taking the inputs again outside the history, on a replay
    (pdr_core.corrections.replay.Worker)."""

    filter: CorrectableFilter

    def rerun(self, item: FilterBlock | TakenCorrection) -> None:
        self.filter._take(item)

    def apply_correction(self, correction: Correction) -> tuple[bool, str]:
        return self.filter.gated(correction)


def _applied(nis: dict[str, float]) -> str:
    return "applied: " + ", ".join(f"{name} (NIS {value:.2f})" for name, value in nis.items())
