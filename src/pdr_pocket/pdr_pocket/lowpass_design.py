"""The footfall detector's low-pass (pdr_pocket.steps), designed in NumPy: an even-order
digital Butterworth filter as second-order sections, and the delays of its steady state.

- :func:`butterworth_sections` is ``scipy.signal.butter(order, cutoff, output="sos")``:
  the analogue prototype's poles −exp(jπ(2k + N + 1)/(2N)), pre-warped to
  4·tan(π·W/2) and mapped by the bilinear transform with fs = 2 (Oppenheim and Schafer
  2010, Section 7.2.1), the N zeros at z = −1; one section per pair of conjugate poles
  (each pair the mean of the two, as scipy's ``_cplxreal`` makes it), the pair farthest
  from the unit circle first, the gain in the first (scipy's ``zpk2sos``, pairing
  "nearest").
- :func:`steady_state_delays` is ``scipy.signal.sosfilt_zi``: each section's delays for a
  unit step held since forever, ``lfilter_zi``'s (I − Aᵀ)·z = b[1:] − a[1:]·b0 scaled by
  the gains at DC of the sections before it.

Both follow scipy's operations in the same order, so they agree with it to the last bit
(src/pdr_pocket/test/test_lowpass_design.py). Why not call it: importing ``scipy.signal``
imports ``scipy.stats`` too, about 1 s at the first block of every pocket navigator, the
node's and the offline tools'.
"""
from __future__ import annotations

import numpy as np

BILINEAR_FS = 2.0
"""The sample rate the bilinear transform is taken at, with the cutoff as a fraction of
the Nyquist frequency (scipy's ``fs=2``)."""


def butterworth_sections(order: int, cutoff: float) -> np.ndarray:
    """The low-pass Butterworth filter of an even ``order``, its −3 dB ``cutoff`` a
    fraction of the Nyquist frequency in (0, 1), as sections (order / 2, 6) [b0, b1, b2,
    1, a1, a2]."""
    if order < 2 or order % 2:
        raise ValueError(f"order {order}: an even order of at least 2")
    if not 0.0 < cutoff < 1.0:
        raise ValueError(f"cutoff {cutoff}: a fraction of the Nyquist frequency in (0, 1)")
    prototype = -np.exp(1j * np.pi * np.arange(-order + 1, order, 2) / (2 * order))
    warped = 2 * BILINEAR_FS * np.tan(np.pi * cutoff / BILINEAR_FS)
    analogue = warped * prototype
    gain = warped ** order
    doubled = 2.0 * BILINEAR_FS
    poles = (doubled + analogue) / (doubled - analogue)
    gain = gain * np.real(1.0 / np.prod(doubled - analogue))
    poles = poles[np.lexsort((np.abs(poles.imag), poles.real))]
    upper = (poles[poles.imag > 0] + poles[poles.imag < 0].conj()) / 2
    upper = upper[np.argsort(np.abs(1 - np.abs(upper)), kind="stable")[::-1]]
    sections = np.zeros((order // 2, 6))
    sections[:, :3] = [1.0, 2.0, 1.0]
    sections[:, 3:] = [np.poly([pole, pole.conj()]).real for pole in upper]
    sections[0, :3] *= gain
    return sections


def steady_state_delays(sections: np.ndarray) -> np.ndarray:
    """The delays (S, 2) of the ``sections`` (S, 6) after a unit input held forever, for
    the direct form II transposed of pdr_pocket.compiled_biquads.sos_filter; times the
    first input, the filter starts without a transient."""
    delays = np.empty((len(sections), 2))
    scale = 1.0
    for k, (b, a) in enumerate(zip(sections[:, :3], sections[:, 3:], strict=True)):
        i_minus_a = np.eye(2) - np.array([[-a[1], -a[2]], [1.0, 0.0]]).T
        delays[k] = scale * np.linalg.solve(i_minus_a, b[1:] - a[1:] * b[0])
        scale *= np.sum(b) / np.sum(a)
    return delays
