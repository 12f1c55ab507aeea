"""zupt_ekf's live adapter against garbage (issue 19): NaN, ±Inf, huge and zero values,
stamps that jump back, repeat or leap hours ahead, resets at any time. Nothing raises,
nothing published is not finite, every sample is kept or counted under the key the rule of
docs/nodes.md names, and after a flush every kept sample from the alignment on has been
estimated once, in order. Found by it: a
window of zero specific force divided by zero in the SHOE detector (its statistic NaN,
never a stance), and finite values of 1e300 reached the filter (now dropped as
implausible, as pocket_pdr does)."""
from __future__ import annotations

import copy

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pdr_ins_ekf.config import load_run_config
from pdr_ins_ekf.streaming import StreamingNavigator
from wstest import drop_reason

CONFIG = load_run_config(None, None)
BASE = 1_700_000_000_000_000_000
PERIOD_NS = 5_000_000                       # 200 Hz
value = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(-1e3, 1e3),
                  st.sampled_from([0.0, 9.81, -9.81, 1e300, -1e300]))
vector = st.tuples(value, value, value)
# the time to the next message: mostly a sample period or so, sometimes a jump back or ahead
advance = st.one_of(st.integers(1, 2 * PERIOD_NS), st.integers(1, 2 * PERIOD_NS),
                    st.integers(-10**12, 10**12), st.just(0), st.just(4 * 3600 * 10**9))
stamp = st.one_of(st.integers(-10**12, 10**12), st.just(4 * 3600 * 10**9))
FUZZ = settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
IMU_KEYS = ("non_finite", "implausible", "stamp_not_increasing")


def _running() -> StreamingNavigator:
    """A navigator aligned on 2 s at rest and filtering: the foot moves for 1 s after it,
    which ends the stance the alignment waits for."""
    live = StreamingNavigator(CONFIG)
    for k in range(400):
        live.push(BASE + k * PERIOD_NS, (0.0, 0.0, 9.81), (0.0, 0.0, 0.0))
    for k in range(400, 600):
        swing = np.sin(k * 0.3)
        live.push(BASE + k * PERIOD_NS, (5.0 * swing, 0.0, 9.81), (0.0, 3.0 * swing, 0.0))
    assert live.ekf is not None and live.next_filtered > 0
    return live


RUNNING, LAST = _running(), BASE + 599 * PERIOD_NS


def assert_finite(run) -> None:
    out = run.output
    for array in (out.position, out.velocity, out.attitude, out.variance, out.position_cov,
                  out.velocity_cov):
        assert np.isfinite(array).all()
    assert (np.isfinite(run.statistic) | (run.statistic == np.inf)).all()


def dropped(live) -> int:
    return sum(v for k, v in live.counts.items() if k != "gaps")


@FUZZ
@given(st.lists(st.tuples(st.sampled_from(["imu", "imu", "imu", "reset"]), advance, vector,
                          vector), max_size=80))
def test_zupt_ekf_adapter_survives_garbage(events):
    live, stamp, last_kept = copy.deepcopy(RUNNING), LAST, LAST
    estimated: list[int] = []
    for kind, step, accel, gyro in events:
        if kind == "reset":
            live.reset()
            last_kept, estimated = None, []
            assert sum(live.counts.values()) == 0
            continue
        stamp += step
        before = [live.counts[k] for k in IMU_KEYS]
        run = live.push(stamp, accel, gyro)
        reason = drop_reason(stamp, last_kept, accel, gyro)
        counted = {k: live.counts[k] - n for k, n in zip(IMU_KEYS, before, strict=True)
                   if live.counts[k] != n}
        assert counted == ({} if reason is None else {reason: 1}), "kept or counted"
        last_kept = stamp if reason is None else last_kept
        assert_finite(run)
        estimated.extend(run.stamp_ns.tolist())
    run = live.flush()
    assert_finite(run)
    estimated.extend(run.stamp_ns.tolist())
    assert estimated == sorted(set(estimated)), "each estimated once, in order"
    if live.ekf is not None:
        assert live.next_filtered == live.received, "every kept sample estimated"
        assert estimated[-1:] == [last_kept] or not estimated


@FUZZ
@given(st.lists(st.lists(st.tuples(stamp, vector, vector), max_size=40), max_size=6))
def test_zupt_ekf_blocks_survive_garbage(blocks):
    """The node takes its backlog in blocks (push_many): every sample of a block is kept
    or counted, and nothing estimated is non-finite."""
    live = copy.deepcopy(RUNNING)
    for block in blocks:
        stamps = np.array([LAST + offset for offset, _, _ in block], np.int64)
        accel = np.array([a for _, a, _ in block], float).reshape(-1, 3)
        gyro = np.array([w for _, _, w in block], float).reshape(-1, 3)
        before, received = dropped(live), live.received
        assert_finite(live.push_many(stamps, accel, gyro))
        assert dropped(live) - before + live.received - received == len(block)
    assert_finite(live.flush())
