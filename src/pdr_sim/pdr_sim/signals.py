"""True sensor signals of any trajectory (before sensor errors).

- Specific force, Zampella et al. 2011, Eq. (6) in ENU: f_b = C_b^nᵀ·(a_n + [0, 0, g]ᵀ).
- Angular rate ω_ib^b = ω_nb^b + C_b^nᵀ·ω_ie^n, with the Earth rate at latitude λ of
  Muñoz Díaz 2016, Eq. (3.24): ω_ie^n = ω_e·[0, cos λ, sin λ]ᵀ (ENU); omitted when
  no latitude is given (the transport rate of a pedestrian is negligible).
- Magnetic field, Muñoz Díaz 2016, Eq. (3.26) without its noise term:
  μ = C_b^nᵀ·H(p), H from :class:`pdr_core.sensors.magnetic_field.MagneticField`.

All outputs are (N, 3) in the body frame (FLU), SI units.
"""
from __future__ import annotations

import numpy as np

from pdr_core.constants import STANDARD_GRAVITY_MPS2, earth_rate_enu
from pdr_core.sensors.magnetic_field import MagneticField
from pdr_sim.trajectory import Trajectory


def specific_force(traj: Trajectory, gravity_mps2: float = STANDARD_GRAVITY_MPS2) -> np.ndarray:
    """f_b [m/s²], Zampella et al. 2011, Eq. (6)."""
    return traj.to_body(traj.acceleration + np.array([0.0, 0.0, gravity_mps2]))


def angular_rate(traj: Trajectory, latitude_deg: float | None = None) -> np.ndarray:
    """ω_ib^b [rad/s]: the body rate, plus the Earth rate at ``latitude_deg`` if given."""
    rate = traj.body_rate
    if latitude_deg is not None:
        rate = rate + traj.to_body(earth_rate_enu(latitude_deg))
    return rate


def magnetic_field(traj: Trajectory, field: MagneticField) -> np.ndarray:
    """μ [T] in the body frame, Muñoz Díaz 2016, Eq. (3.26) (noise is added by the error model)."""
    return traj.to_body(field.at(traj.position))
