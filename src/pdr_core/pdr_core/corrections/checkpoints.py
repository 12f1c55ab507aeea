"""A correction that arrives after its instant: the navigator's state kept at past
instants with the inputs processed since, to take the correction there and run the
inputs again (robot_localization's ``revertTo``).

A correction refers to an instant in the past (the step whose landmark it comes from)
while the navigator has gone on with the inputs after it. :class:`Checkpoints` keeps
snapshots of the navigator's state and the inputs processed since, in order::

    history.remember(t_s, navigator)       # a copy of the state at instant t_s
    navigator.process(inputs)
    history.record(inputs, t_end_s)        # processed after it, the last at t_end_s
    ...
    reverted = history.revert_to(t_c_s)    # a correction at instant t_c_s
    if reverted is None:                   # late (below): from the current state
        navigator.apply_correction(...)
    else:                                  # from reverted.state, then run again
        ...                                # the inputs of reverted.inputs

**Instants.** A checkpoint at ``t_s`` holds every input stamped before ``t_s`` (and those
at ``t_s`` the caller chose to process first); the inputs recorded after it hold the
rest. A correction at ``t_c_s`` ≥ ``t_s`` is taken from it: the recorded inputs stamped
at or before ``t_c_s`` run first, then the correction, then the rest. Instants are in
seconds of the navigator's time (any increasing key in the window's unit would do).

**Generic over the navigator.** A state is any object, copied by the ``copy`` function
given (:meth:`pdr_pocket.navigator.PocketNavigator.copy_state`; for the foot navigator's
:class:`pdr_ins_ekf.streaming.StreamingNavigator`, a deep copy, at instants of its filter,
which runs the stance detector's context behind the input); inputs are any objects
too (sample arrays for :class:`pdr_pocket.streaming.StreamingPocket`), run again by the
caller, which knows how. A caller that keeps its inputs itself
(:func:`pdr_pocket.drift_loop.navigate_online`, the record's arrays) need not record them.

**Bounded.** A checkpoint more than ``window_s`` before the last input recorded is
dropped, with the inputs before the next one, and at most ``capacity`` checkpoints are
kept (the oldest go first).

**Late corrections.** A correction at an instant no checkpoint serves (before the oldest
one kept: beyond the window, or before the first) is late: :meth:`Checkpoints.revert_to`
returns None. Its caller either refuses it by name (the live pocket navigator,
pdr_pocket.streaming: a stamp older than its ``correction_window_s``) or expresses it from
the current state with the drift's effect since its instant carried forward, as position
fixes are: the fix is the position then plus what was walked since (pdr_drift.estimator's
fixes are carried so already, from the revisit's landmark to the step that found it). A
yaw change δ [rad] with a drift ε [rad/s] added to the z gyro bias at ``t_c_s`` stands for
δ − ε·(t_now − t_c_s) of yaw at ``t_now``, as far as the sensor's z axis is vertical (the
bias is subtracted from the measured rate, so the heading would have turned by −ε per
second since). A producer that commits later than its landmark (a multi-hypothesis
association waiting for one hypothesis to dominate) carries the yaw forward itself, to
the step that commits it, and stamps the correction with that step.

**Trying before committing.** :meth:`Checkpoints.look_back` gives the same as
:meth:`revert_to` with a copy of the state and the history left as it is: a correction
tried there and refused by its gate leaves nothing changed.
"""
from __future__ import annotations

from bisect import bisect_right
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

State = TypeVar("State")
Inputs = TypeVar("Inputs")


@dataclass(frozen=True)
class Reverted(Generic[State, Inputs]):
    """A checkpoint taken back: its instant [s], its state (the snapshot itself: the
    history holds it no more) and the inputs recorded since, oldest first."""

    t_s: float
    state: State
    inputs: list[Inputs]


class Checkpoints(Generic[State, Inputs]):
    """Snapshots of a navigator's state at instants [s] in increasing order, with the
    inputs processed since (module docstring): at most ``capacity`` (None: as many as the
    window holds), none more than ``window_s`` [s] before the last input recorded."""

    def __init__(self, copy: Callable[[State], State], window_s: float,
                 capacity: int | None = None) -> None:
        if not window_s >= 0:
            raise ValueError(f"window_s must be >= 0, got {window_s}")
        if capacity is not None and capacity < 1:
            raise ValueError(f"capacity must be at least 1, got {capacity}")
        self.copy, self.window_s, self.capacity = copy, window_s, capacity
        self._t: list[float] = []           # each checkpoint's instant [s] ...
        self._states: list[State] = []      # ... its snapshot ...
        self._first: list[int] = []         # ... and where its inputs start in _inputs
        self._inputs: list[Inputs] = []     # every input since the oldest checkpoint

    def __len__(self) -> int:
        return len(self._t)

    @property
    def instants(self) -> tuple[float, ...]:
        """The checkpoints' instants [s], oldest first."""
        return tuple(self._t)

    @property
    def latest_s(self) -> float | None:
        """The latest checkpoint's instant [s] (None: none kept)."""
        return self._t[-1] if self._t else None

    def remember(self, t_s: float, state: State) -> None:
        """A copy of ``state`` as the checkpoint at ``t_s`` [s], the latest one (instants
        increase: one before the latest is refused with ValueError)."""
        if self._t and t_s < self._t[-1]:
            raise ValueError(f"checkpoint at {t_s} s before the latest one "
                             f"({self._t[-1]} s): instants must increase")
        self._t.append(t_s)
        self._states.append(self.copy(state))
        self._first.append(len(self._inputs))
        if self.capacity is not None and len(self._t) > self.capacity:
            self._drop(len(self._t) - self.capacity)

    def record(self, inputs: Inputs, t_end_s: float) -> None:
        """``inputs`` processed after the latest checkpoint, the last of them at
        ``t_end_s`` [s]; the checkpoints more than ``window_s`` before it are dropped.
        Nothing is kept without a checkpoint."""
        if not self._t:
            return
        self._inputs.append(inputs)
        old = 0
        while old < len(self._t) and t_end_s - self._t[old] > self.window_s:
            old += 1
        self._drop(old)

    def look_back(self, t_s: float) -> Reverted[State, Inputs] | None:
        """The latest checkpoint at or before ``t_s`` [s] as :meth:`revert_to` gives it,
        but a copy of its state, the history left as it is: to try a correction there and
        keep the history when it is refused. None when no checkpoint serves ``t_s``."""
        index = bisect_right(self._t, t_s) - 1
        if index < 0:
            return None
        return Reverted(self._t[index], self.copy(self._states[index]),
                        self._inputs[self._first[index]:])

    def revert_to(self, t_s: float | None = None) -> Reverted[State, Inputs] | None:
        """The latest checkpoint at or before ``t_s`` [s] (None: the latest one), taken
        back with the inputs recorded since; it and the later ones leave the history (the
        caller remembers the state again, corrected, and records the inputs again as it
        runs them). None when no checkpoint serves ``t_s``: the correction is late and is
        expressed from the current state (module docstring)."""
        index = len(self._t) - 1 if t_s is None else bisect_right(self._t, t_s) - 1
        if index < 0:
            return None
        first = self._first[index]
        reverted = Reverted(self._t[index], self._states[index], self._inputs[first:])
        del self._t[index:], self._states[index:], self._first[index:], self._inputs[first:]
        return reverted

    def _drop(self, count: int) -> None:
        """Forget the ``count`` oldest checkpoints and the inputs before the next one."""
        if count <= 0:
            return
        del self._t[:count], self._states[:count], self._first[:count]
        start = self._first[0] if self._first else len(self._inputs)
        del self._inputs[:start]
        self._first = [f - start for f in self._first]
