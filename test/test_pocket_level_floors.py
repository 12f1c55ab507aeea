"""Level floors that stay level (issue 40): on the shared thigh board's recordings, a
staircase must show itself in the height as well as in the pitch
(pdr_pocket.stairs.FlightCheck, shipped configuration).

The level walks (normal, fast, jogging, the timed up-and-go) have no staircase and never
leave their floor; the three stairs recordings keep every staircase, step and floor they
had (up ends on floor 1, down on −1, down-then-up reaches −1 and comes back to 0), none of
their steps refused; the rule decides as the steps come, so the navigator fed the samples
in pieces, as the live node is, publishes the same steps. Each recording is navigated in
this process with the shipped configuration (config/pocket_pdr.yaml, what ``pdr-pocket
run`` reads), once per module (about 2 s in all); the imports are the session's
(wstest.imported)."""
from __future__ import annotations

import itertools

import numpy as np
import pytest

from pdr_pocket.config import PocketConfig, load_pocket_config
from pdr_pocket.inputs import read_pocket_bag
from pdr_pocket.navigator import PocketNavigator
from wstest import THIGH, imported, needs_shared

IMPORT = ["--time-col", "time", "--acc-cols", "accel_x,accel_y,accel_z",
          "--gyro-cols", "gyro_x,gyro_y,gyro_z", "--mag-cols", "mag_x,mag_y,mag_z",
          "--mag-unit", "ut"]
LEVEL = ("norm_thigh_1", "fast_thigh_1", "jog_thigh_1", "tug_thigh_1")
# per stairs recording: its staircases, and the final, lowest and highest floor
STAIRS = {"s_up_thigh_1": (2, 1, 0, 1), "s_down_thigh_1": (2, -1, -1, 0),
          "s_both_thigh_1": (4, 0, -1, 0)}
pytestmark = needs_shared(*(THIGH / name for name in (*LEVEL, *STAIRS)))


def navigated(name: str, config: PocketConfig, chunk_s: float | None = None
              ) -> PocketNavigator:
    """The navigator after recording ``name``, fed whole or in pieces of ``chunk_s``."""
    _, _, inputs = read_pocket_bag(imported(THIGH / name / "imu.csv", IMPORT))
    navigator = PocketNavigator(config)
    cuts = [0, len(inputs.t)] if chunk_s is None else \
        [*np.searchsorted(inputs.t, np.arange(0.0, inputs.t[-1], chunk_s)), len(inputs.t)]
    for a, b in itertools.pairwise(cuts):
        navigator.process(inputs.samples[a:b])
    return navigator


@pytest.fixture(scope="module")
def runs() -> dict[str, PocketNavigator]:
    return {name: navigated(name, load_pocket_config()) for name in (*LEVEL, *STAIRS)}


@pytest.mark.parametrize("name", LEVEL)
def test_a_level_walk_has_no_staircase_and_stays_on_its_floor(runs, name):
    navigator = runs[name]
    assert navigator.staircases.done == []
    assert all(s.vertical_displacement == 0.0 and s.floor == 0 for s in navigator.steps)
    assert np.abs([s.position[2] for s in navigator.steps]).max() == 0.0


@pytest.mark.parametrize("name", STAIRS)
def test_a_staircase_keeps_its_steps_and_floors(runs, name):
    navigator = runs[name]
    count, final, lowest, highest = STAIRS[name]
    floors = [s.floor for s in navigator.steps]
    assert len(navigator.staircases.done) == count
    assert (floors[-1], min(floors), max(floors)) == (final, lowest, highest)
    assert navigator.staircases.check.refused == {"staircases": 0, "steps": 0}
    for staircase in navigator.staircases.done:
        assert len(staircase.steps) >= 3
        assert np.sign(staircase.height_m) == (1 if staircase.direction == 2 else -1)


def test_the_live_node_publishes_the_same_steps():
    """Fed 0.5 s at a time, the navigator holds back and catches up the same steps: the
    rule is causal, so pocket_pdr and pdr-pocket run agree."""
    whole = navigated("s_both_thigh_1", load_pocket_config())
    pieces = navigated("s_both_thigh_1", load_pocket_config(), chunk_s=0.5)
    assert [(s.activity, s.vertical_displacement) for s in pieces.steps] == \
        [(s.activity, s.vertical_displacement) for s in whole.steps]
    np.testing.assert_allclose([s.position for s in pieces.steps],
                               [s.position for s in whole.steps], atol=1e-9)
