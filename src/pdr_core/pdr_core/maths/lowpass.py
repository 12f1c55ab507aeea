"""The gains of a first-order low-pass, each spelled once for every kernel.

A first-order low-pass τ·ẏ = x − y of time constant τ, sampled over a step δt, is
y ← y + α·(x − y) = λ·y + (1 − λ)·x. Three discretisations are in use; each has its helper
here, and a kernel calls the one it needs rather than writing the formula again:

- :func:`lowpass_gain`: α = 1 − e^{−δt/τ}, exact for a signal held over the step, so a
  stream with jittering or missing stamps keeps the filter's time constant (a fixed α
  would be one for a fixed rate only). Two such stages in cascade (the tilt reference of
  pdr_pocket.compiled_attitude) fall off at 40 dB a decade above 1/(2πτ), as a
  second-order filter does. :func:`lowpass_decay` is its λ = e^{−δt/τ}, the weight left
  on the old value (and the correlation e^{−δt/τ} of a first-order Gauss–Markov
  process over δt, as the AR(1) biases use it: the same decay).
- :func:`backward_euler_gain`: α = δt/(τ + δt), the implicit (backward) Euler step of
  τ·ẏ = x − y, y_k = y_{k−1} + (δt/τ)·(x_k − y_k). Within 1 % of the exact gain for
  δt < τ/50 but always smaller (a longer effective time constant for coarse steps); the
  gravity direction without a gyroscope (pdr_pocket.compiled_gravity) was tuned with it.
- :func:`forward_euler_gain`: α = min(δt/τ, 1), the explicit Euler step, clipped at 1
  (no overshoot for δt > τ); larger than the exact gain, by δt/(2τ) relative for small
  steps. The gait window's swing axis (pdr_pocket.compiled_gait_window) uses it.

Each helper computes the same floating-point expression that its kernels wrote inline
before, so moving a kernel onto it left every output bit for bit the same.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from pdr_core.maths import kernel_cache

kernel_cache.forget_if_changed(__file__)


@njit(cache=True)
def lowpass_decay(dt_s, tau_s):
    """λ [0, 1], the weight of the old value in a first-order low-pass of time constant
    ``tau_s`` [s] over ``dt_s`` [s]: e^{−δt/τ} (1 for δt ≤ 0, 0 for τ ≤ 0; 1 for τ = ∞,
    a random constant)."""
    if dt_s <= 0.0:
        return 1.0
    if tau_s <= 0.0:
        return 0.0
    return np.exp(-dt_s / tau_s)


@njit(cache=True)
def lowpass_gain(dt_s, tau_s):
    """α [0, 1] of a first-order low-pass of time constant ``tau_s`` [s] over ``dt_s``
    [s]: 1 − e^{−δt/τ} = 1 − :func:`lowpass_decay` (0 for δt ≤ 0, 1 for τ ≤ 0: no
    filtering)."""
    return 1.0 - lowpass_decay(dt_s, tau_s)


@njit(cache=True)
def backward_euler_gain(dt_s, tau_s):
    """α of a first-order low-pass of time constant ``tau_s`` [s] over ``dt_s`` [s] by the
    backward Euler step: δt/(τ + δt) (0 for δt = 0; the module docstring compares it with
    :func:`lowpass_gain`)."""
    return dt_s / (tau_s + dt_s)


@njit(cache=True)
def forward_euler_gain(dt_s, tau_s):
    """α of a first-order low-pass of time constant ``tau_s`` [s] over ``dt_s`` [s] by the
    forward Euler step, clipped: min(δt/τ, 1) (the module docstring compares it with
    :func:`lowpass_gain`)."""
    return min(dt_s / tau_s, 1.0)
