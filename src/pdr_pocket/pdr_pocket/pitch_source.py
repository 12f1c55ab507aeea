"""The pocket navigator's sensors and pitch source (Muñoz Díaz 2016, chapter 3 and
Section 4.1.1): from a chunk of :class:`~pdr_pocket.samples.Samples` to the thigh's pitch
and heading, and the stream the step detector sees.

- the orientation filter (:mod:`pdr_pocket.orientation`, chapter 3), or without a
  gyroscope (``gyro`` None) the tilt of the gravity direction alone: the specific force
  through a second-order low-pass at ``gravity_cutoff_hz`` (1.5 Hz keeps the gait cycle's
  fundamental, 0.6–1.1 Hz, and drops the heel strikes and harmonics), with the heading
  unknown (yaw 0, σ 180°: the position's covariance says so);
- the thigh frame and pitch (:mod:`pdr_pocket.compiled_mounting`); samples seen while the
  axes are still being learned (the first ``flexion_min_s`` of walking) are kept for
  ``replay_s`` and given the axes once known, so the first steps are not lost;
- the time seen and moving, which say why no step was found;
- with a gyroscope, the footfalls the accelerometer hears apart from the pitch
  (pdr_pocket.steps.FootfallDetector on |f|): two per swing of a thigh's pitch, many more
  on a phone held in the hand (pdr_pocket.placement's "not in a pocket").

:class:`PitchSource` does it chunk by chunk (the same result whatever the chunks);
:class:`PitchChunk` is what it gives.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from pdr_core.maths.rotations import rotation_from_euler, tilt_from_specific_force
from pdr_pocket.compiled_gravity import gravity_loop, new_gravity_state
from pdr_pocket.compiled_mounting import (
    MountingInputs,
    MountingOutputs,
    MountingParams,
    mounting_loop,
    new_mounting_state,
    thigh_angles,
)
from pdr_pocket.config import PocketConfig
from pdr_pocket.orientation import AttitudeEstimate, OrientationFilter
from pdr_pocket.samples import Samples
from pdr_pocket.steps import FootfallDetector

THIGH_UP, THIGH_FLEXION = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])
GRAVITY_TILT_SIGMA_RAD = np.radians(5.0)    # tilt from the low-passed specific force
MOTION_TIME_CONSTANT_S = 0.5                # of the accelerometer's motion measure
# a cascade of two first-order low-passes has its −3 dB point at √(√2 − 1)/(2πτ)
CASCADE_FACTOR = np.sqrt(np.sqrt(2.0) - 1.0)
NO_GAIT_MIN_MOVING_S = 5.0                  # moving this long without a step: no thigh gait


class PitchStream(NamedTuple):
    """The samples the step detector sees, in order: their times ``t`` [s], the thigh's
    pitch θ and heading [rad], the vertical specific force and its norm ``forces``
    (M, 2) [m/s²], the yaw's and the tilt's variances ``variances`` (M, 2) [rad²]."""

    t: np.ndarray
    pitch: np.ndarray
    heading: np.ndarray
    forces: np.ndarray
    variances: np.ndarray


@dataclass(frozen=True)
class PitchChunk:
    """A chunk's attitude C_b^n per sample, the thigh's pitch and heading [rad] per sample
    (NaN while the axes are unknown), the tilt between the sensor's and the thigh's up
    [rad] per sample, the specific force along the navigation frame's up [m/s²] per
    sample, the mounting changes [s] found in it, and the detector's stream
    (:class:`PitchStream`), held samples replayed in it."""

    attitude: AttitudeEstimate
    pitch: np.ndarray
    heading: np.ndarray
    tilt: np.ndarray
    vertical_force: np.ndarray
    remounts_t: list[float]
    stream: PitchStream


def mounting_params(config: PocketConfig) -> MountingParams:
    """The thigh frame kernel's parameters from the configuration, in SI units."""
    m = config.mounting
    return MountingParams(
        fixed=m.rpy_deg is not None, gravity=config.orientation.gravity_mps2,
        rest_rate=np.radians(m.rest_rate_deg_per_s), rest_acc=m.rest_acc_mps2,
        rest_min_s=m.rest_min_s, standing_max_angle=np.radians(m.standing_max_angle_deg),
        moved_min_angle=np.radians(m.moved_min_angle_deg),
        moving_rate=np.radians(m.moving_rate_deg_per_s),
        flexion_tau_s=m.flexion_time_constant_s, flexion_min_s=m.flexion_min_s,
        turned_min_angle=np.radians(m.turned_min_angle_deg), turned_min_s=m.turned_min_s,
        turned_tau_s=m.turned_time_constant_s, turned_angle=np.radians(m.turned_angle_deg),
        turned_pitch_angle=np.radians(m.turned_pitch_angle_deg),
        walking_pitch=np.radians(m.walking_pitch_deg), skew_check=True)


def sample_turns(t: np.ndarray, gyro: np.ndarray | None, attitude: AttitudeEstimate,
                 previous: tuple | None) -> np.ndarray:
    """The phone's own turn over each sample, ω·δt in the sensor frame [rad], (N, 3):
    with a gyroscope the trapezoid of its rate less the filter's bias estimate, so that
    the filter's corrections (a tilt set right by a window of gait cycles, a heading by
    the field) are no turn of the phone in the pocket, and 0 where the gyroscope
    saturated (its turn there is unknown, the clipped rate short of it); without one,
    from consecutive attitudes, C_{k−1}ᵀ·C_k ≈ I + [ω·δt×]. ``previous``:
    (t, ω, C_b^n) of the sample before the first (None: the first turn is 0)."""
    n = len(t)
    c = attitude.attitude
    if previous is None:
        first_t, first_gyro, first_c = (t[0] if n else 0.0), None, (c[0] if n else None)
    else:
        first_t, first_gyro, first_c = previous
    dt = np.diff(t, prepend=first_t)[:, None]
    if gyro is not None:
        before = np.vstack([gyro[:1] if first_gyro is None else first_gyro[None], gyro[:-1]])
        turn = 0.5 * (before + gyro) * dt - attitude.bias * dt
        turn[attitude.detector("saturated")] = 0.0
        return turn
    last = np.concatenate([c[:1] if first_c is None else first_c[None], c[:-1]])
    r = np.einsum("nij,nik->njk", last, c)
    return 0.5 * np.stack([r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0],
                           r[:, 1, 0] - r[:, 0, 1]], axis=1)


def configured_axes(rpy_deg) -> tuple[np.ndarray, np.ndarray]:
    """u and f in the sensor frame of a mounting C_s^t given as ZYX roll, pitch, yaw."""
    c_s_t = rotation_from_euler(*np.radians(rpy_deg)).as_matrix()
    return c_s_t.T @ THIGH_UP, c_s_t.T @ THIGH_FLEXION


class PitchSource:
    """The sensors to the thigh's pitch, chunk by chunk (the module docstring)."""

    def __init__(self, config: PocketConfig) -> None:
        c = config
        self.config = config
        self.orientation = OrientationFilter(c.orientation)
        self.gravity_state = new_gravity_state()
        self.mounting_params = mounting_params(c)
        axes = configured_axes(c.mounting.rpy_deg) if c.mounting.rpy_deg is not None \
            else (None, None)
        self.mounting = new_mounting_state(*axes)
        self.pending: tuple | None = None       # (t, C, forces, variances) held
        self.changes_seen = 0.0
        self.seen_s = self.moving_s = 0.0       # data seen, and moving [s]
        self.last_t: float | None = None
        self.previous: tuple | None = None      # (t, ω, C_b^n) of the last sample seen
        self.footfall_ear = FootfallDetector(c.steps)   # |f|'s footfalls, with a gyroscope
        self.hears_footfalls = False            # a chunk with a gyroscope came

    def run(self, samples: Samples) -> PitchChunk:
        """The chunk's attitude, pitch and detector stream (:class:`PitchChunk`)."""
        t, accel, gyro = samples.t, np.ascontiguousarray(samples.accel, dtype=float), \
            samples.gyro
        if gyro is None:
            attitude, rate = self._gravity_tilt(t, accel)
        else:
            attitude = self.orientation.run(t, gyro, accel, samples.mag)
            rate = np.linalg.norm(gyro, axis=1)
        n = len(t)
        thigh = MountingOutputs.empty(n)
        pitch, heading, known, up, flex, changes = thigh
        # without a gyroscope the checks that read the phone's turns are off (the gravity
        # direction's pitch is too rough for them); the mean walking pitch's stays on: a
        # phone put in the pocket while walking leaves u at the first sample's force
        params = self.mounting_params if gyro is not None else \
            self.mounting_params._replace(turned_angle=np.inf, turned_min_s=np.inf,
                                          skew_check=False)
        turn = sample_turns(t, gyro, attitude, self.previous)
        self.previous = (t[-1], None if gyro is None else gyro[-1].copy(),
                         attitude.attitude[-1].copy()) if n else self.previous
        mounting_loop(self.mounting, params, MountingInputs(
            t, np.ascontiguousarray(rate), accel, attitude.attitude, turn), thigh)
        self._count_motion(t, rate)
        norm = np.linalg.norm(accel, axis=1)
        if gyro is not None:
            self.footfall_ear.push(t, pitch, norm)
            self.hears_footfalls = True
        remounts_t = t[np.flatnonzero(np.diff(changes, prepend=self.changes_seen))].tolist()
        self.changes_seen = changes[-1] if n else self.changes_seen
        # the vertical specific force (the stride model's range) and the norm (footfalls)
        forces = np.column_stack([np.einsum("nj,nj->n", attitude.attitude[:, 2, :], accel),
                                  norm])
        # per sample: the yaw's variance (the step's heading) and the tilt's (how far the
        # pitch can be trusted)
        variances = np.column_stack([attitude.covariance[:, 2, 2],
                                     np.maximum(attitude.covariance[:, 0, 0],
                                                attitude.covariance[:, 1, 1])])
        stream = self._stream(t, attitude.attitude, forces, variances, pitch, heading, known,
                              up, flex)
        tilt = np.arccos(np.clip(np.einsum("nj,nj->n", attitude.attitude[:, 2, :], up), -1, 1))
        return PitchChunk(attitude, pitch, heading, tilt, forces[:, 0], remounts_t, stream)

    def _count_motion(self, t: np.ndarray, rate: np.ndarray) -> None:
        """Add the chunk's time, and its time moving (the turn rate, or without a
        gyroscope the accelerometer's motion measure, above ``moving_rate_deg_per_s``)."""
        if not len(t):
            return
        dt = np.diff(t, prepend=t[0] if self.last_t is None else self.last_t)
        self.last_t = float(t[-1])
        self.seen_s += float(dt.sum())
        self.moving_s += float(dt[rate > np.radians(
            self.config.mounting.moving_rate_deg_per_s)].sum())

    @property
    def heard_footfalls(self) -> int | None:
        """The footfalls the accelerometer heard so far, apart from the pitch (None
        without a gyroscope: then they are the steps themselves)."""
        return self.footfall_ear.footfalls if self.hears_footfalls else None

    def no_step_reason(self, stepped: bool) -> str | None:
        """Why no step was found, when none was (``stepped`` False; None otherwise): the
        signals were still (standing, or stamps in the wrong unit), or something moved that
        was no thigh's gait (the phone in a hand or a bag)."""
        if stepped:
            return None
        if self.moving_s < NO_GAIT_MIN_MOVING_S:
            return (f"no walking found: the signals were still for {self.seen_s:.1f} s "
                    f"(moving {self.moving_s:.1f} s; standing, or a time column in the wrong "
                    "unit?)")
        return (f"motion but no thigh gait: {self.moving_s:.1f} s of {self.seen_s:.1f} s "
                "moving without a step; is the phone in a trouser pocket?")

    def _gravity_tilt(self, t: np.ndarray, accel: np.ndarray
                      ) -> tuple[AttitudeEstimate, np.ndarray]:
        """Without a gyroscope: C_b^n of the gravity direction's tilt (yaw 0, unknown) and
        the motion measure scaled to a turn rate for the thigh frame's rest and motion
        tests. Its vertical, the low-passed specific force, carries the legs' accelerations,
        too rough for the walking checks of a phone turned in the pocket: they are off, and
        a moved phone is found at the next rest."""
        m = self.config.mounting
        n = len(t)
        gravity, motion = np.empty((n, 3)), np.empty(n)
        tau = CASCADE_FACTOR / (2 * np.pi * m.gravity_cutoff_hz)
        gravity_loop(self.gravity_state, tau, MOTION_TIME_CONSTANT_S, t, accel, gravity, motion)
        roll, pitch = tilt_from_specific_force(gravity)
        c = rotation_from_euler(roll, pitch, np.zeros(n)).as_matrix().reshape(n, 3, 3)
        covariance = np.zeros((n, 6, 6))
        covariance[:, 0, 0] = covariance[:, 1, 1] = GRAVITY_TILT_SIGMA_RAD**2
        covariance[:, 2, 2] = np.pi**2
        attitude = AttitudeEstimate(t, c, np.zeros((n, 3)), covariance,
                                    np.zeros((n, 0), dtype=bool), np.zeros((n, 0), dtype=bool))
        scale = np.radians(m.moving_rate_deg_per_s) / m.accel_motion_mps2
        return attitude, motion * scale

    def _stream(self, t, c, forces, variances, pitch, heading, known, up, flex):
        """The samples the detector sees (:class:`PitchStream`), with the pending samples
        given the axes of the first known sample after them. Runs of known and unknown
        samples are taken whole."""
        change = np.flatnonzero(np.diff(known.astype(np.int8))) + 1
        segments = []
        for a, b in zip([0, *change], [*change, len(t)], strict=True):
            if a == b:
                continue
            if not known[a]:
                self._hold(t[a:b], c[a:b], forces[a:b], variances[a:b])
                continue
            if self.pending is not None:
                segments.append(self._replay(up[a], flex[a], t, pitch, heading))
            segments.append((t[a:b], pitch[a:b], heading[a:b], forces[a:b], variances[a:b]))
        if not segments:
            return PitchStream(*(np.empty(0) for _ in range(3)), np.empty((0, 2)),
                               np.empty((0, 2)))
        return PitchStream(*(np.concatenate(parts) for parts in zip(*segments, strict=True)))

    def _hold(self, t, c, forces, variances) -> None:
        """Keep samples while the axes are unknown, the last ``replay_s`` of them."""
        held = (t, c, forces, variances) if self.pending is None else tuple(
            np.concatenate([old, new]) for old, new in
            zip(self.pending, (t, c, forces, variances), strict=True))
        first = np.searchsorted(held[0], held[0][-1] - self.config.mounting.replay_s,
                                side="left")
        self.pending = tuple(x[first:] for x in held)

    def _replay(self, up, flex, t, pitch, heading):
        """The held samples with the axes now known; those of this chunk are reported."""
        tp, cp, vp, yp = self.pending
        self.pending = None
        angles = np.array([thigh_angles(c, up, flex) for c in cp]).reshape(-1, 2)
        mine = tp >= t[0]
        index = np.searchsorted(t, tp[mine])
        pitch[index], heading[index] = angles[mine, 0], angles[mine, 1]
        return tp, angles[:, 0], angles[:, 1], vp, yp
