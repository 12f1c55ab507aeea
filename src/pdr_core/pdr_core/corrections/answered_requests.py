"""A request sent again is answered as the first time and changes nothing (issue 55).

A sender that gets no answer in time (``landmark_drift``'s ``correction_timeout_s``) sends
the same request again, with the same id (``request_id`` of
pdr_msgs/srv/ApplyCorrection); the first may have been applied already, its answer lost
or late. The receiver keeps its answers by id:

- :class:`AnsweredRequests`: the answers to the last :data:`REMEMBERED_ANSWERS` ids, one
  place for both navigators' ``apply_correction`` services (``pocket_pdr``, ``zupt_ekf``);
- :func:`new_request_id`: the sender's id of a new request.

Plain Python, no ROS: the answer kept is whatever the receiver answered (the node keeps
its filled response message).
"""
from __future__ import annotations

import secrets
from collections import OrderedDict
from collections.abc import Callable
from typing import Generic, TypeVar

NO_ID = 0
"""A request without an id: every call is new, nothing is kept."""
REMEMBERED_ANSWERS = 64
"""How many answers a receiver keeps [answers], the oldest forgotten first. A sender
sends again only the request it still waits for (``landmark_drift``: one at a time), so a
request sent again is one of the last few a receiver answered; 64 leaves room for as many
senders at once. The bound keeps the memory small: an answer carries the steps run again
since the correction's stamp (up to ``correction_window_s`` of them)."""
ID_BITS = 64
"""Size of an id [bits]: pdr_msgs/srv/ApplyCorrection's ``uint64 request_id``."""

T = TypeVar("T")


def new_request_id() -> int:
    """A new id [0, 2⁶⁴), never :data:`NO_ID`: drawn at random, so that two senders, or a
    sender started again, reuse one among a receiver's last :data:`REMEMBERED_ANSWERS`
    with a probability of about 64 / 2⁶⁴ per request."""
    request_id = NO_ID
    while request_id == NO_ID:
        request_id = secrets.randbits(ID_BITS)
    return request_id


class AnsweredRequests(Generic[T]):
    """The answers to the last ``capacity`` request ids, by id; :attr:`resent` counts the
    requests answered from memory."""

    def __init__(self, capacity: int = REMEMBERED_ANSWERS) -> None:
        if capacity < 1:
            raise ValueError(f"capacity {capacity} answers: at least 1")
        self.capacity = capacity
        self.answers: OrderedDict[int, T] = OrderedDict()
        self.resent = 0

    def answer(self, request_id: int, compute: Callable[[], T],
               tell: Callable[[str], object] | None = None) -> T:
        """The answer to request ``request_id``: the first answer to that id when it is
        remembered (``compute`` not called: nothing applied again; counted in
        :attr:`resent` and told to ``tell``, a logger's ``info``, in one line), else
        ``compute()``'s, remembered (unless the id is :data:`NO_ID`) in place of the
        oldest beyond ``capacity``."""
        if request_id != NO_ID and request_id in self.answers:
            self.resent += 1
            if tell is not None:
                tell(f"request {request_id} sent again: answered as the first time, nothing "
                     f"applied again ({self.resent} so far)")
            return self.answers[request_id]
        answer = compute()
        if request_id != NO_ID:
            self.answers[request_id] = answer
            while len(self.answers) > self.capacity:
                self.answers.popitem(last=False)
        return answer
