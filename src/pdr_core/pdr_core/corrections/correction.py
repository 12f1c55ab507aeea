"""A drift correction as one value, from the sender to the navigator's filter (issue 41):
:class:`Correction`, the heading and z gyro bias to add and the position fix of Muñoz
Díaz 2016, Eqs. (6.2)-(6.3), with the stamp of the step it belongs to. A part not given
is ``None``.

``pdr_drift`` makes it, ``pdr_msgs/srv/ApplyCorrection`` carries it between processes
(:func:`request_fields` and :func:`from_request`, the only places that know the
service's convention that a value and variance both 0 mean "absent"), and a navigator
takes it whole (pdr_pocket.corrections, pdr_ins_ekf.corrections): every part gated at
:data:`GATE_PROBABILITY` before any is applied. What refuses a correction whatever the
navigator's state is here, for both: :func:`refusal` (no part, :func:`invalid` numbers, a
part without a positive variance).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

GATE_PROBABILITY = 0.999   # χ² gate of each part of a correction against the covariance


@dataclass(frozen=True)
class Correction:
    """The parts, each None when absent:

    - ``yaw_rad`` [rad] to add to the heading (ENU yaw, a difference) and its variance
      ``yaw_variance_rad2`` [rad²];
    - ``gyro_bias_z_radps`` [rad/s] to add to the z gyro bias and its variance
      ``gyro_bias_z_variance_rad2ps2`` [rad²/s²];
    - ``position_m`` (3,) [m], a position fix in the map frame (ENU), and its covariance
      ``position_covariance_m2`` (3, 3) [m²];

    and ``stamp_ns``, the stamp [ns] of the step it belongs to (0: apply now)."""

    yaw_rad: float | None = None
    yaw_variance_rad2: float | None = None
    gyro_bias_z_radps: float | None = None
    gyro_bias_z_variance_rad2ps2: float | None = None
    position_m: np.ndarray | None = None
    position_covariance_m2: np.ndarray | None = None
    stamp_ns: int = 0

    @property
    def empty(self) -> bool:
        """No part given."""
        return self.yaw_rad is None and self.gyro_bias_z_radps is None \
            and self.position_m is None


def _given(value: float, variance: float) -> tuple[float | None, float | None]:
    """A request's part: absent (None, None) when its value and variance are both 0."""
    return (None, None) if value == 0 and variance == 0 else (float(value), float(variance))


def from_request(request, stamp_ns: int) -> Correction:
    """The correction a pdr_msgs/srv/ApplyCorrection request carries, stamped ``stamp_ns``
    [ns] (its ``stamp``)."""
    yaw, yaw_var = _given(request.yaw, request.yaw_variance)
    bias, bias_var = _given(request.gyro_bias_z, request.gyro_bias_z_variance)
    position = covariance = None
    if request.has_position:
        p = request.position
        position = np.array([p.x, p.y, p.z], float)
        covariance = np.asarray(request.position_covariance, float).reshape(3, 3)
    return Correction(yaw, yaw_var, bias, bias_var, position, covariance, stamp_ns)


def request_fields(correction: Correction) -> dict:
    """The pdr_msgs/srv/ApplyCorrection request's fields (``stamp`` aside) of a correction:
    an absent part as value and variance 0, ``has_position`` False without a fix."""
    fields = {"yaw": correction.yaw_rad or 0.0,
              "yaw_variance": correction.yaw_variance_rad2 or 0.0,
              "gyro_bias_z": correction.gyro_bias_z_radps or 0.0,
              "gyro_bias_z_variance": correction.gyro_bias_z_variance_rad2ps2 or 0.0,
              "has_position": correction.position_m is not None}
    if correction.position_m is not None:
        fields["position"] = tuple(map(float, correction.position_m))
        fields["position_covariance"] = [
            float(v) for v in np.asarray(correction.position_covariance_m2, float).ravel()]
    return {k: float(v) if isinstance(v, (float, np.floating)) else v
            for k, v in fields.items()}


def invalid(correction: Correction) -> str | None:
    """Why the correction's numbers cannot be used (None: they can), each named by its
    field of pdr_msgs/srv/ApplyCorrection, in the service's order."""
    c = correction
    problems = [f"{name} {value!r} is not finite" if not np.isfinite(value) else
                f"{name} {value!r} is negative" for name, value, variance in (
                    ("yaw", c.yaw_rad, False), ("yaw_variance", c.yaw_variance_rad2, True),
                    ("gyro_bias_z", c.gyro_bias_z_radps, False),
                    ("gyro_bias_z_variance", c.gyro_bias_z_variance_rad2ps2, True))
                if value is not None and (not np.isfinite(value) or (variance and value < 0))]
    if c.position_m is not None:
        cov = np.asarray(c.position_covariance_m2, float).reshape(3, 3)
        if not np.isfinite(c.position_m).all():
            problems.append(f"position {list(map(float, c.position_m))} is not finite")
        if not np.isfinite(cov).all():
            problems.append("position_covariance is not finite")
        elif np.any(np.diag(cov) < 0):
            problems.append(f"position_covariance has a negative variance "
                            f"(diagonal {np.diag(cov).tolist()} m²)")
    return "; ".join(problems) or None


# each scalar part's request field and unit
PARTS = (("yaw", "rad"), ("gyro_bias_z", "rad/s"))


def refusal(correction: Correction) -> str | None:
    """Why the correction cannot be taken whatever the navigator's state (None: it can):
    no part ("nothing to apply: ..."), numbers that cannot be used (:func:`invalid`), a
    part without a positive variance; each named by its field of
    pdr_msgs/srv/ApplyCorrection. The navigators add what their state refuses."""
    c = correction
    if c.empty:
        return "nothing to apply: no yaw, gyro_bias_z or position given"
    unusable = invalid(c)
    problems = [unusable] if unusable else []
    for (name, unit), value, variance in zip(PARTS, (c.yaw_rad, c.gyro_bias_z_radps),
                                             (c.yaw_variance_rad2,
                                              c.gyro_bias_z_variance_rad2ps2), strict=True):
        if value is not None and np.isfinite(value) and (variance or 0.0) == 0:
            problems.append(f"{name}_variance is 0: a {name} of {value:+.4g} {unit} needs a "
                            "positive variance")
    return "; ".join(problems) or None
