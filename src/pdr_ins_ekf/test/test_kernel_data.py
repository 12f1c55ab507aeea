"""The foot filter's kernel data (issue 31): rows of the error state by name, never by
number; state, parameters and samples as NamedTuples whose numba types do not depend on
how they were made, so each kernel compiles once."""
from __future__ import annotations

import ast
from pathlib import Path

import numba
import numpy as np
import pytest

from pdr_ins_ekf import compiled_filter, kernel_data
from pdr_ins_ekf.kernel_data import (
    ACC,
    ACC_BIAS,
    ATTITUDE,
    GYRO,
    GYRO_BIAS,
    HEADING,
    NAV_AND_BIAS_STATES,
    NAV_STATES,
    POSITION,
    VELOCITY,
)
from pdr_ins_ekf.zupt_ekf import (
    FilterConfig,
    SmootherConfig,
    ZuptEkf,
    kernel_params,
    record_samples,
    smoother_params,
    start_state,
)

PACKAGE = Path(kernel_data.__file__).resolve().parent
# the modules that index the error state, its covariance or the bias vector
FOOT_FILTER = ("compiled_filter.py", "compiled_smoother.py", "zupt_ekf.py", "streaming.py",
               "offline.py", "studies/ekf_montecarlo.py")
ROW_NUMBERS = set(range(3, NAV_AND_BIAS_STATES + 1))
STATE_COUNTS = {NAV_STATES, NAV_AND_BIAS_STATES}
MEASUREMENT_KERNELS = {"correct", "update", "within_gate"}


def bare_rows(source: str) -> list[str]:
    """Expressions that pick error-state rows by number: an integer from 3 to 15 in a
    subscript (``dx[3:6]``, ``P[3, 3]``, ``b[3:]``), a state count in a comparison
    (``n == 15``), or a row passed to a measurement kernel (``update(…, 3, σ)``). Indices
    0–2 are the axes of a 3-vector or a 3×3 block, which stay numbers."""
    hits = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Subscript):
            inner, numbers = node.slice, ROW_NUMBERS
        elif isinstance(node, ast.Compare):
            inner, numbers = node, STATE_COUNTS
        elif (isinstance(node, ast.Call)
              and getattr(node.func, "attr", getattr(node.func, "id", None))
              in MEASUREMENT_KERNELS):
            inner, numbers = ast.Tuple(node.args), None
        else:
            continue
        if any(isinstance(c, ast.Constant) and type(c.value) is int
               and (numbers is None or c.value in numbers) for c in ast.walk(inner)):
            hits.append(f"{node.lineno}: {ast.unparse(node)}")
    return hits


@pytest.mark.parametrize("module", FOOT_FILTER)
def test_no_bare_state_rows(module):
    assert bare_rows((PACKAGE / module).read_text()) == []


@pytest.mark.parametrize("line", [
    "update(p, v, C, b, P, prev, -v, 3, zupt_sigma)", "within_gate(P, w - b[3:], 12, s, g)",
    "x = dx[3:6]", "x = dx[12:15]", "x = P[3, 3] + P[4, 4] + P[5, 5]", "x = b[:3]",
    "x = dx.shape[0] == 15", "x = variance[..., 8]", "x = params[4]", "y[9 + j] -= 1"])
def test_the_row_check_catches_what_it_is_for(line):
    assert bare_rows(line)


@pytest.mark.parametrize("line", [
    "x = C[i, 0] * a[2]", "x = dx[VELOCITY:VELOCITY + AXES]", "x = b[GYRO]",
    "update(state, -v, VELOCITY, sigma)", "x = n == NAV_AND_BIAS_STATES", "x = K_T[2, i]"])
def test_the_row_check_passes_named_rows(line):
    assert bare_rows(line) == []


def test_the_rows_are_the_error_states_blocks():
    """δx = [δp, δv, δθ, δb_a, δb_g], three rows each; b = [b_a, b_g]."""
    blocks = [POSITION, VELOCITY, ATTITUDE, ACC_BIAS, GYRO_BIAS]
    assert blocks == list(range(0, NAV_AND_BIAS_STATES, 3))
    assert NAV_STATES == ACC_BIAS and HEADING == ATTITUDE + 2
    assert np.arange(6)[ACC].tolist() == [0, 1, 2] and np.arange(6)[GYRO].tolist() == [3, 4, 5]


def test_parameter_types_do_not_depend_on_how_a_value_was_written():
    """An integer in the YAML (``bias_tau_s: 300``) must not make numba compile a second
    specialisation of every kernel."""
    written = FilterConfig(acc_noise_mps2_per_sqrt_hz=1, gyro_noise_radps_per_sqrt_hz=1,
                           bias_model="gauss_markov", bias_tau_s=300, zupt_sigma_mps=1,
                           gravity_mps2=10)
    assert numba.typeof(kernel_params(written)) == numba.typeof(kernel_params(FilterConfig()))
    assert (numba.typeof(smoother_params(SmootherConfig("segmented", 1, 0)))
            == numba.typeof(smoother_params(SmootherConfig())))


def test_states_made_in_python_and_in_numba_have_one_type():
    """The live filter's state (built in Python) and the offline loop's (built by
    ``compiled_filter.new_state``) are one numba type, as are a record's samples and a
    live block's, so the kernels compile once for both."""
    config = FilterConfig(bias_model="random_walk", zaru=True)
    live = ZuptEkf(config, np.eye(3))
    offline = start_state(np.eye(3), np.zeros(6), live.P)
    assert numba.typeof(live.state) == numba.typeof(offline)
    assert numba.typeof(compiled_filter.new_state(np.eye(3), np.zeros(6), live.P)) \
        == numba.typeof(live.state)
    f, w = np.zeros((4, 3)), np.zeros((4, 3))
    record = record_samples(np.arange(4.0), f, w, np.ones(4, bool))
    live.run_block(f, w, record.dt, record.stance)
    assert numba.typeof(record) == numba.typeof(kernel_data.Samples(
        record.dt, f, w, np.ones(4, bool)))
