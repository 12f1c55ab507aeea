"""Drift corrections taken by the pocket navigator (Muñoz Díaz 2016, Eqs. (6.2)-(6.3)):
a :class:`~pdr_core.corrections.correction.Correction` from ``pdr_drift``, whole or not at all.

The yaw and the z gyro bias are Kalman updates of the orientation filter
(pdr_pocket.orientation), the position fix one of the position filter
(pdr_pocket.position). Every part is checked and gated once, against the covariances
before any part is applied; one refused part refuses the whole correction, changes
nothing, and the message names each refused part and why, by its field of
pdr_msgs/srv/ApplyCorrection. What refuses a correction whatever the state (no part,
numbers that cannot be used, a part without a variance) is pdr_core.corrections.correction.refusal,
the foot navigator's too.
A yaw correction also turns the heading summed since the last step
(:meth:`pdr_pocket.step_assembly.StepAssembly.turn_partial_heading`), so it counts from
the step it belongs to.
"""
from __future__ import annotations

import numpy as np

from pdr_core.corrections.correction import Correction, refusal
from pdr_pocket.compiled_orientation_measurements import BIAS_Z_CORRECTION, YAW_CORRECTION
from pdr_pocket.orientation import CORRECTION_NAMES, OrientationFilter
from pdr_pocket.position import PSI
from pdr_pocket.step_assembly import StepAssembly


class CorrectionTaker:
    """Takes corrections into a navigator's orientation filter and steps (the module
    docstring); ``counts`` the accepted and the refused."""

    def __init__(self, orientation: OrientationFilter, assembly: StepAssembly) -> None:
        self.orientation = orientation
        self.assembly = assembly
        self.counts = {"accepted": 0, "refused": 0}

    def take(self, correction: Correction) -> tuple[bool, str]:
        """Apply ``correction`` whole or not at all: (accepted, what was done or why
        not)."""
        c = correction
        problem = refusal(c)
        nis: list[float] = []
        # the parts given (a variance is positive once refusal() passed)
        parts = [(kind, value, variance) for kind, value, variance in (
            (YAW_CORRECTION, c.yaw_rad, c.yaw_variance_rad2),
            (BIAS_Z_CORRECTION, c.gyro_bias_z_radps, c.gyro_bias_z_variance_rad2ps2))
            if value is not None]
        if problem is None:
            problem, nis = self._gate(parts, c.position_m, c.position_covariance_m2)
        if problem is not None:
            self.counts["refused"] += 1
            return False, problem if c.empty else f"nothing applied: {problem}"
        self.counts["accepted"] += 1
        return True, ", ".join(
            self._apply_parts(parts, nis, c.position_m, c.position_covariance_m2))

    def _gate(self, parts, position, position_cov) -> tuple[str | None, list[float]]:
        """Why the parts (kind, value to add, variance) and the position fix would be
        refused, every part gated against the covariances as they are now (None: all
        pass), and the NIS of each."""
        f = self.orientation
        if f.state is None:
            return "the navigator has not started (no IMU sample yet)", []
        gated = [f.gate(kind, self._corrected(kind, value), variance)
                 for kind, value, variance in parts]
        if position is not None:
            gated.append(self.assembly.position.gate_position(position, position_cov))
        problems = "; ".join(problem for problem, _ in gated if problem is not None)
        return problems or None, [nis for _, nis in gated]

    def _corrected(self, kind: int, value: float) -> float:
        """The yaw [rad] or the z gyro bias [rad/s] with ``value`` added."""
        f = self.orientation
        return f.yaw + value if kind == YAW_CORRECTION else float(f.state.bias[2]) + value

    def _apply_parts(self, parts, nis, position, position_cov) -> list[str]:
        """Apply what :meth:`_gate` passed, in the request's order, each as a
        measurement of the state before any (not gated again); what was done, in words."""
        f, done = self.orientation, []
        targets = [self._corrected(kind, value) for kind, value, _ in parts]
        for (kind, value, variance), target, part_nis in zip(
                parts, targets, nis[:len(parts)], strict=True):
            before = f.yaw
            f.apply(kind, target, variance)
            name, unit = CORRECTION_NAMES[kind]
            degrees = f"{np.degrees(value):+.2f}°, " if kind == YAW_CORRECTION else ""
            done.append(f"{name} {value:+.4g} {unit} ({degrees}NIS {part_nis:.2f})")
            if kind == YAW_CORRECTION:
                self.assembly.turn_partial_heading(f.yaw - before)
                track = self.assembly.position
                track.correct_heading(track.x[PSI] + value, variance, f.yaw_variance)
            else:
                self.assembly.position.limit_drift(variance)
        if position is not None:
            self.assembly.position.apply_position(position, position_cov)
            done.append(f"position fix (NIS {nis[-1]:.2f})")
        return done
