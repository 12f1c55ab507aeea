"""Magnetic field models and magnetometer calibration (issue 3, acceptance 3)."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdr_core.sensors.magnetic_field import (
    PRESETS_T,
    TABLE_3_3,
    UT,
    Cylinder,
    IronDistortion,
    MagneticField,
    homogeneous,
)
from pdr_core.sensors.magnetometer_calibration import fit_ellipsoid


def test_presets_are_table_3_1():
    np.testing.assert_allclose(PRESETS_T["north_pole"], [0, 0, -65 * UT])
    np.testing.assert_allclose(PRESETS_T["equator"], [0, 25 * UT, 0])
    munich = PRESETS_T["munich"]
    assert np.linalg.norm(munich) == pytest.approx(48 * UT)
    assert np.degrees(np.arctan2(-munich[2], munich[1])) == pytest.approx(64.0)


def test_cylinder_follows_eq_3_29_at_known_points():
    """Equator field (25 µT north), cylinder r_c = 0.3 m, μ_r = 200 at the origin."""
    field = MagneticField(tuple(homogeneous("equator")), (Cylinder(0.0, 0.0, 0.3, 200.0),))
    k = 199 / 201
    # (x, y) = (0, 1): ρ = 0 -> H = |H|·(1 + k·0.3/1)·u_N
    # (x, y) = (1, 1): ρ = 45° -> H_E = |H|·k·0.3/√2, H_N = |H|
    # (x, y) = (2, 0): ρ = 90° -> H_N = |H|·(1 − k·0.3/2)
    points = np.array([[0.0, 1.0, 0.0], [1.0, 1.0, 5.0], [2.0, 0.0, 0.0]])
    expected = 25 * UT * np.array([[0.0, 1 + k * 0.3, 0.0],
                                   [k * 0.3 / np.sqrt(2), 1.0, 0.0],
                                   [0.0, 1 - k * 0.3 / 2, 0.0]])
    np.testing.assert_allclose(field.at(points), expected, rtol=1e-12, atol=1e-18)
    far = field.at(np.array([[0.0, 1e6, 0.0]]))
    np.testing.assert_allclose(far, [homogeneous("equator")], rtol=1e-6)


def test_cylinder_leaves_the_vertical_component():
    field = MagneticField(tuple(homogeneous("munich")), (Cylinder(1.0, 2.0, 2.0),))
    h = field.at(np.random.default_rng(0).uniform(-10, 10, size=(100, 3)))
    np.testing.assert_allclose(h[:, 2], homogeneous("munich")[2])


def test_distortion_roundtrip_and_ellipsoid_fit_recovers_table_3_3():
    h = homogeneous("munich")
    norm = np.linalg.norm(h)
    attitude = Rotation.random(3000, random_state=2)
    mu = attitude.inv().apply(h) + np.random.default_rng(1).normal(scale=0.05 * UT,
                                                                     size=(3000, 3))
    distortion = IronDistortion(**TABLE_3_3)
    raw = distortion.distort(mu, norm)
    np.testing.assert_allclose(distortion.correct(raw, norm), mu, atol=1e-15)
    fit = fit_ellipsoid(raw, norm)
    m = np.asarray(TABLE_3_3["M"])
    assert fit.xi == pytest.approx(TABLE_3_3["xi"] * np.cbrt(np.linalg.det(m)), rel=2e-3)
    np.testing.assert_allclose(fit.offset, TABLE_3_3["offset"], atol=2e-3)
    np.testing.assert_allclose(fit.M, m / np.cbrt(np.linalg.det(m)), atol=2e-3)
    corrected = fit.correct(raw, norm)
    assert np.abs(np.linalg.norm(corrected, axis=1) - norm).max() < 0.5 * UT
