"""The thesis' orientation filter (Muñoz Díaz 2016, chapter 3; ``filter: thesis``): its
rotations, each update and detector, the covariance through any mix of updates,
corrections; the live path of the default filter; the shape of both filters' kernels
(the default, ``filter: ekf``, has its own tests in test_attitude.py)."""
from __future__ import annotations

import ast
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from pdr_core.maths.small_matrix import rodrigues
from pdr_pocket import compiled_attitude, compiled_gait_window
from pdr_pocket import compiled_orientation as k
from pdr_pocket import compiled_orientation_measurements as km
from pdr_pocket.config import PocketConfig
from pdr_pocket.orientation import OrientationFilter, saturation_flags
from pdr_pocket.orientation_config import OrientationConfig, Updates
from pdr_pocket.streaming import StreamingPocket
from pdr_sim.pocket_scenario import pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

CONFIG = Path(__file__).resolve().parents[1] / "config" / "pocket_pdr.yaml"
KERNEL = Path(k.__file__)
KERNELS = (KERNEL, Path(compiled_attitude.__file__), Path(compiled_gait_window.__file__))
NONE = Updates(False, False, False, False, False, False, False)
THESIS = OrientationConfig(filter="thesis", imu_profile="consumer_phone")   # as shipped before


def walk(imu="xsens_mtw", seconds_standing=10, distance_m=60, field="munich", seed=2,
         mounting="thigh_frame", **environment):
    data = {"seed": seed, "mounting": mounting,
            "environment": {"magnetic_field": {"preset": field}, **environment},
            "segments": [{"type": "standing", "duration_s": seconds_standing},
                         {"type": "walk", "distance_m": distance_m, "speed_kmh": 3.5},
                         {"type": "turn", "angle_deg": 90, "steps": 2},
                         {"type": "walk", "distance_m": distance_m / 2},
                         {"type": "standing", "duration_s": seconds_standing}]}
    return simulate(SimulationConfig(pocket_scenario_from_dict(data, "walk"), data, imu, {},
                                     100.0, seed, placement="pocket"))


def run(sim, config):
    return OrientationFilter(config).run(sim.trajectory.t, sim.imu["angular_velocity"],
                                         sim.imu["linear_acceleration"],
                                         sim.mag["magnetic_field"])


def errors_deg(sim, est):
    return np.degrees(np.angle(np.exp(1j * (est.euler - sim.trajectory.euler))))


# --- rotations ---------------------------------------------------------------------------
@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3))
def test_rotation_log_inverts_rodrigues_and_matches_scipy(v):
    v = np.array(v)
    a = np.empty((3, 3))
    rodrigues(*v, a)
    back = np.empty(3)
    k.rotation_log(a, back)
    np.testing.assert_allclose(back, Rotation.from_matrix(a).as_rotvec(), atol=1e-7)


def test_euler_angles_are_finite_through_pitch_90():
    out = np.empty(3)
    for pitch in np.radians([89.999, 90.0, -90.0]):
        k.euler_of(Rotation.from_euler("ZYX", [0.3, pitch, 0.2]).as_matrix(), out)
        assert np.isfinite(out).all() and abs(abs(out[1]) - np.pi / 2) < 1e-3


# --- prediction and updates, one at a time ----------------------------------------------
def test_prediction_alone_follows_an_ideal_gyroscope():
    """No updates, no errors: the attitude is the simulator's to integration accuracy."""
    sim = walk("ideal")
    est = run(sim, replace(THESIS, updates=NONE, initial_yaw_deg=0.0))
    assert np.abs(errors_deg(sim, est)).max() < 0.05


@pytest.mark.parametrize(("updates", "axes"), [
    (Updates(True, False, False, False, False, False, False), (0, 1)),   # absolute gravity
    (Updates(False, True, False, False, False, False, False), (0, 1)),   # differential gravity
    (Updates(False, False, False, False, False, False, True), (0, 1)),   # mean gravity
    (Updates(False, False, False, True, False, False, False), (0, 1, 2)),   # diff. magnetic
    (Updates(False, False, True, False, False, False, False), (0, 1, 2)),   # abs. magnetic
    (Updates(False, False, False, False, False, True, False), (0, 1, 2)),   # ZARU
])
def test_each_update_reduces_the_bias_error_on_the_axes_it_observes(updates, axes):
    """Table 3.2 biases (−0.1, 0.1, −0.1 °/s): each update alone pulls the estimate of the
    biases it can see toward the truth. The measurement noise is set to this profile's
    (no accelerometer error, 0.015 µT magnetometer noise per sample)."""
    sim = walk("thesis_table_3_2", seconds_standing=20, distance_m=120)
    est = run(sim, replace(THESIS, updates=updates, differential_gravity_sigma_mps2=0.002,
                                     magnetic_sigma_ut=0.03))
    err = np.abs(np.degrees(est.bias[-1] - sim.gyro_bias))
    assert (err[list(axes)] < 0.5 * 0.1).all(), err


def test_compass_update_fixes_the_yaw():
    """A yaw started 30° wrong: within 3° at the end with the compass update; without
    it, still more than 15° wrong (the gravity update's pull on a wrong yaw takes it to
    17-30° along the walk; from 20°, to 7°, so that start could not tell the two apart)."""
    sim = walk("xsens_mtw")
    wrong = replace(THESIS, updates=replace(NONE, absolute_gravity=True),
                              initial_yaw_deg=30.0, initial_yaw_sigma_deg=35.0,
                              imu_profile="xsens_mtw")
    without = np.abs(errors_deg(sim, run(sim, wrong))[-1, 2])
    compass = replace(wrong, updates=replace(wrong.updates, compass=True))
    assert without > 15 and np.abs(errors_deg(sim, run(sim, compass))[-1, 2]) < 3


def test_absolute_gravity_keeps_roll_and_pitch():
    sim = walk("xsens_mtw")
    free = run(sim, replace(THESIS, updates=NONE))
    gravity = run(sim, replace(THESIS, updates=replace(NONE, absolute_gravity=True,
                                                         mean_gravity=True)))
    assert np.sqrt((errors_deg(sim, gravity)[:, :2] ** 2).mean()) < 0.5 * np.sqrt(
        (errors_deg(sim, free)[:, :2] ** 2).mean())


def test_earth_rate_compensation_at_rest():
    """A still sensor at 48° N sees the Earth's rotation: compensated, its yaw stays."""
    data = {"seed": 1, "mounting": "thigh_frame",
            "environment": {"latitude_deg": 48.0},
            "segments": [{"type": "standing", "duration_s": 600}]}
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, "rest"), data, "ideal", {},
                                    100.0, 1, placement="pocket"))
    for latitude, small in ((48.0, True), (None, False)):
        est = run(sim, replace(THESIS, updates=NONE, latitude_deg=latitude,
                                         initial_yaw_deg=0.0))
        drift = abs(np.degrees(est.euler[-1, 2]))
        assert (drift < 0.01) if small else (drift > 1.0), drift


# --- detectors ----------------------------------------------------------------------------
def test_detectors_find_rest_and_a_steady_field_and_not_a_perturbed_one():
    sim = walk("xsens_mtw", field="munich")
    est = run(sim, THESIS)
    t = sim.trajectory.t
    rest = (t > 1) & (t < 9)
    assert est.detected[rest, k.ZERO_ACC].all() and est.detected[rest, k.ZERO_RATE].all()
    assert not est.detected[(t > 15) & (t < 30), k.ZERO_RATE].any()
    assert est.detected[:, k.MAG_STEADY].mean() > 0.9
    iron = walk("xsens_mtw", field="equator",
                magnetic_field={"preset": "equator",
                                "cylinders": [{"east_m": 20.0, "north_m": 0.8, "radius_m": 0.3}]})
    perturbed = run(iron, THESIS)
    near = np.linalg.norm(iron.trajectory.position[:, :2] - [20.0, 0.8], axis=1) < 1.0
    assert not perturbed.detected[near, k.MAG_STEADY].any()


def test_saturation_flags_limit_and_flat_tops():
    gyro = np.array([[1.0, 0, 0], [4.36, 0, 0], [4.36, 0, 0], [-5.0, 0, 0], [1.0, 2.5, 0]])
    assert saturation_flags(gyro, None).tolist() == [False, False, True, False, False]
    assert saturation_flags(gyro, np.radians(250)).tolist() == [False, True, True, True, False]


# --- covariance, property test -----------------------------------------------------------
@settings(max_examples=60, deadline=None)
@given(st.lists(st.booleans(), min_size=7, max_size=7), st.integers(0, 2**31 - 1),
       st.floats(0.01, 5.0))
def test_covariance_stays_symmetric_positive_definite(flags, seed, scale):
    """Any mix of updates on random data (scaled) leaves P symmetric positive definite."""
    rng = np.random.default_rng(seed)
    n = 400
    t = np.arange(n) * 0.01
    gyro = rng.normal(0, scale, (n, 3))
    accel = np.array([0, 0, 9.81]) + rng.normal(0, scale, (n, 3))
    mag = 48e-6 * np.array([0, 0.44, -0.9]) + rng.normal(0, 1e-7 * scale, (n, 3))
    est = OrientationFilter(replace(THESIS, updates=Updates(*flags))).run(t, gyro, accel, mag)
    p = est.covariance
    np.testing.assert_allclose(p, np.transpose(p, (0, 2, 1)), atol=1e-15)
    assert (np.linalg.eigvalsh(p) > 0).all()
    assert np.isfinite(est.attitude).all() and np.isfinite(est.bias).all()


# --- external corrections (Eq. (6.2)) ------------------------------------------------------
def test_corrections_are_kalman_updates_gated_and_refused_when_unusable():
    sim = walk("xsens_mtw")
    f = OrientationFilter(replace(THESIS, updates=replace(NONE, absolute_gravity=True)))
    f.run(sim.trajectory.t, sim.imu["angular_velocity"], sim.imu["linear_acceleration"])
    yaw = float(np.arctan2(f.state.attitude[1, 0], f.state.attitude[0, 0]))
    sigma_before = np.sqrt(f.state.covariance[2, 2])
    ok, message = f.correct_yaw(yaw + np.radians(2.0), np.radians(1.0) ** 2)
    after = float(np.arctan2(f.state.attitude[1, 0], f.state.attitude[0, 0]))
    assert ok, message
    assert 0 < np.degrees(after - yaw) < 2.0            # pulled toward, not overwritten
    assert np.sqrt(f.state.covariance[2, 2]) < sigma_before
    ok, message = f.correct_yaw(yaw + np.pi / 2, np.radians(0.5) ** 2)
    assert not ok and "χ² gate" in message
    for bad in (np.nan, -1.0, 0.0):
        ok, message = f.correct_bias_z(0.0, bad)
        assert not ok and "not usable" in message
    ok, _ = f.correct_bias_z(float(f.state.bias[2]) + 1e-4, 1e-8)
    assert ok and f.corrections == {"accepted": 2, "refused": 4}


# --- configuration and the live path -----------------------------------------------------
@pytest.mark.parametrize("mag_lag", [0, -3, 40])
def test_streaming_equals_the_whole_record(mag_lag):
    """The live path, one message at a time, gives the bulk run's estimates: with the
    magnetometer reading sent after the IMU sample of the same stamp (as bag_play sends
    them), before it, or 40 samples (0.4 s) late, as separate topics can deliver them."""
    sim = walk("consumer_phone", distance_m=20)
    stamps = sim.imu.stamp_ns
    bulk = OrientationFilter(OrientationConfig()).run(
        (stamps - stamps[0]) * 1e-9, sim.imu["angular_velocity"],
        sim.imu["linear_acceleration"], sim.mag["magnetic_field"])
    events = sorted([(i, 0, i) for i in range(len(stamps))] +
                    [(i + mag_lag, 1, i) for i in range(len(stamps))])
    live = StreamingPocket(PocketConfig())
    got = []
    for _, is_mag, i in events:
        if is_mag:
            got += live.push_mag(int(stamps[i]), sim.mag["magnetic_field"][i])
        else:
            got += live.push_imu(int(stamps[i]), sim.imu["linear_acceleration"][i],
                                 sim.imu["angular_velocity"][i])
    got += live.flush()
    assert np.concatenate([p.stamp_ns for p in got]).tolist() == stamps.tolist()
    np.testing.assert_allclose(np.concatenate([p.output.attitude.attitude for p in got]),
                               bulk.attitude, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.concatenate([p.output.attitude.bias for p in got]), bulk.bias,
                               rtol=0, atol=1e-15)


def processed(chunks) -> int:
    return sum(len(p.stamp_ns) for p in chunks)


def test_streaming_refuses_g_and_survives_a_silent_magnetometer():
    live = StreamingPocket(PocketConfig())
    for i in range(60):
        live.push_imu(i * 10_000_000, (0.0, 0.0, 1.0), (0.0, 0.0, 0.0))
    assert live.failed is not None and "in g" in live.failed
    live.reset()
    out = []
    for i in range(300):
        out += live.push_imu(i * 10_000_000, (0.0, 0.0, 9.81), (0.01, 0.0, 0.0))
        if i < 100:
            out += live.push_mag(i * 10_000_000, (0.0, 2e-5, -4e-5))
        if i == 199:
            assert processed(out) == 100 and not live.mag_stale   # waiting for a late reading
    assert processed(out) == 300 and live.mag_stale          # quiet: no more waiting
    live.push_imu(5, (0.0, 0.0, 9.81), (0.0, 0.0, 0.0))
    live.push_imu(300 * 10_000_000, (np.nan, 0.0, 9.81), (0.0, 0.0, 0.0))
    assert live.counts["stamp_not_increasing"] == 1 and live.counts["non_finite"] == 1


# --- the kernels' shape (issue 31, acceptance 1) ---------------------------------------------
def _is_njit(decorator: ast.expr) -> bool:
    target = decorator.func if isinstance(decorator, ast.Call) else decorator
    return getattr(target, "id", getattr(target, "attr", None)) == "njit"


@pytest.mark.parametrize("module", KERNELS, ids=lambda path: path.stem)
def test_no_compiled_kernel_takes_more_than_8_arguments(module):
    tree = ast.parse(module.read_text())
    kernels = {f.name: len(f.args.args) for f in ast.walk(tree)
               if isinstance(f, ast.FunctionDef) and any(map(_is_njit, f.decorator_list))}
    assert kernels
    assert {name: n for name, n in kernels.items() if n > 8} == {}


# arrays indexed by the state's rows (ATT_EAST ... BIAS_Z), in the kernel and its wrapper
STATE_INDEXED = {"covariance", "p", "prop", "deviations", "dx", "gain", "pxz", "centre"}


def _bare_rows(source: str) -> list[str]:
    """Subscripts of the state-indexed arrays with an integer literal in them."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.Subscript):
            continue
        value = node.value
        name = value.attr if isinstance(value, ast.Attribute) else getattr(value, "id", None)
        if name in STATE_INDEXED and any(
                isinstance(c, ast.Constant) and isinstance(c.value, int)
                for c in ast.walk(node.slice)):
            found.append(f"line {node.lineno}: {ast.unparse(node)}")
    return found


def test_state_rows_are_named():
    """No bare row numbers for the state: ``p[ATT_UP, ATT_UP]``, never ``p[2, 2]``."""
    from pdr_pocket import orientation

    assert _bare_rows("p[2, 2] + covariance[:, 3:, 3:]") == [
        "line 1: p[2, 2]", "line 1: covariance[:, 3:, 3:]"]
    for module in (*KERNELS, Path(orientation.__file__)):
        assert _bare_rows(module.read_text()) == [], module.name


def test_each_update_has_a_builder_that_cites_its_equation():
    builders = {k.ABS_GRAVITY: k.absolute_gravity, k.DIFF_GRAVITY: k.differential_gravity,
                k.ABS_MAG: k.absolute_magnetic, k.DIFF_MAG: k.differential_magnetic,
                k.COMPASS: k.compass, k.ZARU: k.zaru, k.MEAN_GRAVITY: k.mean_gravity,
                k.YAW_CORRECTION: k.external_correction}
    assert set(range(km.N_UPDATES)) <= set(builders)
    for builder in builders.values():
        doc = " ".join(builder.__doc__.split())
        assert "Muñoz Díaz 2016, Eq" in doc or doc.startswith("Beyond the thesis"), builder


def test_a_field_judgement_holds_until_the_next_reading():
    """docs/pocket.md: a phone's magnetometer comes at half the IMU's rate here (NaN
    between readings, as pdr_pocket.inputs aligns it): each reading is judged once, and
    field_judgement holds that judgement over the samples until the next one; a reading
    far from the field (a magnet) is judged disturbed and held as such."""
    n = 400
    t = np.arange(n) * 0.01
    gyro, accel = np.zeros((n, 3)), np.tile([0.0, 0.0, 9.80665], (n, 1))
    noise = np.random.default_rng(1).normal(0.0, 0.05e-6, (n, 3))
    mag = np.array([0.0, 20e-6, -40e-6]) + noise
    mag[300:310] += [30e-6, 0.0, 0.0]                    # a magnet passes
    mag[1::2] = np.nan
    est = OrientationFilter(OrientationConfig()).run(t, gyro, accel, mag)
    judged = est.field_judgement()
    undisturbed = est.detector("field_undisturbed")
    assert not undisturbed[1::2].any() and undisturbed[0:300:2].all()
    assert (judged[:300] == 0).all()
    assert (judged[301:310] == 1).all() and est.detector("field_disturbed")[300:310:2].all()
