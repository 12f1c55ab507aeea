"""A request sent again is answered as the first time and changes nothing (issue 55)."""
from __future__ import annotations

import pytest

from pdr_core.corrections.answered_requests import (
    NO_ID,
    REMEMBERED_ANSWERS,
    AnsweredRequests,
    new_request_id,
)


class Receiver:
    """A receiver that applies each request it computes: ``applied`` counts them,
    ``told`` holds the lines about requests sent again."""

    def __init__(self, capacity: int = REMEMBERED_ANSWERS) -> None:
        self.answered = AnsweredRequests(capacity)
        self.applied = 0
        self.told: list[str] = []

    def call(self, request_id: int) -> str:
        def apply() -> str:
            self.applied += 1
            return f"answer {self.applied}"
        return self.answered.answer(request_id, apply, self.told.append)


def test_the_same_id_gets_the_first_answer_and_applies_nothing_again():
    receiver = Receiver()
    assert receiver.call(7) == "answer 1"
    assert receiver.call(7) == receiver.call(7) == "answer 1"
    assert receiver.applied == 1 and receiver.answered.resent == 2
    assert receiver.told == [
        "request 7 sent again: answered as the first time, nothing applied again (1 so far)",
        "request 7 sent again: answered as the first time, nothing applied again (2 so far)"]
    assert receiver.call(8) == "answer 2" and receiver.answered.resent == 2
    assert AnsweredRequests().answer(3, lambda: "first") == "first"   # tell is optional


def test_id_0_is_always_new_and_never_kept():
    receiver = Receiver()
    assert [receiver.call(NO_ID) for _ in range(3)] == ["answer 1", "answer 2", "answer 3"]
    assert receiver.applied == 3 and receiver.answered.resent == 0 and not receiver.told
    assert not receiver.answered.answers


def test_the_memory_keeps_the_last_capacity_ids():
    receiver = Receiver(capacity=3)
    for request_id in (1, 2, 3, 4):
        receiver.call(request_id)
    assert list(receiver.answered.answers) == [2, 3, 4]
    assert receiver.call(2) == "answer 2"          # still remembered
    assert receiver.call(1) == "answer 5"          # forgotten: applied again
    assert list(receiver.answered.answers) == [3, 4, 1]
    default = Receiver()
    for request_id in range(1, 2 * REMEMBERED_ANSWERS + 1):
        default.call(request_id)
    assert len(default.answered.answers) == REMEMBERED_ANSWERS
    assert min(default.answered.answers) == REMEMBERED_ANSWERS + 1
    with pytest.raises(ValueError, match="at least 1"):
        AnsweredRequests(0)


def test_new_ids_are_distinct_nonzero_and_fit_the_field():
    ids = [new_request_id() for _ in range(1000)]
    assert len(set(ids)) == 1000
    assert all(NO_ID < i < 2 ** 64 for i in ids)
