"""The shared back-pocket recording's foot switches (stepcounter.csv: t_ns, left, right, no
header), read as ``pdr-pocket evaluate --truth-steps-format foot-switch --truth-steps-time
stamps --truth-steps-unit ns`` reads them (pdr_pocket.evaluation.read_truth_steps): the
footfalls a count by hand finds, at times within the recording's own stamps. No navigator
runs."""
from __future__ import annotations

from itertools import pairwise

import numpy as np

from pdr_pocket.evaluation import TruthStepsFormat, read_truth_steps
from wstest import OXFORD, needs_shared

BACK_POCKET = OXFORD.parent / "opt_Samsung_Dario_Hard_BackPocket_1"
SWITCHES = BACK_POCKET / "stepcounter.csv"


@needs_shared(SWITCHES, BACK_POCKET / "accelerometer.csv")
def test_the_back_pocket_foot_switches_give_the_hand_counted_footfalls():
    footfalls = read_truth_steps(SWITCHES, TruthStepsFormat("foot-switch", "stamps", "ns"))
    # by hand: each line's two switches against the line before, a 0 then a 1 a footfall
    lines = [line.split(",") for line in SWITCHES.read_text().split()]
    by_hand = [int(now[0]) * 1e-9 for before, now in pairwise(lines)
               for was, is_ in zip(before[1:], now[1:], strict=True) if (was, is_) == ("0", "1")]
    assert len(footfalls) == len(by_hand) == 198
    np.testing.assert_allclose(footfalls, by_hand, rtol=0, atol=1e-6)
    # on the stamps pdr-sim import-csv --time-unit ns gives accelerometer.csv's rows
    stamps_s = np.loadtxt(BACK_POCKET / "accelerometer.csv", delimiter=",", usecols=0) * 1e-9
    assert stamps_s[0] < footfalls.min() and footfalls.max() < stamps_s[-1]
