"""The orientation filter of the pocket navigator (Muñoz Díaz 2016, chapter 3).

:class:`OrientationFilter` wraps the compiled loop (:mod:`pdr_pocket.compiled_orientation`,
whose docstring gives the equations): :meth:`~OrientationFilter.run` processes whole
arrays or any run of samples after the last, with the same state and the same result
(the live path feeds it in chunks), :meth:`~OrientationFilter.correct_yaw` and
:meth:`~OrientationFilter.correct_bias_z` apply external corrections (Eq. (6.2)) as
Kalman updates, refused when they fail a χ² gate (:meth:`~OrientationFilter.gate` and
:meth:`~OrientationFilter.apply` do the two apart).

Frames and units: body (sensor) frame as the IMU gives it, ENU navigation frame; SI
inside (rad, rad/s, m/s², T). The filter starts on its first sample: roll and pitch from
that sample's specific force (Eqs. (3.12)-(3.13)), yaw from the compass when a
magnetometer reading comes with it and no ``initial_yaw_deg`` is set (else 0), biases 0.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdr_core.angles import wrap_angle
from pdr_core.chi2 import chi2_quantile
from pdr_core.rotations import rotation_from_euler, tilt_from_specific_force
from pdr_pocket import compiled_orientation as kernel
from pdr_pocket.compiled_orientation import (
    ATT_EAST,
    ATT_NORTH,
    ATT_ROWS,
    ATT_UP,
    BIAS_ROWS,
    BIAS_Z,
    BIAS_Z_CORRECTION,
    N_DETECTORS,
    N_STATE,
    N_UPDATES,
    YAW_CORRECTION,
    FilterInputs,
    FilterOutputs,
    FilterState,
    compass_yaw,
    initial_state,
)
from pdr_pocket.config import OrientationConfig

GATE_PROBABILITY = 0.999            # χ² gate of external corrections (1 dof)
# the external corrections' names and units, in messages
CORRECTION_NAMES = {YAW_CORRECTION: ("yaw", "rad"), BIAS_Z_CORRECTION: ("z gyro bias", "rad/s")}
FLAT_TOP_MIN_RADPS = 2.0            # a repeated reading above this is a saturated flat top
UPDATE_NAMES = ("absolute_gravity", "differential_gravity", "absolute_magnetic",
                "differential_magnetic", "compass", "zaru", "mean_gravity")


@dataclass(frozen=True)
class AttitudeEstimate:
    """Per sample: C_b^n (N, 3, 3), gyro bias (N, 3) [rad/s], covariance (N, 6, 6) of
    [δθ (navigation frame, rad), δb (rad/s)], the detectors (N, 4: zero acceleration,
    zero rate, steady field, saturated gyro) and the updates that ran (N, 7, in the order
    of :data:`UPDATE_NAMES`)."""

    t: np.ndarray
    attitude: np.ndarray
    bias: np.ndarray
    covariance: np.ndarray
    detected: np.ndarray
    ran: np.ndarray

    @property
    def euler(self) -> np.ndarray:
        """Roll, pitch, yaw [rad], (N, 3); yaw in (−π, π]."""
        c = self.attitude
        return np.stack([np.arctan2(c[:, 2, 1], c[:, 2, 2]),
                         -np.arcsin(np.clip(c[:, 2, 0], -1.0, 1.0)),
                         np.arctan2(c[:, 1, 0], c[:, 0, 0])], axis=1)

    @property
    def euler_sigma(self) -> np.ndarray:
        """1σ of roll, pitch, yaw [rad], (N, 3), mapped from the navigation-frame error
        (cos θ bounded away from 0: at θ = ±90° the split between roll and yaw is
        undefined)."""
        roll, pitch, yaw = self.euler.T
        cp = np.maximum(np.abs(np.cos(pitch)), 1e-3)
        # d[φ, θ, ψ] = E·δθ with δθ a navigation-frame rotation (ZYX angles)
        e = np.zeros((len(roll), 3, 3))
        e[:, 0, 0], e[:, 0, 1] = np.cos(yaw) / cp, np.sin(yaw) / cp
        e[:, 1, 0], e[:, 1, 1] = -np.sin(yaw), np.cos(yaw)
        e[:, 2, 0], e[:, 2, 1] = np.cos(yaw) * np.tan(pitch), np.sin(yaw) * np.tan(pitch)
        e[:, 2, 2] = 1.0
        cov = np.einsum("nij,njk,nlk->nil", e, self.covariance[:, ATT_ROWS, ATT_ROWS], e)
        return np.sqrt(np.maximum(np.diagonal(cov, axis1=1, axis2=2), 0.0))

    @property
    def bias_sigma(self) -> np.ndarray:
        return np.sqrt(np.maximum(np.diagonal(self.covariance[:, BIAS_ROWS, BIAS_ROWS],
                                              axis1=1, axis2=2), 0.0))

    def fraction_ran(self) -> dict[str, float]:
        return {name: float(self.ran[:, i].mean()) for i, name in enumerate(UPDATE_NAMES)}


def saturation_flags(gyro: np.ndarray, range_radps: float | None,
                     previous: np.ndarray | None = None) -> np.ndarray:
    """Per sample (N,): a rate at the range limit, or a flat top (the same reading as the
    sample before, above :data:`FLAT_TOP_MIN_RADPS`, on any axis)."""
    gyro = np.asarray(gyro, float)
    before = np.vstack([previous if previous is not None else np.full(3, np.nan), gyro[:-1]])
    flat = (gyro == before) & (np.abs(gyro) > FLAT_TOP_MIN_RADPS)
    out = flat.any(axis=1)
    if range_radps is not None:
        out |= (np.abs(gyro) >= range_radps * (1.0 - 1e-3)).any(axis=1)
    return out


class OrientationFilter:
    """The UKF of chapter 3 over a stream or a record of IMU (and magnetometer) samples."""

    def __init__(self, config: OrientationConfig) -> None:
        self.config = config
        self.params = config.params()
        self.state: FilterState | None = None
        self.previous_gyro: np.ndarray | None = None
        self.corrections = {"accepted": 0, "refused": 0}

    # --- state ----------------------------------------------------------------------
    def _start(self, accel: np.ndarray, mag: np.ndarray) -> FilterState:
        c = self.config
        roll, pitch = tilt_from_specific_force(accel)
        tilt = rotation_from_euler(roll, pitch, 0.0).as_matrix()
        if c.initial_yaw_deg is not None:
            yaw = np.radians(c.initial_yaw_deg)
        elif np.isfinite(mag).all():
            yaw = compass_yaw(tilt, np.asarray(mag, float), self.params.field_azimuth)
        else:
            yaw = 0.0
        attitude = rotation_from_euler(roll, pitch, yaw).as_matrix()
        variances = np.zeros(N_STATE)
        variances[[ATT_EAST, ATT_NORTH]] = np.radians(c.initial_tilt_sigma_deg) ** 2
        variances[ATT_UP] = np.radians(c.initial_yaw_sigma_deg) ** 2
        variances[BIAS_ROWS] = np.radians(c.noise("initial_bias_sigma_deg_per_s")) ** 2
        return initial_state(attitude, np.diag(variances))

    def reset(self) -> None:
        self.state = None
        self.previous_gyro = None

    # --- processing -----------------------------------------------------------------
    def run(self, t: np.ndarray, gyro: np.ndarray, accel: np.ndarray,
            mag: np.ndarray | None = None) -> AttitudeEstimate:
        """Filter samples at times ``t`` (N,) [s]: gyro (N, 3) [rad/s], accel (N, 3)
        [m/s²], mag (N, 3) [T] or None (rows of NaN: no reading at that sample)."""
        n = len(t)
        gyro = np.ascontiguousarray(gyro, dtype=float)
        accel = np.ascontiguousarray(accel, dtype=float)
        mag = np.full((n, 3), np.nan) if mag is None else np.ascontiguousarray(mag, dtype=float)
        if self.state is None and n:
            self.state = self._start(accel[0], mag[0])
        saturated = saturation_flags(gyro, self._range(), self.previous_gyro)
        t = np.ascontiguousarray(t, dtype=float)
        out = FilterOutputs(np.empty((n, 3, 3)), np.empty((n, 3)),
                            np.empty((n, N_STATE, N_STATE)), np.zeros((n, N_DETECTORS), dtype=bool),
                            np.zeros((n, N_UPDATES), dtype=bool))
        kernel.filter_loop(self.state, self.params, FilterInputs(t, gyro, accel, mag, saturated),
                           out)
        if n:
            self.previous_gyro = gyro[-1].copy()
        return AttitudeEstimate(t, **out._asdict())

    def _range(self) -> float | None:
        r = self.config.gyro_range_deg_per_s
        return None if r is None else np.radians(r)

    # --- external corrections (Eq. (6.2)) ---------------------------------------------
    def correct_yaw(self, yaw_rad: float, variance_rad2: float) -> tuple[bool, str]:
        """Update the yaw with ψ_L [rad] and its variance; refused (state untouched) as
        :meth:`gate` says."""
        return self._correct(YAW_CORRECTION, yaw_rad, variance_rad2)

    def correct_bias_z(self, bias_radps: float, variance: float) -> tuple[bool, str]:
        """Update the z gyro bias with a value and its variance [rad/s, rad²/s²]."""
        return self._correct(BIAS_Z_CORRECTION, bias_radps, variance)

    def gate(self, kind: int, value: float, variance: float) -> tuple[str | None, float]:
        """Why a correction of the yaw (ψ_L [rad]) or of the z gyro bias [rad/s] with its
        variance would be refused (None: it passes), and its NIS, against the covariance
        as it is now: the filter has not started, the variance is not positive and
        finite, or the innovation fails the χ² gate."""
        what, unit = CORRECTION_NAMES[kind]
        if self.state is None:
            return f"{what}: the filter has not started", np.nan
        if not (np.isfinite(value) and np.isfinite(variance) and variance > 0):
            return (f"{what}: value {value!r} with variance {variance!r} is not usable "
                    "(finite, variance > 0)"), np.nan
        nis, innovation, predicted = self._nis(kind, value, variance)
        limit = chi2_quantile(GATE_PROBABILITY, 1)
        if nis > limit:
            return (f"{what} refused by the χ² gate: NIS {nis:.1f} > {limit:.1f} (the "
                    f"change {innovation:+.4g} {unit} against the predicted variance "
                    f"{predicted:.3g} and the request's {variance:.3g})"), nis
        return None, nis

    def apply(self, kind: int, value: float, variance: float) -> None:
        """The Kalman update of a correction that :meth:`gate` passed, not gated again: a
        correction of several parts is gated, every part, against the covariance before
        any is applied (PocketNavigator.apply_correction)."""
        kernel.correct(self.state, self.params, kind, value, variance)
        self.corrections["accepted"] += 1

    def _nis(self, kind: int, value: float, variance: float) -> tuple[float, float, float]:
        predicted = self._predicted_variance(kind)
        change = np.float64(value) - self._current(kind)
        innovation = wrap_angle(change) if kind == YAW_CORRECTION else change
        with np.errstate(over="ignore"):     # a huge request: an infinite NIS, refused
            return float(innovation**2 / (predicted + variance)), float(innovation), predicted

    def _correct(self, kind: int, value: float, variance: float) -> tuple[bool, str]:
        problem, nis = self.gate(kind, value, variance)
        if problem is not None:
            return self._refuse(problem)
        self.apply(kind, value, variance)
        return True, f"{CORRECTION_NAMES[kind][0]} applied (NIS {nis:.2f})"

    @property
    def yaw(self) -> float:
        """ψ of the current attitude [rad]."""
        return self._current(YAW_CORRECTION)

    @property
    def yaw_variance(self) -> float:
        """Variance of the yaw (the vertical component of the attitude error) [rad²]."""
        return self._predicted_variance(YAW_CORRECTION)

    def _refuse(self, message: str) -> tuple[bool, str]:
        self.corrections["refused"] += 1
        return False, message

    def _current(self, kind: int) -> float:
        c = self.state.attitude
        return float(np.arctan2(c[1, 0], c[0, 0])) if kind == YAW_CORRECTION \
            else float(self.state.bias[2])

    def _predicted_variance(self, kind: int) -> float:
        """Variance of the yaw (about the vertical: the navigation-frame z error) or of b_z."""
        p = self.state.covariance
        return float(p[ATT_UP, ATT_UP] if kind == YAW_CORRECTION else p[BIAS_Z, BIAS_Z])
