"""The twin of the footfall detector's low-pass: :func:`pdr_pocket.compiled_biquads.sos_filter`
against ``scipy.signal.sosfilt``, on hypothesis-drawn Butterworth designs and signals cut
into chunks anywhere: the same output and the same delays, to the last bit. The last test
changes one line of the kernel and shows that the twin then fails.
"""
from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.signal import butter, sosfilt, sosfilt_zi

from pdr_pocket import compiled_biquads
from pdr_pocket.compiled_biquads import sos_filter


def chunked(kernel, sos, x, zi, cuts):
    """``kernel`` run on ``x`` cut at ``cuts``, the delays carried: the output, the delays."""
    zi = zi.copy()
    parts = [kernel(sos, np.ascontiguousarray(part), zi) for part in np.split(x, cuts)]
    return np.concatenate(parts), zi


@settings(max_examples=60, deadline=None)
@given(order=st.integers(1, 8), cutoff=st.floats(0.01, 0.95),
       x=st.lists(st.floats(-50.0, 50.0), min_size=1, max_size=300),
       cuts=st.lists(st.integers(0, 300), max_size=6), start=st.floats(-20.0, 20.0))
def test_the_kernel_is_sosfilt_to_the_last_bit(order, cutoff, x, cuts, start):
    sos = butter(order, cutoff, output="sos")
    x = np.array(x)
    zi = sosfilt_zi(sos) * start
    expected, expected_zi = sosfilt(sos, x, zi=zi)
    got, got_zi = chunked(sos_filter, sos, x, zi, sorted(c % (len(x) + 1) for c in cuts))
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(got_zi, expected_zi)


def test_a_one_line_slip_fails_the_twin(perturb):
    slipped = perturb(sos_filter, compiled_biquads, "- sos[s, 5] * x_new", "+ sos[s, 5] * x_new")
    sos = butter(4, 0.1, output="sos")
    x = np.sin(np.linspace(0.0, 20.0, 200))
    zi = sosfilt_zi(sos) * x[0]
    got, _ = chunked(slipped, sos, x, zi, [50, 51])
    assert not np.array_equal(got, sosfilt(sos, x, zi=zi)[0])
