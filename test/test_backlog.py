"""A callback takes its subscription's backlog in one go (pdr_core.ros.backlog), with a real
rclpy publisher and subscription in the test's domain; and zupt_ekf's block handler
drops a malformed message without losing the good ones around it (issue 19)."""
from __future__ import annotations

import time

import pytest

from pdr_core.io import cdr
from pdr_core.io.bag import BagReader
from pdr_core.ros.backlog import waiting_messages
from wstest import ROOT

pytestmark = pytest.mark.ros


def test_one_callback_takes_the_messages_waiting_behind_it(ros):
    from rclpy.duration import Duration
    from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
    from std_msgs.msg import String

    node, executor = ros
    qos = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)
    calls: list[list] = []
    subscription = None

    def on_message(raw: bytes) -> None:
        calls.append([raw, *waiting_messages(subscription, 30)])

    subscription = node.create_subscription(String, "backlog", on_message, qos, raw=True)
    publisher = node.create_publisher(String, "backlog", qos)
    deadline = time.monotonic() + 10
    while publisher.get_subscription_count() < 1 and time.monotonic() < deadline:
        time.sleep(0.01)
    for k in range(50):
        publisher.publish(String(data=f"m{k}"))
    assert publisher.wait_for_all_acked(Duration(seconds=10))  # all in the queue
    while sum(len(c) for c in calls) < 50 and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    assert [len(c) for c in calls] == [31, 19]
    texts = [cdr.decode_generic("std_msgs/msg/String", raw).data for c in calls for raw in c]
    assert texts == [f"m{k}" for k in range(50)]


def test_zupt_ekf_block_drops_a_malformed_message_and_keeps_the_rest():
    import rclpy

    from pdr_ins_ekf.nodes.zupt_ekf import ZuptEkfNode

    imu = BagReader(ROOT / "bags" / "foot_walk").read("/imu/data")
    raws = cdr.encode(imu.take(slice(0, 500)))
    malformed = b"\x00\x01\x00\x00" + b"\xff" * 40  # frame_id longer than the message
    rclpy.init()
    try:
        node = ZuptEkfNode()
        node.on_imu_block(raws[:200] + [malformed] + raws[200:])
        assert node.undecodable == 1
        assert node.navigator.received == 500
        node.destroy_node()
    finally:
        rclpy.try_shutdown()
