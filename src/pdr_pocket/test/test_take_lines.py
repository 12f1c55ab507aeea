"""The person's lines taken by the live navigator mid-walk
(pdr_pocket.streaming.StreamingPocket.take_lines, what pocket_pdr does when stride_calibrator
sets its parameters): the steps before keep the configured lines, the level steps after
walk the new one, and a correction that reaches back before the lines were taken runs
the steps again each with the lines it had. The lines as parameters
(pdr_pocket.saved_lines.taken_lines) are refused when not finite or a slope is not
above 0."""
from __future__ import annotations

from dataclasses import fields, replace

import numpy as np
import pytest

from pdr_core.corrections.correction import Correction
from pdr_core.vocabulary import Activity
from pdr_pocket.config import PocketConfig, StairsConfig
from pdr_pocket.saved_lines import taken_lines
from pdr_pocket.step_length import StepLengthConfig
from pdr_pocket.streaming import StreamingPocket
from wstest import pocket_walk

CONFIG = PocketConfig()
TAKEN_AT_S = 20.5       # the lines are taken after this much of the walk [s], between steps
WALK_S = 40.0           # the first 40 s of bags/pocket_walk
NEW_B_H_M = CONFIG.step_length.b_h_m + 0.1


def navigated(take: bool):
    """The walk in two blocks (navigator time [s] from its first sample), the new level
    line taken between them when ``take``: the navigator and its steps."""
    stamps, accel, gyro, field_t = pocket_walk(WALK_S)
    cut = int(np.searchsorted(stamps, stamps[0] + TAKEN_AT_S * 1e9))
    live, steps = StreamingPocket(CONFIG), []
    for block in (slice(0, cut), slice(cut, None)):
        if take and block.start:
            steps += [s for p in live.release() for s in p.output.steps]
            live.take_lines(*taken_lines(CONFIG.step_length, CONFIG.stairs,
                                         {"step_length.b_h_m": NEW_B_H_M}))
        live.push_mags(stamps[block], field_t[block])
        steps += [s for p in live.push_imus(stamps[block], accel[block], gyro[block])
                  for s in p.output.steps]
    steps += [s for p in live.flush() for s in p.output.steps]
    return live, steps


def same(a, b) -> bool:
    """Two steps (pdr_pocket.records.StepRecord) equal field by field, arrays too."""
    return all(np.array_equal(getattr(a, f.name), getattr(b, f.name)) for f in fields(a))


@pytest.fixture(scope="module")
def runs():
    return navigated(take=False), navigated(take=True)


def test_later_steps_walk_the_new_line_earlier_ones_do_not(runs):
    (_, before), (live, after) = runs
    assert len(before) == len(after) > 20
    old = [k for k, s in enumerate(before) if s.t_confirm < TAKEN_AT_S]
    assert len(old) > 5
    for k in old:       # confirmed before the lines were taken: the same steps
        assert same(after[k], before[k])
    new = [k for k, s in enumerate(before)
           if s.t_confirm > TAKEN_AT_S and s.activity == Activity.WALKING]
    assert len(new) > 5 and live.navigator.bounded_steps == 0    # none cut to the bound
    for k in new:
        assert after[k].length == pytest.approx(before[k].length + 0.1, abs=1e-12)
    assert live.config.step_length.b_h_m == NEW_B_H_M
    assert live.config.step_length.calibrated           # the person's line: not scaled
    assert live.navigator.assembly.config.step_length.b_h_m == NEW_B_H_M


def test_a_correction_before_the_lines_keeps_each_step_s_own_line(runs):
    """A correction stamped at a step before the lines were taken runs the steps since
    again: those before the take with the configured line, those after with the new one
    (the lines are an input of the replay's history)."""
    _, (live, after) = runs
    stamps = pocket_walk(WALK_S)[0]
    stamp = int(stamps[0] + (TAKEN_AT_S - 5.0) * 1e9)
    result = live.apply_correction(Correction(0.0, 1e-6, None, None, None, None, stamp))
    assert result.accepted, result.message
    revised = {round(r.step.t, 9): r.step for r in result.revised}
    walked = [s for s in after
              if round(s.t, 9) in revised and s.activity == Activity.WALKING]
    early = [s for s in walked if s.t_confirm < TAKEN_AT_S]
    late = [s for s in walked if s.t_confirm > TAKEN_AT_S]
    assert early and late
    for s in early + late:      # a yaw correction moves Δθ by µdeg, the line by 0.1 m
        assert revised[round(s.t, 9)].length == pytest.approx(s.length, abs=1e-3)


@pytest.mark.parametrize(("values", "says"), [
    ({"step_length.b_h_m": float("nan")}, "step_length.b_h_m: nan is not finite"),
    ({"stairs.a_u_cm_per_deg": 0.0}, "stairs.a_u_cm_per_deg: a slope must be above 0"),
    ({"step_length.a_h_m_per_deg": -0.02}, "step_length.a_h_m_per_deg: a slope must be"),
    ({"step_length.model": 1.0}, "step_length.model: not a line's parameter")])
def test_bad_lines_are_refused_by_name(values, says):
    with pytest.raises(ValueError, match=says):
        taken_lines(StepLengthConfig(), StairsConfig(), values)


def test_unchanged_level_lines_stay_uncalibrated():
    step_length, stairs = taken_lines(StepLengthConfig(), StairsConfig(), {
        "step_length.b_h_m": StepLengthConfig().b_h_m, "stairs.b_d_cm": -18.0})
    assert step_length == StepLengthConfig() and not step_length.calibrated
    assert stairs == replace(StairsConfig(), b_d_cm=-18.0)
