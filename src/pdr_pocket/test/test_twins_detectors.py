"""The NumPy twin of the orientation filter's detectors
(:mod:`pdr_pocket.compiled_orientation_detectors`; Muñoz Díaz 2016, Section 3.2): zero
acceleration, zero angular rate (with ω̄ and its variance over the window's older half),
a steady field and its reference μ̄_r, read by :func:`detect` from a ring of the last RING
samples, against :class:`TrailingWindows`, plain Python written from the module's
docstrings that keeps every sample in a list and reads the trailing windows off it. On
hypothesis-drawn samples (rests, motion, a disturbed or missing field, stamps that repeat
or jump) and parameters, and on a walk with stops longer than the ring, the four
detections, ω̄ with its variance and μ̄_r are equal to the last bit (sums taken newest
first, as the docstrings' "the last ``window_s`` seconds" are read). The last test changes
one line of the kernel and shows that the twin then fails.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_pocket import compiled_orientation_data as kd
from pdr_pocket import compiled_orientation_detectors as kdet
from pdr_pocket.compiled_orientation_data import ATT_EAST, ATT_NORTH, RING, Detected, Sample
from pdr_pocket.compiled_orientation_detectors import detect
from pdr_pocket.orientation_config import OrientationConfig

SHIPPED = OrientationConfig(filter="thesis").params()
EPSILON_S = 1e-9                # a sample at the window's edge is in it


def norm(v) -> float:
    return math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)


def total(rows) -> np.ndarray:
    """The rows summed in their order (newest first)."""
    out = np.zeros(3)
    for row in rows:
        out = out + row
    return out


class TrailingWindows:
    """Every sample kept: t, |‖α‖ − g|, ‖ω‖, ω and C·μ (NaN: none), newest last."""

    def __init__(self, params) -> None:
        self.p = params
        self.t, self.acc, self.rate, self.gyro, self.mag = [], [], [], [], []
        self.was_steady, self.reference, self.rest = False, np.zeros(3), np.zeros((2, 3))

    def window(self, now, window_s) -> list[int] | None:
        """The samples of the last ``window_s`` seconds, newest first; None while the ring
        of the last RING samples holds none older."""
        rows = []
        for i in range(len(self.t) - 1, max(len(self.t) - RING, 0) - 1, -1):
            if now - self.t[i] > window_s + EPSILON_S:
                return rows             # the stamps do not decrease: the rest are older
            rows.append(i)
        return None

    def zero_acc(self, now) -> bool:
        """The largest |‖α‖ − g| and ‖ω‖ of the window under their thresholds."""
        rows = self.window(now, self.p.zero_acc_window_s)
        return rows is not None and max(self.acc[i] for i in rows) <= \
            self.p.zero_acc_threshold and max(self.rate[i] for i in rows) <= \
            self.p.zero_acc_max_rate

    def zero_rate(self, now) -> bool:
        """Every ω within the threshold of the window's mean; ω̄ and the variance over the
        window's older half."""
        window_s, threshold = self.p.zero_rate_window_s, self.p.zero_rate_threshold
        rows = self.window(now, window_s)
        if not rows:
            return False
        mean = total(self.gyro[i] for i in rows) / len(rows)
        if any(((self.gyro[i] - mean) ** 2).sum() > threshold * threshold for i in rows):
            return False
        older = [i for i in rows if now - self.t[i] >= 0.5 * window_s]
        if not older:
            return False
        self.rest[0] = total(self.gyro[i] for i in older) / len(older)
        self.rest[1] = total((self.gyro[i] - self.rest[0]) ** 2 / len(older) for i in older)
        return True

    def mag_steady(self, now) -> bool:
        """The field's norm within its threshold, its direction within its angle of the
        mean direction, over the window."""
        rows = self.window(now, self.p.mag_window_s)
        if rows is None or len(rows) < 2:
            return False
        fields = [self.mag[i] for i in rows]
        if not all(np.isfinite(v[0]) for v in fields):
            return False
        norms = [norm(v) for v in fields]
        if max(norms) - min(norms) > self.p.mag_norm_threshold:
            return False
        direction = total(v / max(n, 1e-12) for v, n in zip(fields, norms, strict=True))
        direction = direction / max(norm(direction), 1e-12)
        cosine = math.cos(self.p.mag_direction_threshold)
        return all(v[0] * direction[0] + v[1] * direction[1] + v[2] * direction[2] >= cosine * n
                   for v, n in zip(fields, norms, strict=True))

    def detect(self, now, accel, gyro, mag, attitude, tilt_var) -> Detected:
        self.t.append(now)
        self.acc.append(abs(norm(accel) - self.p.gravity))
        self.rate.append(norm(gyro))
        self.gyro.append(np.array(gyro, dtype=float))
        self.mag.append(np.array([attitude[m, 0] * mag[0] + attitude[m, 1] * mag[1]
                                  + attitude[m, 2] * mag[2] for m in range(3)])
                        if np.isfinite(mag[0]) else np.full(3, np.nan))
        zero_acc, zero_rate = self.zero_acc(now), self.zero_rate(now)
        steady = bool(np.isfinite(mag[0])) and self.mag_steady(now)
        anchored = steady and (self.was_steady or tilt_var <= self.p.mag_reference_max_var)
        if anchored and not self.was_steady:
            self.reference = self.mag[-1].copy()       # μ̄_r: the steady period's first
        self.was_steady = anchored
        return Detected(zero_acc, zero_rate, steady, anchored)


class Stream:
    """Samples for the detectors: t (N,), α, ω, μ (N, 3), C (N, 3, 3) and the tilt's
    variance (N,)."""

    def __init__(self, t, accel, gyro, mag, attitude, tilt_var) -> None:
        self.rows = (t, accel, gyro, mag, attitude, tilt_var)

    def __len__(self) -> int:
        return len(self.rows[0])


def kernel_detections(kernel, stream: Stream, params=SHIPPED):
    """``kernel`` (:func:`detect`) per sample on a filter state given each sample's C and
    tilt variance; the detections, ω̄ and its variance, and μ̄_r after each sample."""
    state = kd.initial_state(np.eye(3), np.eye(kd.N_STATE))
    found, rest, reference = [], [], []
    for now, accel, gyro, mag, attitude, tilt_var in zip(*stream.rows, strict=True):
        state.attitude[:] = attitude
        state.covariance[ATT_EAST, ATT_EAST] = state.covariance[ATT_NORTH, ATT_NORTH] = tilt_var
        found.append(tuple(kernel(state, params, now, Sample(0.0, gyro, gyro, accel, mag,
                                                              False))))
        rest.append(state.rest_rate.copy())
        reference.append(state.mag_reference.copy())
    return np.array(found), np.array(rest), np.array(reference)


def twin_detections(stream: Stream, params=SHIPPED):
    twin = TrailingWindows(params)
    found, rest, reference = [], [], []
    for row in zip(*stream.rows, strict=True):
        found.append(tuple(twin.detect(*row)))
        rest.append(twin.rest.copy())
        reference.append(twin.reference.copy())
    return np.array(found), np.array(rest), np.array(reference)


def assert_twins(kernel, twin) -> None:
    for name, value, expected in zip(("detections", "rest rate", "field reference"), kernel,
                                     twin, strict=True):
        np.testing.assert_array_equal(value, expected, err_msg=name)


# --- drawn samples --------------------------------------------------------------------
@st.composite
def streams(draw) -> Stream:
    """Rests (ω within 0.05 rad/s, α within 0.3 m/s² of g, a steady field) and motion,
    the field steady, disturbed or missing, stamps 1–150 ms apart or repeated."""
    n = draw(st.integers(1, 120))
    unit = draw(arrays(float, (n, 4, 3), elements=st.floats(-1.0, 1.0)))
    still = draw(arrays(bool, n))[:, None]
    field_kind = draw(arrays(np.int8, n, elements=st.integers(0, 2)))
    dt = draw(arrays(float, n, elements=st.sampled_from([0.0, 0.01]) | st.floats(0.001, 0.15)))
    gyro = unit[:, 0] * np.where(still, 0.05, 2.0)
    accel = [0.0, 0.0, STANDARD_GRAVITY_MPS2] + unit[:, 1] * np.where(still, 0.3, 5.0)
    attitude = Rotation.from_rotvec(unit[:, 2] * np.where(still, 0.02, 3.0))
    mag = attitude.inv().apply([0.0, 20e-6, -40e-6]) + 0.3e-6 * unit[:, 3]
    mag[field_kind == 1] = 60e-6 * unit[field_kind == 1, 3]
    mag[field_kind == 2] = np.nan
    tilt_var = draw(arrays(float, n, elements=st.floats(0.0, 0.02)))
    return Stream(np.cumsum(dt), accel, gyro, mag, attitude.as_matrix(), tilt_var)


parameters = st.builds(
    lambda acc, rate, mag, thresholds: SHIPPED._replace(
        zero_acc_window_s=acc, zero_rate_window_s=rate, mag_window_s=mag,
        zero_acc_threshold=thresholds[0], zero_rate_threshold=thresholds[1],
        mag_norm_threshold=thresholds[2], mag_direction_threshold=thresholds[3]),
    st.floats(0.0, 0.5), st.floats(0.0, 1.0), st.floats(0.0, 1.0),
    st.tuples(st.floats(0.1, 1.0), st.floats(0.01, 0.2), st.floats(0.2e-6, 3e-6),
              st.floats(0.01, 0.2)))


@settings(max_examples=40, deadline=None)
@given(stream=streams(), params=st.just(SHIPPED) | parameters)
def test_detect_is_its_twin(stream, params):
    assert_twins(kernel_detections(detect, stream, params), twin_detections(stream, params))


# --- a walk with stops ----------------------------------------------------------------
def walk_with_stops(seconds: float = 30.0, seed: int = 6) -> Stream:
    """A thigh at 100 Hz (more samples than the ring holds): standing, walking ±0.5 rad at
    a 1.1 s gait cycle, standing again, with noise, the field disturbed for 2 s and missing
    for 1 s, the tilt uncertain for the first 3 s."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 0.01)
    walking = (t > 8.0) & (t < 20.0)
    theta = np.where(walking, 0.5 * np.sin(2.0 * np.pi * t / 1.1), 0.0)
    attitude = Rotation.from_euler("ZY", np.column_stack([0.3 * np.ones_like(t), -theta]))
    gyro = np.column_stack([np.zeros_like(t), -np.gradient(theta, t), np.zeros_like(t)])
    gyro += 0.005 * rng.normal(size=gyro.shape)
    accel = attitude.inv().apply([0.0, 0.0, STANDARD_GRAVITY_MPS2])
    accel += np.where(walking, 2.0, 0.05)[:, None] * rng.normal(size=accel.shape)
    field = np.array([0.0, 20e-6, -40e-6]) + 0.1e-6 * rng.normal(size=(len(t), 3))
    field[(t > 24.0) & (t < 26.0)] += [5e-6, 0.0, 0.0]
    mag = attitude.inv().apply(field)
    mag[(t > 27.0) & (t < 28.0)] = np.nan
    tilt_var = np.where(t < 3.0, 0.01, 1e-4)
    return Stream(t, accel, gyro, mag, attitude.as_matrix(), tilt_var)


@pytest.fixture(scope="module")
def walk() -> Stream:
    return walk_with_stops()


def test_detect_is_its_twin_on_a_walk_with_stops(walk):
    twin = twin_detections(walk)
    found = twin[0].mean(axis=0)
    assert len(walk) > RING and 0.3 < found[0] < 0.7 and 0.3 < found[1] < 0.7
    assert 0.05 < found[2] - found[3] < 0.15 and found[2] < 0.95   # μ̄_r needs the tilt
    assert_twins(kernel_detections(detect, walk), twin)


def test_the_rest_rate_over_the_whole_window_fails_its_twin(perturb, walk):
    """ω̄ over the whole window instead of its older half."""
    wrong_rest = perturb(kdet.at_rest, kdet, "if t - ring_t[i] >= 0.5 * window_s:",
                         "if t - ring_t[i] >= 0.0:")
    wrong = perturb(detect, kdet, "zero_rate = at_rest(", "zero_rate = wrong_rest(",
                    calls={"wrong_rest": wrong_rest})
    short = Stream(*(x[:1500] for x in walk.rows))
    with pytest.raises(AssertionError, match="rest rate"):
        assert_twins(kernel_detections(wrong, short), twin_detections(short))
