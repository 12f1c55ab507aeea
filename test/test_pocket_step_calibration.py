"""``pdr-pocket calibrate-step --foot`` and ``pdr-pocket run --step-calibration`` (issue 57,
the offline mode): synthetic ``pdr/foot/step`` and ``pdr/pocket/step`` bags give the saved
fit of ``line_calibration.calibrated`` on the same messages, each wrong input is one line
naming it with exit status 2, and a saved level line 5 cm above the configured one lengthens
bags/pocket_walk by 5 cm a level stride while the stairs lines not walked are kept."""
from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.io.bag import BagReader, BagWriter, write_batches
from pdr_core.io.batch import MessageBatch
from pdr_core.io.msgtypes import STEP
from pdr_core.vocabulary import Activity
from pdr_pocket.config import PocketConfig, load_pocket_config
from pdr_pocket.line_calibration import (
    DOWN,
    LEVEL,
    UP,
    CalibrationSettings,
    StrideCalibrator,
    calibrated,
)
from pdr_pocket.saved_lines import FitStats, applied, read_fit, saved_fit, write_fit
from wstest import ROOT, cli

POCKET_WALK = ROOT / "bags" / "pocket_walk"
PERSON = (0.024, 0.36)          # a_H [m/deg], b_H [m]
PERIOD_S, LAG = 1.1, 0.14       # a gait cycle [s]; the footfall after the pitch maximum [cycles]
START_NS = 1_700_000_000_000_000_000


def step_batch(stamp_s, length_m, amplitude_rad, duration_s) -> MessageBatch:
    """pdr_msgs/Step messages, level walking straight east."""
    n = len(stamp_s)
    zeros = np.zeros(n)
    return MessageBatch(STEP, START_NS + np.round(np.asarray(stamp_s) * 1e9), "map", {
        "index": np.arange(n, dtype=np.uint32), "length": np.asarray(length_m, float),
        "vertical_displacement": zeros, "heading": zeros, "pitch_max": zeros,
        "pitch_min": zeros, "pitch_amplitude": np.asarray(amplitude_rad, float),
        "duration": np.full(n, duration_s), "activity": np.full(n, Activity.WALKING, np.uint8),
        "ride": np.zeros(n, np.uint8), "ride_height": zeros})


def walk(n=80, seed=0) -> dict[str, MessageBatch]:
    """A bout of n cycles: the pocket's steps at the pitch maxima (Δθ 30-50°) and the
    foot's strides of the person's line, LAG cycles later."""
    x = np.random.default_rng(seed).uniform(30.0, 50.0, n)
    t = 10.0 + PERIOD_S * np.arange(n)
    return {topics.POCKET_STEP: step_batch(t, 0.7 * PERSON[1] * np.ones(n), np.radians(x),
                                           PERIOD_S),
            topics.FOOT_STEP: step_batch(t + LAG * PERIOD_S, PERSON[0] * x + PERSON[1],
                                         np.zeros(n), PERIOD_S)}


@pytest.fixture
def bags(tmp_path):
    """The walk as the foot's and the pocket's bags, both in one, and the foot's an hour
    later (another walk)."""
    batches = walk()
    write_batches(tmp_path / "foot", {topics.FOOT_STEP: batches[topics.FOOT_STEP]})
    write_batches(tmp_path / "pocket", {topics.POCKET_STEP: batches[topics.POCKET_STEP]})
    write_batches(tmp_path / "both", batches)
    later = batches[topics.FOOT_STEP]
    write_batches(tmp_path / "later", {topics.FOOT_STEP: replace(
        later, stamp_ns=later.stamp_ns + 3600 * 10**9)})
    return tmp_path


def test_the_saved_fit_is_the_offline_feed_of_the_same_messages(bags):
    folder = bags
    out = folder / "fit.yaml"
    result = cli("pdr-pocket", "calibrate-step", "--foot", folder / "foot", "--pocket",
                 folder / "pocket", "--out", out)
    assert result.returncode == 0, result.stderr
    pocket = BagReader(folder / "pocket").read(topics.POCKET_STEP)
    foot = BagReader(folder / "foot").read(topics.FOOT_STEP)
    expected = saved_fit(calibrated(pocket, foot))
    assert expected.lines[LEVEL].fit.pairs > 40
    saved = read_fit(out)
    assert saved.lines == expected.lines and saved.refused == expected.refused
    assert saved.sources == {"foot": str(folder / "foot"), "pocket": str(folder / "pocket")}
    level = saved.lines[LEVEL]
    assert level.slope * 40.0 + level.offset == pytest.approx(PERSON[0] * 40.0 + PERSON[1],
                                                              abs=0.003)
    sigma = np.sqrt(np.diag(level.fit.covariance))
    assert f"level: {level.fit.pairs} pairs  a {level.slope:.5g} ± {sigma[0]:.2g} m/deg" \
        in result.stdout
    assert "up: no pair, the configured line kept" in result.stdout
    assert f"refused: lag {saved.refused['lag']}, rest 1; undecided at the end: 1" \
        in result.stdout
    # one bag with both topics, as --foot alone or given twice: the same fit
    for pocket_args in ([], ["--pocket", folder / "both"]):
        again = cli("pdr-pocket", "calibrate-step", "--foot", folder / "both", *pocket_args,
                    "--out", folder / "again.yaml", "--forgetting", "1")
        assert again.returncode == 0, again.stderr
        one = read_fit(folder / "again.yaml")
        assert one.forgetting == 1.0
        assert one.lines[LEVEL].fit.pairs == level.fit.pairs
    # strides of another walk: nothing paired, said on stderr, the configured lines saved
    other = cli("pdr-pocket", "calibrate-step", "--foot", folder / "later", "--pocket",
                folder / "pocket", "--out", folder / "none.yaml")
    assert other.returncode == 0 and "warning" in other.stderr and "no step paired" in \
        other.stderr
    assert read_fit(folder / "none.yaml").lines == saved_fit(StrideCalibrator()).lines


@pytest.mark.parametrize(("args", "problem"), [
    (["--foot", "{pocket}", "--pocket", "{pocket}"], "{pocket}: no topic /pdr/foot/step "
                                                     "(the bag has: /pdr/pocket/step)"),
    (["--foot", "{foot}", "--pocket", "{foot}"], "{foot}: no topic /pdr/pocket/step"),
    (["--foot", "{foot}", "--pocket", "{empty}"], "{empty}: /pdr/pocket/step has no messages"),
    (["--foot", "{foot}", "--pocket", "{folder}/nowhere"], "{folder}/nowhere: no such bag"),
    (["--foot", "{foot}", "--pocket", "{folder}/fit.txt"], "{folder}/fit.txt: a CSV log, not a"),
    (["{pocket}", "--distance-m", "30", "--foot", "{foot}"], "--foot: one way at a time"),
    (["--pocket", "{pocket}"], "give walks of known length (BAG... --distance-m D) or"),
    (["{pocket}", "--pocket", "{pocket}"], "--pocket: goes with --foot"),
    (["{pocket}"], "--distance-m: the length of each walk is needed"),
    (["--foot", "{both}", "--forgetting", "0"], "--forgetting: forgetting must be within"),
])
def test_each_wrong_input_is_one_line_naming_it(bags, args, problem):
    folder = bags
    with BagWriter(folder / "empty") as empty:
        empty.add_topic(topics.POCKET_STEP, STEP)
    (folder / "fit.txt").write_text("t,x\n1,2\n")
    names = {name: folder / name for name in ("foot", "pocket", "both", "empty")}
    result = cli("pdr-pocket", "calibrate-step", *(a.format(folder=folder, **names)
                                                   for a in args), "--out", folder / "x.yaml")
    assert result.returncode == 2, result.stderr
    assert problem.format(folder=folder, **names) in result.stderr
    assert len(result.stderr.splitlines()) == 1 and not (folder / "x.yaml").exists()


def test_the_persons_height_bounds_the_strides_as_the_node_does(bags):
    """The configuration's person.height_m bounds the foot strides taken, as it does in the
    node stride_calibrator (its settings); --height-m overrides it."""
    config_file = bags / "short.yaml"
    config_file.write_text("person: {height_m: 1.2}\n")
    pocket = BagReader(bags / "pocket").read(topics.POCKET_STEP)
    foot = BagReader(bags / "foot").read(topics.FOOT_STEP)
    config = load_pocket_config(config_file)
    for height_args, height_m in (([], 1.2), (["--height-m", "1.9"], 1.9)):
        done = cli("pdr-pocket", "calibrate-step", "--foot", bags / "foot", "--pocket",
                   bags / "pocket", "--config", config_file, *height_args, "--out",
                   bags / "fit.yaml")
        assert done.returncode == 0, done.stderr
        expected = saved_fit(calibrated(pocket, foot, StrideCalibrator(
            config.step_length, config.stairs, CalibrationSettings(height_m=height_m))))
        saved = read_fit(bags / "fit.yaml")
        assert saved.lines == expected.lines and saved.refused == expected.refused
        assert (saved.refused["implausible"] > 0) == (height_m == 1.2)


def fit_of(config: PocketConfig, level_offset_m: float):
    """A saved fit of the level line ``config``'s shifted by ``level_offset_m``, the
    stairs not walked."""
    fit = saved_fit(StrideCalibrator(config.step_length, config.stairs))
    stats = FitStats(300, ((1e-8, 0.0), (0.0, 1e-5)), 0.03)
    level = replace(fit.lines[LEVEL], offset=fit.lines[LEVEL].offset + level_offset_m,
                    fit=stats)
    return replace(fit, lines={**fit.lines, LEVEL: level})


def test_a_saved_fit_replaces_the_walked_lines_and_keeps_the_others(tmp_path):
    config = load_pocket_config()
    fit = fit_of(config, 0.05)
    person = applied(config, fit)
    assert person.step_length == replace(config.step_length, b_h_m=config.step_length.b_h_m
                                         + 0.05, calibrated=True)
    assert person.stairs == config.stairs
    up = replace(fit.lines[UP], slope=1.1, offset=-12.0, fit=fit.lines[LEVEL].fit)
    stairs = applied(config, replace(fit, lines={**fit.lines, UP: up})).stairs
    assert (stairs.a_u_cm_per_deg, stairs.b_u_cm) == (1.1, -12.0)
    assert (stairs.a_d_cm_per_deg, stairs.b_d_cm) == (config.stairs.a_d_cm_per_deg,
                                                      config.stairs.b_d_cm)
    down = replace(fit.lines[DOWN], slope=-0.5, fit=fit.lines[LEVEL].fit)
    with pytest.raises(InputError, match=r"fit\.yaml: its down line does not fit"):
        applied(config, replace(fit, lines={**fit.lines, DOWN: down}), tmp_path / "fit.yaml")
    # the configuration's step_calibration, relative to its file
    (tmp_path / "person.yaml").write_text("step_calibration: lines/fit.yaml\n")
    assert load_pocket_config(tmp_path / "person.yaml").step_calibration == \
        str(tmp_path / "lines" / "fit.yaml")


def test_run_with_a_saved_fit_walks_the_persons_strides(tmp_path):
    config = load_pocket_config()
    write_fit(tmp_path / "fit.yaml", fit_of(config, 0.05))
    reports = {}
    for name, extra in (("population", []), ("person", ["--step-calibration",
                                                        tmp_path / "fit.yaml"])):
        result = cli("pdr-pocket", "run", POCKET_WALK, "--out", tmp_path / name, *extra)
        assert result.returncode == 0, result.stderr
        reports[name] = json.loads((tmp_path / name / "report.json").read_text())
    population, person = reports["population"], reports["person"]
    assert "step_calibration" not in population
    assert person["step_calibration"] == {"file": str(tmp_path / "fit.yaml"), "lines": [LEVEL]}
    assert person["step_length"]["calibrated"] and not population["step_length"]["calibrated"]
    level_steps = population["activities"]["walking"]
    assert person["activities"] == population["activities"] and level_steps > 100
    assert person["step_distance_m"] - population["step_distance_m"] == pytest.approx(
        0.05 * level_steps, rel=0.02)
    assert person["height_gained_m"] == population["height_gained_m"]   # the stairs kept
