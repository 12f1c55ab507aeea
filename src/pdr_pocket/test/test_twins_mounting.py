"""The NumPy twin of the thigh frame: :func:`pdr_pocket.compiled_mounting.mounting_loop`
(the long axis u from the rests, the flexion axis f from the swing of the vertical, the
phone turned in the pocket, θ and the thigh's heading; Muñoz Díaz 2016, Section 4.1.3 and
Fig. 4.1) against :class:`ThighFrame`, plain Python written from the module's docstrings:
the axes by ``numpy.linalg.eigh`` where the kernel has its closed-form 2 × 2 eigenvector,
the ring of anchors as a deque. Its helpers are compared on hypothesis-drawn attitudes
and axes, the loop on drawn swings and on simulated pocket walks (a remount while
walking and one at a stop, sitting, a walk from a chair, no gyroscope), whole and split
into chunks. Not bit for bit: the eigenvectors come from other arithmetic, and f is only
known up to its sign until the walk's mean pitch gives it, so the axes and angles agree to
1e-9 (a rounding error of the weighted covariance, about 1e-16, turned by the
eigenvector's sensitivity) and the decisions (axes known, the changes counted) exactly.
The last test changes one line of the kernel (the second moment of the vertical in place
of its covariance, which the docstring warns against) and shows that the twin then fails.
"""
from __future__ import annotations

import itertools
import math
from collections import deque

import numpy as np
import pytest
from hypothesis import Phase, assume, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from pdr_core.maths.angles import wrap_angle
from pdr_pocket import compiled_mounting as km
from pdr_pocket.compiled_mounting import (
    MountingInputs,
    MountingOutputs,
    mounting_loop,
    new_mounting_state,
)
from pdr_pocket.config import PocketConfig
from pdr_pocket.pitch_source import mounting_params
from pdr_sim import signals
from pdr_sim.pocket_scenario import pocket_scenario_from_dict
from pdr_sim.thigh_trajectory import ThighTrajectory

TOLERANCE = 1e-9
NO_SHRINKING = (Phase.explicit, Phase.reuse, Phase.generate)   # a walk shrinks for minutes
PARAMS = mounting_params(PocketConfig())


def unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v)
    return v / n if n > 0 else v


def continued(last: float, angle: float) -> float:
    """θ taken 2π at a time to the nearest of the last θ (NaN: as it is)."""
    return angle if math.isnan(last) or math.isnan(angle) else last + wrap_angle(angle - last)


def signed_axes(up, flex_raw, sign):
    """u and f: f made orthogonal to u, unit, with its sign."""
    return up, unit(flex_raw - (flex_raw @ up) * up) * sign


def angles(c, up, flex) -> tuple[float, float]:
    """θ = atan2(−ℓ·h, ℓ_z), ℓ = C·u, h the unit horizontal of C·(f × u); heading atan2(h)."""
    long_n, forward_n = c @ up, c @ np.cross(flex, up)
    length = np.linalg.norm(forward_n[:2])
    if length < 1e-9:
        return math.nan, math.nan
    h = forward_n[:2] / length
    return math.atan2(-(long_n[:2] @ h), long_n[2]), math.atan2(h[1], h[0])


def least_swung_axis(spread, up) -> np.ndarray:
    """u × d, d the major eigenvector of the spread restricted to the plane ⊥ u."""
    across = np.eye(3) - np.outer(up, up)
    d = np.linalg.eigh(across @ spread @ across)[1][:, -1]
    return unit(np.cross(up, d))


def swing_angle(g, up, flex) -> float:
    """φ about f from the mean vertical's part ⊥ f to u."""
    gp = unit(g - (g @ flex) * flex)
    return math.atan2(np.cross(gp, up) @ flex, gp @ up)


def about(flex, g, angle) -> np.ndarray:
    """The vertical's part ⊥ f turned by ``angle`` about f: where u goes."""
    gp = unit(g - (g @ flex) * flex)
    return math.cos(angle) * gp + math.sin(angle) * np.cross(flex, gp)


class ThighFrame:
    """The thigh frame learned sample by sample, the state as plain attributes."""

    def __init__(self, params) -> None:
        self.p = params
        self.started = self.provisional = self.known = self.turn_seen = False
        self.falling = False
        self.last_t = self.rest_s = self.moving_s = self.mean_pitch = 0.0
        self.recent_s = self.last_check_t = self.turned_s = self.foreign = 0.0
        self.turn_t = self.flip_s = self.seated_s = self.rate2 = self.rate3 = 0.0
        self.change_t, self.changes, self.sign = 0.0, 0, 1.0
        self.change_due, self.last_pitch = km.NO_CHANGE, math.nan
        self.rest_sum, self.up, self.flex_raw = np.zeros(3), np.zeros(3), np.zeros(3)
        self.moment, self.mean = np.zeros((3, 3)), np.zeros(3)
        self.recent, self.recent_mean = np.zeros((3, 3)), np.zeros(3)
        self.anchors: deque = deque(maxlen=km.ANCHOR_RING)   # (φ, heading, t), oldest first
        self.taken: list[int] = []          # the kinds of change taken (for the tests)

    def run(self, t, rate, accel, attitude, turn) -> MountingOutputs:
        out = MountingOutputs.empty(len(t))
        for k in range(len(t)):
            self.step(k, t[k], rate[k], accel[k], attitude[k], turn[k], out)
        return out

    def step(self, k, now, w, a, c, turn, out) -> None:
        dt = now - self.last_t if self.started else 0.0
        self.last_t = now
        changes = self.changes
        if not self.p.fixed:
            if not self.started:
                self.up, self.provisional, self.started = unit(a), True, True
            self.rest(w, a, dt)
            self.foreign_turn(w, dt, c, turn)
            self.motion(w, dt, c)
            self.change_when_due(c)
        if self.changes != changes:
            self.last_pitch = math.nan
        up, flex = signed_axes(self.up, self.flex_raw, self.sign)
        out.up[k], out.flex[k], out.known[k], out.changes[k] = up, flex, self.known, self.changes
        if self.known:
            pitch, out.heading[k] = angles(c, up, flex)
            out.pitch[k] = continued(self.last_pitch, pitch)
            self.falling = out.pitch[k] < self.last_pitch
            self.last_pitch = out.pitch[k]

    def rest(self, w, a, dt) -> None:
        """A rest of rest_min_s: the first gives u, a standing one refines it, one out of
        the swing plane resets the mounting."""
        p = self.p
        if w >= p.rest_rate or abs(np.linalg.norm(a) - p.gravity) >= p.rest_acc:
            self.rest_s, self.rest_sum = 0.0, np.zeros(3)
            return
        self.rest_s += dt
        self.rest_sum = self.rest_sum + a
        if self.rest_s < p.rest_min_s:
            return
        g = unit(self.rest_sum)
        if self.provisional or g @ self.up >= math.cos(p.standing_max_angle):
            self.up, self.provisional = g, False
        elif self.known and abs(g @ signed_axes(self.up, self.flex_raw, 1.0)[1]) > \
                math.sin(p.moved_min_angle):
            self.up, self.known, self.moving_s, self.mean_pitch = g, False, 0.0, 0.0
            self.changes += 1
            self.moment, self.mean, self.flex_raw = np.zeros((3, 3)), np.zeros(3), np.zeros(3)

    def foreign_turn(self, w, dt, c, turn) -> None:
        """The turn about f × (vertical ⊥ f), leaky-integrated; the pitch rate's moments."""
        if dt > 0 and self.known and w > self.p.moving_rate:
            f = signed_axes(self.up, self.flex_raw, self.sign)[1]
            normal = unit(np.cross(f, c[2] - (c[2] @ f) * f))
            self.foreign = math.exp(-dt / km.FOREIGN_TAU_S) * self.foreign + turn @ normal
            if not self.turn_seen and abs(self.foreign) > self.p.turned_angle:
                self.seen_turn(self.last_t)
            pitch_rate = -(turn @ f) / dt
            lam = math.exp(-dt / km.SKEW_TAU_S)
            self.rate2 = lam * self.rate2 + (1.0 - lam) * pitch_rate ** 2
            self.rate3 = lam * self.rate3 + (1.0 - lam) * pitch_rate ** 3
        if self.turn_seen and self.last_t - self.turn_t < km.TURN_HOLD_S:
            self.forget_recent()

    def seen_turn(self, began) -> None:
        self.turn_seen, self.turn_t, self.turned_s = True, began, 0.0
        self.forget_recent()

    def forget_recent(self) -> None:
        self.recent_s, self.recent, self.recent_mean = 0.0, np.zeros((3, 3)), np.zeros(3)

    def motion(self, w, dt, c) -> None:
        """The vertical's weighted mean and second moment (long and recent); f from its
        covariance; f's sign from the mean pitch after flexion_min_s."""
        p = self.p
        if w <= p.moving_rate or dt <= 0:
            return
        g = c[2]
        lam = math.exp(-dt / p.flexion_tau_s)
        self.mean = lam * self.mean + (1.0 - lam) * g
        self.moment = lam * self.moment + (1.0 - lam) * np.outer(g, g)
        lam = math.exp(-dt / p.turned_tau_s)
        self.recent_mean = lam * self.recent_mean + (1.0 - lam) * g
        self.recent = lam * self.recent + (1.0 - lam) * np.outer(g, g)
        self.recent_s += dt
        v = least_swung_axis(self.moment - np.outer(self.mean, self.mean), self.up)
        self.flex_raw = -v if v @ self.flex_raw < 0 else v
        if self.known:
            self.check_turned(c)
            return
        self.moving_s += dt
        pitch = angles(c, *signed_axes(self.up, self.flex_raw, 1.0))[0]
        if math.isfinite(pitch):
            self.mean_pitch += pitch * dt
        if self.moving_s >= p.flexion_min_s:
            self.sign, self.known = (1.0 if self.mean_pitch >= 0 else -1.0), True

    def check_turned(self, c) -> None:
        """Every CHECK_PERIOD_S of a planar recent swing: a turn seen (remount), a seated
        start, f reversed, or a swing about another axis or at another mean pitch."""
        p = self.p
        if self.change_due or self.recent_s < p.turned_tau_s or \
                self.last_t - self.last_check_t < km.CHECK_PERIOD_S:
            return
        self.last_check_t = self.last_t
        values, vectors = np.linalg.eigh(self.recent)
        if values[1] < km.SWING_MIN or values[0] > km.PLANAR_RATIO * values[1]:
            return
        up, flex = signed_axes(self.up, self.flex_raw, self.sign)
        if self.turn_seen:
            self.decide(km.REMOUNT)
            return
        phi = swing_angle(self.recent_mean, up, flex)
        skew = self.rate2 ** 1.5 * km.SKEW_FLIP if p.skew_check else math.inf
        self.flip_s = self.flip_s + km.CHECK_PERIOD_S if phi > 0 or self.rate3 < -skew \
            else 0.0
        self.seated_s = self.seated_s + km.CHECK_PERIOD_S if -phi > p.turned_pitch_angle \
            else 0.0
        if self.seated_s >= km.SEATED_MIN_S:
            self.seated_s = 0.0
            self.decide(km.REORIENT)
            return
        axis = vectors[:, 0]
        same_axis = abs(axis @ flex) >= math.cos(p.turned_min_angle) and \
            abs(axis @ up) <= math.sin(p.turned_min_angle)
        same_pitch = not self.anchors or \
            abs(wrap_angle(phi - self.anchors[0][0])) <= p.turned_pitch_angle
        if same_axis and same_pitch:
            self.turned_s = 0.0
            if self.flip_s >= km.FLIP_MIN_S:
                self.decide(km.REORIENT_FLIPPED if self.rate3 <= skew else km.REORIENT)
                return
            heading = angles(c, up, flex)[1]
            if math.isfinite(heading):
                self.anchors.append((swing_angle(self.mean, up, flex), heading, self.last_t))
            return
        self.turned_s += km.CHECK_PERIOD_S
        if self.turned_s >= p.turned_min_s:
            self.seen_turn(self.last_t - p.turned_min_s - p.turned_tau_s)

    def decide(self, change) -> None:
        self.change_due, self.change_t = change, self.last_t

    def change_when_due(self, c) -> None:
        """New axes at the swing's minimum (θ stops falling) or after CHANGE_WAIT_S."""
        if self.change_due == km.NO_CHANGE:
            return
        up, flex = signed_axes(self.up, self.flex_raw, self.sign)
        pitch = continued(self.last_pitch, angles(c, up, flex)[0])
        if not ((self.falling and pitch >= self.last_pitch)
                or self.last_t - self.change_t >= km.CHANGE_WAIT_S):
            return
        self.taken.append(self.change_due)
        if self.change_due == km.REMOUNT:
            self.remount(c, np.linalg.eigh(self.recent)[1][:, 0], up, flex)
        else:
            self.reorient(self.change_due == km.REORIENT_FLIPPED, flex)
        self.change_due = km.NO_CHANGE

    def reorient(self, flip, flex) -> None:
        """f reversed if ``flip``, u about it at the level walking pitch from the mean
        vertical."""
        f = -flex if flip else flex
        self.up = about(f, self.recent_mean, -abs(self.p.walking_pitch))
        self.flex_raw, self.sign, self.flip_s = f, 1.0, 0.0
        if flip:
            self.rate3 = -self.rate3
        self.anchors.clear()
        self.changes += 1

    def remount(self, c, axis, up, flex) -> None:
        """f along the recent swing axis, u at the anchored φ from the recent mean vertical,
        the sign of f that keeps the anchor's thigh heading; only a material change."""
        self.turned_s, self.turn_seen = 0.0, False
        if not self.anchors:
            return
        before = [row for row in self.anchors if row[2] <= self.turn_t - km.ANCHOR_LEAD_S]
        phi, heading, _ = before[-1] if before else self.anchors[0]
        g = unit(self.recent_mean)
        scored = [(math.cos(angles(c, u, f)[1] - heading), u, f)
                  for u, f in ((about(f, g, phi), f) for f in (axis, -axis))]
        scored = [row for row in scored if math.isfinite(row[0])]
        _, new_up, new_flex = max(scored, key=lambda row: row[0]) if scored else (0, up, flex)
        material = math.cos(self.p.turned_min_angle / 2)
        if new_up @ up >= material and new_flex @ flex >= material:
            return
        self.up, self.flex_raw, self.sign = new_up, new_flex, 1.0
        self.moment, self.mean = self.recent.copy(), self.recent_mean.copy()
        self.rate2 = self.rate3 = 0.0
        self.provisional = False
        self.anchors.clear()
        self.changes += 1


# --- inputs ---------------------------------------------------------------------------
def walk_inputs(segments, mounting, remounts=(), seed=5) -> MountingInputs:
    """A simulated pocket walk at 100 Hz (pdr_sim): the true attitude, specific force,
    ‖ω‖ and the trapezoid ω·δt, as the navigator hands them to the kernel."""
    scenario = {"name": "twin", "seed": seed, "mounting": {"rpy_deg": mounting},
                "remounts": list(remounts), "segments": segments}
    traj = ThighTrajectory(pocket_scenario_from_dict(scenario, "twin")).sample(100.0)
    return kinematic_inputs(traj.t, traj.attitude.as_matrix(), signals.specific_force(traj),
                            traj.body_rate)


def kinematic_inputs(t, attitude, accel, rate) -> MountingInputs:
    dt = np.diff(t, prepend=t[0])[:, None]
    turn = 0.5 * (np.vstack([rate[:1], rate[:-1]]) + rate) * dt
    return MountingInputs(np.ascontiguousarray(t), np.linalg.norm(rate, axis=1),
                          np.ascontiguousarray(accel), np.ascontiguousarray(attitude), turn)


def chunk(inputs: MountingInputs, part: slice) -> MountingInputs:
    return MountingInputs(*(np.ascontiguousarray(x[part]) for x in inputs))


def kernel_outputs(loop, inputs: MountingInputs, params=PARAMS, splits=()) -> MountingOutputs:
    """``loop`` over the inputs in chunks cut at ``splits``, the state carried between."""
    state = new_mounting_state()
    state = state._replace(scalars=state.scalars.view(np.recarray))  # plain copies read it
    bounds = [0, *splits, len(inputs.t)]
    parts = []
    for start, stop in itertools.pairwise(bounds):
        out = MountingOutputs.empty(stop - start)
        loop(state, params, chunk(inputs, slice(start, stop)), out)
        parts.append(out)
    return MountingOutputs(*(np.concatenate(x) for x in zip(*parts, strict=True)))


def assert_twins(kernel: MountingOutputs, twin: MountingOutputs) -> None:
    """Equal decisions, equal axes and angles to TOLERANCE; f up to its sign until known."""
    np.testing.assert_array_equal(kernel.known, twin.known)
    np.testing.assert_array_equal(kernel.changes, twin.changes)
    unsigned = np.where(kernel.known, 1.0, np.sign(np.einsum("ij,ij->i", kernel.flex,
                                                               twin.flex)))
    for name in ("pitch", "heading"):
        assert_same_angles(getattr(kernel, name), getattr(twin, name), TOLERANCE, name)
    for name, value, expected in (("up", kernel.up, twin.up),
                                  ("flex", kernel.flex * unsigned[:, None], twin.flex)):
        np.testing.assert_allclose(value, expected, rtol=0, atol=TOLERANCE, err_msg=name)


def assert_same_angles(value, expected, tolerance, name="") -> None:
    """Equal angles [rad] (NaN where the other is NaN), ±π being one angle."""
    value, expected = np.asarray(value), np.asarray(expected)
    np.testing.assert_array_equal(np.isnan(value), np.isnan(expected), err_msg=name)
    difference = wrap_angle(np.nan_to_num(value) - np.nan_to_num(expected))
    np.testing.assert_allclose(difference, 0.0, rtol=0, atol=tolerance, err_msg=name)


# --- the helpers ----------------------------------------------------------------------
rotations = st.builds(lambda v: Rotation.from_rotvec(v).as_matrix(),
                      st.tuples(*[st.floats(-3.0, 3.0)] * 3).map(np.array))
directions = st.tuples(*[st.floats(-1.0, 1.0)] * 3).map(np.array).filter(
    lambda v: np.linalg.norm(v) > 0.1).map(unit)


@settings(max_examples=60, deadline=None)
@given(c=rotations, up=directions, flex=directions, sign=st.sampled_from([1.0, -1.0]))
def test_the_thigh_angles_are_their_twins(c, up, flex, sign):
    """θ and heading of u and f (f ⊥ u by _thigh_axes), and φ of the vertical; not for a
    long axis lying along the horizontal lateral direction, where θ is undefined."""
    u, f = km._thigh_axes(up, flex, sign)
    twin_u, twin_f = signed_axes(up, flex, sign)
    long_n, forward_n = c @ twin_u, c @ np.cross(twin_f, twin_u)
    across = np.linalg.norm(forward_n[:2])
    assume(across > 1e-6 and np.hypot(long_n[:2] @ forward_n[:2] / across, long_n[2]) > 1e-6)
    np.testing.assert_allclose(np.r_[u, f], np.r_[twin_u, twin_f], rtol=0, atol=1e-15)
    assert_same_angles(km.thigh_angles(c, u, f), angles(c, twin_u, twin_f), 1e-12)
    assert km._swing_angle(c[2], u, f) == pytest.approx(swing_angle(c[2], twin_u, twin_f),
                                                        abs=1e-12)


@settings(max_examples=60, deadline=None)
@given(up=directions, axes=rotations, spread=st.tuples(*[st.floats(0.0, 1.0)] * 3),
       last=st.floats(-50.0, 50.0), angle=st.floats(-4.0, 4.0))
def test_the_least_swung_axis_and_the_continued_angle_are_their_twins(up, axes, spread,
                                                                       last, angle):
    """The closed-form 2 × 2 eigenvector against eigh (up to its sign, which f's sign
    fixes later), with its eigenvalues at least 1 % apart; θ continued through ±π."""
    values = np.sort(spread)[::-1]
    across = np.eye(3) - np.outer(up, up)
    projected = np.linalg.eigvalsh(across @ (axes * values) @ axes.T @ across)
    if projected[2] - projected[1] > 0.01 * projected[2] > 1e-6:
        kernel = km._least_swung_axis((axes * values) @ axes.T, up)
        assert abs(kernel @ least_swung_axis((axes * values) @ axes.T, up)) == \
            pytest.approx(1.0, abs=1e-9)
    assert km._continued(last, angle) == pytest.approx(continued(last, angle), abs=1e-12)


# --- the loop -------------------------------------------------------------------------
@pytest.fixture(scope="module")
def remounted() -> MountingInputs:
    """Standing, a walk with the phone turned in the pocket at 35 s, sitting, a walk."""
    return walk_inputs([{"type": "standing", "duration_s": 4},
                        {"type": "walk", "distance_m": 50, "speed_kmh": 4.0},
                        {"type": "sitting", "duration_s": 8, "pitch_deg": 80},
                        {"type": "walk", "distance_m": 15},
                        {"type": "standing", "duration_s": 2}],
                       [20.0, -35.0, 110.0],
                       [{"at_s": 35, "duration_s": 1, "mounting": {"rpy_deg": [60, 10, 20]}}])


@pytest.fixture(scope="module")
def from_a_chair() -> MountingInputs:
    """A walk from a chair: the first rest is sitting (u seated, then put right)."""
    return walk_inputs([{"type": "sitting", "duration_s": 4, "pitch_deg": 85},
                        {"type": "walk", "distance_m": 30, "speed_kmh": 3.5},
                        {"type": "standing", "duration_s": 2}], [-70.0, 15.0, 200.0], seed=8)


def test_mounting_loop_is_its_twin_with_the_phone_turned_while_standing():
    """Turned in the pocket at a stop: the turn is seen at once, the axes are derived again
    from the next walk's swing, and f then turns round (its mean pitch negative)."""
    inputs = walk_inputs([{"type": "standing", "duration_s": 3},
                          {"type": "walk", "distance_m": 20, "speed_kmh": 4.0},
                          {"type": "standing", "duration_s": 6},
                          {"type": "walk", "distance_m": 15}],
                         [20.0, -35.0, 110.0],
                         [{"at_s": 22, "duration_s": 1,
                           "mounting": {"rpy_deg": [-60, 40, 200]}}], seed=3)
    twin = ThighFrame(PARAMS)
    expected = twin.run(*inputs)
    assert twin.taken == [km.REMOUNT, km.REORIENT_FLIPPED]
    assert_twins(kernel_outputs(mounting_loop, inputs, splits=(2500,)), expected)


def test_mounting_loop_is_its_twin_through_a_remount(remounted):
    twin = ThighFrame(PARAMS)
    expected = twin.run(*remounted)
    assert twin.taken == [km.REMOUNT] and expected.known.mean() > 0.9
    assert_twins(kernel_outputs(mounting_loop, remounted), expected)
    assert_twins(kernel_outputs(mounting_loop, remounted, splits=(1, 3000, 3001, 5555)),
                 expected)


def test_mounting_loop_is_its_twin_on_a_walk_from_a_chair(from_a_chair):
    twin = ThighFrame(PARAMS)
    expected = twin.run(*from_a_chair)
    assert km.REORIENT in twin.taken
    assert_twins(kernel_outputs(mounting_loop, from_a_chair, splits=(777,)), expected)


def test_mounting_loop_is_its_twin_without_a_gyroscope(remounted):
    """The parameters the navigator gives without a gyroscope: no turn checks, no skew."""
    params = PARAMS._replace(turned_angle=np.inf, turned_min_s=np.inf, skew_check=False)
    assert_twins(kernel_outputs(mounting_loop, remounted, params), ThighFrame(params).run(
        *remounted))


@settings(max_examples=10, deadline=None, phases=NO_SHRINKING)
@given(mounting=rotations, amplitude=st.floats(0.2, 0.7), offset=st.floats(-0.3, 0.3),
       period=st.floats(0.9, 1.4), sway=st.floats(0.0, 0.2), stand=st.floats(0.0, 3.0),
       rate_hz=st.sampled_from([50.0, 100.0]))
def test_mounting_loop_is_its_twin_on_drawn_swings(mounting, amplitude, offset, period,
                                                   sway, stand, rate_hz):
    """A thigh standing, then swinging θ = offset + amplitude·sin about its flexion axis
    with a yaw sway, the phone at a drawn mounting C_s^t (no lever arm: the specific force
    is gravity). The swing starts off θ = 0: a first moving sample with the vertical along
    u has no swing axis (the spread ⊥ u is zero), and kernel and twin pick different ones."""
    t = np.arange(0.0, stand + 12.0, 1.0 / rate_hz)
    moving = t >= stand
    phase = 2.0 * np.pi * (t - stand) / period + 0.5
    theta = np.where(moving, offset + amplitude * np.sin(phase), 0.0)
    psi = np.where(moving, sway * np.sin(0.5 * phase), 0.0)
    thigh = Rotation.from_euler("ZY", np.column_stack([psi, -theta]))
    sensor = thigh * Rotation.from_matrix(mounting)
    omega = 2.0 * np.pi / period * moving
    theta_d, psi_d = omega * amplitude * np.cos(phase), omega * sway * 0.5 * np.cos(0.5 * phase)
    rate_thigh = np.column_stack([np.sin(theta) * psi_d, -theta_d, np.cos(theta) * psi_d])
    inputs = kinematic_inputs(t, sensor.as_matrix(), sensor.inv().apply([0.0, 0.0, 9.80665]),
                              rate_thigh @ mounting)
    assert_twins(kernel_outputs(mounting_loop, inputs), ThighFrame(PARAMS).run(*inputs))


def test_the_second_moment_for_the_covariance_fails_its_twin(perturb, remounted):
    """f from ∑ggᵀ without its mean: the axis leans, θ moves by degrees (module docstring)."""
    wrong_motion = perturb(km._motion, km,
                           "spread = state.moment - np.outer(state.mean, state.mean)",
                           "spread = state.moment")
    wrong_loop = perturb(mounting_loop, km, "_motion(state, params, w, dt, attitude[k])",
                         "wrong_motion(state, params, w, dt, attitude[k])",
                         calls={"wrong_motion": wrong_motion})
    walk = chunk(remounted, slice(0, 2000))
    expected = ThighFrame(PARAMS).run(*walk)
    with pytest.raises(AssertionError, match="Not equal to tolerance"):
        assert_twins(kernel_outputs(wrong_loop, walk), expected)
