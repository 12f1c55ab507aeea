"""Fixtures for the cross-package tests.

Every test that starts ROS processes gets its own ROS_DOMAIN_ID, so concurrent runs and
leftover processes cannot disturb it (../shared/ROS_JAZZY_FROM_PYPI.md). Under
pytest-xdist each worker draws from its own block of ids, so two workers never share one.

Tests marked ``shared_data`` (wstest.needs_shared) skip when a recording is missing, with
one line naming it, and fail instead under PDR_REQUIRE_SHARED_DATA=1 (CI).
"""
from __future__ import annotations

import itertools
import os
import shutil
import tempfile

import pytest

from wstest import IMPORTS_ENV, REQUIRE_SHARED_DATA, Processes, missing_shared

DOMAIN_IDS = 100                    # 1..100: ids every RMW accepts on one machine


def domain_block() -> range:
    """This process's ROS domain ids: all of them, or its worker's share under xdist."""
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1"))
    worker = int(os.environ.get("PYTEST_XDIST_WORKER", "gw0")[2:])
    size = DOMAIN_IDS // workers
    return range(1 + worker * size, 1 + (worker + 1) * size)


def domain_ids():
    """The block's ids in turn, from a start that depends on the process id (two runs at
    once rarely start on the same id)."""
    block = domain_block()
    start = (os.getpid() * 17) % len(block)
    return (block[(start + k) % len(block)] for k in itertools.count())


_domains = domain_ids()


def pytest_configure(config):
    """The session's folder of imported recordings (wstest.imported), made by the main
    process before the xdist workers start, so they inherit it."""
    if IMPORTS_ENV not in os.environ:
        os.environ[IMPORTS_ENV] = tempfile.mkdtemp(prefix="pdr-test-imports-")
        config._pdr_imports = os.environ[IMPORTS_ENV]


def pytest_unconfigure(config):
    folder = getattr(config, "_pdr_imports", None)
    if folder is not None:
        shutil.rmtree(folder, ignore_errors=True)
        del os.environ[IMPORTS_ENV]


def pytest_collection_modifyitems(items):
    """Skip, at the test's own line, a test whose shared recording is missing."""
    if REQUIRE_SHARED_DATA:
        return
    for item in items:
        for mark in item.iter_markers("shared_data"):
            reason = missing_shared(mark.args)
            if reason is not None:
                item.add_marker(pytest.mark.skip(reason=reason))


def pytest_runtest_setup(item):
    """Under PDR_REQUIRE_SHARED_DATA=1 a missing recording is an error."""
    for mark in item.iter_markers("shared_data"):
        reason = missing_shared(mark.args)
        if reason is not None:
            pytest.fail(f"{reason}; PDR_REQUIRE_SHARED_DATA=1", pytrace=False)


@pytest.fixture
def domain_id() -> int:
    return next(_domains)


@pytest.fixture
def procs(domain_id, tmp_path):
    processes = Processes(domain_id, tmp_path)
    yield processes
    processes.cleanup()


@pytest.fixture(scope="module")
def module_procs(tmp_path_factory):
    """Processes in a ROS domain of their own for a module's shared runs (one graph run
    that several tests assert on), their logs in a folder of the module's."""
    processes = Processes(next(_domains), tmp_path_factory.mktemp("graph"))
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
