"""χ² gate limits, shared by every gate of the project (the pocket orientation filter's
and position filter's corrections, the landmark database's association, the foot
study's confidence bounds; Bar-Shalom et al. 2001, Section 5.4).

:func:`chi2_quantile` is ``scipy.stats.chi2.ppf`` through ``scipy.special.chdtri``, the
same numbers without importing ``scipy.stats`` (0.7 s at every command's start).
"""
from __future__ import annotations

from scipy.special import chdtri


def chi2_quantile(probability: float, dof: int) -> float:
    """The value a χ² variable of ``dof`` degrees of freedom stays below with
    ``probability`` (a gate's limit on the normalised innovation squared)."""
    return float(chdtri(dof, 1.0 - probability))
