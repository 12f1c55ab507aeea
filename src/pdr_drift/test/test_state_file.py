"""The drift estimator's state across a restart (pdr_drift.state_file, issue 32): saved
mid-walk and loaded, it goes on exactly as it would have; the navigator's history sent
again is recognised; a file it cannot use is refused with its name and the problem."""
from __future__ import annotations

import numpy as np
import pytest
from drift_walks import LEVEL, SIDES, walk

from pdr_core.errors import InputError
from pdr_drift.config import DriftConfig
from pdr_drift.state_file import load_state, save_state
from pdr_drift.streaming import StreamingDrift

BASE = 1_700_000_000_000_000_000
STEPS = walk([(0, 45, LEVEL), *SIDES, (90, 45, LEVEL), *SIDES, (90, 45, LEVEL), *SIDES],
             drift_radps=np.radians(0.03))


def feed(stream: StreamingDrift, steps) -> list:
    """What the estimator returned for each step: landmarks, drifts and corrections."""
    out = []
    for s in steps:
        stamp = BASE + round(s.t * 1e9)
        stream.push_step(stamp, s.heading, s.activity)
        result = stream.push_pose(stamp, s.position, s.covariance)
        out.append(None if result is None else (
            [m.id for m in result.landmarks],
            [(d.landmark_first, d.landmark_revisit, d.drift) for d in result.drifts],
            [(c.yaw_rad, c.gyro_bias_z_radps, *c.position_m) for c in result.corrections]))
    return out


@pytest.mark.parametrize("association", ["nearest", "multi_hypothesis"])
def test_a_restart_mid_walk_changes_nothing(tmp_path, association):
    config = DriftConfig(association=association)
    whole = feed(StreamingDrift(config), STEPS)
    assert any(r and r[2] for r in whole)                     # corrections to keep
    cut = len(STEPS) // 2
    first = StreamingDrift(config)
    before = feed(first, STEPS[:cut])
    save_state(tmp_path / "state", first)
    again = load_state(tmp_path / "state", config)
    # the navigator's transient-local history comes again first: known, dropped
    assert feed(again, STEPS[:cut]) == [None] * cut
    assert again.counts["before_restart"] == 2 * cut
    assert before + feed(again, STEPS[cut:]) == whole


def test_a_state_it_cannot_use_is_refused_by_name(tmp_path):
    garbage = tmp_path / "garbage"
    garbage.write_bytes(b"not a pickle")
    with pytest.raises(InputError, match="garbage: not a drift estimator state"):
        load_state(garbage, DriftConfig())
    stream = StreamingDrift(DriftConfig())
    feed(stream, STEPS[:20])
    save_state(tmp_path / "state", stream)
    with pytest.raises(InputError, match=r"another configuration \(association: 'nearest' there"):
        load_state(tmp_path / "state", DriftConfig(association="multi_hypothesis"))
    assert not list(tmp_path.glob("*.partial"))
