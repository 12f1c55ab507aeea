"""The pocket navigator against the simulator's truth (Muñoz Díaz 2016, chapter 4): steps
(Table 4.1), activities, stride (Table 4.4), stairs (Table 4.5), the thigh frame of an
unknown mounting, the position filter and its corrections, and one sample at a time."""
from __future__ import annotations

import itertools
import warnings
from dataclasses import replace
from functools import cache

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core.corrections.correction import Correction
from pdr_core.errors import InputError
from pdr_core.vocabulary import Activity
from pdr_core.walking.gait import PLACEMENT_WINDOW_STEPS
from pdr_pocket.compiled_mounting import CHANGES
from pdr_pocket.config import (
    MountingConfig,
    PersonConfig,
    PocketConfig,
    PositionConfig,
    StepLengthConfig,
)
from pdr_pocket.navigator import PocketNavigator
from pdr_pocket.orientation_config import OrientationConfig
from pdr_pocket.position import PositionFilter
from pdr_pocket.run_report import match_steps, riser_errors, steps_since
from pdr_pocket.samples import Samples
from pdr_pocket.step_length import fit_line, fit_offset
from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate
from wstest import samples_of

# The filter matched to the simulated sensor (config/pocket_pdr_xsens_mtw.yaml): the walks
# here carry the xsens_mtw errors the thesis's tables were measured with
MTW = PocketConfig(orientation=OrientationConfig(imu_profile="xsens_mtw"))

@cache
def simulated(name: str, mounting=None, seed: int = 0, carried: str = "front_pocket"):
    """A built-in pocket scenario with the xsens_mtw errors, its mounting replaced when
    given (a name, or roll, pitch, yaw in degrees), the phone carried as given."""
    _, data = load_pocket_scenario(name)
    data = {**data, "carried": carried}
    if mounting is not None:
        data = {**data, "mounting": mounting if isinstance(mounting, str)
                else {"rpy_deg": list(mounting)}}
    return simulate(SimulationConfig(pocket_scenario_from_dict(data, name), data, "xsens_mtw",
                                     {}, 100.0, seed, placement="pocket"))


@cache
def navigated(name: str, mounting=None, seed: int = 0, config: PocketConfig | None = None,
              carried: str = "front_pocket"):
    sim = simulated(name, mounting, seed, carried)
    out = PocketNavigator(config or PocketConfig()).process(samples_of(sim))
    return sim, out


def matched(sim, out):
    truth = sim.model.true_steps
    return match_steps(np.array([s.t for s in out.steps]), truth.end_s, truth.duration)


@pytest.mark.parametrize("name", ["h1_rectangle", "h2_rectangle_speeds", "up_dw"])
def test_pitch_maximum_finds_every_step_and_nothing_else(name):
    sim, out = navigated(name)
    match = matched(sim, out)
    assert (match >= 0).all(), f"missed {(match < 0).sum()}"
    assert len(out.steps) == len(match)


@pytest.mark.parametrize(("name", "wrong"), [("up_dw", 3), ("sit_stand", 0)])
def test_activities_of_the_steps(name, wrong):
    """docs/pocket.md: 175 of 178 steps right on UP/DW (the first step of three of its 16
    flights read as level: against the level gait at the step's amplitude one step up is
    about 2σ of level; the thesis' filter, 0.43° off in tilt against the default's 0.25°,
    got one of the three right by its error there: 176 before issue 53), 66 of 66 on
    sit/stand."""
    sim, out = navigated(name)
    match = matched(sim, out)
    truth = sim.model.true_steps.activity
    labels = np.array([s.activity for s in out.steps])[match]
    assert (labels != truth).sum() <= wrong


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_walk_that_speeds_up_stays_level(seed):
    """H2 walks its long sides at 2.5 km/h and its short ones at 4.8 (Δθ doubles): every
    step level at every seed (scaled to the step's amplitude, the level gait explains
    the faster swing; unscaled, 46 and 47 steps read as up at seeds 1 and 2)."""
    sim, out = navigated("h2_rectangle_speeds", seed=seed)
    assert [s.activity for s in out.steps] == [Activity.WALKING] * len(sim.model.true_steps.end_s)


def test_steps_of_a_refused_flight_walk_the_level_line():
    """A person who swings the thigh 44-49° at 4.8 km/h (a_H 0.022 m/°, b_H 0.52 m; issue
    57's study, H2 at seed 1008) and all of the faster swing's growth forward
    (``faster_swing_back_fraction`` 0.15, the thesis' fixed fraction: θ_max 39°, θ_min
    −7°, shaped like a step up): the pitch reads runs of fast level steps as upstairs, and
    the flight check refuses them (no climb in their height). Those steps are published as
    level walking and take the level line's stride, not the stairs' 0.52 m (they did: 34
    steps, 13.6 % of the walk short)."""
    _, data = load_pocket_scenario("h2_rectangle_speeds")
    data = {**data, "seed": 1008,
            "person": {"a_h_m_per_deg": 0.022, "b_h_m": 0.52, "b_u_cm": -7.5, "b_d_cm": -21.0,
                       "faster_swing_back_fraction": 0.15}}
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, "h2"), data, "xsens_mtw",
                                    {}, 100.0, 1008, placement="pocket"))
    navigator = PocketNavigator(PocketConfig())
    out = navigator.process(samples_of(sim))
    assert navigator.staircases.check.refused["steps"] >= 20, \
        "the pitch no longer reads these fast steps as stairs (the classifier mended?): " \
        "this test needs another walk whose flights the check refuses"
    level = [s.length for s in out.steps if s.activity == Activity.WALKING]
    stairs_stride = PocketConfig().step_length.stairs_stride_m
    assert min(level) > 0.8 > stairs_stride


def test_sitting_and_standing_periods_have_no_step_and_are_named():
    sim, out = navigated("sit_stand")
    steps_t = np.array([s.t for s in out.steps])
    t = sim.trajectory.t
    for period in sim.model.periods:
        if period.activity not in (Activity.STANDING, Activity.SITTING):
            continue
        assert not ((steps_t > period.start_s + 1.5) & (steps_t < period.end_s - 1.5)).any()
        inside = (t > period.start_s + 4.0) & (t < period.end_s - 2.0)
        if inside.any():
            assert (out.activity[inside] == period.activity).mean() > 0.95


@pytest.mark.parametrize("name", ["h1_rectangle", "h2_rectangle_speeds", "h3_museum"])
def test_distance_with_the_persons_line_within_a_tenth_of_a_percent(name):
    """docs/pocket.md: within 0.11 % with the person's line (−0.06, −0.06 and −0.10 %
    measured)."""
    sim, out = navigated(name)
    true = sim.model.true_steps.length.sum()
    assert abs(sum(s.length for s in out.steps) / true - 1) <= 0.0011


def test_riser_heights_and_floors():
    """Every flight found; risers within 0.4 % up and down (Table 4.5; 0.29 % measured);
    floors exact."""
    sim = simulated("up_dw")
    nav = PocketNavigator(MTW)
    out = nav.process(samples_of(sim))
    truth = sim.truth["/ground_truth/step"]
    flights = riser_errors(nav.staircases, truth, sim.model.true_steps.end_s)
    assert len(flights) == 16 and all(f["riser_m"] is not None for f in flights)
    assert {f["direction"] for f in flights} == {"upstairs", "downstairs"}
    for flight in flights:
        assert abs(flight["error_pct"]) <= 0.4
    assert max(s.floor for s in out.steps) == 4 and out.steps[-1].floor == 0


def h1_outcome(mounting) -> tuple[int, int, float]:
    """Missed and false steps and the distance error % of H1 with a mounting."""
    sim, out = navigated("h1_rectangle", mounting=mounting)
    match = matched(sim, out)
    length = sum(s.length for s in out.steps)
    return (int((match < 0).sum()), len(out.steps) - int((match >= 0).sum()),
            100 * (length / sim.model.true_steps.length.sum() - 1))


def test_twenty_random_mountings_do_as_well_as_the_default():
    """Issue 17, acceptance 6: with 20 random fixed phone mountings on H1, every step is
    found and nothing else, and the distance error is within 0.3 percentage points of the
    default mounting's (docs/pocket.md; two processes, as CI has two cores)."""
    from concurrent.futures import ProcessPoolExecutor

    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(17)
    mountings = [None] + [tuple(np.round(Rotation.random(random_state=rng).as_euler(
        "ZYX", degrees=True)[::-1], 1)) for _ in range(20)]
    with ProcessPoolExecutor(2) as pool:
        (_, _, reference), *others = pool.map(h1_outcome, mountings)
    for mounting, (missed, false, error) in zip(mountings[1:], others, strict=True):
        assert missed == 0 and false == 0, mounting
        assert abs(error - reference) <= 0.3, mounting


# A phone put back in the front pocket another way, as a turn of the phone about its own
# axes (Android: x right, y up, z out of the screen; a rotation vector [deg]) over 1.5 s in
# the middle of H1. The last two are random turns that bench_remount.py once failed: one
# reverses the flexion axis unseen by the turn checks (the skew of the pitch rate finds
# it), the other moves the mean walking pitch by about 40° (the swing lies wholly above
# the level one: not downstairs)
REPOCKETED = {"upside down": (0.0, 0.0, 180.0), "screen facing in": (0.0, 180.0, 0.0),
              "turned sideways": (0.0, 0.0, 90.0), "tilted out": (35.0, 0.0, 0.0),
              "flexion axis reversed": (13.7, 134.2, 24.9),
              "mean pitch moved 40°": (-43.8, 47.7, 23.6)}
REMOUNT_AT_S, REMOUNT_S, FOUND_AGAIN_S = 60.0, 1.5, 10.0


@cache
def repocketed_h1_simulated(turn: tuple[float, float, float]):
    """H1 with the phone turned in the pocket mid-walk, simulated."""
    from scipy.spatial.transform import Rotation

    from pdr_sim.pocket_scenario import mounting_matrix

    _, data = load_pocket_scenario("h1_rectangle")
    after = mounting_matrix(data.get("mounting", "phone_front_pocket")) @ \
        Rotation.from_rotvec(turn, degrees=True).as_matrix()
    with warnings.catch_warnings():      # at ±90° of pitch the roll is set to 0: the
        warnings.simplefilter("ignore")  # angles still give the matrix (asserted)
        rpy = list(Rotation.from_matrix(after).as_euler("ZYX", degrees=True)[::-1])
    np.testing.assert_allclose(mounting_matrix({"rpy_deg": rpy}), after, atol=1e-9)
    data = {**data, "remounts": [{"at_s": REMOUNT_AT_S, "duration_s": REMOUNT_S,
                                  "mounting": {"rpy_deg": rpy}}]}
    return simulate(SimulationConfig(pocket_scenario_from_dict(data, "h1"), data, "xsens_mtw",
                                     {}, 100.0, 0, placement="pocket"))


def repocketed_h1(turn: tuple[float, float, float]):
    """H1 with the phone turned in the pocket mid-walk: the simulation and the steps."""
    sim = repocketed_h1_simulated(turn)
    nav = PocketNavigator(PocketConfig())
    out = nav.process(samples_of(sim))
    return sim, out


@pytest.mark.parametrize("name", sorted(REPOCKETED))
def test_steps_are_found_again_within_10_s_of_a_mid_walk_change_of_mounting(name):
    """Issue 17, acceptance 6: from 10 s after the phone was turned in the pocket, every
    step is found, nothing else, and every step is labelled level walking (H1 is level:
    the activities' level steps start afresh)."""
    sim, out = repocketed_h1(REPOCKETED[name])
    truth = sim.model.true_steps
    steps, match = steps_since(out.steps, truth.end_s, truth.duration,
                               REMOUNT_AT_S + REMOUNT_S + FOUND_AGAIN_S)
    assert (match >= 0).all(), f"missed {(match < 0).sum()}"
    assert len(steps) == len(match)
    assert all(s.activity == Activity.WALKING for s in steps)


def test_without_a_gyroscope_a_phone_found_turned_at_the_last_rest_loses_no_step():
    """The phone turned in the pocket is found at the next rest without a gyroscope: here
    the last, so the axes stay unknown to the end and the detector is given no sample
    after the change (the footfall detector once stopped on that with a ValueError). Every
    step is found, whole and in chunks alike."""
    sim = repocketed_h1_simulated(REPOCKETED["mean pitch moved 40°"])
    samples = samples_of(sim, gyro=False, mag=False)
    navigator = PocketNavigator(PocketConfig())
    whole = navigator.process(samples).steps
    assert int(navigator.mounting.scalars[CHANGES]) == 1
    assert len(whole) == len(sim.model.true_steps.end_s)
    nav = PocketNavigator(PocketConfig())
    rng = np.random.default_rng(0)
    cuts = np.unique(np.r_[0, np.cumsum(rng.integers(1, 400, 200)), len(samples)])
    cuts = cuts[cuts <= len(samples)]
    chunked = [s for i, j in itertools.pairwise(cuts)
               for s in nav.process(samples[i:j]).steps]
    assert [s.t for s in chunked] == [s.t for s in whole]


def test_a_configured_mounting_is_used_as_given():
    config = PocketConfig(mounting=MountingConfig(rpy_deg=(0.0, 0.0, 0.0)))
    sim, out = navigated("sit_stand", mounting="thigh_frame", config=config)
    match = matched(sim, out)
    assert (match >= 0).all() and len(out.steps) == len(match)
    assert np.isfinite(out.pitch).all()


def test_one_sample_at_a_time_equals_the_whole_record():
    sim = simulated("sit_stand")
    samples = samples_of(sim)
    whole = PocketNavigator(PocketConfig()).process(samples).steps
    nav = PocketNavigator(PocketConfig())
    rng = np.random.default_rng(0)
    cuts = np.unique(np.r_[0, np.cumsum(rng.integers(1, 400, 200)), len(samples)])
    cuts = cuts[cuts <= len(samples)]
    pieces = [nav.process(samples[i:j]).steps for i, j in itertools.pairwise(cuts)]
    chunked = [s for piece in pieces for s in piece]
    assert len(chunked) == len(whole)
    for a, b in zip(chunked, whole, strict=True):
        assert a.t == b.t and a.activity == b.activity
        assert np.allclose(a.position, b.position, atol=1e-9, rtol=0)
        assert np.allclose(a.covariance, b.covariance, atol=1e-9, rtol=0)


# --- position filter ---------------------------------------------------------------------
def test_position_filter_step_is_equation_5_1_and_covariance_grows():
    f = PositionFilter(PositionConfig())
    f.step(0.8, 0.0, np.pi / 2, 1e-4, 0.03**2, 0.0, 1.0)
    f.step(0.8, 0.34, np.pi / 2, 2e-4, 0.03**2, 0.02**2, 1.0)
    assert np.allclose(f.position, [0.0, 1.6, 0.34])
    first = f.covariance
    f.step(0.8, 0.0, 0.0, 3e-4, 0.03**2, 0.0, 1.0)
    assert np.trace(f.covariance) > np.trace(first)
    assert np.all(np.linalg.eigvalsh(f.p) >= -1e-15)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.tuples(st.floats(0.3, 2.0), st.floats(-np.pi, np.pi)), min_size=1,
                max_size=40))
def test_position_covariance_stays_symmetric_positive_semidefinite(steps):
    f = PositionFilter(PositionConfig())
    for k, (length, heading) in enumerate(steps):
        f.step(length, 0.0, heading, 1e-4 * (1 + k), 0.03**2, 0.0, 1.1)
        if k % 7 == 3:
            f.correct_position(f.position + 0.1, np.eye(3) * 0.5)
    assert np.allclose(f.p, f.p.T) and np.linalg.eigvalsh(f.p).min() >= -1e-12


def test_corrections_gated_and_refused_when_unusable():
    sim = simulated("sit_stand")
    nav = PocketNavigator(PocketConfig())
    n = 4000
    nav.process(samples_of(sim)[:n])
    yaw = nav.orientation.yaw
    ok, message = nav.apply_correction(Correction(np.radians(1.0), np.radians(2.0) ** 2))
    assert ok, message
    assert nav.orientation.yaw != yaw
    before, p = nav.position.position, nav.position.covariance
    ok, message = nav.apply_correction(Correction(position_m=before + 0.2,
                                                  position_covariance_m2=np.eye(3) * 0.25))
    # the fix moves the position by the Kalman gain of Eq. (6.3), K·(fix − x) with
    # K = P·(P + R)⁻¹ (the level walk's exact height stays)
    assert ok
    np.testing.assert_allclose(nav.position.position - before,
                               p @ np.linalg.solve(p + np.eye(3) * 0.25, np.full(3, 0.2)),
                               atol=1e-9)
    for bad in [Correction(np.nan, 0.1), Correction(0.1, -1.0),
                Correction(gyro_bias_z_radps=1e-4, gyro_bias_z_variance_rad2ps2=-1e-8)]:
        ok, message = nav.apply_correction(bad)
        assert not ok and ("not finite" in message or "negative" in message)
    state = nav.position.position
    ok, message = nav.apply_correction(Correction(position_m=state + 500.0,
                                                  position_covariance_m2=np.eye(3) * 0.01))
    assert not ok and "χ² gate" in message
    assert np.array_equal(nav.position.position, state)
    assert nav.corrections == {"accepted": 2, "refused": 4}


def test_a_correction_is_all_or_nothing_every_part_gated_before_any_is_applied():
    """docs/nodes.md: every part is gated once against the covariance before any part is
    applied. Here the yaw's update would shrink b_z's variance (their correlation −0.8,
    no magnetometer) so that a bias gated after it fails (NIS 10.2 before, 23 after): the
    request is accepted whole. With one part refused, nothing changes and the message
    names the part; an empty request is refused as nothing to apply."""
    import copy

    from scipy.stats import chi2

    from pdr_pocket.compiled_orientation_data import ATT_UP, BIAS_Z
    from pdr_pocket.compiled_orientation_measurements import (
        BIAS_Z_CORRECTION,
        YAW_CORRECTION,
    )
    from pdr_pocket.config import default_config_path, load_pocket_config

    sim = simulated("h1_rectangle")
    nav = PocketNavigator(load_pocket_config(
        default_config_path().with_name("pocket_pdr_no_mag.yaml")))
    n = 12000
    nav.process(samples_of(sim, mag=False)[:n])
    p = nav.orientation.state.covariance
    yaw, yaw_var = 0.01, 0.1 * p[ATT_UP, ATT_UP]
    bias_var = 0.1 * p[BIAS_Z, BIAS_Z]
    bias = 0.97 * np.sqrt(chi2.ppf(0.999, 1) * (p[BIAS_Z, BIAS_Z] + bias_var))
    after_yaw = copy.deepcopy(nav.orientation)
    after_yaw.apply(YAW_CORRECTION, after_yaw.yaw + yaw, yaw_var)
    target = float(nav.orientation.state.bias[2]) + bias
    assert after_yaw.gate(BIAS_Z_CORRECTION, target, bias_var)[0] is not None  # the trap
    refused = copy.deepcopy(nav)
    ok, message = nav.apply_correction(Correction(yaw, yaw_var, bias, bias_var))
    assert ok, message
    assert message.startswith("yaw +0.01 rad (+0.57°, NIS") and "z gyro bias +" in message
    assert nav.orientation.state.bias[2] != refused.orientation.state.bias[2]

    state = copy.deepcopy(refused)
    ok, message = refused.apply_correction(Correction(yaw, yaw_var, 100 * bias, bias_var,
                                                      refused.position.position, np.eye(3)))
    assert not ok
    assert message.startswith("nothing applied: z gyro bias refused by the χ² gate")
    for before, after in ((state.orientation.state.attitude, refused.orientation.state.attitude),
                          (state.orientation.state.covariance,
                           refused.orientation.state.covariance),
                          (state.orientation.state.bias, refused.orientation.state.bias),
                          (state.position.x, refused.position.x),
                          (state.position.p, refused.position.p)):
        np.testing.assert_array_equal(before, after)
    assert (refused.assembly.sum_cos, refused.assembly.sum_sin) == \
        (state.assembly.sum_cos, state.assembly.sum_sin)
    ok, message = refused.apply_correction(Correction())
    assert not ok and message.startswith("nothing to apply")
    assert refused.corrections == {"accepted": 0, "refused": 2}


# --- stride calibration ------------------------------------------------------------------
def test_stride_calibration_recovers_the_line_and_refuses_bad_walks():
    rng = np.random.default_rng(1)
    amp = np.r_[rng.normal(22, 1, 60), rng.normal(40, 1, 60)]
    segment = np.r_[np.zeros(60, int), np.ones(60, int)]
    strides = 0.025 * amp + 0.42
    distances = np.array([strides[:60].sum(), strides[60:].sum()])
    assert fit_offset(amp, strides.sum(), 0.025, "w") == pytest.approx(0.42)
    assert fit_line(amp, segment, distances, "w") == pytest.approx((0.025, 0.42))
    with pytest.raises(InputError, match="too few"):
        fit_offset(amp[:5], 4.0, 0.025, "w")
    with pytest.raises(InputError, match="too uniform"):
        fit_line(np.full(40, 30.0), np.r_[np.zeros(20, int), np.ones(20, int)],
                 np.array([10.0, 10.0]), "w")


def test_walking_label_for_level_steps_at_any_speed():
    _, out = navigated("h2_rectangle_speeds")
    assert all(s.activity == Activity.WALKING for s in out.steps)



# --- corrections over the service, stamped with their step ----------------------------
CORRECTION = (np.radians(5.0), np.radians(2.0) ** 2, np.radians(0.01), np.radians(0.005) ** 2)


def late_correction(delay: int, stamped: bool = True, window_s: float = 30.0,
                    chunk: int = 1) -> tuple[list, object]:
    """sit_stand through the live navigator, ``chunk`` samples at a time (no
    magnetometer), with a yaw, z bias and position correction stamped with its 20th step
    (``stamped`` False: stamp 0, now), called ``delay`` samples after that step; the 15
    steps after it as the navigator finally has them, and the correction's result."""
    from pdr_pocket.streaming import StreamingPocket

    sim = simulated("sit_stand")
    live = StreamingPocket(PocketConfig(), correction_window_s=window_s)
    stamps = (sim.trajectory.t * 1e9).astype(np.int64)
    steps, due, result = [], None, None
    for i in range(0, len(stamps), chunk):
        part = slice(i, i + chunk)
        for out in live.push_imus(stamps[part], sim.imu["linear_acceleration"][part],
                                  sim.imu["angular_velocity"][part]):
            steps += [(out.stamp_of(s.t_confirm), s) for s in out.output.steps]
        if due is None and len(steps) >= 20:
            due, (stamp, step) = i + delay, steps[19]
        if due is not None and result is None and i >= due:
            position = step.position + np.array([0.5, -0.3, 0.0])
            result = live.apply_correction(Correction(
                *CORRECTION, position, np.eye(3).ravel() * 0.5, stamp if stamped else 0))
            assert result.accepted, result.message
            steps = steps[:20] + [(r.stamp_ns, r.step) for r in result.revised]
        if len(steps) >= 35:
            for (_, a), b in zip(steps, live.navigator.steps, strict=False):
                assert a.t == b.t
                np.testing.assert_allclose(a.position, b.position, rtol=0, atol=1e-9)
            return [s for _, s in steps[20:35]], result
    raise AssertionError("sit_stand has fewer than 35 steps")


def test_a_stamped_correction_counts_from_its_step_however_late_it_comes():
    """pocket_pdr's service call comes some samples after the step that found the
    landmark; stamped with that step, the navigator takes it as of right after it, as
    ``pdr-pocket run --drift online`` does, so the steps after it do not depend on the
    delay nor on how the samples came in chunks; the steps it ran again are given back."""
    right_after, _ = late_correction(0, chunk=5)
    for delay, chunk in ((60, 13), (1500, 37)):
        late, result = late_correction(delay, chunk=chunk)
        revised = [r.stamp_ns for r in result.revised]
        assert revised == sorted(revised)
        assert all(r.step.t_confirm >= right_after[0].t_confirm for r in result.revised)
        assert len(revised) >= (8 if delay == 1500 else 0)     # 15 s: 9 steps run again
        for a, b in zip(right_after, late, strict=True):
            assert a.t == b.t
            assert a.heading == pytest.approx(b.heading, abs=1e-9)
            np.testing.assert_allclose(a.position, b.position, atol=1e-9)
    # and the correction did move them: a 0.5 m fix and a 5° turn (no correction: one
    # due after the walk)
    never, result = late_correction(10**9, chunk=37)
    assert result is None
    assert np.linalg.norm(never[-1].position - late[-1].position) > 0.3
    # stamp 0: applied now, to the current state, nothing run again
    _, now = late_correction(0, stamped=False, chunk=37)
    assert now.accepted and now.revised == []


def test_a_stamp_outside_the_window_is_refused_by_name():
    """docs/nodes.md: a stamp older than ``correction_window_s`` of IMU data, or after
    the last sample processed, is refused with a message naming the stamp and the window;
    nothing changes."""
    from pdr_pocket.streaming import StreamingPocket

    sim = simulated("sit_stand")
    live = StreamingPocket(PocketConfig(), correction_window_s=10.0)
    stamps = (sim.trajectory.t * 1e9).astype(np.int64)
    n = 3000                                          # 30 s at 100 Hz
    live.push_imus(stamps[:n], sim.imu["linear_acceleration"][:n],
                   sim.imu["angular_velocity"][:n])
    before = live.navigator.copy_state()
    old = int(stamps[n - 1500])                       # 15 s back
    result = live.apply_correction(Correction(*CORRECTION, stamp_ns=old))
    assert not result.accepted and result.revised == []
    assert f"stamp {old} ns is older than the correction window" in result.message
    assert "correction_window_s 10 s of IMU data" in result.message
    ahead = int(stamps[n]) + 1
    result = live.apply_correction(Correction(*CORRECTION, stamp_ns=ahead))
    assert not result.accepted and f"stamp {ahead} ns is after the last sample" in result.message
    assert live.corrections == {"accepted": 0, "refused": 2}
    assert live.navigator.orientation.yaw == before.orientation.yaw
    within = live.apply_correction(Correction(*CORRECTION, stamp_ns=int(stamps[n - 500])))
    assert within.accepted, within.message


@settings(max_examples=10, deadline=None)
@given(st.lists(st.integers(300, 2900), min_size=1, max_size=3), st.integers(5, 60))
def test_corrections_reaching_back_replay_the_ones_taken_since(instants, chunk):
    """Corrections stamped in any order equal the same corrections applied in time order
    at their instants (a later-stamped one taken first is run again in its place), and
    the live navigator equals the in-process one to rounding."""
    from pdr_pocket.streaming import StreamingPocket

    sim = simulated("sit_stand")
    stamps = (sim.trajectory.t * 1e9).astype(np.int64)
    a, w = sim.imu["linear_acceleration"], sim.imu["angular_velocity"]
    n = 3000
    live = StreamingPocket(PocketConfig())
    for i in range(0, n, chunk):
        live.push_imus(stamps[i:min(i + chunk, n)], a[i:min(i + chunk, n)],
                       w[i:min(i + chunk, n)])
    yaw = Correction(np.radians(1.0), np.radians(3.0) ** 2)
    for k in instants:
        assert live.apply_correction(replace(yaw, stamp_ns=int(stamps[k]))).accepted
    straight = PocketNavigator(PocketConfig())
    t = (stamps - stamps[0]) * 1e-9
    start = 0
    for k in sorted(instants):
        straight.process(Samples(t[start:k + 1], a[start:k + 1], w[start:k + 1]))
        ok, message = straight.apply_correction(yaw)
        assert ok, message
        start = k + 1
    straight.process(Samples(t[start:n], a[start:n], w[start:n]))
    assert live.navigator.orientation.yaw == pytest.approx(straight.orientation.yaw, abs=1e-9)
    assert len(live.navigator.steps) == len(straight.steps)
    for x, y in zip(live.navigator.steps, straight.steps, strict=True):
        np.testing.assert_allclose(x.position, y.position, atol=1e-9)


# --- real recorders, other placements -----------------------------------------------
def with_gaps(sim, count: int = 40, seed: int = 4):
    """The samples a recorder that drops ``count`` packets of 0.11–0.27 s keeps (as the
    real thigh recordings drop them)."""
    rng = np.random.default_rng(seed)
    keep = np.ones(len(sim.trajectory.t), bool)
    for start in rng.integers(500, len(keep) - 100, count):
        keep[start:start + rng.integers(11, 28)] = False
    return keep


@pytest.mark.parametrize("name", ["h1_rectangle", "up_dw"])
def test_packets_dropped_lose_and_invent_no_step(name):
    """40 gaps of 0.11–0.27 s (one every 10 s; the TUG recording has one a second): the
    attitude is propagated over each gap with its uncertainty grown, no step is lost or
    invented, and the stairs are still found: UP/DW 12 of 176 steps labelled wrong, the
    first flight's start after a gap (13 before the flight check, 15 with it when it
    refused the landings the gaps turned into stairs), H1 2 of 294."""
    sim = simulated(name)
    keep = with_gaps(sim)
    out = PocketNavigator(PocketConfig()).process(samples_of(sim)[keep])
    assert len(out.steps) == len(sim.model.true_steps.length)
    match = matched(sim, out)
    assert (match < 0).sum() <= 2, "a maximum inside a gap may move to the next cycle"
    truth = sim.model.true_steps.activity[match >= 0]
    labels = np.array([s.activity for s in out.steps])[match[match >= 0]]
    assert (labels != truth).mean() <= 0.075


def test_a_walk_from_a_chair_finds_its_standing_axis():
    """The first rest is seated (the thigh level, θ taken as 0 there): once walking, the
    mean walking pitch says so and the thigh's long axis is put back (the timed up-and-go
    starts this way). Every step is found and none is on stairs."""
    data = {"name": "from_a_chair", "segments": [
        {"type": "sitting", "duration_s": 8, "pitch_deg": 80},
        {"type": "walk", "steps": 30}, {"type": "standing", "duration_s": 3}]}
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, "from_a_chair"), data,
                                    "xsens_mtw", {}, 100.0, 0, placement="pocket"))
    out = PocketNavigator(PocketConfig()).process(samples_of(sim))
    match = matched(sim, out)
    assert (match >= 0).all() and len(out.steps) == len(match)
    assert all(s.activity == Activity.WALKING for s in out.steps)


@pytest.mark.parametrize("gyroscope", [True, False], ids=["gyroscope", "accelerometer only"])
def test_a_back_pocket_is_named_and_walks_its_distance(gyroscope):
    """On the buttock the phone follows 40 % of the thigh's pitch (pdr_sim's back_pocket):
    the steps are all found, the swing is named a back pocket's (pdr_pocket.placement) and
    the strides come from the cadence: H1's distance within 5 % (issue 40; by the front
    pocket's pitch line it was −39 %). Without a gyroscope the first footfall pair may
    start a cycle late."""
    sim = simulated("h1_rectangle", None, 0, "back_pocket")
    navigator = PocketNavigator(PocketConfig())
    out = navigator.process(samples_of(sim, gyro=gyroscope, mag=False))
    match = matched(sim, out)
    assert (match < 0).sum() <= (0 if gyroscope else 1) and len(out.steps) == len(match)
    assert all(s.activity == Activity.WALKING for s in out.steps)
    error = sum(s.length for s in out.steps) / sim.model.true_steps.length.sum() - 1
    assert abs(error) < 0.05
    summary = navigator.placement.summary()
    assert summary["placement"] == "back pocket" and summary["stride_model"] == "frequency"
    assert summary["cycles"]["back pocket"] == len(out.steps) - PLACEMENT_WINDOW_STEPS + 1


def test_a_walk_faster_than_a_person_walks_is_a_warning():
    """The level steps of H1 are walked at 3.5 km/h (0.97 m/s): no warning. The same
    strides in a quarter of the time (stamps in another unit, say) walk 3.9 m/s: said,
    with the figure."""
    sim = simulated("h1_rectangle")
    navigator = PocketNavigator(PocketConfig())
    navigator.process(samples_of(sim, mag=False))
    assert navigator.speed_warning() is None and navigator.warnings() == []
    navigator.assembly.steps = [replace(s, duration=s.duration / 4) for s in navigator.steps]
    warning = navigator.speed_warning()
    assert warning.startswith("the level steps walk 3.9 m/s") and "(2.5 m/s)" in warning
    assert navigator.warnings() == [warning]


def test_a_phone_in_the_hand_makes_no_step_and_says_why():
    sim, out = navigated("h1_rectangle", seed=0, carried="hand")
    assert out.steps == []
    nav = PocketNavigator(PocketConfig())
    nav.process(samples_of(sim))
    assert nav.no_step_reason().startswith("motion but no thigh gait")


def test_the_population_line_scales_with_height_unless_calibrated():
    _, out = navigated("h1_rectangle")
    tall = PocketConfig(person=PersonConfig(height_m=1.87))
    _, taller = navigated("h1_rectangle", config=tall)
    ratio = sum(s.length for s in taller.steps) / sum(s.length for s in out.steps)
    assert ratio == pytest.approx(1.87 / 1.70, rel=1e-9)
    mine = PocketConfig(person=PersonConfig(height_m=1.87),
                        step_length=StepLengthConfig(calibrated=True))
    _, calibrated = navigated("h1_rectangle", config=mine)
    assert [s.length for s in calibrated.steps] == [s.length for s in out.steps]


def test_live_without_a_gyroscope_equals_the_whole_record():
    """An IMU without gyroscope (REP-145: angular_velocity_covariance[0] = −1, the node
    passes gyro None) in blocks of 1 to 99 samples, as messages arrive together, gives the
    steps of the offline navigator."""
    from pdr_pocket.streaming import StreamingPocket

    sim = simulated("sit_stand")
    whole = PocketNavigator(PocketConfig()).process(samples_of(sim, gyro=False, mag=False)).steps
    live, steps = StreamingPocket(PocketConfig()), []
    stamps = (sim.trajectory.t * 1e9).astype(np.int64)
    ends = np.cumsum(np.random.default_rng(0).integers(1, 100, len(stamps)))
    for block in np.split(np.arange(len(stamps)), ends[ends < len(stamps)]):
        steps += [s for chunk in live.push_imus(stamps[block], sim.imu["linear_acceleration"][
            block], None) for s in chunk.output.steps]
    steps += [s for chunk in live.flush() for s in chunk.output.steps]
    assert len(whole) >= 30 and len(steps) == len(whole)
    np.testing.assert_allclose([s.t for s in steps], [s.t for s in whole], atol=1e-6)
    assert live.navigator.detection()["activities"].startswith("level only")


@pytest.mark.parametrize(("name", "off"), [("h1_rectangle", 1), ("h2_rectangle_speeds", 1),
                                           ("h3_museum", 1), ("up_dw", 1), ("sit_stand", 2)])
def test_footfalls_without_a_gyroscope(name, off):
    """docs/pocket.md: the footfall detector counts 588/588, 627/628, 372/372, 356/356 and
    134/132 (the sit/stand walk's standing up and sitting down shake the force too)."""
    sim = simulated(name)
    navigator = PocketNavigator(PocketConfig())
    out = navigator.process(samples_of(sim, gyro=False, mag=False))
    true = 2 * len(sim.model.true_steps.end_s)
    assert abs(navigator.footfalls - true) <= off
    assert len(out.steps) == navigator.footfalls // 2
    assert navigator.detection()["step_detector"] == "footfalls in the specific force's norm"
