"""Drift corrections taken by the foot navigator's filter (Muñoz Díaz 2016, Eqs.
(6.2)-(6.3)): a :class:`~pdr_core.corrections.correction.Correction` from ``pdr_drift``, whole or
not at all, with the pocket navigator's semantics (pdr_pocket.corrections).

Each part is a measurement of the error state δx = [δp, δv, δθ (, δb_a, δb_g)]
(pdr_ins_ekf.zupt_ekf), with C = (I − [δθ×])·Ĉ:

- the yaw change Δψ [rad] with variance σ²: the heading is ψ = ψ̂ − δθ_z (a rotation about
  the navigation frame's up axis by −δθ_z), so z = Δψ with H = −e_θz;
- the z gyro bias change Δb [rad/s] (15 states only): z = Δb with H = e_bgz, the body z
  axis's bias (δb = b − b̂). With 9 states the filter has no bias to change and the part
  is refused, saying so;
- the position fix p_f [m] (3,) with covariance R (3, 3): z = p_f − p̂ with H = [I 0].

Every part is gated on its own against the covariance before any is applied: its
normalised innovation squared z·S⁻¹·z, S = H·P·Hᵀ + R, below the χ² bound at
:data:`pdr_core.corrections.correction.GATE_PROBABILITY` (1 dof for the yaw and the bias, 3 for the
position). Then all parts are one Kalman update, in Joseph form, fed back into the nominal
state as the ZUPT's is (Simón Colomar et al. 2012, Eq. (8)), with the attitude turned by the
exact rotation exp(−[δθ×]) rather than its first order: a correction may be degrees. A
correction therefore moves the heading by the share of the request its variance gives it
against the filter's: a filter that is sure of its heading takes little of it
(docs/foot_ins.md, "Drift corrections", says which configuration to use).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import block_diag
from scipy.spatial.transform import Rotation

from pdr_core.corrections.correction import GATE_PROBABILITY, Correction
from pdr_core.corrections.correction import refusal as stateless_refusal
from pdr_core.maths.chi2 import chi2_quantile
from pdr_ins_ekf.kernel_data import (
    ACC_BIAS,
    ATTITUDE,
    AXES,
    GYRO_BIAS,
    HEADING,
    NAV_AND_BIAS_STATES,
    POSITION,
    PREV_FORCE,
    PREV_NAV_FORCE,
    VELOCITY,
    NavState,
)

BIAS_Z = GYRO_BIAS + 2       # the error state's row of the body z gyro bias


def refusal(correction: Correction, states: int) -> str | None:
    """Why the correction cannot be taken whatever the state (None: it can): those of
    pdr_core.corrections.correction.refusal, and a bias part for a filter without bias states, named
    by its field of pdr_msgs/srv/ApplyCorrection."""
    problem = stateless_refusal(correction)
    problems = [problem] if problem else []
    if correction.gyro_bias_z_radps is not None and states != NAV_AND_BIAS_STATES:
        problems.append(f"gyro_bias_z: the filter has {states} states and no gyro bias to "
                        f"correct; the bias part needs the {NAV_AND_BIAS_STATES}-state form "
                        "(filter.bias_model random_walk or gauss_markov)")
    return "; ".join(problems) or None


@dataclass(frozen=True)
class Part:
    """One part of a correction as a measurement: its field's name, the innovation
    ν = z − H·x̂ (k,), H (k, n) and R (k, k)."""

    name: str
    innovation: np.ndarray
    H: np.ndarray
    R: np.ndarray


def _selecting(n: int, first: int, count: int, sign: float = 1.0) -> np.ndarray:
    """H (count, n) picking ``count`` error states from row ``first``, times ``sign``."""
    H = np.zeros((count, n))
    H[:, first:first + count] = sign * np.eye(count)
    return H


def parts(correction: Correction, state: NavState) -> list[Part]:
    """The parts given, in the request's order (module docstring)."""
    c, n = correction, state.P.shape[0]
    out = []
    if c.yaw_rad is not None:
        out.append(Part("yaw", np.array([c.yaw_rad]), _selecting(n, HEADING, 1, -1.0),
                        np.array([[c.yaw_variance_rad2]])))
    if c.gyro_bias_z_radps is not None:
        out.append(Part("gyro_bias_z", np.array([c.gyro_bias_z_radps]),
                        _selecting(n, BIAS_Z, 1), np.array([[c.gyro_bias_z_variance_rad2ps2]])))
    if c.position_m is not None:
        out.append(Part("position", np.asarray(c.position_m, float) - state.p,
                        _selecting(n, POSITION, AXES),
                        np.asarray(c.position_covariance_m2, float).reshape(AXES, AXES)))
    return out


def gate(correction: Correction, state: NavState) -> tuple[str | None, dict[str, float]]:
    """Why the parts would be refused against the covariance now (None: all pass), and
    each part's NIS (module docstring)."""
    problems, nis = [], {}
    for part in parts(correction, state):
        S = part.H @ state.P @ part.H.T + part.R
        value = float(part.innovation @ np.linalg.solve(S, part.innovation))
        limit = float(chi2_quantile(GATE_PROBABILITY, len(part.innovation)))
        nis[part.name] = value
        if not value <= limit:
            problems.append(f"{part.name} refused by the χ² gate: NIS {value:.1f} > "
                            f"{limit:.1f}")
    return "; ".join(problems) or None, nis


def apply(correction: Correction, state: NavState) -> None:
    """The Kalman update of every part at once (module docstring), not gated again, fed
    back into ``state`` in place."""
    given = parts(correction, state)
    H = np.vstack([part.H for part in given])
    R = block_diag(*(part.R for part in given))
    nu = np.concatenate([part.innovation for part in given])
    P = state.P
    K = np.linalg.solve(H @ P @ H.T + R, H @ P).T
    joseph = np.eye(len(P)) - K @ H
    P[:, :] = joseph @ P @ joseph.T + K @ R @ K.T
    P[:, :] = (P + P.T) / 2
    Pb = state.Pb       # the biases' share, with the same gain (compiled_filter.bias_share)
    Pb[:, :] = joseph @ Pb @ joseph.T
    Pb[:, :] = (Pb + Pb.T) / 2
    _feed_back(state, K @ nu)


def _feed_back(state: NavState, dx: np.ndarray) -> None:
    """p̂ += δp, v̂ += δv, Ĉ ← exp(−[δθ×])·Ĉ, b̂ += δb (15 states), then the last sample's
    navigation-frame specific force turned with Ĉ, as the compiled feed_back does."""
    state.p[:] += dx[POSITION:POSITION + AXES]
    state.v[:] += dx[VELOCITY:VELOCITY + AXES]
    turn = Rotation.from_rotvec(-dx[ATTITUDE:ATTITUDE + AXES]).as_matrix()
    state.C[:, :] = turn @ state.C
    if len(dx) == NAV_AND_BIAS_STATES:
        state.b[:] += dx[ACC_BIAS:ACC_BIAS + 2 * AXES]
    state.prev[PREV_NAV_FORCE] = state.C @ state.prev[PREV_FORCE]
