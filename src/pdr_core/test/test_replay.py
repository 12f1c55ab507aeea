"""pdr_core.corrections.replay: the one replay of a late correction, on a toy navigator whose state
is a running sum: a correction adds its yaw to the sum, and a correction whose yaw is
negative is refused. Taken late at its instant, with the inputs since run again, it gives
what the correction taken in its place, in time, gives."""
from __future__ import annotations

import copy
from dataclasses import dataclass

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core.corrections.correction import Correction, refusal
from pdr_core.corrections.replay import Replay, TakenCorrection, split


@dataclass
class Values:
    """Inputs: values at instants t [s]."""

    t: np.ndarray
    v: np.ndarray

    def __len__(self) -> int:
        return len(self.t)

    @property
    def end_s(self) -> float:
        return float(self.t[-1])

    def split(self, t_s: float) -> tuple[Values, Values]:
        cut = int(np.searchsorted(self.t, t_s, side="right"))
        return Values(self.t[:cut], self.v[:cut]), Values(self.t[cut:], self.v[cut:])


@dataclass
class Sum:
    """The navigator's state and its worker: a running sum and every sum it gave."""

    total: float = 0.0

    def run(self, values: Values) -> list[float]:
        sums = []
        for v in values.v:
            self.total += v
            sums.append(self.total)
        return sums

    def rerun(self, item: Values | TakenCorrection) -> None:
        if isinstance(item, TakenCorrection):
            self.apply_correction(item.correction)
        else:
            self.run(item)

    def apply_correction(self, correction: Correction) -> tuple[bool, str]:
        if correction.yaw_rad < 0:
            return False, "negative"
        self.total += correction.yaw_rad
        return True, "added"


class Navigator:
    """A Replayable over :class:`Sum`: a checkpoint before every chunk."""

    def __init__(self) -> None:
        self.sum = Sum()
        self.replay: Replay[Sum, Values] = Replay(copy.deepcopy, window_s=100.0)

    def push(self, values: Values) -> list[float]:
        self.replay.history.remember(float(values.t[0]), self.sum)
        return self.take(values)

    def worker(self, state: Sum) -> Sum:
        return state

    def adopt(self, worker: Sum) -> None:
        self.sum = worker

    def take(self, item: Values | TakenCorrection) -> list[float]:
        if isinstance(item, TakenCorrection):
            self.sum.apply_correction(item.correction)
            self.replay.history.record(item, item.t_s)
            return []
        sums = self.sum.run(item)
        self.replay.history.record(item, item.end_s)
        return sums


def in_time(values: np.ndarray, corrections: list[tuple[int, float]]) -> list[float]:
    """The sums with each correction (after sample i, yaw) taken in its place: from
    sample i + 1 on."""
    total, sums = 0.0, []
    for i, v in enumerate(values):
        total += v
        sums.append(total)
        total += sum(yaw for after, yaw in corrections if after == i and yaw >= 0)
    return sums


def test_split_cuts_a_chunk_at_the_instant_and_keeps_corrections_in_order():
    chunk = Values(np.array([0.0, 1.0, 2.0, 3.0]), np.ones(4))
    taken = TakenCorrection(1.5, Correction(yaw_rad=1.0))
    before, after = split([chunk, taken], 1.0)
    assert [len(x) for x in before] == [2] and after[0].t.tolist() == [2.0, 3.0]
    assert after[1] is taken
    before, after = split([chunk, taken], 2.0)
    assert before[1] is taken and after[0].t.tolist() == [3.0]


@settings(max_examples=60, deadline=None)
@given(values=st.lists(st.integers(-5, 5), min_size=2, max_size=40),
       chunk=st.integers(1, 7),
       late=st.lists(st.tuples(st.integers(0, 39), st.integers(-3, 3), st.integers(0, 39)),
                     max_size=4))
def test_a_late_correction_gives_what_it_gives_taken_in_its_place(values, chunk, late):
    """``late``: corrections (after sample i, yaw, arriving after sample j ≥ i): each is
    taken when sample j has been pushed, at its instant i; the last sums, the replayed
    ones in place of those they revise, are the sums with every correction in time. A
    refused one (negative yaw) changes nothing; one reaching further back takes those
    before it again."""
    n = len(values)
    t = np.arange(n, dtype=float)
    late = [(i % n, yaw, max(i % n, j % n)) for i, yaw, j in late]
    navigator, sums = Navigator(), []
    for start in range(0, n, chunk):
        sums += navigator.push(Values(t[start:start + chunk],
                                      np.asarray(values[start:start + chunk], float)))
        pushed = min(start + chunk, n) - 1
        for i, yaw, j in late:
            if start <= j <= pushed:            # it arrives with this chunk
                result = navigator.replay.correct(navigator, Correction(yaw_rad=float(yaw)),
                                                  float(i))
                assert result.accepted == (yaw >= 0)
                if result.accepted:
                    sums = sums[:i + 1] + result.revised
                    assert len(sums) == pushed + 1
    assert sums == in_time(np.asarray(values, float), [(i, yaw) for i, yaw, _ in late])


def test_a_refused_correction_leaves_the_history_as_it_was():
    navigator = Navigator()
    navigator.push(Values(np.arange(3.0), np.ones(3)))
    kept = (navigator.replay.history.instants, list(navigator.replay.history._inputs))
    result = navigator.replay.correct(navigator, Correction(yaw_rad=-1.0), 1.0)
    assert not result.accepted and result.message == "negative" and result.revised == []
    assert (navigator.replay.history.instants, navigator.replay.history._inputs) == kept
    assert navigator.sum.total == 3.0
    assert navigator.replay.serves(0.0) and not navigator.replay.serves(-1.0)


def test_what_no_state_can_take_is_refused_once_for_both_navigators():
    """pdr_core.corrections.correction.refusal, which the pocket and the foot navigators both ask
    first: no part, numbers that cannot be used, a part without a variance."""
    assert refusal(Correction()).startswith("nothing to apply")
    assert refusal(Correction(yaw_rad=0.1)) == \
        "yaw_variance is 0: a yaw of +0.1 rad needs a positive variance"
    both = refusal(Correction(yaw_rad=np.nan, yaw_variance_rad2=1.0,
                              gyro_bias_z_radps=1e-4, gyro_bias_z_variance_rad2ps2=0.0))
    assert both == ("yaw nan is not finite; gyro_bias_z_variance is 0: a gyro_bias_z of "
                    "+0.0001 rad/s needs a positive variance")
    assert refusal(Correction(yaw_rad=0.1, yaw_variance_rad2=-1.0)) == \
        "yaw_variance -1.0 is negative"
    assert refusal(Correction(yaw_rad=0.1, yaw_variance_rad2=1e-4,
                              position_m=np.zeros(3), position_covariance_m2=np.eye(3))) is None
