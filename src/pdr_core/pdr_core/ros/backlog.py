"""Taking a subscription's backlog in one callback, and giving a block back out.

rclpy's executor hands a callback one message per pass through its wait set, and that
pass, not the callback, is what limits a Python node to a few thousand messages a
second. A callback that also takes the messages already waiting behind its own, and
handles them as one block, keeps up with input far faster than real time, while a
bound on the block keeps the node's timers and services served. Duck-typed on rclpy's
``Subscription`` and ``Publisher`` (no rclpy import here).

- :func:`waiting_messages`: the messages queued behind the callback's own;
- :func:`decode_block`: a block of serialized messages decoded at once (pdr_core.io.cdr),
  a malformed one counted and left out;
- :func:`publish_acked`: a block's messages published in slices, each once the reliable
  subscribers have acknowledged the one before (a subscriber slower than the node, a
  recorder behind a bag played at full speed, then slows the node down instead of losing
  what the publishers' history overwrote before it was delivered).
"""
from __future__ import annotations

import contextlib

from pdr_core.io import cdr
from pdr_core.io.batch import MessageBatch


def waiting_messages(subscription, limit: int) -> list:
    """Up to ``limit`` messages already in ``subscription``'s queue, oldest first, taken
    as the executor takes one (``Subscription.handle.take_message``): serialized bytes for
    a raw subscription, message objects otherwise."""
    out = []
    while len(out) < limit:
        with subscription.handle:
            taken = subscription.handle.take_message(subscription.msg_type, subscription.raw)
        if taken is None:
            break
        out.append(taken[0])
    return out


def decode_block(msgtype: str, raws: list[bytes]) -> tuple[MessageBatch, int]:
    """The block decoded, and how many of its messages were malformed (those are left
    out: the others are then decoded one by one)."""
    try:
        return cdr.decode(msgtype, raws), 0
    except ValueError:
        good = []
        for raw in raws:
            with contextlib.suppress(ValueError):
                good.append(cdr.decode(msgtype, [raw]))
        batch = MessageBatch.concatenate(good) if good else cdr.decode(msgtype, [])
        return batch, len(raws) - len(batch)


def publish_acked(outputs: list[tuple[object, MessageBatch]], slice_len: int,
                  ack_timeout) -> None:
    """Publish every (publisher, batch) pair's messages as CDR, ``slice_len`` messages of
    each at a time, waiting before each slice until the publishers' reliable subscribers
    have acknowledged what went before (at most ``ack_timeout``, an rclpy Duration)."""
    n = max((len(batch) for _, batch in outputs), default=0)
    for start in range(0, n, slice_len):
        for publisher, _ in outputs:
            publisher.wait_for_all_acked(ack_timeout)
        part = slice(start, start + slice_len)
        for publisher, batch in outputs:
            for data in cdr.encode(batch.take(part)):
                publisher.publish(data)
