"""Magnetometer calibration for the pocket navigator (Muñoz Díaz 2016, Section 3.4.4).

The fit itself is :func:`pdr_core.sensors.magnetometer_calibration.fit_ellipsoid` (rotation M,
offset l, scale ξ bringing the raw ellipsoid to the unit sphere, l in units of the local
field strength |H∞|). This module adds what a user needs around it:

- :func:`sphere_coverage`: how much of the sphere of directions the readings cover, seen
  from the centre of their best-fitting sphere (a fit from readings along one arc, as a
  walking thigh gives, is meaningless);
- :class:`MagCalibration`: the fitted parameters with |H∞|, applied to raw readings and
  kept in a YAML file the filter's configuration names (``magnetometer_calibration``).

Units: tesla inside; µT in the YAML file and in messages to the user.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from pdr_core.errors import InputError
from pdr_core.sensors.magnetic_field import IronDistortion
from pdr_core.sensors.magnetometer_calibration import fit_ellipsoid

COVERAGE_CELLS = 200                # equal-area directions (Fibonacci sphere)
MIN_COVERAGE = 0.6                  # below this share of the sphere a fit is refused (more
                                    # than a hemisphere)


def _fibonacci_sphere(n: int) -> np.ndarray:
    """n nearly equally spaced unit vectors, (n, 3)."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    r = np.sqrt(1.0 - z * z)
    phi = np.pi * (1.0 + np.sqrt(5.0)) * k
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def sphere_centre(raw: np.ndarray) -> np.ndarray:
    """The centre of the sphere that best fits the readings (linear least squares on
    ‖x − c‖² = r²); along a direction the readings do not span it stays near their mean."""
    mean = raw.mean(axis=0)
    x = raw - mean
    design = np.column_stack([2.0 * x, np.ones(len(x))])
    solution, *_ = np.linalg.lstsq(design, (x * x).sum(axis=1), rcond=1e-6)
    return mean + solution[:3]


def sphere_coverage(raw_t: np.ndarray) -> float:
    """Share (0-1) of :data:`COVERAGE_CELLS` equal-area cells of the sphere of directions
    hit by the readings, seen from the centre of their best-fitting sphere (readings along
    one arc, as a walking thigh gives, are seen from its centre and cover little)."""
    raw = np.asarray(raw_t, float)
    raw = raw[np.isfinite(raw).all(axis=1)]
    if len(raw) < 4:
        return 0.0
    d = raw - sphere_centre(raw)
    d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-30)
    cells = _fibonacci_sphere(COVERAGE_CELLS)
    nearest = np.argmax(d @ cells.T, axis=1)
    return float(len(np.unique(nearest)) / COVERAGE_CELLS)


@dataclass(frozen=True)
class MagCalibration:
    """Hard/soft-iron correction: calibrated = |H∞|·ξ·M·(raw/|H∞| − l) (Table 3.3 form)."""

    distortion: IronDistortion
    field_norm_t: float
    residual_rms: float             # of ‖calibrated‖/|H∞| − 1 over the fitted readings
    coverage: float

    def apply(self, raw_t: np.ndarray) -> np.ndarray:
        """Calibrated readings [T] from raw ones [T], (N, 3)."""
        return self.distortion.correct(np.asarray(raw_t, float), self.field_norm_t)

    def to_yaml(self) -> str:
        d = self.distortion
        return yaml.safe_dump({
            "xi": float(d.xi), "offset": [float(v) for v in d.offset],
            "M": [[float(v) for v in row] for row in d.M],
            "field_norm_ut": float(self.field_norm_t * 1e6),
            "residual_rms": float(self.residual_rms), "coverage": float(self.coverage)},
            sort_keys=False)

    @classmethod
    def load(cls, path: str | Path) -> MagCalibration:
        path = Path(path)
        try:
            data = yaml.safe_load(path.read_text())
            distortion = IronDistortion(xi=float(data["xi"]),
                                        offset=tuple(float(v) for v in data["offset"]),
                                        M=tuple(tuple(float(v) for v in row)
                                                for row in data["M"]))
            return cls(distortion, float(data["field_norm_ut"]) * 1e-6,
                       float(data.get("residual_rms", np.nan)),
                       float(data.get("coverage", np.nan)))
        except (OSError, yaml.YAMLError, KeyError, TypeError, ValueError) as exc:
            raise InputError(path, f"not a magnetometer calibration of pdr-pocket "
                                   f"calibrate-mag ({exc})") from exc


def calibrate(raw_t: np.ndarray, field_norm_t: float | None = None,
              min_coverage: float = MIN_COVERAGE, where: str = "magnetometer") -> MagCalibration:
    """Fit the calibration to raw readings [T] (N, 3) turned through many directions in a
    homogeneous field of strength ``field_norm_t`` (default: the readings' median norm,
    so that ξ absorbs the scale). Refuses data covering less than ``min_coverage`` of the
    sphere, saying how much it covers."""
    raw = np.asarray(raw_t, float)
    raw = raw[np.isfinite(raw).all(axis=1)]
    coverage = sphere_coverage(raw)
    if coverage < min_coverage:
        raise InputError(where, f"the readings cover {100 * coverage:.0f} % of the sphere of "
                                f"directions, {100 * min_coverage:.0f} % are needed: turn the "
                                "sensor through all directions (a walk in the pocket covers "
                                "little more than one plane)")
    norm = float(field_norm_t or np.median(np.linalg.norm(raw, axis=1)))
    distortion = fit_ellipsoid(raw, norm)
    corrected = distortion.correct(raw, norm) / norm
    residual = float(np.sqrt(np.mean((np.linalg.norm(corrected, axis=1) - 1.0) ** 2)))
    return MagCalibration(distortion, norm, residual, coverage)
