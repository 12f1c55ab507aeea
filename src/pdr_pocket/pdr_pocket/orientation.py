"""The orientation filter of the pocket navigator: two filters behind one interface.

:class:`OrientationFilter` runs the filter its configuration names (``orientation.filter``,
:data:`FILTERS`): ``ekf``, the phone's error-state filter (pdr_pocket.compiled_attitude,
the default), or ``thesis``, the unscented filter of Muñoz Díaz 2016, chapter 3
(pdr_pocket.compiled_orientation). :meth:`~OrientationFilter.run` processes whole arrays
or any run of samples after the last, with the same state and the same result (the live
path feeds it in chunks), :meth:`~OrientationFilter.correct_yaw` and
:meth:`~OrientationFilter.correct_bias_z` apply external corrections (Eq. (6.2)) as Kalman
updates, refused when they fail a χ² gate (:meth:`~OrientationFilter.gate` and
:meth:`~OrientationFilter.apply` do the two apart). Each filter's kernel data and its
loop stay in its compiled module; :class:`EkfKernel` and :class:`ThesisKernel` start its
state and run it.

Frames and units: body (sensor) frame as the IMU gives it, ENU navigation frame; SI
inside (rad, rad/s, m/s², T). Both filters carry the attitude error as a small rotation in
the navigation frame, and the first six rows of their covariance are the same:
[δθ_east, δθ_north, δθ_up, δb_x, δb_y, δb_z]. The filter starts on its first sample: roll
and pitch from that sample's specific force (Eqs. (3.12)-(3.13)), yaw from the
magnetometer's first reading when no ``initial_yaw_deg`` is set (else that yaw, or 0
without a magnetometer), biases 0.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdr_core import units
from pdr_core.maths.angles import wrap_angle
from pdr_core.maths.chi2 import chi2_quantile
from pdr_core.maths.rotations import rotation_from_euler, tilt_from_specific_force
from pdr_pocket import (
    compiled_attitude,
    compiled_attitude_data,
    compiled_orientation,
    compiled_orientation_data,
)
from pdr_pocket.compiled_orientation_data import (
    ATT_EAST,
    ATT_NORTH,
    ATT_ROWS,
    ATT_UP,
    BIAS_ROWS,
    BIAS_Z,
)
from pdr_pocket.compiled_orientation_measurements import (
    BIAS_Z_CORRECTION,
    N_UPDATES,
    YAW_CORRECTION,
    compass_yaw,
)
from pdr_pocket.orientation_config import OrientationConfig

GATE_PROBABILITY = 0.999            # χ² gate of external corrections (1 dof)
# the external corrections' names and units, in messages
CORRECTION_NAMES = {YAW_CORRECTION: ("yaw", "rad"), BIAS_Z_CORRECTION: ("z gyro bias", "rad/s")}
FLAT_TOP_MIN_RADPS = 2.0            # a repeated reading above this is a saturated flat top
N_OUTPUT = 6                        # the covariance rows written per sample: δθ and δb
THESIS_UPDATE_NAMES = ("absolute_gravity", "differential_gravity", "absolute_magnetic",
                       "differential_magnetic", "compass", "zaru", "mean_gravity")
THESIS_DETECTOR_NAMES = ("zero_acceleration", "zero_rate", "steady_field", "saturated")
# what the default filter made of a magnetometer reading: its detectors' names
FIELD_JUDGEMENTS = compiled_attitude_data.DETECTOR_NAMES[compiled_attitude_data.FIELD_UNDISTURBED:
                                                    compiled_attitude_data.FIELD_IMPLAUSIBLE + 1]


@dataclass(frozen=True)
class AttitudeEstimate:
    """Per sample: C_b^n (N, 3, 3), gyro bias (N, 3) [rad/s], covariance (N, 6, 6) of
    [δθ (navigation frame, rad), δb (rad/s)], the detectors (N, D) and the updates that ran
    (N, U), their columns named by ``detector_names`` and ``update_names`` (the filter's
    own)."""

    t: np.ndarray
    attitude: np.ndarray
    bias: np.ndarray
    covariance: np.ndarray
    detected: np.ndarray
    ran: np.ndarray
    update_names: tuple[str, ...] = ()
    detector_names: tuple[str, ...] = ()

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
    def heading_sigma(self) -> np.ndarray:
        """1σ [rad] of the heading, the vertical component δθ_up of the attitude error."""
        return np.sqrt(np.maximum(self.covariance[:, ATT_UP, ATT_UP], 0.0))

    @property
    def bias_sigma(self) -> np.ndarray:
        return np.sqrt(np.maximum(np.diagonal(self.covariance[:, BIAS_ROWS, BIAS_ROWS],
                                              axis1=1, axis2=2), 0.0))

    def fraction_ran(self) -> dict[str, float]:
        """The share of samples each update ran, by name."""
        return {name: float(self.ran[:, i].mean()) if len(self.ran) else 0.0
                for i, name in enumerate(self.update_names)}

    def detector(self, name: str) -> np.ndarray:
        """The detector ``name``'s output per sample (N,) bool; all False when this
        filter has none of that name."""
        if name not in self.detector_names:
            return np.zeros(len(self.t), dtype=bool)
        return self.detected[:, self.detector_names.index(name)]

    def field_judgement(self) -> np.ndarray:
        """Per sample (N,), what the filter made of the last magnetometer reading: the
        index in :data:`FIELD_JUDGEMENTS` (undisturbed, disturbed, implausible), −1 before
        the first. A phone's magnetometer comes at its own rate (50–73 Hz on the OxIOD
        iPhones) and holds its output between readings, so each judgement holds until the
        next reading (the thesis' filter, which judges none, gives −1 throughout)."""
        judged = np.full(len(self.t), -1)
        for i, name in enumerate(FIELD_JUDGEMENTS):
            judged[self.detector(name)] = i
        last = np.maximum.accumulate(np.where(judged >= 0, np.arange(len(judged)), 0))
        return judged[last]


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


def _first_attitude(accel: np.ndarray, yaw: float) -> np.ndarray:
    """C_b^n of roll and pitch from the specific force α (body) and ``yaw`` [rad]."""
    roll, pitch = tilt_from_specific_force(accel)
    return rotation_from_euler(roll, pitch, yaw).as_matrix()


def _initial_yaw(config: OrientationConfig) -> float:
    return 0.0 if config.initial_yaw_deg is None else float(np.radians(config.initial_yaw_deg))


class EkfKernel:
    """``filter: ekf``: pdr_pocket.compiled_attitude."""

    update_names = compiled_attitude_data.UPDATE_NAMES
    detector_names = compiled_attitude_data.DETECTOR_NAMES

    def __init__(self, config: OrientationConfig) -> None:
        self.config = config
        self.params = config.ekf_params()

    def start(self, accel: np.ndarray, mag: np.ndarray) -> compiled_attitude_data.AttitudeState:
        """The state at the first sample. With the field update on, the kernel takes the
        yaw from the field's first reading, with its covariance against the offset;
        without it, a reading with the first sample gives the compass yaw, as the thesis'
        filter takes it."""
        c, k = self.config, compiled_attitude_data
        yaw = _initial_yaw(c)
        if c.initial_yaw_deg is None and not c.ekf.field and np.isfinite(mag).all():
            yaw = compass_yaw(_first_attitude(accel, 0.0), np.asarray(mag, float),
                              self.params.field_azimuth)
        variances = np.zeros(k.N_STATE)
        variances[[k.ATT_EAST, k.ATT_NORTH]] = np.radians(c.initial_tilt_sigma_deg) ** 2
        variances[k.ATT_UP] = np.radians(c.initial_yaw_sigma_deg) ** 2
        variances[k.BIAS:k.BIAS + 3] = np.radians(c.noise("initial_bias_sigma_deg_per_s")) ** 2
        variances[k.OFFSET:k.OFFSET + 3] = (c.ekf.mag_offset_sigma_ut * 1e-6) ** 2
        variances[[k.FIELD_HORIZONTAL, k.FIELD_DOWN]] = (c.ekf.field_sigma_ut * 1e-6) ** 2
        variances[k.ACCEL_BIAS:k.ACCEL_BIAS + 3] = units.mg_to_si(c.ekf.accel_bias_sigma_mg) ** 2
        return k.initial_state(_first_attitude(accel, yaw), np.diag(variances))

    def run(self, state, t, gyro, accel, mag, saturated) -> dict:
        n, k = len(t), compiled_attitude_data
        out = compiled_orientation_data.FilterOutputs(
            np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((n, N_OUTPUT, N_OUTPUT)),
            np.zeros((n, k.N_DETECTORS), dtype=bool), np.zeros((n, k.N_UPDATES), dtype=bool))
        compiled_attitude.filter_loop(
            state, self.params,
            compiled_orientation_data.FilterInputs(t, gyro, accel, mag, saturated), out)
        return out._asdict()

    def correct(self, state, kind: int, value: float, variance: float) -> None:
        compiled_attitude.correct(state, self.params, kind, value, variance)

    @staticmethod
    def gaps(state) -> int:
        return int(state.scalars[0]["gaps"])


class ThesisKernel:
    """``filter: thesis``: pdr_pocket.compiled_orientation, the UKF of chapter 3."""

    update_names = THESIS_UPDATE_NAMES
    detector_names = THESIS_DETECTOR_NAMES

    def __init__(self, config: OrientationConfig) -> None:
        self.config = config
        self.params = config.thesis_params()

    def start(self, accel: np.ndarray, mag: np.ndarray) -> compiled_orientation_data.FilterState:
        """The state at the first sample: yaw from the compass when the sample has a
        magnetometer reading and no ``initial_yaw_deg`` is set."""
        c = self.config
        yaw = _initial_yaw(c)
        if c.initial_yaw_deg is None and np.isfinite(mag).all():
            tilt = _first_attitude(accel, 0.0)
            yaw = compass_yaw(tilt, np.asarray(mag, float), self.params.field_azimuth)
        variances = np.zeros(compiled_orientation_data.N_STATE)
        variances[[ATT_EAST, ATT_NORTH]] = np.radians(c.initial_tilt_sigma_deg) ** 2
        variances[ATT_UP] = np.radians(c.initial_yaw_sigma_deg) ** 2
        variances[BIAS_ROWS] = np.radians(c.noise("initial_bias_sigma_deg_per_s")) ** 2
        return compiled_orientation_data.initial_state(_first_attitude(accel, yaw),
                                                  np.diag(variances))

    def run(self, state, t, gyro, accel, mag, saturated) -> dict:
        n, d = len(t), compiled_orientation_data
        out = d.FilterOutputs(np.empty((n, 3, 3)), np.empty((n, 3)),
                              np.empty((n, d.N_STATE, d.N_STATE)),
                              np.zeros((n, d.N_DETECTORS), dtype=bool),
                              np.zeros((n, N_UPDATES), dtype=bool))
        compiled_orientation.filter_loop(state, self.params,
                                         d.FilterInputs(t, gyro, accel, mag, saturated), out)
        return out._asdict()

    def correct(self, state, kind: int, value: float, variance: float) -> None:
        compiled_orientation.correct(state, self.params, kind, value, variance)

    @staticmethod
    def gaps(state) -> int:
        return int(state.scalars[0]["gaps"])


FILTERS = {"ekf": EkfKernel, "thesis": ThesisKernel}


class OrientationFilter:
    """The configured filter over a stream or a record of IMU (and magnetometer) samples
    (the module docstring)."""

    def __init__(self, config: OrientationConfig) -> None:
        self.config = config
        self.kernel = FILTERS[config.filter](config)
        self.params = self.kernel.params
        self.state = None
        self.previous_gyro: np.ndarray | None = None
        self.corrections = {"accepted": 0, "refused": 0}

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
            self.state = self.kernel.start(accel[0], mag[0])
        saturated = saturation_flags(gyro, self._range(), self.previous_gyro)
        out = self.kernel.run(self.state, np.ascontiguousarray(t, dtype=float), gyro, accel,
                              mag, saturated)
        if n:
            self.previous_gyro = gyro[-1].copy()
        out["covariance"] = out["covariance"][:, :N_OUTPUT, :N_OUTPUT]
        return AttitudeEstimate(t, **out, update_names=self.kernel.update_names,
                                detector_names=self.kernel.detector_names)

    def _range(self) -> float | None:
        r = self.config.gyro_range_deg_per_s
        return None if r is None else np.radians(r)

    @property
    def gyro_noise_var(self) -> float:
        """σ_ν² [rad²/s²] per sample at the nominal rate: the gyroscope's white noise the
        filter assumes (what ``pdr/pocket/gyro_bias`` and the attitude messages state)."""
        return self.params.gyro_noise_var

    @property
    def gaps(self) -> int:
        """Gaps longer than ``max_gap_s`` the filter propagated over so far (0 before its
        first sample)."""
        return 0 if self.state is None else self.kernel.gaps(self.state)

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
        self.kernel.correct(self.state, kind, value, variance)
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
