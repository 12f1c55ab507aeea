"""The footfall detector for an IMU without gyroscope (pdr_pocket.steps.FootfallDetector,
pdr_pocket.compiled_peaks.footfall_loop): footfalls in the specific force's norm, two per
gait cycle, the same in chunks as whole and at any sample rate."""
from __future__ import annotations

import numpy as np
import pytest

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_pocket.compiled_peaks import (
    EV_MAX,
    EV_MIN,
    EV_T_CONFIRM,
    EV_T_MAX,
    N_EVENT_COLUMNS,
    footfall_loop,
    new_footfall_state,
)
from pdr_pocket.config import StepsConfig
from pdr_pocket.steps import FootfallDetector

FOOTFALL_HZ = 1.8        # footfalls per second, both feet


def walk(rate_hz: float, seconds: float = 20.0):
    """‖α‖ of a walk: a footfall every 1/FOOTFALL_HZ s, 3 m/s² over gravity, with the
    second harmonic of a heel strike and a sensor's noise; the pitch one sine per cycle."""
    t = np.arange(0.0, seconds, 1.0 / rate_hz)
    phase = 2 * np.pi * FOOTFALL_HZ * t
    norm = STANDARD_GRAVITY_MPS2 + 3.0 * np.cos(phase) + 0.8 * np.cos(2 * phase + 0.5)
    norm += np.random.default_rng(1).normal(0.0, 0.1, len(t))
    return t, np.radians(30.0) * np.sin(phase / 2), norm


def test_a_footfall_per_peak_and_a_cycle_per_two():
    t, pitch, norm = walk(100.0)
    detector = FootfallDetector(StepsConfig())
    events = detector.push(t, pitch, norm)
    # the last footfall is held min_interval_s, so the record's last peak may be pending
    expected = int(t[-1] * FOOTFALL_HZ) + 1
    assert expected - 1 <= detector.footfalls <= expected
    assert len(events) == detector.footfalls // 2
    np.testing.assert_allclose(np.diff(events[:, EV_T_MAX]), 2 / FOOTFALL_HZ, atol=0.02)
    # each cycle carries the pitch's extremes since the last one
    np.testing.assert_allclose(events[1:, EV_MAX], np.radians(30.0), atol=np.radians(0.5))
    np.testing.assert_allclose(events[1:, EV_MIN], -np.radians(30.0), atol=np.radians(0.5))


@pytest.mark.parametrize("chunk", [1, 7, 333])
def test_chunks_give_the_footfalls_of_the_whole_record(chunk):
    t, pitch, norm = walk(100.0)
    whole = FootfallDetector().push(t, pitch, norm)
    live = FootfallDetector()
    parts = [live.push(t[i:i + chunk], pitch[i:i + chunk], norm[i:i + chunk])
             for i in range(0, len(t), chunk)]
    np.testing.assert_array_equal(np.concatenate(parts), whole)


@pytest.mark.parametrize("rate_hz", [50.0, 100.0, 200.0])
def test_the_sample_rate_is_read_off_the_stamps(rate_hz):
    t, pitch, norm = walk(rate_hz)
    detector = FootfallDetector()
    detector.push(t, pitch, norm)
    expected = int(t[-1] * FOOTFALL_HZ) + 1
    assert expected - 1 <= detector.footfalls <= expected


def test_a_higher_peak_within_the_interval_takes_the_place_of_the_first():
    """find_peaks' ``distance`` rule, causally: two peaks 0.2 s apart (under
    min_interval_s) are one footfall, at the higher; ones 0.5 s and 1.0 s later are two
    more (three in a row: a gait)."""
    t = np.arange(0.0, 2.5, 0.01)
    force = np.full(len(t), STANDARD_GRAVITY_MPS2)
    for at, height in ((0.3, 3.0), (0.5, 4.0), (1.0, 3.0), (1.5, 3.0)):
        force += height * np.exp(-0.5 * ((t - at) / 0.03) ** 2)
    state, events = new_footfall_state(), np.empty((4, N_EVENT_COLUMNS))
    count = footfall_loop(state, 1.5, 0.3, 1.25, t, force, np.zeros(len(t)), events)
    assert state.scalars[0].footfalls == 3 and count == 1
    assert events[0, EV_T_MAX] == pytest.approx(1.0)      # the second footfall closes it


@pytest.mark.parametrize(("gap_s", "counted"), [(1.2, 5), (1.3, 3)])
def test_footfalls_count_in_a_run_of_three(gap_s, counted):
    """A gait is a rhythm (pdr_core.walking.gait.GAIT_MIN_FOOTFALLS): a footfall farther than half
    the longest gait cycle (1.25 s) from the last starts a new run, and a run of two is
    dropped: a bump, or the phone taken out of the pocket. The run's first footfalls wait
    for the third, and the cycles keep the pitch of their own stretch."""
    at = np.r_[1.0, 1.5, 2.0, 2.0 + gap_s, 2.5 + gap_s]
    t = np.arange(0.0, at[-1] + 1.0, 0.01)
    force = np.full(len(t), STANDARD_GRAVITY_MPS2)
    for peak in at:
        force += 3.0 * np.exp(-0.5 * ((t - peak) / 0.03) ** 2)
    pitch = np.where(t < 1.2, 0.1, 0.3)
    state, events = new_footfall_state(), np.empty((4, N_EVENT_COLUMNS))
    count = footfall_loop(state, 1.5, 0.3, 1.25, t, force, pitch, events)
    assert state.scalars[0].footfalls == counted and count == counted // 2
    assert events[0, EV_T_MAX] == pytest.approx(1.5) and events[0, EV_T_CONFIRM] > 2.0
    assert events[0, EV_MIN] == 0.1 and events[0, EV_MAX] == 0.3


def test_a_still_signal_has_no_footfall():
    t = np.arange(0.0, 10.0, 0.01)
    detector = FootfallDetector()
    events = detector.push(t, np.zeros(len(t)), STANDARD_GRAVITY_MPS2 + 0.2 * np.sin(9 * t))
    assert detector.footfalls == 0 and len(events) == 0


def test_an_empty_chunk_gives_no_cycle_and_changes_nothing():
    """The navigator hands the detector no sample between two mounting changes."""
    t, pitch, norm = walk(100.0)
    whole = FootfallDetector().push(t, pitch, norm)
    detector, empty = FootfallDetector(), np.empty(0)
    parts = [detector.push(empty, empty, empty), detector.push(t[:500], pitch[:500], norm[:500]),
             detector.push(empty, empty, empty), detector.push(t[500:], pitch[500:], norm[500:])]
    assert all(part.shape == (0, N_EVENT_COLUMNS) for part in parts[::2])
    np.testing.assert_array_equal(np.concatenate(parts), whole)
