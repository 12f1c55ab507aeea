"""Allan analysis of static IMU data: the table, CSV and PNG of ``pdr-sim allan``.

Units at this edge: gyroscope ARW in °/√h, bias instability in °/h, RRW in °/s/√h;
accelerometer VRW in m/s/√h and µg/√Hz, bias instability in mg, random walk in
m/s²/√h. AR(1) parameters follow Muñoz Díaz 2016, Eqs. (3.10)–(3.11).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdr_core import units
from pdr_core.io.batch import MessageBatch
from pdr_core.sensors.allan import NoiseParameters, allan_deviation, noise_parameters

SENSORS = {"gyro": "angular_velocity", "accel": "linear_acceleration"}


@dataclass(frozen=True)
class AllanReport:
    """Curves and parameters per sensor and axis."""

    rate_hz: float
    curves: dict[str, tuple[np.ndarray, np.ndarray]]
    params: dict[str, NoiseParameters]

    def rows(self) -> list[dict[str, float | str]]:
        out = []
        for name, p in self.params.items():
            gyro = name.startswith("gyro")
            row: dict[str, float | str] = {"axis": name}
            if gyro:
                row |= {"arw_deg_per_sqrt_h": units.arw_from_si(p.white_density),
                        "bias_instability_deg_per_h": p.bias_instability / units.DEG * 3600,
                        "t_beta_s": p.bias_instability_tau_s,
                        "rrw_deg_per_s_per_sqrt_h": p.random_walk_density / units.DEG
                        * units.SQRT_HOUR,
                        "ar1_tau_samples": p.ar1_tau_samples,
                        "ar1_sigma_bias_deg_per_s": p.ar1_sigma_bias / units.DEG}
            else:
                row |= {"vrw_mps_per_sqrt_h": units.vrw_from_si(p.white_density),
                        "vrw_ug_per_sqrt_hz": p.white_density
                        / units.ug_per_sqrt_hz_to_si(1.0),
                        "bias_instability_mg": p.bias_instability / units.mg_to_si(1.0),
                        "t_beta_s": p.bias_instability_tau_s,
                        "random_walk_mps2_per_sqrt_h": p.random_walk_density * units.SQRT_HOUR,
                        "ar1_tau_samples": p.ar1_tau_samples,
                        "ar1_sigma_bias_mg": p.ar1_sigma_bias / units.mg_to_si(1.0)}
            out.append(row)
        return out

    def table(self) -> str:
        lines = []
        for row in self.rows():
            cells = [f"{k}={v:.4g}" if isinstance(v, float) else f"{v:<7}"
                     for k, v in row.items()]
            lines.append("  ".join(cells))
        return "\n".join(lines)

    def csv(self) -> str:
        lines = []
        for sensor in ("gyro", "accel"):
            rows = [r for r in self.rows() if str(r["axis"]).startswith(sensor)]
            if rows:
                lines.append(",".join(rows[0]))
                lines += [",".join(f"{v:.6g}" if isinstance(v, float) else str(v)
                                   for v in r.values()) for r in rows]
        return "\n".join(lines) + "\n"

    def plot(self, path: Path, title: str) -> None:
        from pdr_sim import plots  # Matplotlib: only for the plots

        base = path.with_suffix("")
        plots.allan_png({k: v for k, v in self.curves.items() if k.startswith("gyro")},
                        path, "σ_A [rad/s]", f"gyroscope: {title}")
        plots.allan_png({k: v for k, v in self.curves.items() if k.startswith("accel")},
                        base.with_name(base.name + "_accel.png"), "σ_A [m/s²]",
                        f"accelerometer: {title}")


def allan_report(imu: MessageBatch) -> AllanReport:
    """Allan deviation of both sensors of an Imu batch (static data, uniform rate)."""
    rate = (len(imu) - 1) / (imu.t_s[-1] - imu.t_s[0])
    curves, params = {}, {}
    for sensor, field in SENSORS.items():
        if sensor == "gyro" and imu["angular_velocity_covariance"][0, 0] == -1:
            continue
        for axis, name in enumerate("xyz"):
            taus, adev = allan_deviation(imu[field][:, axis], rate)
            curves[f"{sensor}_{name}"] = (taus, adev)
            params[f"{sensor}_{name}"] = noise_parameters(taus, adev, rate)
    return AllanReport(rate, curves, params)
