"""Error-state EKF of a foot-mounted INS aided by zero-velocity (ZUPT) and zero-angular-rate
(ZARU) pseudo-measurements: 001_5b5dbf275b14cf0a.txt, Eq. (8) (closed loop, 9 states) and
004_1269ce0256f0c590.txt, Eq. (2) (15 states with accelerometer and gyro biases).

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

Frames and units: ENU navigation frame, FLU body frame, SI.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdr_core.rotations import rotation_from_euler, skew
from pdr_ins_ekf.attitude_update import closed_form_increments
from pdr_ins_ekf.compiled_filter import BIAS_MODEL_CODES, filter_loop

BIAS_MODELS = ("none", "random_walk", "gauss_markov")


@dataclass(frozen=True)
class FilterConfig:
    """Noise and aiding parameters (SI; densities per √Hz)."""

    acc_noise: float = 0.002          # [m/s²/√Hz]
    gyro_noise: float = 0.0002        # [rad/s/√Hz]
    zupt_sigma_mps: float = 0.01      # [m/s]
    zaru_sigma_radps: float = 0.01    # [rad/s]
    zaru: bool = False
    bias_model: str = "none"
    acc_bias_noise: float = 1e-4      # [m/s²/√s]
    gyro_bias_noise: float = 1e-5     # [rad/s/√s]
    bias_tau_s: float = 300.0         # Gauss–Markov correlation time [s]
    init_pos_sigma_m: float = 1e-5
    init_vel_sigma_mps: float = 1e-5
    init_att_sigma_rad: float = (0.1 * np.pi / 180)
    init_yaw_sigma_rad: float = (0.1 * np.pi / 180)
    init_acc_bias_sigma: float = 0.05  # [m/s²]
    init_gyro_bias_sigma: float = 0.005  # [rad/s]
    gravity_mps2: float = 9.80665

    def __post_init__(self) -> None:
        if self.bias_model not in BIAS_MODELS:
            raise ValueError(f"bias_model must be one of {', '.join(BIAS_MODELS)}, "
                             f"got {self.bias_model!r}")
        if self.zaru and self.bias_model == "none":
            raise ValueError("ZARU needs the gyro bias states (bias_model random_walk or "
                             "gauss_markov)")
        for name in ("acc_noise", "gyro_noise", "zupt_sigma_mps", "zaru_sigma_radps"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")

    @property
    def states(self) -> int:
        return 9 if self.bias_model == "none" else 15


@dataclass
class FilterOutput:
    """Per-sample estimates: position, velocity (N, 3), attitude C_b^n (N, 3, 3), biases
    (N, 6) (zero for 9 states), covariance diagonal (N, states) and full position and
    velocity covariance blocks (N, 3, 3)."""

    position: np.ndarray
    velocity: np.ndarray
    attitude: np.ndarray
    bias: np.ndarray
    variance: np.ndarray
    position_cov: np.ndarray
    velocity_cov: np.ndarray


class ZuptEkf:
    """The filter state and one-sample step; :func:`run` drives it over arrays."""

    def __init__(self, config: FilterConfig, attitude: np.ndarray, gyro_bias=(0.0, 0.0, 0.0),
                 position=(0.0, 0.0, 0.0)) -> None:
        self.config = config
        n = config.states
        self.p = np.asarray(position, float).copy()
        self.v = np.zeros(3)
        self.C = np.asarray(attitude, float).copy()
        self.b = np.concatenate([np.zeros(3), np.asarray(gyro_bias, float)])
        sig = ([config.init_pos_sigma_m] * 3 + [config.init_vel_sigma_mps] * 3
               + [config.init_att_sigma_rad] * 2 + [config.init_yaw_sigma_rad])
        if n == 15:
            sig += [config.init_acc_bias_sigma] * 3 + [config.init_gyro_bias_sigma] * 3
        self.P = np.diag(np.square(sig))
        self.prev_f = None
        self.prev_w = None
        self._H_zupt = np.zeros((3, n))
        self._H_zupt[:, 3:6] = np.eye(3)
        if n == 15:
            self._H_zaru = np.zeros((3, n))
            self._H_zaru[:, 12:15] = np.eye(3)

    def predict(self, f: np.ndarray, w: np.ndarray, dt: float) -> None:
        """Propagate the nominal state (trapezoidal) and the covariance over dt."""
        cfg = self.config
        f_c, w_c = f - self.b[:3], w - self.b[3:]
        if self.prev_f is None:
            self.prev_f, self.prev_w, self.prev_a = f_c, w_c, self.C @ f_c
        g = np.array([0.0, 0.0, cfg.gravity_mps2])
        a_prev = self.prev_a
        self.C = self.C @ closed_form_increments(((self.prev_w + w_c) / 2)[None], dt)[0]
        a_now = self.C @ f_c
        v_new = self.v + ((a_prev + a_now) / 2 - g) * dt
        self.p = self.p + (self.v + v_new) / 2 * dt
        self.v = v_new
        self.prev_f, self.prev_w, self.prev_a = f_c, w_c, a_now
        n = cfg.states
        F = np.eye(n)
        F[0:3, 3:6] = np.eye(3) * dt
        F[3:6, 6:9] = skew(a_now) * dt
        Q = np.zeros((n, n))
        Q[3:6, 3:6] = np.eye(3) * cfg.acc_noise**2 * dt
        Q[6:9, 6:9] = np.eye(3) * cfg.gyro_noise**2 * dt
        if n == 15:
            F[3:6, 9:12] = -self.C * dt
            F[6:9, 12:15] = self.C * dt
            if cfg.bias_model == "gauss_markov":
                F[9:15, 9:15] -= np.eye(6) * dt / cfg.bias_tau_s
            Q[9:12, 9:12] = np.eye(3) * cfg.acc_bias_noise**2 * dt
            Q[12:15, 12:15] = np.eye(3) * cfg.gyro_bias_noise**2 * dt
            Q[3:6, 3:6] = self.C @ Q[3:6, 3:6] @ self.C.T
            Q[6:9, 6:9] = self.C @ Q[6:9, 6:9] @ self.C.T
        self.P = F @ self.P @ F.T + Q
        self.P = (self.P + self.P.T) / 2

    def _update(self, z: np.ndarray, H: np.ndarray, sigma: float) -> None:
        R = np.eye(len(z)) * sigma**2
        S = H @ self.P @ H.T + R
        K = np.linalg.solve(S, H @ self.P).T
        dx = K @ z
        I_KH = np.eye(len(dx)) - K @ H
        self.P = I_KH @ self.P @ I_KH.T + K @ R @ K.T
        self.P = (self.P + self.P.T) / 2
        self.p = self.p + dx[0:3]
        self.v = self.v + dx[3:6]
        self.C = (np.eye(3) - skew(dx[6:9])) @ self.C
        u, _, vt = np.linalg.svd(self.C)
        self.C = u @ vt
        if len(dx) == 15:
            self.b = self.b + dx[9:15]
        self.prev_a = self.C @ self.prev_f

    @classmethod
    def aligned(cls, config: FilterConfig, accel_rest: np.ndarray, gyro_rest: np.ndarray,
                yaw_rad: float = 0.0) -> ZuptEkf:
        """A filter aligned on samples at rest: roll and pitch from the mean specific
        force, gyro bias from the mean rate, the given yaw."""
        return cls(config, initial_attitude(accel_rest, yaw_rad),
                   gyro_bias=gyro_rest.mean(axis=0))

    def step(self, f: np.ndarray, w: np.ndarray, dt: float, stance: bool) -> None:
        """One sample: propagate over dt (0 for the first), then the pseudo-measurements."""
        self.predict(f, w, dt)
        if stance:
            self.zupt()
            if self.config.zaru:
                self.zaru(w)

    def zupt(self) -> None:
        """Zero-velocity pseudo-measurement."""
        self._update(-self.v, self._H_zupt, self.config.zupt_sigma_mps)

    def zaru(self, w: np.ndarray) -> None:
        """Zero-angular-rate pseudo-measurement (15 states)."""
        self._update(w - self.b[3:], self._H_zaru, self.config.zaru_sigma_radps)


def initial_attitude(accel: np.ndarray, yaw_rad: float) -> np.ndarray:
    """C_b^n from the mean specific force at rest (roll, pitch) and a given yaw."""
    f = accel.mean(axis=0)
    roll = np.arctan2(f[1], f[2])
    pitch = np.arctan2(-f[0], np.hypot(f[1], f[2]))
    return rotation_from_euler(np.array([roll]), np.array([pitch]), np.array([yaw_rad])
                               ).as_matrix()[0]


def run(t: np.ndarray, accel: np.ndarray, gyro: np.ndarray, stance: np.ndarray,
        config: FilterConfig, alignment: slice, yaw_rad: float = 0.0) -> FilterOutput:
    """Filter a whole recording: stamps t (N,) [s], specific force and rate (N, 3), the
    stance mask (N,) and the samples to align on (at rest). The loop runs compiled
    (:mod:`pdr_ins_ekf.compiled_filter`), with the equations of :meth:`ZuptEkf.step`."""
    ekf = ZuptEkf.aligned(config, accel[alignment], gyro[alignment], yaw_rad)
    c = config
    return FilterOutput(*filter_loop(
        np.ascontiguousarray(t, float), np.ascontiguousarray(accel, float),
        np.ascontiguousarray(gyro, float), np.ascontiguousarray(stance, bool), c.zaru,
        ekf.C, ekf.b, ekf.P, c.acc_noise, c.gyro_noise, c.acc_bias_noise, c.gyro_bias_noise,
        c.bias_tau_s, BIAS_MODEL_CODES[c.bias_model], c.zupt_sigma_mps, c.zaru_sigma_radps,
        c.gravity_mps2))
