"""Position error of pure INS for each attitude method over sample rates: the study of
Zampella et al. 2011, section III-A, Fig. 6.

A noiseless simulated 10-stride straight walk (the basic pattern of Fig. 4) is mechanized
from the true initial state with every method of :data:`METHODS`, at rates from 50 Hz to
1 kHz; the error is the distance between the final estimated and true positions.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdr_ins_ekf.attitude_update import METHODS
from pdr_ins_ekf.strapdown import mechanize
from pdr_sim import signals
from pdr_sim.foot_trajectory import FootTrajectory
from pdr_sim.scenario import scenario_from_dict

RATES_HZ = (50.0, 100.0, 200.0, 400.0, 1000.0)
TEN_STEPS = {"name": "ten_steps", "segments": [{"type": "standing", "duration_s": 1.0},
                                               {"type": "straight", "steps": 10},
                                               {"type": "standing", "duration_s": 0.4}]}


@dataclass(frozen=True)
class MechanizationStudy:
    """errors_m[i, j]: final position error [m] of METHODS[j] at rates_hz[i]."""

    rates_hz: tuple[float, ...]
    methods: tuple[str, ...]
    errors_m: np.ndarray
    integration: str

    def table(self) -> str:
        head = f"{'rate [Hz]':>10}" + "".join(f"{m:>13}" for m in self.methods)
        rows = [f"{r:>10g}" + "".join(f"{e:>13.3e}" for e in row)
                for r, row in zip(self.rates_hz, self.errors_m, strict=True)]
        return "\n".join([f"final position error [m], {self.integration} integration", head,
                          *rows])

    def csv(self) -> str:
        lines = ["rate_hz," + ",".join(self.methods)]
        lines += [f"{r:g}," + ",".join(f"{e:.6e}" for e in row)
                  for r, row in zip(self.rates_hz, self.errors_m, strict=True)]
        return "\n".join(lines) + "\n"


def run_study(rates_hz=RATES_HZ, methods=METHODS, integration: str = "trapezoidal",
              scenario: dict | None = None) -> MechanizationStudy:
    """Mechanize the noiseless walk with every method at every rate."""
    model = FootTrajectory(scenario_from_dict(scenario or TEN_STEPS, "mechanization study"))
    errors = np.empty((len(rates_hz), len(methods)))
    for i, rate in enumerate(rates_hz):
        traj = model.sample(rate)
        gyro, accel = signals.angular_rate(traj), signals.specific_force(traj)
        for j, method in enumerate(methods):
            sol = mechanize(gyro, accel, rate, traj.matrix[0], method=method,
                            integration=integration)
            errors[i, j] = np.linalg.norm(sol.position[-1] - traj.position[-1])
    return MechanizationStudy(tuple(rates_hz), tuple(methods), errors, integration)
