"""Shared by the NumPy twins (test_twins_*.py): the ``perturb`` fixture makes a copy of a
compiled kernel with one source line changed, to show that a twin catches a one-line
slip (test/mutants.py)."""
from __future__ import annotations

import pytest
from mutants import perturbed


@pytest.fixture
def perturb():
    """:func:`mutants.perturbed`."""
    return perturbed
