"""Taking a subscription's backlog in one callback.

rclpy's executor hands a callback one message per pass through its wait set, and that
pass, not the callback, is what limits a Python node to a few thousand messages a
second. A callback that also takes the messages already waiting behind its own, and
handles them as one block, keeps up with input far faster than real time, while a
bound on the block keeps the node's timers and services served. Duck-typed on rclpy's
``Subscription`` (no rclpy import here).
"""
from __future__ import annotations


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
