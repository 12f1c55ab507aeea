"""The closed-form ZUPT error model (Wang et al. 2020, section III) and its check
against the EKF (section IV-A, Figs. 3-6)."""
import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core import units
from pdr_ins_ekf.studies import error_sweep
from pdr_ins_ekf.studies.ekf_montecarlo import filter_for
from pdr_ins_ekf.studies.zupt_error_model import Gait, NoiseDensities, ZuptErrorModel
from pdr_ins_ekf.zupt_ekf import run

G = 9.80665
VN200 = NoiseDensities(units.arw_to_si(0.21), units.mg_to_si(0.14), units.rrw_to_si(0.048))


def model(noise=VN200, **gait) -> ZuptErrorModel:
    return ZuptErrorModel(noise, Gait(**{"t_stance_s": 0.2, "t_stride_s": 0.536, **gait}))


@settings(max_examples=200, deadline=None)
@given(arw=st.floats(0.005, 20), vrw=st.floats(0.005, 20), rrw=st.floats(0.1, 1000),
       stance=st.floats(0.1, 0.9), rate=st.floats(50, 2000), r=st.floats(0.002, 0.1))
def test_root_closes_the_balance_equations(arw, vrw, rrw, stance, rate, r):
    """σ_v² solves Eq. (44); with P12 of Eq. (45) and P41 of Eq. (46) it balances the
    velocity (Eq. (43)) and the angle (Eq. (42)) over a stride."""
    noise = NoiseDensities(units.arw_to_si(arw), units.mg_to_si(vrw),
                           units.rrw_to_si(rrw * 1e-3))
    m = ZuptErrorModel(noise, Gait(stance * 0.536, 0.536), r, rate)
    s = m.steady_state()
    x, k = s.sigma_v_mps**2, m.k
    assert s.p12 < 0
    vrw2 = noise.vrw_mps2_per_sqrt_hz**2
    assert (vrw2 - 2 * G * s.p12) == pytest.approx(x**2 / k, rel=1e-6)        # Eq. (43)
    arw2 = noise.arw_rad_per_sqrt_s**2
    assert (arw2 - 2 * 0.84 * s.p41) == pytest.approx(s.p12**2 / k, rel=1e-6)  # Eq. (42)


def test_without_gyro_noise_velocity_is_set_by_vrw_alone():
    """ARW = RRW = 0: Eq. (44) has the double root σ_v² = √K·VRW and σ_gN = 0."""
    m = model(NoiseDensities(0.0, units.mg_to_si(0.14), 0.0))
    s = m.steady_state()
    assert s.sigma_v_mps**2 == pytest.approx(math.sqrt(m.k) * units.mg_to_si(0.14), rel=1e-5)
    assert s.sigma_gn_radps == 0


def test_growth_laws():
    """σ_ψ is Eq. (38); σ_∥ grows as √t (Eq. (56)); σ_⊥ as t^2.5 once RRW dominates
    (Wang et al. 2020, section III-E, comment 4)."""
    m = model()
    t = np.array([1.0, 100.0, 1e4])
    arw, rrw = VN200.arw_rad_per_sqrt_s, VN200.rrw_radps_per_sqrt_s
    np.testing.assert_allclose(m.sigma_yaw_rad(t), np.sqrt(arw**2 * t + rrw**2 * t**3 / 3))
    par = m.sigma_par_m(t)
    assert par[2] / par[1] == pytest.approx(10.0)
    perp = m.sigma_perp_m(np.array([1e4, 1e5]))
    assert np.log10(perp[1] / perp[0]) == pytest.approx(2.5, abs=0.01)
    assert m.sigma_perp_m(0.0) == 0


def test_rederived_eq56_drops_the_printed_factor():
    m = model()
    ratio = m.sigma_par_m(50.0) / ZuptErrorModel(m.noise, m.gait, rederived_eq56=True
                                                 ).sigma_par_m(50.0)
    assert ratio == pytest.approx(math.sqrt(2 - 0.536 / 4))


@pytest.mark.parametrize("make, message", [
    (lambda: Gait(0.6, 0.536), "t_stance_s must be in (0, t_stride_s = 0.536)"),
    (lambda: Gait(0.2, 0.0), "t_stride_s must be > 0"),
    (lambda: Gait(0.2, 0.5, cos_pitch_mean=1.5), "cos_pitch_mean (a_c) must be in (0, 1]"),
    (lambda: NoiseDensities(-1e-4, 0.0, 0.0), "arw_rad_per_sqrt_s must be a finite density"),
    (lambda: NoiseDensities(0.0, math.nan, 0.0), "vrw_mps2_per_sqrt_hz must be a finite"),
    (lambda: model().__class__(VN200, Gait(0.2, 0.5), zupt_sigma_mps=0.0), "r) must be > 0"),
    (lambda: model().sigma_par_m(-1.0), "times must be finite and >= 0 s"),
])
def test_impossible_inputs_are_refused(make, message):
    with pytest.raises(ValueError) as error:
        make()
    assert message in str(error.value)


@pytest.fixture(scope="module")
def walk():
    return error_sweep.paper_walk()


def test_paper_walk_has_the_papers_length_and_duration(walk):
    gait = error_sweep.gait_of(walk)
    assert walk.position[-1, 0] == pytest.approx(77.0)
    assert walk.t_s[-1] - walk.rest_s == pytest.approx(53.6, abs=0.01)
    assert gait.t_stride_s == pytest.approx(0.536, abs=1e-3)
    assert gait.t_stance_s == pytest.approx(0.2, abs=0.005)


# Wang et al. 2020, section IV-A: "a difference within 10 %" where its assumptions hold.
# σ_∥ (Eq. (56), re-derived) assumes the swing's velocity error small against r (section
# III-E, comment 6), true up to VRW ≈ 0.3 mg/√Hz; σ_⊥ assumes an unobservable azimuth,
# true up to RRW ≈ 20 mdeg/s/√h (see the next test).
@pytest.mark.parametrize("parameter, value, along, across", [
    ("arw", 0.01, True, False), ("arw", 0.21, True, False), ("arw", 1.0, True, False),
    ("vrw", 0.01, True, False), ("vrw", 0.3, True, False), ("vrw", 1.0, False, False),
    ("rrw", 0.6, True, True), ("rrw", 6.0, True, True), ("rrw", 19.0, True, True)])
def test_analytic_levels_agree_with_the_ekf_within_10_percent(walk, parameter, value, along,
                                                               across):
    point = error_sweep.sweep_point(walk, error_sweep.gait_of(walk), parameter, value, runs=0)
    for quantity in ("sigma_v_mps", "sigma_theta_rad"):
        assert abs(error_sweep.agreement(point, quantity)) < 0.10, quantity
    if along:
        # docs/error_analysis.md: "a re-derived Eq. (56) agrees within 4 %" (up to VRW
        # 0.3); −0.5 to −3.6 % measured on these points
        assert point.rederived_par_m == pytest.approx(point.simulated["sigma_par_m"][0],
                                                      rel=0.04)
    if across:
        # docs/error_analysis.md: σ_⊥ "−1 to +2 %" for RRW ≤ 19; −1.4, +0.4, +1.7 % measured
        assert abs(error_sweep.agreement(point, "sigma_perp_m")) < 0.02


def test_where_the_assumptions_fail_the_model_departs(walk):
    """Found, and reported by ``pdr-ekf study sweep``: (1) the printed Eq. (56) is 24-26 %
    above the filter along track; (2) at RRW 600 mdeg/s/√h the foot's pitch makes the body
    z gyro bias partly observable, so the heading (Eq. (38)) and σ_⊥ grow far less than the
    model, which takes the azimuth as unobservable."""
    gait = error_sweep.gait_of(walk)
    base = error_sweep.sweep_point(walk, gait, "rrw", 48.0, runs=0)
    # docs/error_analysis.md: 24–26 %, ±0.5 point; the filter's σ_∥ is 25.9 % below the
    # printed Eq. (56) (measured)
    assert -0.265 < error_sweep.agreement(base, "sigma_par_m") < -0.235
    # docs/error_analysis.md: σ_⊥ "−21 % at 60, −85 % at 600"; −20.95 and −84.8 % measured
    rrw_60 = error_sweep.sweep_point(walk, gait, "rrw", 60.0, runs=0)
    assert error_sweep.agreement(rrw_60, "sigma_perp_m") == pytest.approx(-0.21, rel=0.05)
    high = error_sweep.sweep_point(walk, gait, "rrw", 600.0, runs=0)
    assert error_sweep.agreement(high, "sigma_perp_m") == pytest.approx(-0.85, rel=0.05)
    # the heading: the filter's σ_ψ at the end against Eq. (38), 89.6 % below at RRW 600
    # (measured; within 2.4 % at RRW 0.6-19), ±5 %
    assert heading_agreement(walk, gait, 19.0) == pytest.approx(0.0, abs=0.03)
    assert heading_agreement(walk, gait, 600.0) == pytest.approx(-0.896, rel=0.05)


def heading_agreement(walk, gait, rrw: float) -> float:
    """The filter's σ_ψ at the end of the walk / Eq. (38) − 1, with RRW [mdeg/s/√h] and the
    others at the baseline, set up as :func:`error_sweep.sweep_point` sets up its filter."""
    densities, noise = error_sweep.noise_point(**{**error_sweep.BASELINE, "rrw": rrw})
    model = ZuptErrorModel(densities, gait, error_sweep.SWEEP_ZUPT_SIGMA_MPS, walk.rate_hz)
    config = replace(filter_for(noise, error_sweep.SWEEP_ZUPT_SIGMA_MPS),
                     **error_sweep.KNOWN_START)
    rest = slice(0, int(np.searchsorted(walk.t_s, walk.rest_s)))
    filtered = run(walk.t_s, walk.accel, walk.gyro, walk.at_rest, config, rest, walk.yaw[0])
    duration = float(walk.t_s[-1] - walk.rest_s)
    return float(np.sqrt(filtered.variance[-1, 8]) / model.sigma_yaw_rad(duration)) - 1
