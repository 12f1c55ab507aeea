"""The NumPy twin of the windows of whole gait cycles
(:mod:`pdr_pocket.compiled_gait_window`, shared by both orientation filters): the swing
axis and its markers, the window's sums Σ C·α·δt, A = Σ C·δt and the attitude memory
S = Σ_k δt_k·∫_{t_k}^{t} C ds, its closing by time (2, 4, 8 s ... up to ``window_max_s``)
or at a marker after ``cycle_min_s`` of whole cycles, its restart, its turn by a
correction, the turn of the walker over it and whether it holds gravity, against
:class:`WindowTwin`, written from the module docstring, driven sample by sample as the
filters drive the kernel (a gap forgets the window, a correction turns it). On
hypothesis-drawn rates, forces, attitudes, steps, gaps and corrections and on a walking
thigh with stops: equal to the last bit (the kernel's sums are per sample, each product
of three terms added left to right, as :func:`dot3` adds them). (``across``, the last
helper, has its twin in test_twins_orientation.py.) The last test changes one line of the
kernel and shows that the twin then fails.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_pocket import compiled_gait_window as kg
from pdr_pocket.compiled_gait_window import (
    add_to_window,
    force_in_body,
    forget_window,
    holds_gravity,
    new_gait_window,
    restart_window,
    swing_marker,
    turn_window,
    turned,
)
from pdr_pocket.orientation_config import OrientationConfig

SHIPPED = OrientationConfig().window_params()


def dot3(x, y) -> float:
    return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]


def times(a, b) -> np.ndarray:
    """a·b for 3 × 3 matrices, each entry a row of a dotted with a column of b."""
    return np.array([[dot3(a[i], b[:, j]) for j in range(3)] for i in range(3)])


class WindowTwin:
    """The window's memory as plain attributes."""

    def __init__(self, params) -> None:
        self.p = params
        self.swing, self.axis = np.zeros((3, 3)), np.full(3, 1.0 / math.sqrt(3.0))
        self.armed = self.from_marker = False
        self.done = 0
        self.start = np.eye(3)
        self.forget()

    def forget(self) -> None:
        """Empty (after a close, at a first marker, after a gap)."""
        self.time, self.force = 0.0, np.zeros(3)
        self.memory, self.attitude_sum = np.zeros((3, 3)), np.zeros((3, 3))

    def marker(self, gyro, dt) -> bool:
        """E[ω·ωᵀ] low-passed (gain δt/τ, at most 1), its principal axis by one power
        iteration; a marker where the rate about it falls through zero after a lobe faster
        than the threshold."""
        self.swing = self.swing + min(dt / self.p.swing_time_constant_s, 1.0) * (
            np.outer(gyro, gyro) - self.swing)
        v = np.array([dot3(row, self.axis) for row in self.swing])
        length = math.sqrt(dot3(v, v))
        if length > 0.0:
            self.axis = v / length
        rate = dot3(gyro, self.axis)
        if rate > self.p.swing_rate_threshold:
            self.armed = True
        elif rate < 0.0 and self.armed:
            self.armed = False
            return True
        return False

    def add(self, c, accel, dt, marker) -> tuple[bool, bool, bool]:
        """The sample into the sums; (marker, closes, cycles)."""
        if self.time == 0.0:
            self.start = c.copy()
        # S(t + δt) = S(t) + (Σ_k δt_k)·C·δt: every earlier sample's integral grows by C·δt
        self.memory = self.memory + self.time * c * dt
        self.attitude_sum = self.attitude_sum + c * dt
        self.time += dt
        self.force = self.force + dt * np.array([dot3(row, accel) for row in c])
        longest = min(self.p.window_max_s, 2.0 * 2.0 ** self.done)
        cycles = marker and self.from_marker and self.time >= self.p.cycle_min_s
        return marker, cycles or self.time >= longest, cycles

    def restart(self, marker, closes) -> None:
        if closes or (marker and not self.from_marker):
            self.done += closes
            self.from_marker = marker
            self.forget()

    def turned(self, c) -> float:
        """The up component of C·C_startᵀ."""
        r = times(c, self.start.T)
        return math.atan2(r[1, 0] - r[0, 1], r[0, 0] + r[1, 1])

    def turn(self, rot) -> None:
        self.force = np.array([dot3(row, self.force) for row in rot])
        self.memory, self.attitude_sum = times(rot, self.memory), times(rot, self.attitude_sum)
        self.start = times(rot, self.start)

    def body_force(self, c) -> np.ndarray:
        return np.array([dot3(c[:, m], self.force) for m in range(3)])

    def holds_gravity(self, c) -> bool:
        body = self.body_force(c)
        return math.sqrt(body[0] ** 2 + body[1] ** 2 + body[2] ** 2) > \
            0.5 * (self.p.gravity * self.time)


class Drive(NamedTuple):
    """Per sample: δt [s], ω [rad/s], α [m/s²], C_b^n, a gap before it, and a correction
    of the attitude after it (identity: none)."""

    dt: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    attitude: np.ndarray
    gap: np.ndarray
    correction: np.ndarray


def kernel_trace(drive: Drive, params=SHIPPED, marker_kernel=swing_marker):
    """The kernel driven as the filters drive it: per sample the marker, closes, cycles,
    holds gravity, the turn, the force in the body, and the sums before the restart."""
    window, rows = new_gait_window(), []
    window = window._replace(scalars=window.scalars.view(np.recarray))  # plain copies read it
    for dt, gyro, accel, c, gap, rot in zip(*drive, strict=True):
        if gap:
            forget_window(window)
        end = add_to_window(window, params, c, accel, dt,
                            marker_kernel(window, params, gyro, dt))
        rows.append((*end, holds_gravity(window, params, c), turned(window, c),
                     *force_in_body(c, window.force_sum), *window.memory.ravel(),
                     *window.attitude_sum.ravel(), window.scalars[0]["time_s"]))
        restart_window(window, end)
        turn_window(window, rot)
    return np.array(rows, dtype=float)


def twin_trace(drive: Drive, params=SHIPPED):
    twin, rows = WindowTwin(params), []
    for dt, gyro, accel, c, gap, rot in zip(*drive, strict=True):
        if gap:
            twin.from_marker = False
            twin.forget()
        marker, closes, cycles = twin.add(c, accel, dt, twin.marker(gyro, dt))
        rows.append((marker, closes, cycles, twin.holds_gravity(c), twin.turned(c),
                     *twin.body_force(c), *twin.memory.ravel(), *twin.attitude_sum.ravel(),
                     twin.time))
        twin.restart(marker, closes)
        twin.turn(rot)
    return np.array(rows, dtype=float)


@st.composite
def drives(draw) -> Drive:
    """Rates about a flexion axis (none, or swinging up to 4 rad/s) with noise, forces near
    gravity, attitudes anywhere, steps of 1 ms to 0.3 s, a few gaps and small corrections."""
    n = draw(st.integers(1, 200))
    unit = draw(arrays(float, (n, 4, 3), elements=st.floats(-1.0, 1.0)))
    dt = draw(arrays(float, n, elements=st.sampled_from([0.01, 0.02]) | st.floats(0.001, 0.3)))
    swing = draw(st.sampled_from([0.0, 4.0]) | st.floats(0.0, 4.0)) * np.sin(
        np.cumsum(dt) * 2.0 * np.pi / draw(st.floats(0.8, 1.5)))
    gyro = np.outer(swing, [0.0, 1.0, 0.0]) + 0.5 * unit[:, 0]
    accel = [0.0, 0.0, STANDARD_GRAVITY_MPS2] + 3.0 * unit[:, 1]
    attitude = Rotation.from_rotvec(3.0 * unit[:, 2]).as_matrix()
    corrected = draw(arrays(bool, n, elements=st.sampled_from([False] * 9 + [True])))
    correction = Rotation.from_rotvec(0.02 * unit[:, 3] * corrected[:, None]).as_matrix()
    gap = draw(arrays(bool, n, elements=st.sampled_from([False] * 19 + [True])))
    return Drive(dt, gyro, accel, attitude, gap, correction)


parameters = st.builds(kg.WindowParams, st.floats(0.5, 20.0), st.floats(0.1, 3.0),
                       st.floats(0.1, 5.0), st.floats(0.1, 3.0), st.just(STANDARD_GRAVITY_MPS2))


@settings(max_examples=30, deadline=None)
@given(drive=drives(), params=st.just(SHIPPED) | parameters)
def test_the_gait_window_is_its_twin(drive, params):
    np.testing.assert_array_equal(kernel_trace(drive, params), twin_trace(drive, params))


def walking_thigh(seconds: float = 40.0, seed: int = 9) -> Drive:
    """A thigh at 100 Hz pitching ±0.5 rad at a 1.1 s gait cycle with its swing's lever-arm
    acceleration, turning slowly, a 5 s stop, a 1 s gap and a heading correction each 5 s."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 0.01)
    t = t[(t < 30.0) | (t > 31.0)]
    walking = (t < 15.0) | (t > 20.0)
    phase = 2.0 * np.pi * t / 1.1
    theta = np.where(walking, 0.5 * np.sin(phase), 0.0)
    theta_d = np.where(walking, 0.5 * 2.0 * np.pi / 1.1 * np.cos(phase), 0.0)
    attitude = Rotation.from_euler("ZY", np.column_stack([0.02 * t, -theta]))
    gyro = np.column_stack([np.zeros_like(t), -theta_d, 0.02 * np.ones_like(t)])
    accel = attitude.inv().apply([0.0, 0.0, STANDARD_GRAVITY_MPS2])
    accel[:, 0] += 0.25 * theta_d ** 2 * np.sign(np.sin(phase))
    dt = np.diff(t, prepend=t[0])
    correction = np.tile(np.eye(3), (len(t), 1, 1))
    correction[np.flatnonzero(np.diff(np.floor(t / 5.0), prepend=0.0))] = \
        Rotation.from_euler("z", 0.01).as_matrix()
    return Drive(dt, gyro + 0.01 * rng.normal(size=gyro.shape), accel, attitude.as_matrix(),
                 dt > 0.5, correction)


def test_the_gait_window_is_its_twin_on_a_walking_thigh():
    drive = walking_thigh()
    twin = twin_trace(drive)
    assert 25 <= twin[:, 0].sum() <= 40 and twin[:, 2].sum() >= 15    # a marker per cycle
    np.testing.assert_array_equal(kernel_trace(drive), twin)


def test_a_marker_on_the_rising_rate_fails_its_twin(perturb):
    """The marker where the swing rate turns back up through zero instead of down."""
    wrong = perturb(swing_marker, kg, "elif rate < 0.0 and s.armed:",
                    "elif rate > 0.0 and s.armed:")
    drive = walking_thigh()
    with pytest.raises(AssertionError, match="Arrays are not equal"):
        np.testing.assert_array_equal(kernel_trace(drive, marker_kernel=wrong),
                                      twin_trace(drive))
