"""The footfall detector's low-pass design (pdr_pocket.lowpass_design) against
``scipy.signal.butter`` and ``sosfilt_zi``, to the last bit, on hypothesis-drawn orders and
cutoffs; its refusals; and the reason it exists: a pocket navigator's run does not import
``scipy.signal``.
"""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.signal import butter, sosfilt_zi

from pdr_pocket.lowpass_design import butterworth_sections, steady_state_delays


@settings(max_examples=200, deadline=None)
@given(order=st.sampled_from([2, 4, 6, 8]), cutoff=st.floats(1e-3, 0.999))
def test_the_design_is_scipys_to_the_last_bit(order, cutoff):
    sections = butterworth_sections(order, cutoff)
    np.testing.assert_array_equal(sections, butter(order, cutoff, output="sos"))
    np.testing.assert_array_equal(steady_state_delays(sections), sosfilt_zi(sections))


@pytest.mark.parametrize(("order", "cutoff"), [(3, 0.1), (0, 0.1), (4, 0.0), (4, 1.0),
                                               (4, -0.2)])
def test_an_odd_order_or_a_cutoff_outside_the_band_is_refused(order, cutoff):
    with pytest.raises(ValueError, match="order" if order != 4 else "cutoff"):
        butterworth_sections(order, cutoff)


def test_a_pocket_run_imports_no_scipy_signal():
    """The footfall detector designs its filter at its first block; scipy.signal (and the
    scipy.stats it imports) would cost about 1 s there, in every node and offline run."""
    code = ("import sys, numpy as np\n"
            "from pdr_pocket.steps import FootfallDetector\n"
            "t = np.arange(500) / 100.0\n"
            "FootfallDetector().push(t, np.sin(t), 9.81 + np.sin(6 * t))\n"
            "print(sorted(m for m in sys.modules if m.startswith(('scipy.signal', "
            "'scipy.stats'))))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"
