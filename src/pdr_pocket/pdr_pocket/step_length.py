"""Stride (one gait cycle) length models behind one interface, and their calibration.

- :class:`PitchLine`: s = a_H·Δθ_H + b_H (Muñoz Díaz 2016, Eq. (4.2)), Δθ in degrees, with
  a universal slope a_H and a personal offset b_H (Section 4.2.3);
- :class:`FrequencyLine`: s = c_H·f + d_H (Eq. (4.3)), f = 1/duration of the cycle;
- :class:`Weinberg`: s = ζ·(α_z,max − α_z,min)^¼ (Eq. (2.3)), the vertical specific force
  in the navigation frame over the cycle.

Each is built from the configuration (``from_config``) and takes a :class:`StrideInputs`
to return metres. :data:`STRIDE_MODELS` names them for ``step_length.model`` (or
``auto``, the default: the model of the placement found, pdr_pocket.placement), as
pdr_ins_ekf.config.DETECTORS names the stance detectors: a new model is a class here with
those two methods and an entry there (its parameters, if any, keys of
:class:`StepLengthConfig`). Stairs steps are not walked at the level
line: the navigator gives them ``stairs_stride_m`` (two treads, Section 4.3.3).

:func:`fit_offset` and :func:`fit_line` calibrate from a walk of known length
(``pdr-pocket calibrate-step``).

For a person nobody calibrated, the shipped line is a population's: a_H = 0.025 m/°, the
slope the thesis finds alike among its 18 volunteers (Section 4.2.3), and b_H = 0.42 m,
which puts a thigh swing of Δθ ≈ 41° at a stride of 1.45 m, the mean of adult men
(1.58 m) and women (1.32 m) walking at their free speed (Murray, Drought and Kory 1964;
Murray, Kory and Sepic 1970). People's own lines lie up to 14 cm per step from it
(Section 4.2.3), so an uncalibrated distance is good to about ±10 % (the report says it is
uncalibrated). ``person.height_m`` scales the line by height/``POPULATION_HEIGHT_M``:
walkers of one build at equal angles differ in stride as in leg length (geometric
similarity, as in Alexander's dynamic similarity of gaits, "Stride length and speed for
adults, children, and fossil hominids", 1984). A calibrated line is the person's and is
not scaled.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from pdr_core.config_files import check_positive
from pdr_core.errors import InputError
from pdr_core.walking.gait import POPULATION_HEIGHT_M

MIN_CALIBRATION_STEPS = 20
MIN_AMPLITUDE_SPREAD_DEG = 3.0      # a slope needs Δθ spread over at least this (1σ)


@dataclass(frozen=True)
class StrideInputs:
    """One cycle: Δθ [deg], duration [s], vertical specific force range [m/s²]."""

    amplitude_deg: float
    duration_s: float
    vertical_range_mps2: float


class StrideModel(Protocol):
    """What :data:`STRIDE_MODELS` holds: a model built from the configuration, giving a
    cycle's stride [m]."""

    @classmethod
    def from_config(cls, config: StepLengthConfig) -> StrideModel: ...

    def length(self, x: StrideInputs) -> float: ...


class PitchLine:
    def __init__(self, a_h_m_per_deg: float, b_h_m: float) -> None:
        self.a, self.b = a_h_m_per_deg, b_h_m

    @classmethod
    def from_config(cls, config: StepLengthConfig) -> PitchLine:
        return cls(config.a_h_m_per_deg, config.b_h_m)

    def length(self, x: StrideInputs) -> float:
        return self.a * x.amplitude_deg + self.b


class FrequencyLine:
    def __init__(self, c_h_m_per_hz: float, d_h_m: float) -> None:
        self.c, self.d = c_h_m_per_hz, d_h_m

    @classmethod
    def from_config(cls, config: StepLengthConfig) -> FrequencyLine:
        return cls(config.c_h_m_per_hz, config.d_h_m)

    def length(self, x: StrideInputs) -> float:
        return self.c / x.duration_s + self.d


class Weinberg:
    def __init__(self, zeta: float) -> None:
        self.zeta = zeta

    @classmethod
    def from_config(cls, config: StepLengthConfig) -> Weinberg:
        return cls(config.weinberg_zeta)

    def length(self, x: StrideInputs) -> float:
        return self.zeta * max(x.vertical_range_mps2, 0.0) ** 0.25


STRIDE_MODELS: dict[str, type[StrideModel]] = {
    "pitch": PitchLine, "frequency": FrequencyLine, "weinberg": Weinberg}
"""``step_length.model`` → its class (module docstring)."""
AUTO_MODEL = "auto"
"""``step_length.model``: the model of the placement found (pdr_pocket.placement)."""


class Scaled:
    """A model's strides times a factor (a person's height over the population's)."""

    def __init__(self, model, factor: float) -> None:
        self.model, self.factor = model, factor

    def length(self, x: StrideInputs) -> float:
        return self.factor * self.model.length(x)


def height_scale(config: StepLengthConfig, height_m: float | None) -> float:
    """The factor on an uncalibrated line's strides: height / POPULATION_HEIGHT_M
    (:mod:`pdr_core.walking.gait`; 1 for a calibrated line or an unknown height)."""
    return 1.0 if config.calibrated or height_m is None else height_m / POPULATION_HEIGHT_M


def stride_model(config: StepLengthConfig, height_m: float | None = None,
                 name: str | None = None):
    """The model ``name`` (:data:`STRIDE_MODELS`; the configured one by default), scaled to
    the person's height when uncalibrated."""
    model = STRIDE_MODELS[name or config.model].from_config(config)
    factor = height_scale(config, height_m)
    return model if factor == 1.0 else Scaled(model, factor)


def _check_walk(amplitude_deg: np.ndarray, where: str) -> None:
    if len(amplitude_deg) < MIN_CALIBRATION_STEPS:
        raise InputError(where, f"{len(amplitude_deg)} level steps are too few to calibrate "
                                f"(at least {MIN_CALIBRATION_STEPS}: walk farther)")


def fit_offset(amplitude_deg: np.ndarray, distance_m: float, a_h_m_per_deg: float,
               where: str) -> float:
    """b_H such that the level steps' strides add up to ``distance_m`` with slope a_H."""
    amplitude_deg = np.asarray(amplitude_deg, float)
    _check_walk(amplitude_deg, where)
    return (distance_m - a_h_m_per_deg * amplitude_deg.sum()) / len(amplitude_deg)


def fit_line(amplitude_deg: np.ndarray, segment: np.ndarray, distances_m: np.ndarray,
             where: str) -> tuple[float, float]:
    """a_H and b_H by least squares from walks of known lengths: steps of segment i
    (``segment`` per step) add up to ``distances_m[i]``. Refused when the steps are too
    few or too uniform (Δθ spread below :data:`MIN_AMPLITUDE_SPREAD_DEG`)."""
    amplitude_deg = np.asarray(amplitude_deg, float)
    _check_walk(amplitude_deg, where)
    spread = float(np.std(amplitude_deg))
    if spread < MIN_AMPLITUDE_SPREAD_DEG:
        raise InputError(where, f"the steps' pitch amplitudes vary by {spread:.1f}° (1σ), "
                                f"too uniform to fit a slope (at least "
                                f"{MIN_AMPLITUDE_SPREAD_DEG:g}°: walk at several speeds)")
    sums = np.array([amplitude_deg[segment == i].sum() for i in range(len(distances_m))])
    counts = np.array([(segment == i).sum() for i in range(len(distances_m))], float)
    if len(distances_m) < 2:
        raise InputError(where, "a slope needs at least two stretches of known length "
                                "walked at different speeds")
    (a, b), *_ = np.linalg.lstsq(np.c_[sums, counts], np.asarray(distances_m, float),
                                 rcond=None)
    return float(a), float(b)


@dataclass(frozen=True)
class StepLengthConfig:
    """Stride (one gait cycle) models. ``model``: auto (the placement's: the pitch line on a
    thigh's swing, the frequency line otherwise, pdr_pocket.placement), pitch (Eq. (4.2),
    the thesis'), frequency (Eq. (4.3)) or weinberg (Eq. (2.3), ζ·(α_z,max − α_z,min)^¼).
    The shipped a_H, b_H are a population's line (pdr_pocket.step_length); ``calibrated``
    true (what ``pdr-pocket calibrate-step`` writes) says they are the person's."""

    model: str = AUTO_MODEL
    a_h_m_per_deg: float = 0.025        # universal slope a_H
    b_h_m: float = 0.42                 # offset b_H: a population's, or the person's
    calibrated: bool = False            # the line fitted to this person's walks
    c_h_m_per_hz: float = 1.60          # s = c_H·f + d_H, f in gait cycles per second
    d_h_m: float = 0.0
    weinberg_zeta: float = 0.95         # s = ζ·(Δα_z [m/s²])^¼
    stairs_stride_m: float = 0.52       # horizontal stride on stairs (Section 4.3.3)
    length_sigma_m: float = 0.03        # 1σ of one stride about the line

    def __post_init__(self) -> None:
        if self.model not in (AUTO_MODEL, *STRIDE_MODELS):
            raise ValueError(f"model must be one of {AUTO_MODEL}, {', '.join(STRIDE_MODELS)}, "
                             f"got {self.model!r}")
        check_positive(self, ("a_h_m_per_deg", "weinberg_zeta", "stairs_stride_m",
                         "length_sigma_m"))
