"""One replay for the corrections that come late, for any navigator: the foot's filter
(pdr_ins_ekf.correctable), the live pocket navigator (pdr_pocket.streaming) and the
pocket's drift loop in one process (pdr_pocket.drift_loop) take a correction at the
instant it belongs to through :meth:`Replay.correct`, as robot_localization's filters all
go through its one ``revertTo``.

A correction names an instant in the past (the stride or step whose landmark it comes
from) while the navigator has gone on. :class:`Replay` keeps the navigator's state at
past instants with the inputs it took since (pdr_core.corrections.checkpoints) and takes the
correction in six moves:

1. **look back** to the latest checkpoint at or before the instant, a copy of its state,
   the history left as it is;
2. **split** the inputs kept since at the instant (:func:`split`: a chunk straddling it
   cut in two);
3. **run before**: a worker at that state (:meth:`Replayable.worker`) takes the inputs up
   to the instant again, outside the history;
4. **gate**: the worker takes the correction (:meth:`Worker.apply_correction`), whole or not at
   all; a refusal changes nothing and ends here;
5. **revert and remember**: the history goes back to the checkpoint, which it keeps
   again, with the inputs before the instant and the correction (a
   :class:`TakenCorrection`, an input like the others: a later correction reaching further
   back takes it again in its place);
6. **run after**: the navigator continues from the worker's state
   (:meth:`Replayable.adopt`) and takes the inputs after the instant again, kept in the
   history (:meth:`Replayable.take`); what they give comes back in the
   :class:`CorrectionResult`, to replace what was given out before the call came.

A navigator gives the replay its own inputs (chunks with ``end_s`` and ``split``: the
pocket's :class:`pdr_pocket.samples.Samples`, the foot's
:class:`pdr_ins_ekf.correctable.FilterBlock`), its state (copied by the function the
:class:`Replay` is made with) and its way of taking a correction; the refusals that need no
state are pdr_core.corrections.correction's, and the ones that need the history (a stamp after the
last sample, or older than the window) each navigator's, before it calls
:meth:`Replay.correct`.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Generic, Protocol, TypeVar

from pdr_core.corrections.checkpoints import Checkpoints
from pdr_core.corrections.correction import Correction

State = TypeVar("State")
Output = TypeVar("Output")


@dataclass(frozen=True)
class TakenCorrection:
    """A correction taken at instant ``t_s`` [s of the navigator's time]: an input of the
    history, taken again in its place on a replay."""

    t_s: float
    correction: Correction

    @property
    def end_s(self) -> float:
        return self.t_s


@dataclass(frozen=True)
class CorrectionResult(Generic[Output]):
    """What became of a correction: accepted, what was done or why not, and when it was
    taken at a past instant, what the inputs after it gave when taken again (the
    navigator's outputs, oldest first)."""

    accepted: bool
    message: str
    revised: list[Output] = field(default_factory=list)


class Chunk(Protocol):
    """Consecutive inputs of a navigator, its last at ``end_s`` [s]."""

    @property
    def end_s(self) -> float: ...

    def split(self, t_s: float) -> tuple[Chunk, Chunk]:
        """The inputs at or before ``t_s`` [s] and those after it (either may be empty:
        ``len`` 0)."""
        ...

    def __len__(self) -> int: ...


Input = TypeVar("Input", bound=Chunk)


class Worker(Protocol[Input]):
    """A navigator at a kept state, taking inputs again outside the history."""

    def rerun(self, item: Input | TakenCorrection) -> None:
        """An input again: a chunk, or a correction taken before."""
        ...

    def apply_correction(self, correction: Correction) -> tuple[bool, str]:
        """Gate the correction against the state now and apply it, whole or not at all:
        (accepted, what was done or why not)."""
        ...


class Replayable(Protocol[State, Input, Output]):
    """What a navigator gives :meth:`Replay.correct`."""

    def worker(self, state: State) -> Worker[Input]:
        """A worker at ``state`` (the replay's copy: the worker may keep it)."""
        ...

    def adopt(self, worker: Worker[Input]) -> None:
        """Go on from the worker's state."""
        ...

    def take(self, item: Input | TakenCorrection) -> list[Output]:
        """An input taken again and kept in the replay's history; its outputs."""
        ...


def split(inputs: list, t_s: float) -> tuple[list, list]:
    """The inputs at or before instant ``t_s`` [s] and those after it, a chunk straddling
    it cut in two there."""
    before, after = [], []
    for item in inputs:
        if item.end_s <= t_s:
            before.append(item)
        elif isinstance(item, TakenCorrection):
            after.append(item)
        else:
            early, late = item.split(t_s)
            if len(early):
                before.append(early)
            if len(late):
                after.append(late)
    return before, after


class Replay(Generic[State, Input]):
    """The navigator's states at past instants with the inputs taken since
    (``history``, a :class:`~pdr_core.corrections.checkpoints.Checkpoints` with the ``copy``,
    ``window_s`` [s] and ``capacity`` given), and the one replay of a late correction
    (module docstring)."""

    def __init__(self, copy: Callable[[State], State], window_s: float,
                 capacity: int | None = None) -> None:
        self.history: Checkpoints[State, Input | TakenCorrection] = Checkpoints(
            copy, window_s, capacity)

    def serves(self, t_s: float) -> bool:
        """A checkpoint is kept at or before instant ``t_s`` [s]."""
        return bool(self.history.instants) and t_s >= self.history.instants[0]

    def correct(self, navigator: Replayable[State, Input, Output], correction: Correction,
                t_s: float) -> CorrectionResult[Output]:
        """Take ``correction`` at instant ``t_s`` [s], which a checkpoint serves
        (:meth:`serves`), and the inputs since again (module docstring)."""
        looked = self.history.look_back(t_s)
        if looked is None:
            raise ValueError(f"no checkpoint at or before {t_s} s: ask serves() first")
        worker = navigator.worker(looked.state)
        before, after = split(looked.inputs, t_s)
        for item in before:
            worker.rerun(item)
        accepted, message = worker.apply_correction(correction)
        if not accepted:
            return CorrectionResult(False, message)
        reverted = self.history.revert_to(looked.t_s)
        self.history.remember(reverted.t_s, reverted.state)
        for item in [*before, TakenCorrection(t_s, correction)]:
            self.history.record(item, item.end_s)
        navigator.adopt(worker)
        return CorrectionResult(True, message, [out for item in after
                                                for out in navigator.take(item)])
