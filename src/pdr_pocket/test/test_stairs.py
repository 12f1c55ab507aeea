"""Staircases that show themselves in the height as well as in the pitch
(pdr_pocket.stairs.FlightCheck, issue 40): on constructed runs of steps, each step's v as
Eqs. (4.4)-(4.5) give it. The real flights are the shared thigh board's (s_up_thigh_1,
s_down_thigh_1, s_both_thigh_1 as the navigator measures them); the refused runs are the
three level recordings of issue 40 as their aggregates describe them, a turn of the phone
in the pocket and a phone turned so that every later step reads as downstairs."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pdr_core.vocabulary import Activity
from pdr_core.walking.stair_geometry import RISER_MAX_M, RISER_MIN_M
from pdr_pocket.config import StairsConfig
from pdr_pocket.stairs import Staircases, flight_problem, max_flight_cycles

UP, DOWN, LEVEL = Activity.UPSTAIRS, Activity.DOWNSTAIRS, Activity.WALKING
# v [m] per step of the shared board's flights, as the pitch gives them
REAL_FLIGHTS = {"s_up 1": (UP, [0.363, 0.34, 0.352, 0.411]),
                "s_up 2": (UP, [0.455, 0.332, 0.341, 0.331]),
                "s_down 1": (DOWN, [-0.435, -0.415, -0.438, -0.169]),
                "s_down 2": (DOWN, [-0.386, -0.459, -0.397, -0.266]),
                "s_both down 1": (DOWN, [-0.453, -0.405, -0.384, -0.316]),
                "s_both down 2": (DOWN, [-0.503, -0.426, -0.376, -0.297]),
                "s_both up 1": (UP, [0.329, 0.354, 0.389]),
                "s_both up 2": (UP, [0.411, 0.309, 0.311, 0.295])}


def walked(steps, config: StairsConfig | None = None) -> tuple[Staircases, list]:
    """(activity, v) per step through Staircases.admit, level steps around: the
    staircases and what was published."""
    book = Staircases(config or StairsConfig())
    steps = [(LEVEL, 0.0), *steps, (LEVEL, 0.0)]
    return book, [book.admit(i, float(i), a, v) for i, (a, v) in enumerate(steps)]


@pytest.mark.parametrize("name", REAL_FLIGHTS)
def test_a_real_flight_climbs_as_without_the_check(name):
    """Held back one step, then caught up: the same staircase, height and mean riser, every
    step labelled as the pitch labelled it; only the first step's height comes a step late."""
    direction, heights = REAL_FLIGHTS[name]
    book, published = walked([(direction, v) for v in heights])
    assert [a for a, _ in published[1:-1]] == [direction] * len(heights)
    assert [v for _, v in published[1:3]] == [0.0, pytest.approx(heights[0] + heights[1])]
    assert [v for _, v in published[3:-1]] == heights[2:]
    [staircase] = book.done
    assert staircase.height_m == pytest.approx(sum(heights))
    assert staircase.riser_m == pytest.approx(np.mean(np.abs(heights)) / 2)
    assert book.check.refused == {"staircases": 0, "steps": 0}


def test_a_single_stairs_step_climbs_nothing():
    """A flight is at least three risers (DIN 18065): one gait cycle the pitch reads as up
    (the phone turned in the pocket, 0.46–0.61 m) keeps its label and climbs nothing, and
    is no staircase."""
    book, published = walked([(UP, 0.55)])
    assert published[1] == (UP, 0.0)
    assert book.done == [] and book.check.refused == {"staircases": 1, "steps": 1}


@pytest.mark.parametrize(("what", "direction", "per_step_m", "steps"), [
    # issue 40's level recordings, by their aggregates: a phone in a pocket, 11 steps
    # down to −6.2 m (risers of 0.28 m); a motion-capture loop, 33 steps down to −5.9 m
    # (0.09 m)
    ("pocket", DOWN, -6.2 / 11, 11),
    ("motion capture loop", DOWN, -5.9 / 33, 33),
    ("a level swing read as up", UP, 0.16, 6),
])
def test_a_run_whose_riser_is_no_stair_stays_level(what, direction, per_step_m, steps):
    rng = np.random.default_rng(1)
    heights = per_step_m * (1.0 + 0.1 * rng.standard_normal(steps))
    book, published = walked([(direction, float(v)) for v in heights])
    assert [v for _, v in published] == [0.0] * (steps + 2), what
    assert [a for a, _ in published[2:]] == [LEVEL] * steps
    assert book.done == []
    assert book.check.refused == {"staircases": 1, "steps": steps}


def test_a_run_longer_than_a_flight_is_cut_at_a_flight():
    """A phone turned so that every later step reads as downstairs (250 steps, −112 m in
    simulation): no more than a flight's gait cycles climb, 18 risers / 2 + 1."""
    book, published = walked([(DOWN, -0.36)] * 40)
    climbed = [v for _, v in published if v != 0.0]
    assert sum(climbed) == pytest.approx(-0.36 * max_flight_cycles(StairsConfig()))
    assert max_flight_cycles(StairsConfig()) == 10
    assert [a for a, _ in published[11:-1]] == [LEVEL] * 30
    assert book.check.refused == {"staircases": 0, "steps": 30}


def test_flights_joined_by_a_landing_read_as_stairs_climb_on_after_its_turn():
    """A U-shaped stair down, its landing's two cycles read as stairs (a gap in the samples
    over it, UP/DW in test_navigator): the run outgrows a flight after the heading turned
    180°, so a new flight starts there and every step climbs, one staircase as without the
    check; straight on, it is refused."""
    config = StairsConfig()
    cycles = max_flight_cycles(config)
    headings = [0.0] * 6 + [np.pi / 2, np.pi] + [np.pi] * 8
    book = Staircases(config)
    published = [book.admit(i, float(i), DOWN, -0.36, h) for i, h in enumerate(headings)]
    assert [a for a, _ in published] == [DOWN] * len(headings)
    assert sum(v for _, v in published) == pytest.approx(-0.36 * len(headings))
    assert [len(s.steps) for s in book.done] == [len(headings)]   # one staircase, as published
    assert book.check.refused == {"staircases": 0, "steps": 0}
    straight = Staircases(config)
    published = [straight.admit(i, float(i), DOWN, -0.36, 0.0) for i in range(len(headings))]
    assert [a for a, _ in published[cycles:]] == [LEVEL] * (len(headings) - cycles)


def test_a_step_that_disagrees_ends_the_staircase():
    """Each step is one or two of the run's risers ±50 %: six 0.36 m steps then one of
    0.9 m (4.1 risers of 0.22 m) end the staircase there, and the rest of the run is
    level."""
    book, published = walked([(UP, 0.36)] * 6 + [(UP, 0.9), (UP, 0.36)])
    assert [v for _, v in published[1:-1]] == \
        pytest.approx([0.0, 0.72, 0.36, 0.36, 0.36, 0.36, 0.0, 0.0])
    assert [a for a, _ in published[7:-1]] == [LEVEL, LEVEL]
    assert book.done[0].height_m == pytest.approx(2.16)
    assert book.check.refused == {"staircases": 0, "steps": 2}


def test_up_then_down_are_two_runs_and_level_ends_one():
    """Up and down are separate runs; a level step ends a run, so the next stairs step
    starts a new one, held again."""
    steps = [(UP, 0.36)] * 3 + [(DOWN, -0.36)] * 3 + [(LEVEL, 0.0)] + [(DOWN, -0.36)] * 2
    book, published = walked(steps)
    assert [v for _, v in published[1:-1]] == pytest.approx(
        [0.0, 0.72, 0.36, 0.0, -0.72, -0.36, 0.0, 0.0, -0.72])
    assert [round(c.height_m, 2) for c in book.done] == [1.08, -1.08, -0.72]


def test_the_rule_on_whole_runs():
    config = StairsConfig()
    assert flight_problem(UP, [0.34] * 5, config) is None
    assert "against the run" in flight_problem(UP, [0.34, -0.1], config)
    assert "outside" in flight_problem(DOWN, [-0.6, -0.6], config)
    assert "outside" in flight_problem(UP, [0.18, 0.18], config)
    assert "step 7 climbs 4.12 risers" in flight_problem(UP, [0.36] * 6 + [0.9], config)
    assert "more than a flight" in flight_problem(DOWN, [-0.34] * 11, config)
    # the first step of a flight may be its odd one: only its sign counts before a second
    assert flight_problem(DOWN, [-0.6], config, whole=False) is None
    # the edges are the codes' (pdr_core.walking.stair_geometry)
    assert flight_problem(UP, [2.001 * RISER_MIN_M] * 3, config) is None
    assert flight_problem(UP, [1.999 * RISER_MAX_M] * 3, config) is None
    assert flight_problem(UP, [1.99 * RISER_MIN_M] * 3, config) is not None


def test_switched_off_every_stairs_step_climbs():
    book, published = walked([(UP, 0.55)], replace(StairsConfig(), check_flights=False))
    assert published[1] == (UP, 0.55) and book.done[0].height_m == 0.55


def test_bad_settings_are_refused():
    with pytest.raises(ValueError, match="riser_max_m must be above riser_min_m"):
        StairsConfig(riser_min_m=0.2, riser_max_m=0.1)
    with pytest.raises(ValueError, match="riser_count_tolerance must be below 1"):
        StairsConfig(riser_count_tolerance=1.0)
    with pytest.raises(ValueError, match="flight_max_risers must be at least 3"):
        StairsConfig(flight_max_risers=2)
