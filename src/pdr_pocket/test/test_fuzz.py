"""The pocket navigator's live adapter against garbage (issue 19's rule, started here for
pocket_pdr and landmark_drift): NaN, ±Inf, huge and zero values, stamps that jump back,
repeat or leap ahead, garbage corrections, resets at any time. Nothing raises, nothing
published is not finite, every IMU sample is kept or counted under the key the rule of
docs/nodes.md names, and a correction with a non-finite value or a negative variance is
refused. Garbage that the rule drops, mixed into a real walk, leaves its steps exactly as
they were. Found by it: a window of zero specific force divided by zero in the mean
gravity update, and a finite rate of 1e151 rad/s did too.

With ``block_s`` (pdr_pocket.streaming, .arrivals; the node's default), live at the IMU's
rate, one message at a time, the samples go to the navigator in blocks of ``block_s`` of
IMU data: the steps and attitude are those of one sample at a time, to rounding (a step's
heading is a sum over its samples, added block by block), with garbage among them too; the
samples dropped are counted under the same keys; nothing waits after ``flush``; and the
navigator is called once a block, not once a sample."""
from __future__ import annotations

import itertools
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pdr_core.corrections.correction import from_request
from pdr_pocket.config import PocketConfig
from pdr_pocket.streaming import BLOCK_S, UNIT_CHECK_SAMPLES, StreamingPocket
from wstest import drop_reason, pocket_walk

CONFIG = PocketConfig()
BASE = 1_700_000_000_000_000_000
value = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(-1e3, 1e3),
                  st.sampled_from([0.0, 9.81, -9.81, 1e300, -1e300]))
vector = st.tuples(value, value, value)
stamp = st.integers(-10**12, 10**15)
FUZZ = settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
IMU_KEYS = ("non_finite", "implausible", "stamp_not_increasing")


def started() -> StreamingPocket:
    live = StreamingPocket(CONFIG)
    for k in range(60):
        live.push_imu(BASE + k * 10_000_000, (0.0, 0.0, 9.81), (0.01, 0.0, 0.0))
    return live


@FUZZ
@given(st.lists(st.tuples(st.sampled_from(["imu", "mag", "correction", "reset"]), stamp,
                          vector, vector, st.tuples(value, value, value, value)), max_size=60))
def test_pocket_pdr_adapter_survives_garbage(events):
    live = started()
    for kind, offset, a, b, c in events:
        if kind == "imu":
            before, last = [live.counts[k] for k in IMU_KEYS], live.last_stamp_ns
            chunks = live.push_imu(BASE + offset, a, b)
            reason = drop_reason(BASE + offset, last, a, b)
            counted = {k: live.counts[k] - n for k, n in zip(IMU_KEYS, before, strict=True)
                       if live.counts[k] != n}
            assert counted == ({} if reason is None else {reason: 1}), "kept or counted"
            assert live.last_stamp_ns == (BASE + offset if reason is None else last)
        elif kind == "mag":
            chunks = live.push_mag(BASE + offset, np.asarray(a) * 1e-6)
        elif kind == "reset":              # the ~/reset service
            live.reset()
            assert sum(live.counts.values()) == 0
            chunks = []
        else:
            with np.errstate(all="ignore"):     # stamped at a step, any stamp, or now
                request = SimpleNamespace(        # the service's fields, as pocket_pdr gets them
                    yaw=c[0], yaw_variance=c[1], gyro_bias_z=c[2], gyro_bias_z_variance=c[3],
                    has_position=True, position=SimpleNamespace(x=b[0], y=b[1], z=b[2]),
                    position_covariance=np.eye(3).ravel() * c[0])
                result = live.apply_correction(from_request(
                    request, 0 if offset % 3 == 0 else BASE + offset))
            ok, message = result.accepted, result.message
            assert isinstance(ok, bool) and message
            if not np.isfinite([*c, *b]).all() or min(c[0], c[1], c[3]) < 0:
                assert not ok, message     # docs/nodes.md: the whole request is refused
            chunks = []
        for chunk in chunks:
            assert_finite(chunk.output)


def assert_finite(out) -> None:
    assert np.isfinite(out.attitude.attitude).all()
    assert np.isfinite(out.attitude.covariance).all()
    for step in out.steps:
        assert np.isfinite(step.position).all() and np.isfinite(step.covariance).all()


def navigate(garbage: dict[int, str], cuts: tuple[int, ...] = ()) -> tuple[list, dict]:
    """The walk through StreamingPocket, with a sample of kind ``garbage[k]`` pushed
    before sample k: 'nan', 'inf' or 'huge' values at a valid stamp, or valid values at a
    'repeat'ed stamp or one going 'back'; a NaN magnetometer reading with each. The valid
    samples between two bad ones (and the ``cuts``) go in as one block of readings and one
    of IMU samples, as the node passes on what arrived together."""
    stamps, accel, gyro, field_t = pocket_walk()
    live, steps = StreamingPocket(CONFIG), []
    for start, end in itertools.pairwise(sorted({0, *garbage, *cuts, len(stamps)})):
        if start in garbage:
            kind, stamp = garbage[start], int(stamps[start])
            at = {"repeat": stamps[start - 1],
                  "back": stamps[start - 1] - 7_000_000}.get(kind, stamp)
            steps.extend(steps_of(live.push_imu(int(at), *GARBAGE[kind])))
            steps.extend(steps_of(live.push_mag(stamp, np.full(3, np.nan))))
        block = slice(start, end)
        steps.extend(steps_of(live.push_mags(stamps[block], field_t[block])))
        steps.extend(steps_of(live.push_imus(stamps[block], accel[block], gyro[block])))
    steps.extend(steps_of(live.flush()))
    return steps, live.counts


def steps_of(chunks) -> list:
    return [step for chunk in chunks for step in chunk.output.steps]


def clean_walk(cuts: tuple[int, ...]) -> list:
    """The steps of the walk without garbage, its valid samples in the same blocks."""
    steps, counts = navigate({}, cuts)
    assert sum(counts.values()) == 0
    return steps


REST = ((0.0, 0.0, 9.81), (0.0, 0.0, 0.0))        # specific force, rate of a valid sample
GARBAGE = {"nan": ((np.nan, 0.0, 9.81), (0.0, 0.0, 0.0)), "inf": ((0.0, 0.0, 9.81),
                                                               (np.inf, 0.0, 0.0)),
           "huge": ((1e300, 0.0, 0.0), (0.0, 0.0, 0.0)), "repeat": REST, "back": REST}
KEY = {"nan": "non_finite", "inf": "non_finite", "huge": "implausible",
       "repeat": "stamp_not_increasing", "back": "stamp_not_increasing"}


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.dictionaries(st.integers(1, 1499), st.sampled_from(sorted(GARBAGE)), max_size=40))
def test_garbage_in_a_real_walk_changes_no_step(where):
    clean = clean_walk(tuple(where))
    assert len(clean) >= 12, "the walk's first 30 s hold steps to compare"
    steps, counts = navigate(where)
    assert [s.t for s in steps] == [s.t for s in clean]
    assert all(np.array_equal(a.position, b.position) for a, b in zip(steps, clean,
                                                                       strict=True))
    for key in set(KEY.values()):
        assert counts[key] == sum(KEY[kind] == key for kind in where.values())
    assert counts["mag_non_finite"] == len(where)


# --- blocks of block_s ---------------------------------------------------------------
WHERE = {101: "nan", 340: "back", 341: "repeat", 777: "huge", 1200: "inf"}


def one_by_one(block_s: float, garbage: dict[int, str]) -> tuple[StreamingPocket, list]:
    """The walk's first 30 s pushed a message at a time, the magnetometer's reading before
    its IMU sample, a garbage sample of kind ``garbage[k]`` before sample k: the
    navigator and its processed chunks."""
    stamps, accel, gyro, field_t = pocket_walk()
    live, chunks = StreamingPocket(CONFIG, block_s=block_s), []
    for k, stamp in enumerate(stamps):
        if k in garbage:
            at = {"repeat": stamps[k - 1], "back": stamps[k - 1] - 7_000_000}.get(
                garbage[k], stamp)
            chunks += live.push_imu(int(at), *GARBAGE[garbage[k]])
        chunks += live.push_mag(int(stamp), field_t[k])
        chunks += live.push_imu(int(stamp), accel[k], gyro[k])
    return live, chunks + live.flush()


@pytest.fixture(scope="module")
def at_once():
    return one_by_one(0.0, WHERE)


def test_blocks_give_the_steps_and_attitude_of_one_sample_at_a_time(at_once):
    reference, expected = at_once
    live, chunks = one_by_one(BLOCK_S, WHERE)
    steps = [s for c in chunks for s in c.output.steps]
    expected_steps = [s for c in expected for s in c.output.steps]
    assert len(steps) == len(expected_steps) >= 12
    assert [s.t for s in steps] == [s.t for s in expected_steps]
    for a, b in zip(steps, expected_steps, strict=True):
        np.testing.assert_allclose(a.position, b.position, rtol=0, atol=1e-9)
        assert a.heading == pytest.approx(b.heading, abs=1e-12)
    np.testing.assert_array_equal(np.concatenate([c.stamp_ns for c in chunks]),
                                  np.concatenate([c.stamp_ns for c in expected]))
    np.testing.assert_allclose(np.concatenate([c.output.attitude.attitude for c in chunks]),
                               np.concatenate([c.output.attitude.attitude for c in expected]),
                               rtol=0, atol=1e-12)
    assert live.counts == reference.counts
    for key in set(KEY.values()):
        assert live.counts[key] == sum(KEY[kind] == key for kind in WHERE.values())


def test_the_navigator_is_called_once_a_block(at_once):
    _, expected = at_once
    _, chunks = one_by_one(BLOCK_S, {})
    samples = sum(len(c.stamp_ns) for c in chunks)
    rate_hz = 1e9 / np.median(np.diff(pocket_walk()[0]))
    assert len(expected) >= samples - UNIT_CHECK_SAMPLES    # at once: a chunk a sample
    assert len(chunks) <= samples / (BLOCK_S * rate_hz) + 1


def test_nothing_waits_after_flush():
    stamps, accel, gyro, field_t = pocket_walk()
    live = StreamingPocket(CONFIG, block_s=10.0)
    assert live.push_mags(stamps[:200], field_t[:200]) == []
    assert live.push_imus(stamps[:200], accel[:200], gyro[:200]) == []
    assert sum(len(c.stamp_ns) for c in live.flush()) == 200
    assert live.flush() == []


def test_release_lets_go_what_waits_only_for_its_block():
    """The node's idle timer and its service call ``release``: the samples held for their
    block go, with their magnetometer readings; one whose reading has not come stays."""
    stamps, accel, gyro, field_t = pocket_walk()
    live = StreamingPocket(CONFIG, block_s=10.0)
    assert live.push_mags(stamps[:199], field_t[:199]) == []
    assert live.push_imus(stamps[:200], accel[:200], gyro[:200]) == []
    assert sum(len(c.stamp_ns) for c in live.release()) == 199
    assert live.release() == []
    assert sum(len(c.stamp_ns) for c in live.flush()) == 1
