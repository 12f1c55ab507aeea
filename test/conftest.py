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
