"""``ros2 topic hz``'s rate maths against ros2cli's ``ros2topic/verb/hz.py`` (Jazzy):
``get_hz`` gives rate = 1e9 / mean interval [ns], min, max and the population standard
deviation of the kept intervals, and the number of them; it reports nothing until a
first interval only sets the 1 s mark, then once a reception is 1 s or more after the
mark; ``print_hz`` prints ``'average rate: %.3f\\n\\tmin: %.3fs max: %.3fs std dev:
%.5fs window: %s'``; the window keeps the last N intervals (default 10000)."""
from __future__ import annotations

import math

import pytest

from pdr_core.ros.reception_rate import DEFAULT_WINDOW, ReceptionRate, rate_report

MS = 1_000_000


def reports(receptions_ns, window=DEFAULT_WINDOW):
    """The reports made when ``report()`` is asked after each reception, as ros2cli asks
    after each ``spin_once``."""
    rate = ReceptionRate(window)
    made = []
    for t in receptions_ns:
        rate.received(t)
        made.append(rate.report())
    return [(i, r) for i, r in enumerate(made) if r is not None]


def test_a_report_is_the_rate_extremes_and_population_deviation_of_the_intervals():
    report = rate_report([10 * MS, 20 * MS, 30 * MS])
    assert report.rate_hz == pytest.approx(50.0)
    assert (report.min_s, report.max_s, report.window) == (pytest.approx(0.01),
                                                           pytest.approx(0.03), 3)
    assert report.std_s == pytest.approx(math.sqrt(200 / 3) * 1e-3)
    assert report.text() == ("average rate: 50.000\n\tmin: 0.010s max: 0.030s "
                             "std dev: 0.00816s window: 3")


def test_intervals_of_zero_give_a_rate_of_zero():
    assert rate_report([0, 0]).rate_hz == 0.0


def test_reports_come_once_a_second_of_receptions_after_the_first_interval():
    at_100_hz = [k * 10 * MS for k in range(251)]          # 0 .. 2.5 s
    made = reports(at_100_hz)
    # the second message (10 ms) sets the mark; reports at 1.01 s and 2.01 s
    assert [i for i, _ in made] == [101, 201]
    assert [r.window for _, r in made] == [101, 201]
    assert all(r.rate_hz == pytest.approx(100.0) and r.std_s == pytest.approx(0.0)
               for _, r in made)


def test_nothing_is_reported_before_two_messages_nor_while_none_comes():
    rate = ReceptionRate()
    assert rate.report() is None
    rate.received(5 * MS)
    assert rate.report() is None
    rate.received(15 * MS)
    assert rate.report() is None                # sets the mark only
    assert rate.report() is None                # no new reception: nothing due


def test_the_window_keeps_the_last_intervals_only():
    receptions = [k * 10 * MS for k in range(101)]                  # 100 intervals of 10 ms
    receptions += [receptions[-1] + k * 20 * MS for k in range(1, 101)]  # then 100 of 20 ms
    (_, report) = reports(receptions, window=50)[-1]            # at 2.02 s
    assert report.window == 50 and report.rate_hz == pytest.approx(50.0)
    assert report.min_s == pytest.approx(0.02)
