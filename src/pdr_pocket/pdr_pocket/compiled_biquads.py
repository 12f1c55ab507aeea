"""A cascade of second-order sections (biquads), compiled with numba, its state carried
from one chunk to the next: the footfall detector's low-pass (pdr_pocket.steps).

:func:`sos_filter` is the direct form II transposed of ``scipy.signal.sosfilt`` (Oppenheim
and Schafer 2010, Section 6.4.3), section by section in the same order of operations, so
the two agree to the last bit (src/pdr_pocket/test/test_twins_biquads.py, where sosfilt is
the twin). scipy's call costs about 40 µs whatever its length, most of a live chunk of one
sample; this one costs the arithmetic.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache

kernel_cache.forget_if_changed(__file__)


@njit(cache=True)
def sos_filter(sos, x, zi):
    """``x`` (N,) through the sections ``sos`` (S, 6) [b0, b1, b2, a0 = 1, a1, a2], from
    and into their delays ``zi`` (S, 2), updated in place; the output (N,). Per sample and
    section: y = b0·x + z0; z0 ← b1·x − a1·y + z1; z1 ← b2·x − a2·y."""
    out = np.empty_like(x)
    for n in range(x.shape[0]):
        x_cur = x[n]
        for s in range(sos.shape[0]):
            x_new = sos[s, 0] * x_cur + zi[s, 0]
            zi[s, 0] = sos[s, 1] * x_cur - sos[s, 4] * x_new + zi[s, 1]
            zi[s, 1] = sos[s, 2] * x_cur - sos[s, 5] * x_new
            x_cur = x_new
        out[n] = x_cur
    return out
