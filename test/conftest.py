"""Fixtures for the cross-package tests.

Every test that starts ROS processes gets its own ROS_DOMAIN_ID, so concurrent runs and
leftover processes cannot disturb it (../shared/ROS_JAZZY_FROM_PYPI.md).
"""
from __future__ import annotations

import itertools
import os

import pytest

from wstest import Processes

_domains = itertools.count((os.getpid() * 17) % 100)


@pytest.fixture
def domain_id() -> int:
    return 1 + next(_domains) % 100


@pytest.fixture
def procs(domain_id, tmp_path):
    processes = Processes(domain_id, tmp_path)
    yield processes
    processes.cleanup()


@pytest.fixture
def ros(domain_id):
    """A node of the test process in the test's domain, and its executor."""
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor

    context = Context()
    rclpy.init(context=context, domain_id=domain_id)
    node = rclpy.create_node("pdr_test", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    yield node, executor
    node.destroy_node()
    rclpy.shutdown(context=context)
