"""A drift correction is a measurement, weighed against the navigator's own covariance
(pdr_pocket.corrections, issue 55): a part far less certain than the navigator barely
moves it, one the covariance says is impossible is refused, and a yaw correction turns
the heading without moving the position (PositionFilter.correct_heading)."""
from __future__ import annotations

from functools import cache

import numpy as np
import pytest

from pdr_core.correction import Correction
from pdr_pocket.config import PocketConfig
from pdr_pocket.navigator import PocketNavigator
from pdr_pocket.position import EPS, PSI, PositionFilter
from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate
from wstest import samples_of


@cache
def started() -> PocketNavigator:
    """A navigator 40 s into a simulated walk (sit_stand, xsens_mtw errors)."""
    _, data = load_pocket_scenario("sit_stand")
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, "sit_stand"), data,
                                    "xsens_mtw", {}, 100.0, 0, placement="pocket"))
    nav = PocketNavigator(PocketConfig())
    nav.process(samples_of(sim)[:4000])
    return nav


def fresh() -> PocketNavigator:
    return started().copy_state()


def test_a_yaw_far_less_certain_than_the_navigator_barely_moves_it():
    """K = P/(P + R): a yaw correction with a variance 10⁴ times the navigator's moves the
    heading by 10⁻⁴ of itself, one as certain as the navigator by half."""
    for ratio, share in ((1e4, 1e-4), (1.0, 0.5)):
        nav = fresh()
        before, p = nav.orientation.yaw, nav.orientation.yaw_variance
        change = 2 * np.sqrt(p)
        ok, message = nav.apply_correction(Correction(change, ratio * p))
        assert ok, message
        assert nav.orientation.yaw - before == pytest.approx(share * change, rel=0.02)


def test_a_position_fix_far_less_certain_than_the_navigator_barely_moves_it():
    nav = fresh()
    before, p = nav.position.position, nav.position.covariance
    scale = 1e4 * max(np.max(np.diag(p)), 1e-6)
    ok, message = nav.apply_correction(Correction(position_m=before + [2.0, -1.0, 0.0],
                                                  position_covariance_m2=np.eye(3) * scale))
    assert ok, message
    assert np.linalg.norm(nav.position.position - before) < 1e-3


def test_the_gate_refuses_what_the_covariance_says_is_impossible():
    """A yaw 30 σ away from what the navigator and the correction's own variance allow is
    refused whole (χ² gate at 0.999), nothing moved; the same change with a variance that
    allows it passes."""
    nav = fresh()
    p = nav.orientation.yaw_variance
    change = 30 * np.sqrt(2 * p)
    yaw = nav.orientation.yaw
    ok, message = nav.apply_correction(Correction(change, p))
    assert not ok and "χ² gate" in message
    assert nav.orientation.yaw == yaw
    ok, message = nav.apply_correction(Correction(change, 900 * p))
    assert ok, message


def test_a_heading_fix_moves_the_heading_not_the_position():
    """The position's correlation with ψ is the heading's error since the start; a
    landmark's yaw is the error since the first visit: the fix gains nothing on x, y, z,
    and the covariance stays that of the gain used (Joseph form)."""
    f = PositionFilter()
    for k in range(60):
        f.step(0.7, 0.0, 0.02 * k, 1e-4 * (1 + k), 0.03**2, 1e-4, 1.1)
    x, p = f.x.copy(), f.p.copy()
    assert abs(p[0, PSI]) + abs(p[1, PSI]) > 1e-3          # correlated before
    f.correct_heading(x[PSI] + 0.05, 1e-3, 1e-3)
    np.testing.assert_array_equal(f.x[:3], x[:3])
    gain = p[:, PSI] / (p[PSI, PSI] + 1e-3)
    assert f.x[PSI] - x[PSI] == pytest.approx(gain[PSI] * 0.05)
    assert f.x[EPS] - x[EPS] == pytest.approx(gain[EPS] * 0.05)
    k = gain.copy()
    k[:3] = 0.0
    i_kh = np.eye(5) - np.outer(k, np.eye(5)[PSI])
    np.testing.assert_allclose(f.p, i_kh @ p @ i_kh.T + 1e-3 * np.outer(k, k), atol=1e-15)
    np.testing.assert_allclose(f.p[:3, :3], p[:3, :3], atol=1e-15)
    assert np.linalg.eigvalsh(f.p).min() > -1e-12
    assert f.p[PSI, PSI] < p[PSI, PSI]
