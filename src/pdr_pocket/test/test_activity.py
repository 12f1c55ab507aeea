"""The step activity classifiers (pdr_pocket.activity) on constructed steps: the level
floor as the strong prior, a staircase shown by one unmistakable step or by consistent
ones, and the thesis' rule kept for its tables."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pdr_core.vocabulary import Activity
from pdr_pocket.activity import (
    LevelOnlyActivity,
    LevelPriorActivity,
    StepShape,
    ThesisActivity,
    activity_classifier,
)
from pdr_pocket.config import ActivityConfig

# θ_max, θ_min [deg] of the thesis' signatures (Section 4.1.2) as the shared recordings
# show them: level, up (θ_max almost doubled), down (θ_min positive)
LEVEL, UP, DOWN = (22.0, -9.0), (50.0, -6.0), (36.0, 5.0)


def step(shape_deg, turn_deg=0.0, duration_s=1.25, tilt_sigma_deg=0.0) -> StepShape:
    return StepShape(np.radians(shape_deg[0]), np.radians(shape_deg[1]),
                     np.radians(turn_deg), duration_s, np.radians(tilt_sigma_deg))


def labels(classifier, steps) -> list[int]:
    return [classifier.classify(s) for s in steps]


def test_level_walk_at_changing_speeds_stays_level():
    """A brisk level step swings the thigh further both ways (Δθ up 35 %, θ_min down),
    which the thesis' rule can read as stairs: the level prior keeps it level."""
    slow, brisk = (18.0, -7.0), (28.0, -14.0)
    model = LevelPriorActivity(ActivityConfig())
    walk = [step(slow)] * 10 + [step(brisk, duration_s=1.0)] * 10 + [step(slow)] * 5
    assert labels(model, walk) == [Activity.WALKING] * len(walk)


def test_a_walk_that_starts_on_a_staircase_is_read_against_a_level_gait():
    """The thesis' rule learns its level reference from the first steps; a walk that
    begins on the stairs then reads as level. The population's level gait does not."""
    walk = [step(UP)] * 6 + [step(LEVEL)] * 4 + [step(DOWN)] * 6 + [step(LEVEL)] * 3
    assert labels(LevelPriorActivity(ActivityConfig()), walk) == \
        [Activity.UPSTAIRS] * 6 + [Activity.WALKING] * 4 + [Activity.DOWNSTAIRS] * 6 + \
        [Activity.WALKING] * 3
    assert labels(ThesisActivity(ActivityConfig()), walk)[:6] == [Activity.WALKING] * 6


def test_one_odd_step_is_no_staircase():
    """A level step that looks a little like a step down (a stumble, a kerb) in a level
    walk is not a staircase: the level state's tails are heavy and its prior strong."""
    odd = (30.0, 1.0)
    walk = [step(LEVEL)] * 8 + [step(odd)] + [step(LEVEL)] * 4
    assert labels(LevelPriorActivity(ActivityConfig()), walk) == [Activity.WALKING] * 13


def test_stairs_are_walked_not_run():
    """A jog's short cycle (0.8 s) that looks somewhat like a step down (θ_min just
    above 0) is level; the same step at a walking cadence is down."""
    model = LevelPriorActivity(ActivityConfig())
    before, down_ish = [step(LEVEL)] * 8, (32.0, 2.0)
    jog = labels(model, [*before, step(down_ish, duration_s=0.8)])
    model.restart()
    walked = labels(model, [*before, step(down_ish, duration_s=1.25)])
    assert jog[-1] == Activity.WALKING and walked[-1] == Activity.DOWNSTAIRS


def test_an_uncertain_tilt_weakens_the_evidence():
    """Across a gap in the data the attitude's tilt is uncertain: a step down then needs
    the next to confirm it."""
    model = LevelPriorActivity(ActivityConfig())
    walk = [step(LEVEL)] * 8 + [step(DOWN, tilt_sigma_deg=20.0), step(DOWN), step(DOWN)]
    assert labels(model, walk)[-3:] == [Activity.WALKING, Activity.DOWNSTAIRS, Activity.DOWNSTAIRS]


def test_the_level_gait_is_learned_from_level_steps():
    model = LevelPriorActivity(ActivityConfig())
    labels(model, [step((30.0, -12.0))] * 10)
    np.testing.assert_allclose(model.reference(),
                               [(3 * 8.0 + 6 * 9.0) / 9, np.log((3 * 32.0 + 6 * 42.0) / 9),
                                (3 * -8.0 + 6 * -12.0) / 9], rtol=0.05)


@pytest.mark.parametrize(("model", "kind"), [("thesis", ThesisActivity),
                                              ("level_prior", LevelPriorActivity)])
def test_the_model_is_chosen_by_the_configuration(model, kind):
    config = replace(ActivityConfig(), model=model)
    assert isinstance(activity_classifier(config), kind)
    assert isinstance(activity_classifier(config, gyroscope=False), LevelOnlyActivity)


def test_unknown_model_and_bad_probabilities_are_refused():
    with pytest.raises(ValueError, match="model must be one of thesis, level_prior"):
        ActivityConfig(model="hmm")
    with pytest.raises(ValueError, match="enter_stairs_probability"):
        ActivityConfig(enter_stairs_probability=0.0)
