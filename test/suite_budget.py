"""The suite's time budget (issue 39), loaded by every pytest run (``-p suite_budget`` in
pyproject.toml).

A test whose setup or call takes more than :data:`SLOW_TEST_S` fails, with a message
saying by how much, unless it carries ``@pytest.mark.slow("why")``: a marker that names
the reason (a live graph played at real-time rate, say). Such tests are few:
``test/test_suite.py`` fails when more than :data:`MAX_SLOW_TESTS` carry the marker. A
fixture shared by a module (one graph run that several tests assert on) is set up in the
first test that uses it, so that test carries its time.

``PDR_SLOW_TEST_S`` overrides the limit, for the test of this rule itself.
"""
from __future__ import annotations

import os

import pytest

SLOW_TEST_S = float(os.environ.get("PDR_SLOW_TEST_S", "30"))
MAX_SLOW_TESTS = 10


def slow_reason(item: pytest.Item) -> str | None:
    """The reason the test's ``slow`` marker gives (None: no marker, or one without a
    reason)."""
    marker = item.get_closest_marker("slow")
    if marker is None or not marker.args or not str(marker.args[0]).strip():
        return None
    return str(marker.args[0])


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo):
    outcome = yield
    report = outcome.get_result()
    if report.when == "teardown" or not report.passed or call.duration <= SLOW_TEST_S:
        return
    if slow_reason(item) is not None:
        return
    report.outcome = "failed"
    report.longrepr = (
        f"{item.nodeid}: its {report.when} took {call.duration:.1f} s, over the suite's "
        f"{SLOW_TEST_S:g} s per test. Make it faster or share its run with the tests that "
        f"start the same processes; if it must stay, mark it @pytest.mark.slow(\"why\") (at "
        f"most {MAX_SLOW_TESTS} tests may: test/test_suite.py)")
