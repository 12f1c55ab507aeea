"""The gain of a first-order low-pass, spelled once for every kernel.

:func:`lowpass_gain` is α of y ← y + α·(x − y) for a time constant τ over a step δt:
α = 1 − e^{−δt/τ}, exact for a signal held over the step, so a stream with jittering or
missing stamps keeps the filter's time constant (a fixed α would be one for a fixed rate
only). Two such stages in cascade (the tilt reference of pdr_pocket.compiled_attitude)
fall off at 40 dB a decade above 1/(2πτ), as a second-order filter does.
"""
from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def lowpass_gain(dt_s, tau_s):
    """α [0, 1] of a first-order low-pass of time constant ``tau_s`` [s] over ``dt_s``
    [s]: 1 − e^{−δt/τ} (0 for δt ≤ 0, 1 for τ ≤ 0: no filtering)."""
    if dt_s <= 0.0:
        return 0.0
    if tau_s <= 0.0:
        return 1.0
    return 1.0 - np.exp(-dt_s / tau_s)
