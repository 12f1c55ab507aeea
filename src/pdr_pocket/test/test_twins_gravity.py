"""The NumPy twin of the gravity direction without a gyroscope:
:func:`pdr_pocket.compiled_gravity.gravity_loop` (the specific force through two
first-order low-passes in cascade, and ‖α − gravity‖ through a third) against
:func:`low_passed`, written from the module docstring, on hypothesis-drawn forces, time
steps and time constants and on a swinging thigh's specific force with jittered stamps and
a gap, in one call or split anywhere with the state carried over: equal to the last bit
(the kernel's arithmetic is per sample and per axis, in the docstring's order, and
the norm ‖d‖ = √(d·d) with numpy's dot as the kernel's). The last
test changes one line of the kernel and shows that the twin then fails.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_pocket import compiled_gravity
from pdr_pocket.compiled_gravity import gravity_loop, new_gravity_state
from pdr_pocket.config import MountingConfig
from pdr_pocket.pitch_source import CASCADE_FACTOR, MOTION_TIME_CONSTANT_S

TAU_S = CASCADE_FACTOR / (2.0 * np.pi * MountingConfig().gravity_cutoff_hz)   # as shipped


def low_passed(t, accel, tau_s, motion_tau_s):
    """x ← x + δt/(τ + δt)·(input − x) twice for gravity, once for the motion measure;
    both stages start at the first sample's force, the motion at 0."""
    gravity, motion = np.empty_like(accel), np.empty(len(t))
    first = second = accel[0].copy()
    moving, last_t = 0.0, t[0]
    for k in range(len(t)):
        dt = t[k] - last_t
        last_t = t[k]
        alpha, beta = dt / (tau_s + dt), dt / (motion_tau_s + dt)
        first = first + alpha * (accel[k] - first)
        second = second + alpha * (first - second)
        d = accel[k] - second
        moving = moving + beta * (math.sqrt(d @ d) - moving)
        gravity[k], motion[k] = second, moving
    return gravity, motion


def kernel_outputs(kernel, t, accel, tau_s, motion_tau_s, split=None):
    state = new_gravity_state()
    state = state._replace(scalars=state.scalars.view(np.recarray))  # plain copies read it
    gravity, motion = np.empty_like(accel), np.empty(len(t))
    for part in (slice(0, split), slice(split, None)) if split is not None else (slice(None),):
        out_gravity, out_motion = np.empty_like(accel[part]), np.empty(len(t[part]))
        kernel(state, tau_s, motion_tau_s, np.ascontiguousarray(t[part]),
               np.ascontiguousarray(accel[part]), out_gravity, out_motion)
        gravity[part], motion[part] = out_gravity, out_motion
    return gravity, motion


def swinging_thigh(seconds: float = 30.0, seed: int = 2):
    """The specific force [m/s²] of a thigh swinging ±0.5 rad at a 1.1 s gait cycle with
    2 m/s² of swing acceleration and noise, at 100 Hz with 1 ms jitter and a 0.5 s gap."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 0.01) + 0.001 * rng.random(int(seconds * 100))
    t = t[(t < 12.0) | (t > 12.5)]
    theta = 0.5 * np.sin(2.0 * np.pi * t / 1.1)
    accel = Rotation.from_euler("y", theta[:, None]).inv().apply([0.0, 0.0, STANDARD_GRAVITY_MPS2])
    accel[:, 0] += 2.0 * np.cos(2.0 * np.pi * t / 0.55)
    return t, accel + 0.1 * rng.normal(size=accel.shape)


@settings(max_examples=100, deadline=None)
@given(samples=st.lists(st.tuples(st.floats(0.0, 0.5), *[st.floats(-40.0, 40.0)] * 3),
                        min_size=1, max_size=200),
       tau_s=st.floats(0.01, 5.0), motion_tau_s=st.floats(0.01, 5.0), data=st.data())
def test_gravity_loop_is_its_twin(samples, tau_s, motion_tau_s, data):
    """Drawn forces and time steps (a repeated stamp among them), split anywhere."""
    steps = np.array(samples)
    t, accel = np.cumsum(steps[:, 0]), np.ascontiguousarray(steps[:, 1:])
    split = data.draw(st.integers(0, len(t)))
    twin = low_passed(t, accel, tau_s, motion_tau_s)
    for where in (None, split):
        for value, expected in zip(kernel_outputs(gravity_loop, t, accel, tau_s, motion_tau_s,
                                                  where), twin, strict=True):
            np.testing.assert_array_equal(value, expected)


def test_gravity_loop_is_its_twin_on_a_swinging_thigh():
    t, accel = swinging_thigh()
    twin = low_passed(t, accel, TAU_S, MOTION_TIME_CONSTANT_S)
    for split in (None, 1, 1500):
        for value, expected in zip(kernel_outputs(gravity_loop, t, accel, TAU_S,
                                                  MOTION_TIME_CONSTANT_S, split), twin,
                                   strict=True):
            np.testing.assert_array_equal(value, expected)


def test_one_stage_for_two_fails_its_twin(perturb):
    """The second low-pass fed the raw force instead of the first stage's output."""
    wrong = perturb(gravity_loop, compiled_gravity, "gravity += alpha * (first - gravity)",
                    "gravity += alpha * (a - gravity)")
    t, accel = swinging_thigh()
    with pytest.raises(AssertionError, match="Arrays are not equal"):
        np.testing.assert_array_equal(kernel_outputs(wrong, t, accel, TAU_S, 1.0)[0],
                                      low_passed(t, accel, TAU_S, 1.0)[0])
