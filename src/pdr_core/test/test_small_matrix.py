"""The compiled small-matrix kernels against NumPy and SciPy."""
from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from pdr_core.maths.small_matrix import cholesky, product3, rodrigues

vectors = st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3)


@settings(max_examples=200, deadline=None)
@given(vectors)
def test_rodrigues_is_scipys_rotation_vector(v):
    out = np.empty((3, 3))
    rodrigues(*v, out)
    np.testing.assert_allclose(out, Rotation.from_rotvec(v).as_matrix(), rtol=0, atol=1e-12)


def test_rodrigues_near_zero_uses_the_series():
    out = np.empty((3, 3))
    rodrigues(1e-9, -2e-9, 3e-10, out)
    np.testing.assert_allclose(out, Rotation.from_rotvec([1e-9, -2e-9, 3e-10]).as_matrix(),
                               rtol=0, atol=1e-17)


@settings(max_examples=100, deadline=None)
@given(vectors, vectors)
def test_product3_is_the_matrix_product(u, v):
    a, b = Rotation.from_rotvec(u).as_matrix(), Rotation.from_rotvec(v).as_matrix() * 2.0
    out = np.empty((3, 3))
    product3(a, b, out)
    np.testing.assert_allclose(out, a @ b, rtol=0, atol=1e-15)


def test_cholesky_factors_spd_and_refuses_the_rest():
    rng = np.random.default_rng(3)
    m = rng.normal(size=(6, 6))
    spd = m @ m.T + 0.1 * np.eye(6)
    low = np.full((6, 6), np.nan)
    assert cholesky(spd, low)
    np.testing.assert_allclose(low, np.linalg.cholesky(spd), rtol=0, atol=1e-12)
    indefinite = spd - 20.0 * np.eye(6)
    assert not cholesky(indefinite, np.empty((6, 6)))
    assert not cholesky(np.full((2, 2), np.nan), np.empty((2, 2)))
