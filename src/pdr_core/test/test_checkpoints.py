"""pdr_core.corrections.checkpoints: taken back and run again, a checkpoint gives the run as it went
(and, corrected, the run corrected at its instant), within its window and capacity; a
correction no checkpoint serves is late (None)."""
from __future__ import annotations

import copy
from dataclasses import dataclass, field

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core.corrections.checkpoints import Checkpoints


@dataclass
class Toy:
    """A navigator whose state depends on its inputs and their order."""

    x: float = 0.0
    seen: list[float] = field(default_factory=list)

    def process(self, t_s: float, u: float) -> None:
        self.x = 0.9 * self.x + u * (1.0 + 0.1 * t_s)
        self.seen.append(t_s)

    def apply_correction(self, dx: float) -> None:
        self.x += dx


def history(window_s: float = float("inf"), capacity: int | None = None
            ) -> Checkpoints[Toy, tuple[float, float]]:
    return Checkpoints(copy.deepcopy, window_s, capacity)


def run(inputs, marks: set[int], kept: Checkpoints, toy: Toy | None = None) -> Toy:
    """``inputs`` (t [s], u) through a Toy, a checkpoint before each input whose index is
    in ``marks`` (at that input's instant: it holds the inputs before)."""
    toy = toy or Toy()
    for i, (t, u) in enumerate(inputs):
        if i in marks:
            kept.remember(t, toy)
        toy.process(t, u)
        kept.record((t, u), t)
    return toy


walks = st.lists(st.tuples(st.floats(0.01, 2.0), st.floats(-5.0, 5.0)), min_size=1,
                 max_size=40).map(lambda xs: [(sum(d for d, _ in xs[:i + 1]), u)
                                              for i, (_, u) in enumerate(xs)])


@settings(max_examples=200, deadline=None)
@given(walks, st.data())
def test_revert_and_replay_of_the_remembered_inputs_is_the_run_as_it_went(inputs, data):
    marks = set(data.draw(st.lists(st.integers(0, len(inputs) - 1), max_size=8)))
    window_s = data.draw(st.sampled_from([float("inf"), 0.0, 1.0, 5.0, 20.0]))
    capacity = data.draw(st.sampled_from([None, 1, 2, 5]))
    kept = history(window_s, capacity)
    toy = run(inputs, marks, kept)
    t_end = inputs[-1][0]
    instants = kept.instants
    assert len(instants) <= (capacity or len(marks))
    assert all(t_end - t <= window_s for t in instants)
    assert instants == tuple(sorted(instants))
    query = data.draw(st.floats(-1.0, t_end + 1.0))
    reverted = kept.revert_to(query)
    served = [t for t in instants if t <= query]
    if not served:
        assert reverted is None
        assert kept.instants == instants        # a late correction changes nothing
        return
    assert reverted.t_s == served[-1]
    assert kept.instants == tuple(t for t in instants if t < reverted.t_s)
    replayed = reverted.state
    for t, u in reverted.inputs:
        replayed.process(t, u)
    assert replayed == toy


@settings(max_examples=100, deadline=None)
@given(walks, st.data())
def test_correcting_the_reverted_state_is_the_run_corrected_at_the_checkpoint(inputs, data):
    mark = data.draw(st.integers(0, len(inputs) - 1))
    dx = data.draw(st.floats(-3.0, 3.0))
    kept = history()
    toy = run(inputs, {mark}, kept)
    reverted = kept.revert_to()
    reverted.state.apply_correction(dx)
    kept.remember(reverted.t_s, reverted.state)
    for t, u in reverted.inputs:
        reverted.state.process(t, u)
        kept.record((t, u), t)
    straight = run(inputs[:mark], set(), history())
    straight.apply_correction(dx)
    assert reverted.state == run(inputs[mark:], set(), history(), straight)
    assert toy.seen == reverted.state.seen
    # remembered again as it ran: a second correction takes the first one's place
    again = kept.revert_to(reverted.t_s)
    assert again.t_s == reverted.t_s and again.inputs == reverted.inputs


@settings(max_examples=100, deadline=None)
@given(walks, st.data())
def test_looking_back_gives_what_reverting_gives_and_keeps_the_history(inputs, data):
    marks = set(data.draw(st.lists(st.integers(0, len(inputs) - 1), max_size=8)))
    kept = history(data.draw(st.sampled_from([float("inf"), 1.0, 5.0])))
    run(inputs, marks, kept)
    query = data.draw(st.floats(-1.0, inputs[-1][0] + 1.0))
    instants = kept.instants
    looked = kept.look_back(query)
    assert kept.instants == instants
    as_looked = None if looked is None else copy.deepcopy(looked.state)
    if looked is not None:
        looked.state.apply_correction(1.0)         # a copy: the kept state stays
    reverted = kept.revert_to(query)
    if reverted is None:
        assert looked is None
        return
    assert (looked.t_s, looked.inputs) == (reverted.t_s, reverted.inputs)
    assert reverted.state == as_looked


def test_a_snapshot_is_a_copy():
    kept, toy = history(), Toy()
    kept.remember(0.0, toy)
    toy.process(0.0, 1.0)
    assert kept.revert_to().state == Toy()


def test_the_window_drops_checkpoints_and_their_inputs():
    kept = history(window_s=2.0)
    run([(0.0, 1.0), (1.0, 1.0), (2.0, 1.0)], {0, 1}, kept)
    assert kept.instants == (0.0, 1.0)           # 2 s after the first: kept
    kept.record((2.5, 1.0), 2.5)
    assert kept.instants == (1.0,)
    assert kept.revert_to(0.5) is None            # late: before every kept checkpoint
    assert kept.revert_to(1.0).inputs == [(1.0, 1.0), (2.0, 1.0), (2.5, 1.0)]


def test_capacity_keeps_the_latest_checkpoints():
    kept = history(capacity=1)
    run([(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)], {0, 1, 2}, kept)
    assert kept.instants == (2.0,)
    assert kept.revert_to(1.5) is None
    assert kept.revert_to().inputs == [(2.0, 3.0)]


def test_nothing_is_recorded_without_a_checkpoint():
    kept = history()
    kept.record((0.0, 1.0), 0.0)
    kept.remember(1.0, Toy())
    assert kept.revert_to().inputs == []
    assert kept.revert_to() is None


def test_instants_must_increase():
    kept = history()
    kept.remember(1.0, Toy())
    kept.remember(1.0, Toy())
    with pytest.raises(ValueError, match="instants must increase"):
        kept.remember(0.5, Toy())


@pytest.mark.parametrize(("window_s", "capacity"), [(-1.0, None), (float("nan"), None),
                                                    (1.0, 0)])
def test_bounds_are_checked(window_s, capacity):
    with pytest.raises(ValueError):
        history(window_s, capacity)
