"""The NumPy twin of the thigh model's kinematics: :func:`pdr_sim.compiled_thigh.thigh_kinematics`
(the pocket model's spline channels turned into the sensor's position, velocity,
acceleration, attitude and body rate) against :func:`sensor_motion`, the module
docstring's equations in NumPy and SciPy (the channels by ``PPoly``, the rotations by
``Rotation``), on hypothesis-drawn splines and bodies and on a simulated walk with stairs,
turns and sitting. Not bit for bit: SciPy evaluates the polynomials and rotations with
other arithmetic, so on the walk positions agree to 1e-12 m, velocities and body rates to
1e-12 m/s and rad/s, accelerations to 1e-9 m/s² (the chain rule's products of rates), and
attitudes to 1e-12 rad; on drawn splines, whose values reach hundreds, to as much of their
scale. The last test changes one line of the kernel and shows that the twin then fails.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from mutants import perturbed
from scipy.interpolate import PPoly
from scipy.spatial.transform import Rotation

from pdr_sim import compiled_thigh
from pdr_sim.compiled_thigh import (
    HEADING,
    PITCH,
    SWAY,
    SensorMotion,
    ThighBody,
    ThighSpline,
    thigh_kinematics,
)
from pdr_sim.pocket_scenario import pocket_scenario_from_dict
from pdr_sim.thigh_trajectory import ThighTrajectory


def sensor_motion(t, spline: ThighSpline, body: ThighBody) -> SensorMotion:
    """With ψ = heading + sway, α = −k·θ (k the pitch coupling) and C_t = Rz(ψ)·Ry(α):
    ω_t, ω̇_t, p, ṗ, p̈ of the module docstring, the attitude C_t·C_s^t and ω_s = C_s^tᵀ·ω_t."""
    poly = PPoly(spline.coeffs, spline.breaks)
    s0, s1, s2 = poly(t), poly(t, 1), poly(t, 2)
    psi, psi_d, psi_dd = (s[:, HEADING] + s[:, SWAY] for s in (s0, s1, s2))
    a, a_d, a_dd = (-body.pitch_coupling * s[:, PITCH] for s in (s0, s1, s2))
    thigh = Rotation.from_euler("ZY", np.column_stack([psi, a]))
    yaw = Rotation.from_euler("Z", psi[:, None])
    w = np.column_stack([-np.sin(a) * psi_d, a_d, np.cos(a) * psi_d])
    w_d = np.column_stack([-np.cos(a) * a_d * psi_d - np.sin(a) * psi_dd, a_dd,
                           -np.sin(a) * a_d * psi_d + np.cos(a) * psi_dd])
    ez = np.tile([0.0, 0.0, 1.0], (len(t), 1))
    h, r = body.hip_offset, body.lever_arm
    w_r = np.cross(w, r)
    position = s0[:, :3] + yaw.apply(h) + thigh.apply(r)
    velocity = s1[:, :3] + yaw.apply(psi_d[:, None] * np.cross(ez, h)) + thigh.apply(w_r)
    acceleration = (s2[:, :3]
                    + yaw.apply(psi_dd[:, None] * np.cross(ez, h)
                                + psi_d[:, None] ** 2 * np.cross(ez, np.cross(ez, h)))
                    + thigh.apply(np.cross(w_d, r) + np.cross(w, w_r)))
    attitude = thigh * Rotation.from_matrix(body.mounting)
    return SensorMotion(position, velocity, acceleration, attitude.as_quat(),
                        w @ body.mounting)


def kernel_motion(kernel, t, spline: ThighSpline, body: ThighBody) -> SensorMotion:
    out = SensorMotion.empty(len(t))
    kernel(np.ascontiguousarray(t, dtype=float), spline, body, out)
    return out


def assert_twins(kernel: SensorMotion, twin: SensorMotion, scale: float = 1.0) -> None:
    """Equal to the module docstring's tolerances; ``scale`` that of the rates."""
    np.testing.assert_allclose(kernel.position, twin.position, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(kernel.velocity, twin.velocity, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(kernel.acceleration, twin.acceleration, rtol=0,
                               atol=1e-9 * scale ** 2)
    np.testing.assert_allclose(kernel.body_rate, twin.body_rate, rtol=0, atol=1e-12 * scale)
    turned = Rotation.from_quat(kernel.quaternion).inv() * Rotation.from_quat(twin.quaternion)
    np.testing.assert_allclose(turned.magnitude(), 0.0, rtol=0, atol=1e-12)


def body_of(mounting: np.ndarray, hip, lever, coupling) -> ThighBody:
    return ThighBody(np.array(hip), np.array(lever), np.ascontiguousarray(mounting),
                     Rotation.from_matrix(mounting).as_quat(), coupling)


@st.composite
def splines(draw) -> ThighSpline:
    """K pieces 0.05–2 s long, coefficients up to 2 (channels in m and rad)."""
    k = draw(st.integers(1, 6))
    steps = draw(arrays(float, k, elements=st.floats(0.05, 2.0)))
    coeffs = draw(arrays(float, (4, k, 6), elements=st.floats(-2.0, 2.0)))
    return ThighSpline(np.concatenate([[0.0], np.cumsum(steps)]), coeffs)


vectors = st.tuples(*[st.floats(-0.5, 0.5)] * 3)


@settings(max_examples=100, deadline=None)
@given(spline=splines(), rotvec=st.tuples(*[st.floats(-3.0, 3.0)] * 3), hip=vectors,
       lever=vectors, coupling=st.sampled_from([1.0, 0.0]) | st.floats(0.0, 1.0),
       data=st.data())
def test_thigh_kinematics_is_its_twin(spline, rotvec, hip, lever, coupling, data):
    """Drawn splines, at times inside them, at their knots and beyond their ends (the end
    pieces extended); the scale the rates reach, |c|·(1 + piece length)³."""
    end = spline.breaks[-1]
    t = np.concatenate([data.draw(arrays(float, 20, elements=st.floats(-0.5, end + 0.5))),
                        spline.breaks])
    body = body_of(Rotation.from_rotvec(rotvec).as_matrix(), hip, lever, coupling)
    longest = np.max(np.diff(spline.breaks)) + 0.5
    assert_twins(kernel_motion(thigh_kinematics, t, spline, body),
                 sensor_motion(t, spline, body), scale=(1.0 + longest) ** 3 * 10.0)


WALK = {"name": "twin", "seed": 4, "mounting": {"rpy_deg": [20.0, -35.0, 110.0]},
        "segments": [{"type": "standing", "duration_s": 3},
                     {"type": "walk", "distance_m": 20, "speed_kmh": 4.0},
                     {"type": "turn", "angle_deg": 90, "steps": 2},
                     {"type": "stairs", "direction": "up", "flights": 1, "risers": 8,
                      "riser_m": 0.17},
                     {"type": "sitting", "duration_s": 5, "pitch_deg": 85},
                     {"type": "walk", "distance_m": 10, "speed_kmh": 3.0}]}


@pytest.fixture(scope="module")
def walk() -> ThighTrajectory:
    return ThighTrajectory(pocket_scenario_from_dict(WALK, "twin"))


def walk_inputs(model: ThighTrajectory, n: int):
    t = np.linspace(0.0, model.duration_s, n)
    return t, ThighSpline(model.spline.x, np.ascontiguousarray(model.spline.c)), model.body


def test_thigh_kinematics_is_its_twin_on_a_walk(walk):
    t, spline, body = walk_inputs(walk, 20001)
    assert_twins(kernel_motion(thigh_kinematics, t, spline, body),
                 sensor_motion(t, spline, body))


def test_the_centripetal_term_dropped_fails_its_twin(walk):
    """ω_t × (ω_t × r) left out of the sensor's acceleration."""
    wrong = perturbed(thigh_kinematics, compiled_thigh,
                      "wwr = _cross(w0, w1, w2, wr[0], wr[1], wr[2])", "wwr = (0.0, 0.0, 0.0)")
    t, spline, body = walk_inputs(walk, 2001)
    with pytest.raises(AssertionError, match="Not equal to tolerance"):
        assert_twins(kernel_motion(wrong, t, spline, body), sensor_motion(t, spline, body))
