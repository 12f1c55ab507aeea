"""The foot INS's calibration of the pocket's lines (pdr_pocket.line_calibration): the
recursive least squares against batch least squares, its forgetting and P clip, the
pairing by stamps with each refusal, the lag phase for either leg, any interleaving of the
streams, and the saved fit. Synthetic streams only, no simulation."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core.errors import InputError
from pdr_core.vocabulary import Activity
from pdr_pocket.line_calibration import (
    DOWN,
    LEVEL,
    LINES,
    REASONS,
    UP,
    CalibrationSettings,
    FootStride,
    LineFit,
    PocketStep,
    StrideCalibrator,
)
from pdr_pocket.saved_lines import read_fit, saved_fit, write_fit

PERSON = (0.024, 0.36)          # a_H [m/deg], b_H [m]: 6 cm per stride off the population's
PERIOD_S = 1.1
SAME_LEG, OTHER_LEG = 0.14, 0.64   # the footfall's phase after the pitch maximum [cycles]


def batch(x, y, r, theta0, sigma0):
    """argmin (θ − θ₀)ᵀP₀⁻¹(θ − θ₀) + Σ (yᵢ − a·xᵢ − b)²/Rᵢ by lstsq: the prior as two
    pseudo-observations θ = θ₀ of σ₀, each pair a row weighted by 1/√Rᵢ. (With λ < 1 the
    clip acts from the first pair on, in the direction it does not excite: no batch form.)"""
    n = len(x)
    w = 1.0 / np.sqrt(np.asarray(r))
    prior_w = 1.0 / np.asarray(sigma0)
    rows = np.vstack([np.diag(prior_w), np.c_[x, np.ones(n)] * w[:, None]])
    rhs = np.concatenate([prior_w * theta0, np.asarray(y) * w])
    return np.linalg.lstsq(rows, rhs, rcond=None)[0]


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.floats(25.0, 55.0), st.floats(-0.1, 0.1), st.floats(0.01, 0.05)),
                min_size=1, max_size=40))
def test_the_recursion_is_the_batch_least_squares_with_the_prior(pairs):
    x, noise, sigma = map(np.array, zip(*pairs, strict=True))
    y = PERSON[0] * x + PERSON[1] + noise
    theta0, sigma0 = np.array([0.025, 0.42]), np.array([0.0025, 0.07])
    fit = LineFit(*theta0, *sigma0)
    for xi, yi, si in zip(x, y, sigma, strict=True):
        fit.update(xi, yi, si ** 2)
    expected = batch(x, y, sigma ** 2, theta0, sigma0)
    assert fit.theta == pytest.approx(expected, rel=1e-7, abs=1e-9)
    assert fit.pairs == len(x)


def test_forgetting_shortens_the_memory():
    """A person whose stride changes (new shoes): λ = 0.98 (a memory of ~50 pairs) follows
    the new line, λ = 1 stays between the two."""
    rng = np.random.default_rng(1)
    fits = {lam: LineFit(0.025, 0.42, 0.0025, 0.07, lam) for lam in (1.0, 0.98)}
    for b in (0.36, 0.44):
        for x in rng.uniform(30.0, 50.0, 400):
            for fit in fits.values():
                fit.update(x, 0.024 * x + b, 0.03 ** 2)
    assert fits[0.98].offset == pytest.approx(0.44, abs=0.005)
    assert 0.38 < fits[1.0].offset < 0.42


def test_p_never_exceeds_the_prior_and_the_unexcited_slope_falls_back_to_it():
    """At one speed (one Δθ) the data fix a·40 + b alone; with forgetting the other
    direction would grow without bound, and is clipped at P₀."""
    fit = LineFit(0.025, 0.42, 0.0025, 0.07, forgetting=0.95)
    for _ in range(500):
        fit.update(40.0, 0.024 * 40.0 + 0.36, 0.03 ** 2)
        scaled = fit.p / np.outer(fit.sigma0, fit.sigma0)
        assert np.linalg.eigvalsh(scaled).max() <= 1.0 + 1e-12
    assert np.linalg.eigvalsh(fit.p / np.outer(fit.sigma0, fit.sigma0)).max() \
        == pytest.approx(1.0)
    phi = np.array([40.0, 1.0])
    assert fit.theta @ phi == pytest.approx(0.024 * 40.0 + 0.36, abs=1e-6)
    assert math.sqrt(phi @ fit.p @ phi) < 0.01


def test_the_residual_scale_says_when_the_noise_is_wrong():
    rng = np.random.default_rng(2)
    fit = LineFit(0.025, 0.42, 0.0025, 0.07)
    for x in rng.uniform(30.0, 50.0, 2000):
        fit.update(x, 0.025 * x + 0.42 + rng.normal(0.0, 0.06), 0.03 ** 2)   # R 4× too small
    assert fit.residual_scale == pytest.approx(4.0, rel=0.15)
    assert fit.residual_sigma == pytest.approx(0.06, rel=0.1)
    assert np.all(np.diag(fit.covariance) == pytest.approx(4.0 * np.diag(fit.p), rel=0.15))


def walk(n=60, phase=SAME_LEG, start_s=10.0, line=PERSON, activity=Activity.WALKING,
         seed=0, vertical=lambda x: 0.0):
    """A bout of n cycles: pocket steps at the pitch maxima with Δθ 30-50°, and the foot's
    footfalls ``phase`` cycles later, of the person's stride."""
    rng = np.random.default_rng(seed)
    pocket, foot = [], []
    for k in range(n):
        t = start_s + k * PERIOD_S
        x = float(rng.uniform(30.0, 50.0))
        pocket.append(PocketStep(t, PERIOD_S, x, activity, 0.0))
        length = line[0] * x + line[1] if activity == Activity.WALKING else 0.52
        foot.append(FootStride(t + phase * PERIOD_S, length, vertical(x), PERIOD_S, activity,
                               0.0))
    return pocket, foot


def assert_paired_right(cal, decisions, line=PERSON, name=LEVEL, tolerance=0.002):
    """Every pair took its own cycle's stride (the person's line at its Δθ, exactly), and
    the fit puts the mean Δθ's stride within ``tolerance`` of it (the prior pulls the
    slope and offset themselves along the line)."""
    paired = [d for d in decisions if d.line == name]
    assert paired and all(d.reason is None for d in paired)
    x = np.array([d.amplitude_deg for d in paired])
    assert [d.measured for d in paired] == pytest.approx(line[0] * x + line[1], abs=1e-12)
    fit = cal.fits[name]
    assert fit.slope * x.mean() + fit.offset == pytest.approx(
        line[0] * x.mean() + line[1], abs=tolerance)


def run(pocket, foot):
    cal = StrideCalibrator()
    decisions = cal.push_pocket(pocket) + cal.push_foot(foot)
    return cal, decisions


@pytest.mark.parametrize("phase", [SAME_LEG, OTHER_LEG], ids=["same leg", "other leg"])
def test_the_lag_is_learned_for_either_leg_and_the_line_follows(phase):
    cal, decisions = run(*walk(200, phase))
    assert cal.lag.phase == pytest.approx(phase, abs=1e-9)
    # the first step is a bout's, the lag takes the next 10, the last waits for a next one
    assert cal.refused["rest"] == 1 and cal.refused["lag"] == 10
    assert cal.fits[LEVEL].pairs == 200 - 1 - 10 - 1 == len(
        [d for d in decisions if d.reason is None])
    assert cal.pending == 1
    assert_paired_right(cal, decisions)
    assert sum(cal.refused.values()) == 11


def test_a_lag_that_does_not_settle_is_not_learned():
    pocket, foot = walk(40)
    rng = np.random.default_rng(3)
    foot = [replace(f, stamp_s=p.stamp_s + rng.uniform(0.05, 0.95) * PERIOD_S)
            for p, f in zip(pocket, foot, strict=True)]
    cal, _ = run(pocket, foot)
    assert cal.lag.phase is None and cal.fits[LEVEL].pairs == 0


def learned(n=80, **changes):
    """A walk whose steps 40-49 are changed by ``changes(step, stride)``, and what the
    calibrator made of them."""
    pocket, foot = walk(n)
    for k in range(40, 50):
        pocket[k], foot[k] = changes["edit"](pocket[k], foot[k])
    return run(pocket, foot)


@pytest.mark.parametrize(("reason", "edit"), [
    ("turn", lambda p, f: (replace(p, heading_change_deg=45.0), f)),
    ("turn", lambda p, f: (p, replace(f, heading_change_deg=-30.0))),
    ("activity", lambda p, f: (p, replace(f, activity=Activity.UPSTAIRS))),
    ("activity", lambda p, f: (replace(p, activity=Activity.STANDING), f)),
    ("cadence", lambda p, f: (p, replace(f, duration_s=1.4 * PERIOD_S))),
    ("implausible", lambda p, f: (p, replace(f, length_m=0.15))),
    ("implausible", lambda p, f: (p, replace(f, length_m=3.0))),
    ("outlier", lambda p, f: (p, replace(f, length_m=f.length_m + 0.4))),
])
def test_each_refusal_is_counted(reason, edit):
    cal, decisions = learned(edit=edit)
    refused = [d for d in decisions if d.reason == reason]
    assert [d.stamp_s for d in refused] == [10.0 + k * PERIOD_S for k in range(40, 50)]
    assert cal.refused[reason] == 10
    assert all(d.detail for d in refused)
    assert cal.refused["rest"] == 1 and cal.refused["lag"] == 10
    assert_paired_right(cal, decisions)


def test_a_window_without_its_one_footfall_is_refused():
    """Footfalls lost (5 steps with none) or doubled (5 with two: a stride split at a
    short stance)."""
    pocket, foot = walk(80)
    doubled = [replace(f, stamp_s=p.stamp_s + 0.3 * PERIOD_S)
               for p, f in zip(pocket[45:50], foot[45:50], strict=True)]
    foot = sorted(foot[:40] + foot[45:] + doubled, key=lambda f: f.stamp_s)
    cal, decisions = run(pocket, foot)
    refused = [d for d in decisions if d.reason == "count"]
    assert [d.detail for d in refused] == ["0 footfalls"] * 5 + ["2 footfalls"] * 5
    assert cal.refused["count"] == 10
    assert_paired_right(cal, decisions)


def test_a_pause_ends_a_bout_and_both_of_its_ends_are_refused():
    first, foot1 = walk(30)
    second, foot2 = walk(30, start_s=first[-1].stamp_s + 5.0, seed=1)
    second[0] = replace(second[0], duration_s=PERIOD_S)
    decisions = run(first + second, foot1 + foot2)[1]
    rests = [d.detail for d in decisions if d.reason == "rest"]
    assert rests == ["a bout's first step", "a bout's last step", "a bout's first step"]


def test_stairs_pairs_feed_their_lines_with_the_grade_taken_off():
    """A foot INS whose height lifts by 1 % of every stride: the level strides show the
    grade, and the risers come out without it."""
    lift = 0.01
    up_line, down_line = (0.81, -8.9), (2.1, -20.0)          # cm/deg, cm
    level, level_foot = walk(60)
    level_foot = [replace(f, vertical_m=lift * f.length_m) for f in level_foot]
    ups, up_foot = walk(40, start_s=level[-1].stamp_s + PERIOD_S, activity=Activity.UPSTAIRS,
                        vertical=lambda x: (up_line[0] * x + up_line[1]) / 100.0 + lift * 0.52)
    downs, down_foot = walk(40, start_s=ups[-1].stamp_s + PERIOD_S,
                            activity=Activity.DOWNSTAIRS, seed=1,
                            vertical=lambda x: -(down_line[0] * (x - 10) + down_line[1]) / 100.0
                            + lift * 0.52)
    downs = [replace(p, amplitude_deg=p.amplitude_deg - 10) for p in downs]
    cal, decisions = run(level + ups + downs, level_foot + up_foot + down_foot)
    assert cal.grade == pytest.approx(lift)
    assert cal.fits[UP].pairs == 40 and cal.fits[DOWN].pairs == 39     # the transition: activity
    assert_paired_right(cal, decisions, up_line, UP, tolerance=0.2)
    assert_paired_right(cal, decisions, down_line, DOWN, tolerance=0.2)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(1, 12), min_size=1, max_size=40), st.integers(0, 2 ** 16),
       st.sampled_from([SAME_LEG, OTHER_LEG]))
def test_chunked_in_any_interleaving_is_one_batch(chunks, seed, phase):
    pocket, foot = walk(70, phase, seed=seed)
    pocket[30] = replace(pocket[30], heading_change_deg=40.0)
    whole, whole_decisions = run(pocket, foot)
    cal = StrideCalibrator()
    decisions, streams, i = [], {"pocket": list(pocket), "foot": list(foot)}, 0
    while streams["pocket"] or streams["foot"]:
        name = ("pocket", "foot")[i % 2] if all(streams.values()) else \
            next(k for k, v in streams.items() if v)
        size = chunks[i % len(chunks)]
        part, streams[name] = streams[name][:size], streams[name][size:]
        decisions += (cal.push_pocket if name == "pocket" else cal.push_foot)(part)
        i += 1
    assert decisions == whole_decisions
    assert cal.refused == whole.refused
    for name in LINES:
        assert cal.fits[name].theta.tolist() == whole.fits[name].theta.tolist()
        assert cal.fits[name].p.tolist() == whole.fits[name].p.tolist()


def test_streams_out_of_order_are_refused():
    cal = StrideCalibrator()
    pocket, foot = walk(3)
    cal.push_foot(foot[1:])
    with pytest.raises(ValueError, match="foot strides must come in increasing stamp order"):
        cal.push_foot(foot[:1])
    with pytest.raises(ValueError, match="pocket steps"):
        cal.push_pocket([pocket[1], pocket[0]])


def test_the_saved_fit_round_trips(tmp_path):
    cal, _ = run(*walk(120))
    saved = saved_fit(cal, {"foot": "out/walk1_ekf", "pocket": "out/walk1_pocket"})
    assert saved.lines[UP].fit is None and saved.lines[LEVEL].fit.pairs == 108
    path = write_fit(tmp_path / "fit.yaml", saved)
    assert path.read_text().startswith("# The person's lines")
    assert read_fit(path) == saved
    assert set(saved.refused) == set(REASONS)
    unwalked = saved_fit(StrideCalibrator())
    assert read_fit(write_fit(tmp_path / "prior.yaml", unwalked)) == unwalked
    assert "calibrated: false" in (tmp_path / "prior.yaml").read_text()


@pytest.mark.parametrize(("text", "problem"), [
    ("step_length: [1, 2]\nstairs: {}\nfit: {}\n", "step_length: expected a mapping"),
    ("{", "invalid YAML"),
    ("stairs: {}\nfit: {}\n", "step_length: required"),
    ("KEEP\nfit:\n  level: {pairs: 0, covariance: [[1, 0], [0, 1]], residual_sigma_m: 0.03}"
     "\n  up: null\n  down: null\n  forgetting: 0.999\n  refused: {}\n",
     "fit.level.pairs: must be >= 1"),
    ("KEEP\nfit:\n  level: {pairs: 3, covariance: [[1, 2], [2, 1]], residual_sigma_m: 0.03}"
     "\n  up: null\n  down: null\n  forgetting: 0.999\n  refused: {}\n",
     "fit.level.covariance: not a covariance"),
    ("KEEP\nfit:\n  level: {pairs: 3, covariance: [[1, 0], [0, 1]], residual_sigma_m: 0.03}"
     "\n  up: null\n  down: null\n  forgetting: 0.999\n  refused: {tired: 3}\n",
     "fit.refused.tired: unknown reason"),
    ("KEEP\nfit:\n  level: null\n  up: null\n  down: null\n  forgetting: 0.999\n"
     "  refused: {}\n", "step_length.calibrated: true exactly when fit.level is given"),
    ("KEEP\nfit:\n  level: null\n  up: null\n  forgetting: 0.999\n  refused: {}\n",
     "fit.down: required"),
])
def test_a_malformed_fit_is_refused_naming_the_file(tmp_path, text, problem):
    keep = ("step_length: {a_h_m_per_deg: 0.025, b_h_m: 0.42, calibrated: true}\n"
            "stairs: {a_u_cm_per_deg: 0.8, b_u_cm: -8.4, a_d_cm_per_deg: 2.0, b_d_cm: -19.2}")
    path = tmp_path / "fit.yaml"
    path.write_text(text.replace("KEEP", keep))
    with pytest.raises(InputError, match=problem) as refused:
        read_fit(path)
    assert str(path) in str(refused.value)
    with pytest.raises(InputError, match="cannot read"):
        read_fit(tmp_path / "missing.yaml")


@pytest.mark.parametrize(("change", "problem"), [
    ({"forgetting": 0.0}, "forgetting must be within"),
    ({"forgetting": 1.01}, "forgetting must be within"),
    ({"cadence_ratio_min": 1.2}, "cadence_ratio_max must be above"),
])
def test_settings_out_of_range_are_refused(change, problem):
    with pytest.raises(ValueError, match=problem):
        CalibrationSettings(**change)
