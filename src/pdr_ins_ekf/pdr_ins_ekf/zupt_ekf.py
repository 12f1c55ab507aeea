"""Error-state EKF of a foot-mounted INS aided by zero-velocity (ZUPT) and zero-angular-rate
(ZARU) pseudo-measurements: Simón Colomar et al. 2012, Eq. (8) (closed loop, 9 states) and
Wang et al. 2020, Eq. (2) (15 states with accelerometer and gyro biases).

Error state δx = [δp, δv, δθ (, δb_a, δb_g)] with δp = p − p̂, δv = v − v̂, δb = b − b̂ and
the attitude error defined by C = (I − [δθ×])·Ĉ, so that Eq. (8)'s compensation is
p̂ += δp, v̂ += δv, Ĉ ← (I − [δθ×])·Ĉ, b̂ += δb, δx ← 0. Continuous error dynamics:

    δṗ = δv
    δv̇ = [fⁿ×]·δθ − Ĉ·δb_a − Ĉ·n_a          (fⁿ = Ĉ·(f − b̂_a))
    δθ̇ = Ĉ·δb_g + Ĉ·n_g
    δḃ = n_b (random walk) or −δb/τ + n_b (Gauss–Markov)

discretised to first order, F = I + A·T_s, Q = G·diag(σ²)·Gᵀ·T_s. The nominal state is
propagated by :mod:`pdr_ins_ekf.strapdown`'s trapezoidal mechanization, one sample at a
time. Updates use the Joseph form, and the covariance is symmetrised after every step.

ZUPT: z = −v̂ = δv + noise (H picks δv). ZARU (15 states only): z = ω − b̂_g = δb_g + noise.
The error state's rows are named in :mod:`pdr_ins_ekf.kernel_data` (``VELOCITY``,
``GYRO_BIAS``, …), as are the state, parameters and samples the kernels take.

Frames and units: ENU navigation frame, FLU body frame, SI.
"""
from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.maths.rotations import rotation_from_euler, tilt_from_specific_force
from pdr_ins_ekf import compiled_filter as kernels
from pdr_ins_ekf import compiled_smoother
from pdr_ins_ekf.compiled_smoother import SmootherParams
from pdr_ins_ekf.kernel_data import (
    BIAS_MODEL_CODES,
    GYRO,
    GYRO_BIAS,
    NAV_AND_BIAS_STATES,
    NAV_STATES,
    VELOCITY,
    FilterParams,
    NavState,
    Samples,
    intervals,
)

BIAS_MODELS = ("none", "random_walk", "gauss_markov")
# The covariance published with the estimates (pose, odometry, velocity): the filter's P
# (``configured``), or its white noises' part times the mean touchdown νᵀ·P_v⁻¹·ν / 3 so
# far plus the biases' share, λ·(P − Pb) + Pb (``innovations``,
# pdr_ins_ekf.compiled_filter.covariance_scale and bias_share; Pb = 0 with 9 states); the
# estimates, and the strides' covariance (landmark_drift's gates are set for it), are the same.
COVARIANCE_SCALES = ("configured", "innovations")


@dataclass(frozen=True)
class FilterConfig:
    """Noise and aiding parameters (SI; densities per √Hz)."""

    acc_noise_mps2_per_sqrt_hz: float = 0.002
    gyro_noise_radps_per_sqrt_hz: float = 0.0002
    zupt_sigma_mps: float = 0.01      # [m/s]
    zaru_sigma_radps: float = 0.01    # [rad/s]
    zaru: bool = False
    zaru_gate_nis: float = 16.27      # ZARU where νᵀS⁻¹ν < this (χ², 3 dof, 0.999)
    covariance_scale: str = "configured"   # configured | innovations (COVARIANCE_SCALES)
    bias_model: str = "none"
    acc_bias_noise_mps2_per_sqrt_s: float = 1e-4    # bias random walk / GM driving noise
    gyro_bias_noise_radps_per_sqrt_s: float = 1e-5
    bias_tau_s: float = 300.0         # Gauss–Markov correlation time [s]
    init_pos_sigma_m: float = 1e-5
    init_vel_sigma_mps: float = 1e-5
    init_att_sigma_rad: float = (0.1 * np.pi / 180)
    init_yaw_sigma_rad: float = (0.1 * np.pi / 180)
    init_acc_bias_sigma_mps2: float = 0.05
    init_gyro_bias_sigma_radps: float = 0.005
    gravity_mps2: float = STANDARD_GRAVITY_MPS2

    def __post_init__(self) -> None:
        if self.bias_model not in BIAS_MODELS:
            raise ValueError(f"bias_model must be one of {', '.join(BIAS_MODELS)}, "
                             f"got {self.bias_model!r}")
        if self.covariance_scale not in COVARIANCE_SCALES:
            raise ValueError(f"covariance_scale must be one of {', '.join(COVARIANCE_SCALES)}"
                             f", got {self.covariance_scale!r}")
        if self.zaru and self.bias_model == "none":
            raise ValueError("ZARU needs the gyro bias states (bias_model random_walk or "
                             "gauss_markov)")
        for name in ("acc_noise_mps2_per_sqrt_hz", "gyro_noise_radps_per_sqrt_hz",
                     "zupt_sigma_mps", "zaru_sigma_radps", "zaru_gate_nis"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")

    @property
    def states(self) -> int:
        return NAV_STATES if self.bias_model == "none" else NAV_AND_BIAS_STATES


@dataclass
class FilterOutput:
    """Per-sample estimates: position, velocity (N, 3), attitude C_b^n (N, 3, 3), biases
    (N, 6) (zero for 9 states), covariance diagonal (N, states) and full position and
    velocity covariance blocks (N, 3, 3), the filter's own P; the factor (N,) the
    published covariances (pose, odometry, velocity) scale the white noises' part of
    these by (FilterConfig.covariance_scale; not given: ones); and the biases' share of
    the diagonal (N, states) and of the position and velocity blocks (N, 3, 3), which is
    published as it is (pdr_ins_ekf.compiled_filter.bias_share; not given: zeros)."""

    position: np.ndarray
    velocity: np.ndarray
    attitude: np.ndarray
    bias: np.ndarray
    variance: np.ndarray
    position_cov: np.ndarray
    velocity_cov: np.ndarray
    covariance_scale: np.ndarray | None = None
    bias_variance: np.ndarray | None = None
    bias_position_cov: np.ndarray | None = None
    bias_velocity_cov: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.covariance_scale is None:
            self.covariance_scale = np.ones(len(self.position))
        if self.bias_variance is None:
            self.bias_variance = np.zeros_like(self.variance)
        if self.bias_position_cov is None:
            self.bias_position_cov = np.zeros_like(self.position_cov)
        if self.bias_velocity_cov is None:
            self.bias_velocity_cov = np.zeros_like(self.velocity_cov)

    def published(self, own: np.ndarray, bias_share: np.ndarray, index: slice
                  ) -> np.ndarray:
        """The published covariance of the samples ``index`` from the filter's own
        ``own`` and its biases' share ``bias_share`` (N, ...) of the same quantity: the
        white noises' part scaled, λ·(P − Pb) + Pb (covariance_scale)."""
        scale = self.covariance_scale[index].reshape(-1, *[1] * (own.ndim - 1))
        return scale * (own[index] - bias_share[index]) + bias_share[index]

    def part(self, index: slice) -> FilterOutput:
        """The estimates of the samples ``index``."""
        return FilterOutput(*(getattr(self, f.name)[index] for f in fields(self)))

    @classmethod
    def concatenate(cls, parts: list[FilterOutput]) -> FilterOutput:
        """Consecutive estimates as one."""
        return cls(*(np.concatenate([getattr(p, f.name) for p in parts])
                     for f in fields(cls)))


SMOOTHER_MODES = ("none", "segmented", "full")


@dataclass(frozen=True)
class SmootherConfig:
    """RTS smoothing (Simón Colomar et al. 2012, section III; :mod:`compiled_smoother`).

    ``segmented`` cuts a segment ``tau_s`` seconds after Σ diag(P_v) falls below
    ``gamma_s_m2ps2`` at a ZUPT; ``full`` smooths the whole record in one backward pass
    (memory grows with the record), its forward pass closing the loop at the same cuts.
    ``gamma_s_m2ps2`` must lie between the velocity variance just before a ZUPT and at
    the end of a stance, which depend on the filter's noise: 1.5e-5 suits the
    FilterConfig defaults, 3e-4 the shipped foot_ekf.yaml.
    ``zero_heading_position`` zeroes the heading–position cross-covariance after each
    prediction (the paper's remedy for sharp smoothing corrections); the covariance is
    then no longer the filter's, and the smoothed heading stops following position
    corrections.
    ``covariance`` also smooths the covariance (Pₙ|ₑ of Eq. (9); the outputs'
    ``velocity_variance``, NaN without it): the smoother then takes about 2.6× the
    filter's time instead of 1.3–1.8×, and stores the covariances of every sample.
    """

    mode: str = "none"
    gamma_s_m2ps2: float = 1.5e-5
    tau_s: float = 0.04
    zero_heading_position: bool = False
    covariance: bool = False

    def __post_init__(self) -> None:
        if self.mode not in SMOOTHER_MODES:
            raise ValueError(f"mode must be one of {', '.join(SMOOTHER_MODES)}, "
                             f"got {self.mode!r}")
        if self.gamma_s_m2ps2 <= 0 or self.tau_s < 0:
            raise ValueError("need gamma_s_m2ps2 > 0 and tau_s >= 0")


@dataclass
class SmoothedOutput:
    """Smoothed position, velocity (N, 3), attitude C_b^n (N, 3, 3), smoothed velocity
    variances (N, 3; NaN unless SmootherConfig.covariance) and the index of each
    segment's last sample."""

    position: np.ndarray
    velocity: np.ndarray
    attitude: np.ndarray
    velocity_variance: np.ndarray
    segment_ends: np.ndarray


@dataclass
class SmoothedSegment:
    """One smoothed segment of the live smoother: stamps (m,) [ns], position (m, 3),
    attitude C_b^n (m, 3, 3) and smoothed velocity variances (m, 3)."""

    stamp_ns: np.ndarray
    position: np.ndarray
    attitude: np.ndarray
    velocity_variance: np.ndarray


class SegmentSmoother:
    """The segmented 3-pass smoother one sample at a time (the node's
    ``pdr/foot/smoothed_path``), with the kernels of :func:`smooth`, so that it gives
    the offline segments exactly. Memory: the store of the longest segment so far."""

    def __init__(self, config: FilterConfig, smoother: SmootherConfig, start: ZuptEkf
                 ) -> None:
        self.config = config
        self.params = kernel_params(config)
        self.smoother = smoother_params(smoother)
        self.state = start_state(start.state.C, start.state.b, start.state.P)
        self.store = compiled_smoother.new_segment_store(
            1024, self.state.P.shape[0], smoother.covariance, smoother.zero_heading_position,
            2 if config.zaru else 1)
        self.stamps: list[int] = []
        self.started = False

    @property
    def store_bytes(self) -> int:
        """Bytes held by the segment store."""
        return sum(array.nbytes for array in self.store if isinstance(array, np.ndarray))

    def step(self, stamp_ns: int, f: np.ndarray, w: np.ndarray, dt: float, stance: bool
             ) -> SmoothedSegment | None:
        """One sample (dt = 0 for the first); the segment when this sample ends one."""
        f, w = np.asarray(f, float), np.asarray(w, float)
        if not self.started:
            kernels.start(self.state, f, w)
            self.started = True
        j = len(self.stamps)
        self.store = compiled_smoother.grown(self.store, j + 1)
        self.stamps.append(int(stamp_ns))
        sample = Samples(np.array([dt], float), f.reshape(1, 3), w.reshape(1, 3),
                         np.array([stance], bool))
        cut = compiled_smoother.open_loop_step(self.store, j, self.state, sample, 0,
                                               self.params, self.smoother)
        return self.finish() if cut else None

    def finish(self) -> SmoothedSegment | None:
        """Smooth and close the current segment (at a cut, or at the end of the input)."""
        m = len(self.stamps)
        if not m:
            return None
        self.store = compiled_smoother.close_segment(self.store, m - 1, self.state)
        out = SmoothedSegment(np.array(self.stamps, np.int64), np.empty((m, 3)),
                              np.empty((m, 3, 3)), np.empty((m, 3)))
        compiled_smoother.smooth_segment(self.store, m, self.params, out.position,
                                         np.empty((m, 3)), out.attitude,
                                         out.velocity_variance)
        self.stamps = []
        return out


class ZuptEkf:
    """The filter state and its steps over blocks of samples (the live node's engine);
    the equations are the compiled kernels of :mod:`pdr_ins_ekf.compiled_filter`, which
    :func:`run` also loops over, so both give the same numbers. ``state`` is the
    :class:`~pdr_ins_ekf.kernel_data.NavState` they change in place (also read as
    ``p``, ``v``, ``C``, ``b``, ``P``)."""

    def __init__(self, config: FilterConfig, attitude: np.ndarray, gyro_bias=(0.0, 0.0, 0.0),
                 position=(0.0, 0.0, 0.0)) -> None:
        self.config = config
        b = np.zeros(6)
        b[GYRO] = gyro_bias
        self.state = start_state(attitude, b, initial_covariance(config))
        self.state.p[:] = position
        self.started = False
        self.params = kernel_params(config)

    p = property(lambda self: self.state.p, doc="Position p̂ (3,) [m], navigation frame.")
    v = property(lambda self: self.state.v, doc="Velocity v̂ (3,) [m/s], navigation frame.")
    C = property(lambda self: self.state.C, doc="Attitude Ĉ = C_b^n (3, 3).")
    b = property(lambda self: self.state.b,
                 doc="Biases b̂ (6,): accelerometer [m/s²], gyroscope [rad/s], body frame.")
    P = property(lambda self: self.state.P, doc="Error-state covariance (n, n).")

    def predict(self, f: np.ndarray, w: np.ndarray, dt: float) -> None:
        """Propagate the nominal state (trapezoidal) and the covariance over dt [s] with
        the specific force f [m/s²] and rate w [rad/s] (3,), body frame."""
        f, w = np.asarray(f, float), np.asarray(w, float)
        if not self.started:
            kernels.start(self.state, f, w)
            self.started = True
        kernels.predict(self.state, f, w, float(dt), self.params)

    @classmethod
    def aligned(cls, config: FilterConfig, accel_rest: np.ndarray, gyro_rest: np.ndarray,
                yaw_rad: float = 0.0) -> ZuptEkf:
        """A filter aligned on samples at rest: roll and pitch from the mean specific
        force, gyro bias from the mean rate, the given yaw."""
        return cls(config, initial_attitude(accel_rest, yaw_rad),
                   gyro_bias=gyro_rest.mean(axis=0))

    def run_block(self, f: np.ndarray, w: np.ndarray, dt: np.ndarray, stance: np.ndarray
                  ) -> FilterOutput:
        """Consecutive samples f, w (N, 3), each propagated over dt (N,) [s] (0 for the
        first of the record), then ZUPT (and ZARU) where ``stance``: the estimates after
        each (:func:`pdr_ins_ekf.compiled_filter.filter_block`, as :func:`run`)."""
        f, w = np.ascontiguousarray(f, float), np.ascontiguousarray(w, float)
        if len(f) and not self.started:
            kernels.start(self.state, f[0], w[0])
            self.started = True
        samples = Samples(np.ascontiguousarray(dt, float), f, w,
                          np.ascontiguousarray(stance, bool))
        return FilterOutput(*kernels.filter_block(self.state, samples, self.params))

    def zupt(self) -> None:
        """Zero-velocity pseudo-measurement: z = −v̂ observes δv."""
        kernels.update(self.state, -self.state.v, VELOCITY, self.config.zupt_sigma_mps)

    def zaru(self, w: np.ndarray) -> None:
        """Zero-angular-rate pseudo-measurement (15 states): z = ω − b̂_g observes δb_g."""
        kernels.update(self.state, np.asarray(w, float) - self.state.b[GYRO], GYRO_BIAS,
                       self.config.zaru_sigma_radps)


def initial_covariance(config: FilterConfig) -> np.ndarray:
    """The error-state covariance at alignment (n, n), diagonal from the init_* σ."""
    sig = ([config.init_pos_sigma_m] * 3 + [config.init_vel_sigma_mps] * 3
           + [config.init_att_sigma_rad] * 2 + [config.init_yaw_sigma_rad])
    if config.states == NAV_AND_BIAS_STATES:
        sig += [config.init_acc_bias_sigma_mps2] * 3 + [config.init_gyro_bias_sigma_radps] * 3
    return np.diag(np.square(sig))


def kernel_params(config: FilterConfig) -> FilterParams:
    """The :class:`~pdr_ins_ekf.kernel_data.FilterParams` of the compiled kernels."""
    return FilterParams(
        acc_noise=float(config.acc_noise_mps2_per_sqrt_hz),
        gyro_noise=float(config.gyro_noise_radps_per_sqrt_hz),
        acc_bias_noise=float(config.acc_bias_noise_mps2_per_sqrt_s),
        gyro_bias_noise=float(config.gyro_bias_noise_radps_per_sqrt_s),
        bias_tau_s=float(config.bias_tau_s),
        bias_model=BIAS_MODEL_CODES[config.bias_model],
        gravity_mps2=float(config.gravity_mps2), zupt_sigma_mps=float(config.zupt_sigma_mps),
        zaru=bool(config.zaru), zaru_sigma_radps=float(config.zaru_sigma_radps),
        zaru_gate_nis=float(config.zaru_gate_nis),
        innovation_scale=config.covariance_scale == "innovations")


def smoother_params(smoother: SmootherConfig) -> SmootherParams:
    """The :class:`~pdr_ins_ekf.compiled_smoother.SmootherParams` of the compiled
    smoother."""
    return SmootherParams(
        gamma_s_m2ps2=float(smoother.gamma_s_m2ps2), tau_s=float(smoother.tau_s),
        zero_heading_position=bool(smoother.zero_heading_position),
        full=smoother.mode == "full", covariance=bool(smoother.covariance))


def start_state(C0: np.ndarray, b0: np.ndarray, P0: np.ndarray) -> NavState:
    """A :class:`~pdr_ins_ekf.kernel_data.NavState` at the origin at rest with copies of
    the attitude C0 (3, 3), biases b0 (6,) and covariance P0 (n, n)
    (:func:`pdr_ins_ekf.compiled_filter.new_state`)."""
    return kernels.new_state(np.ascontiguousarray(C0, float), np.ascontiguousarray(b0, float),
                             np.ascontiguousarray(P0, float))


def initial_attitude(accel: np.ndarray, yaw_rad: float) -> np.ndarray:
    """C_b^n (3, 3) from the mean specific force at rest (roll, pitch) over the samples
    of ``accel`` (n, 3) and a given yaw; for runs (R, n, 3), one per run (R, 3, 3)."""
    f = accel.mean(axis=-2)
    roll, pitch = tilt_from_specific_force(f)
    matrix = rotation_from_euler(np.atleast_1d(roll), np.atleast_1d(pitch),
                                 np.full(np.atleast_1d(roll).shape, yaw_rad)).as_matrix()
    return matrix.reshape(*f.shape[:-1], 3, 3)


def run(t: np.ndarray, accel: np.ndarray, gyro: np.ndarray, stance: np.ndarray,
        config: FilterConfig, alignment: slice, yaw_rad: float = 0.0) -> FilterOutput:
    """Filter a whole recording: stamps t (N,) [s], specific force and rate (N, 3), the
    stance mask (N,) and the samples to align on (at rest). The loop runs compiled
    (:mod:`pdr_ins_ekf.compiled_filter`), with the equations of :meth:`ZuptEkf.run_block`."""
    return FilterOutput(*kernels.filter_loop(
        *_loop_inputs(t, accel, gyro, stance, config, alignment, yaw_rad)))


def smooth(t: np.ndarray, accel: np.ndarray, gyro: np.ndarray, stance: np.ndarray,
           config: FilterConfig, smoother: SmootherConfig, alignment: slice,
           yaw_rad: float = 0.0) -> SmoothedOutput:
    """The 3-pass smoother of :mod:`pdr_ins_ekf.compiled_smoother` over a recording, from
    the same alignment and equations as :func:`run`."""
    return SmoothedOutput(*compiled_smoother.smoother_loop(
        *_loop_inputs(t, accel, gyro, stance, config, alignment, yaw_rad),
        smoother_params(smoother)))


def record_samples(t: np.ndarray, accel: np.ndarray, gyro: np.ndarray, stance: np.ndarray
                   ) -> Samples:
    """The :class:`~pdr_ins_ekf.kernel_data.Samples` of a record: stamps t (N,) [s] as
    intervals, contiguous specific force and rate (N, 3) and stance mask (N,); with a
    leading runs axis on accel, gyro and stance for
    :func:`pdr_ins_ekf.studies.ekf_montecarlo.ekf_batch`."""
    return Samples(intervals(np.asarray(t, float)), np.ascontiguousarray(accel, float),
                   np.ascontiguousarray(gyro, float), np.ascontiguousarray(stance, bool))


def _loop_inputs(t: np.ndarray, accel: np.ndarray, gyro: np.ndarray, stance: np.ndarray,
                 config: FilterConfig, alignment: slice, yaw_rad: float) -> tuple:
    """The leading arguments of the compiled loops: the samples, the aligned initial
    attitude, biases and covariance, and the filter's parameters."""
    ekf = ZuptEkf.aligned(config, accel[alignment], gyro[alignment], yaw_rad)
    return (record_samples(t, accel, gyro, stance), ekf.state.C, ekf.state.b, ekf.state.P,
            ekf.params)
