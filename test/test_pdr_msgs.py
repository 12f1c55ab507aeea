"""pdr_msgs between two processes: each message type published and received, and an
ApplyCorrection service call."""
from __future__ import annotations

import importlib.util
import os
import signal
import subprocess
import sys
import time

import pytest
from rclpy.qos import QoSProfile, ReliabilityPolicy

from pdr_msgs.srv import ApplyCorrection
from wstest import ROOT

PEER = ROOT / "test" / "peers" / "pdr_msgs_peer.py"
pytestmark = pytest.mark.ros


def load_peer():
    spec = importlib.util.spec_from_file_location("pdr_msgs_peer", PEER)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def peer(domain_id, role):
    env = {**os.environ, "ROS_DOMAIN_ID": str(domain_id)}
    return subprocess.Popen([sys.executable, str(PEER), role], env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT)


def test_each_message_type_crosses_processes(ros, domain_id):
    node, executor = ros
    expected = load_peer().samples()
    received = {}
    qos = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
    for topic, msg in expected.items():
        node.create_subscription(type(msg), topic,
                                 lambda m, topic=topic: received.setdefault(topic, m), qos)
    proc = peer(domain_id, "publish")
    deadline = time.monotonic() + 60
    while len(received) < len(expected) and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    out, _ = proc.communicate(timeout=30)
    assert proc.returncode == 0, out
    assert received == expected


def test_apply_correction_service_across_processes(ros, domain_id):
    node, executor = ros
    server = peer(domain_id, "serve")
    try:
        client = node.create_client(ApplyCorrection, "pdr/pocket/apply_correction")
        assert client.wait_for_service(timeout_sec=60)
        request = ApplyCorrection.Request(yaw=0.123, yaw_variance=1e-4, gyro_bias_z=2e-5,
                                          gyro_bias_z_variance=1e-10, has_position=True)
        request.position.x, request.position.y = 4.0, -5.0
        request.position_covariance = [1.0] * 9
        future = client.call_async(request)
        executor.spin_until_future_complete(future, timeout_sec=30)
        response = future.result()
        assert response.accepted
        assert response.message == "yaw 0.123 bias 2.00e-05 at 4.0,-5.0 cov 9.0"
    finally:
        server.send_signal(signal.SIGINT)  # the peer serves until SIGINT
        server.wait(timeout=30)
