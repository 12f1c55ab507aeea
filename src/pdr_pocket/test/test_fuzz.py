"""The pocket navigator's live adapter against garbage (issue 19's rule, started here for
pocket_pdr and landmark_drift): NaN, ±Inf, huge and zero values, stamps that jump back,
repeat or leap ahead, garbage corrections, resets at any time. Nothing raises, nothing
published is not finite, and what was dropped is counted. Found by it: a window of zero
specific force divided by zero in the mean gravity update, and a finite rate of 1e151
rad/s did too."""
from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pdr_drift.streaming import StreamingDrift
from pdr_pocket.config import PocketConfig
from pdr_pocket.streaming import StreamingPocket

CONFIG = PocketConfig()
BASE = 1_700_000_000_000_000_000
value = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(-1e3, 1e3),
                  st.sampled_from([0.0, 9.81, -9.81, 1e300, -1e300]))
vector = st.tuples(value, value, value)
stamp = st.integers(-10**12, 10**15)
FUZZ = settings(max_examples=500, deadline=None, suppress_health_check=list(HealthCheck))


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
            chunks = live.push_imu(BASE + offset, a, b)
        elif kind == "mag":
            chunks = live.push_mag(BASE + offset, np.asarray(a) * 1e-6)
        elif kind == "reset":              # the ~/reset service
            live.reset()
            chunks = []
        else:
            with np.errstate(all="ignore"):
                ok, message = live.apply_correction(
                    c[0], c[1], c[2], c[3], b, np.eye(3).ravel() * c[0])
            assert isinstance(ok, bool) and message
            chunks = []
        for chunk in chunks:
            out = chunk.output
            assert np.isfinite(out.attitude.attitude).all()
            assert np.isfinite(out.attitude.covariance).all()
            for step in out.steps:
                assert np.isfinite(step.position).all() and np.isfinite(step.covariance).all()
    assert sum(live.counts.values()) >= 0


@FUZZ
@given(st.lists(st.tuples(st.booleans(), stamp, value, st.integers(-3, 8), vector,
                          st.lists(value, min_size=9, max_size=9)), max_size=60))
def test_landmark_drift_adapter_survives_garbage(events):
    live = StreamingDrift()
    for is_step, offset, heading, activity, position, covariance in events:
        with np.errstate(all="ignore"):
            result = (live.push_step(BASE + offset, heading, activity) if is_step
                      else live.push_pose(BASE + offset, position, covariance))
        for correction in [] if result is None else result.corrections:
            assert np.isfinite([correction.yaw, correction.gyro_bias_z]).all()
