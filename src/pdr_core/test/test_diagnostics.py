"""pdr_core.ros.diagnostics: the level, the reason and the key-values of a report from the
counters at its period's start and end (issue 42): ERROR while not navigating, WARN when a
problem counter rose since the last report or while a condition holds, OK again after a
clean period."""
from __future__ import annotations

import pytest

from pdr_core.ros.diagnostics import Counters, Level, StatusReports, risen, status

DROPS = {"non_finite": 0, "implausible": 0, "stamp_not_increasing": 0, "gaps": 0}


def counters(samples_in: int = 100, failed: str | None = None, paused: str | None = None,
             **problems: int) -> Counters:
    """A pocket-like node's counters: the drops (``problems`` overrides), the refused and
    accepted corrections, the magnetometer's pause."""
    return Counters(samples_in, {**DROPS, "corrections_refused": 0, **problems},
                    {"corrections_accepted": 2}, {"mag_paused": paused}, failed)


def test_a_clean_period_is_ok_with_the_counters_and_the_arrival_rate():
    report = status(counters(100), counters(300), 2.0)
    assert report.level == Level.OK and report.message == "navigating"
    assert report.values == [
        ("samples_in", "300"), ("input_rate_hz", "100.0"), ("navigating", "true"),
        ("non_finite", "0"), ("implausible", "0"), ("stamp_not_increasing", "0"),
        ("gaps", "0"), ("corrections_refused", "0"), ("corrections_accepted", "2"),
        ("mag_paused", "false")]
    assert all(isinstance(v, str) for _, v in report.values)


def test_a_counter_that_rose_is_a_warn_naming_it_and_how_many():
    report = status(counters(100, non_finite=1), counters(200, non_finite=3,
                                                          corrections_refused=1), 1.0)
    assert report.level == Level.WARN
    assert report.message == "non_finite +2, corrections_refused +1 since the last report"
    values = dict(report.values)
    assert values["non_finite"] == "3" and values["corrections_refused"] == "1"


def test_back_to_ok_after_a_clean_period():
    reports = StatusReports(start_s=10.0)
    levels = [reports.report(c, t).level for c, t in [
        (counters(100), 11.0), (counters(200, implausible=1), 12.0),
        (counters(300, implausible=1), 13.0), (counters(400, implausible=1), 14.0)]]
    assert levels == [Level.OK, Level.WARN, Level.OK, Level.OK]


def test_a_condition_warns_while_it_holds_with_its_reason():
    reports = StatusReports(start_s=0.0)
    why = "no reading on /imu/mag for 1 s of IMU data, magnetic updates paused"
    first = reports.report(counters(100, paused=why), 1.0)
    second = reports.report(counters(200, paused=why), 2.0)
    third = reports.report(counters(300), 3.0)
    assert first.level == second.level == Level.WARN
    assert second.message == f"mag_paused: {why}"
    assert dict(second.values)["mag_paused"] == "true"
    assert third.level == Level.OK and dict(third.values)["mag_paused"] == "false"


def test_warnings_and_conditions_together():
    report = status(counters(100), counters(200, gaps=1, paused="quiet"), 1.0)
    assert report.message == "gaps +1 since the last report; mag_paused: quiet"


def test_not_navigating_is_an_error_with_its_reason_while_it_lasts():
    why = "/imu/data: median |f| 1 m/s²: the accelerometer looks like it is in g"
    reports = StatusReports(start_s=0.0)
    first = reports.report(counters(100, failed=why, non_finite=1), 1.0)
    second = reports.report(counters(200, failed=why, non_finite=1), 2.0)
    assert first.level == second.level == Level.ERROR
    assert first.message == f"not navigating: {why}; non_finite +1 since the last report"
    assert second.message == f"not navigating: {why}"
    assert dict(second.values)["navigating"] == "false"


def test_before_the_first_sample_and_when_the_input_stops_is_ok():
    waiting = status(Counters(), Counters(), 1.0)
    assert waiting.level == Level.OK and waiting.message == "waiting for IMU samples"
    assert dict(waiting.values)["input_rate_hz"] == "0.0"
    stopped = status(counters(500), counters(500), 1.0)
    assert stopped.level == Level.OK
    assert stopped.message == "no IMU sample since the last report"


def test_a_counter_started_again_at_reset_counts_whole():
    assert risen(5, 7) == 2 and risen(5, 2) == 2 and risen(5, 0) == 0
    after_reset = status(counters(100, non_finite=5), counters(200, non_finite=0), 1.0)
    assert after_reset.level == Level.OK
    again = status(counters(100, non_finite=5), counters(200, non_finite=1), 1.0)
    assert again.message == "non_finite +1 since the last report"


def test_a_counter_new_since_the_last_report_counts_from_zero():
    """Counters that appear on the way (pocket_pdr's ``pressure_non_finite`` once the
    barometer has read) are compared with 0."""
    before = Counters(100, {"non_finite": 0})
    after = Counters(200, {"non_finite": 0, "pressure_non_finite": 2})
    assert status(before, after, 1.0).message == "pressure_non_finite +2 since the last report"


def test_the_levels_are_diagnostic_msgs_values():
    msg = pytest.importorskip("diagnostic_msgs.msg")
    for level in Level:
        assert getattr(msg.DiagnosticStatus, level.name) == bytes([level.value])
