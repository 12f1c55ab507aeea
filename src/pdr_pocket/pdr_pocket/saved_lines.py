"""The saved fit of a person's lines (pdr_pocket.line_calibration), as YAML.

``pdr-pocket calibrate-step --foot`` writes it and ``pdr-pocket run --step-calibration``
reads it (issue 57); its own loader, not ``--config``::

    # The person's lines (pdr-pocket calibrate-step --foot), Muñoz Díaz 2016 Eqs. ...
    step_length: {a_h_m_per_deg: 0.02512, b_h_m: 0.3714, calibrated: true}
    stairs: {a_u_cm_per_deg: 0.81, b_u_cm: -8.9, a_d_cm_per_deg: 2.0, b_d_cm: -19.24}
    fit:
      level: {pairs: 412, covariance: [[1.1e-7, -3.6e-6], [-3.6e-6, 1.3e-4]],
              residual_sigma_m: 0.036}
      up: {pairs: 38, covariance: [[...], [...]], residual_sigma_cm: 1.2}
      down: null                # not walked: the configured line is kept
      forgetting: 0.999
      refused: {lag: 10, count: 0, rest: 14, turn: 31, ...}
      sources: {foot: out/walk1_ekf, pocket: out/walk1_pocket}

Units as in Eqs. (4.2), (4.4), (4.5): level a [m/deg], b [m]; stairs a [cm/deg], b [cm]; a
covariance is of [a, b] in those units², row-major.

- :func:`saved_fit`: a calibrator's state as a :class:`SavedFit`;
- :func:`write_fit`, :func:`read_fit`: the file; a malformed one is an InputError naming
  the file and the key;
- :func:`applied`: a configuration with the person's lines of a saved fit (``run
  --step-calibration``, the configuration's ``step_calibration``), :func:`fitted` the lines
  it took;
- :data:`LINE_PARAMETERS`, :func:`line_parameters`, :func:`taken_lines`: the lines as
  ``pocket_pdr``'s parameters (``step_length.b_h_m``, ...), which ``stride_calibrator``
  sets live; :func:`lines_text` says them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import yaml

from pdr_core.config_files import check_keys, key_path, parse_yaml, typed_value
from pdr_core.errors import InputError
from pdr_pocket.config import PocketConfig, StairsConfig
from pdr_pocket.line_calibration import DOWN, LEVEL, LINES, REASONS, UP, StrideCalibrator
from pdr_pocket.step_length import StepLengthConfig


@dataclass(frozen=True)
class FitStats:
    """One fitted line's pairs, covariance of [a, b] (row-major 2×2, the line's units²)
    and residual σ (m level, cm stairs)."""

    pairs: int
    covariance: tuple[tuple[float, float], tuple[float, float]]
    residual_sigma: float


@dataclass(frozen=True)
class LineEstimate:
    """A line's slope and offset; ``fit`` None: not walked, the configured line kept."""

    slope: float
    offset: float
    fit: FitStats | None


@dataclass(frozen=True)
class SavedFit:
    """What ``calibrate-step --foot`` saves: the lines by :data:`LINES` name, λ, the
    refusals by reason and the sources (``foot``, ``pocket``: the runs read)."""

    lines: dict[str, LineEstimate]
    forgetting: float
    refused: dict[str, int]
    sources: dict[str, str]


def saved_fit(calibrator: StrideCalibrator, sources: dict[str, str] | None = None) -> SavedFit:
    """The calibrator's lines as :func:`write_fit` saves them (a line without pairs is its
    prior, the configured one, with ``fit`` None); ``sources``: the runs read."""
    lines = {}
    for name, fit in calibrator.fits.items():
        stats = None if fit.pairs == 0 else FitStats(
            fit.pairs, _pair_of_pairs(fit.covariance), fit.residual_sigma)
        lines[name] = LineEstimate(fit.slope, fit.offset, stats)
    return SavedFit(lines, calibrator.settings.forgetting, dict(calibrator.refused),
                    dict(sources or {}))


def _pair_of_pairs(matrix: np.ndarray) -> tuple[tuple[float, float], tuple[float, float]]:
    return ((float(matrix[0, 0]), float(matrix[0, 1])), (float(matrix[1, 0]), float(matrix[1, 1])))


FIT_HEADER = "# The person's lines ({}), Muñoz Díaz 2016 Eqs. (4.2), (4.4), (4.5)\n"
WRITTEN_BY = "pdr-pocket calibrate-step --foot"
_KEYS = {LEVEL: ("step_length", "a_h_m_per_deg", "b_h_m"),
         UP: ("stairs", "a_u_cm_per_deg", "b_u_cm"),
         DOWN: ("stairs", "a_d_cm_per_deg", "b_d_cm")}
_SIGMA_KEY = {LEVEL: "residual_sigma_m", UP: "residual_sigma_cm", DOWN: "residual_sigma_cm"}
LINE_PARAMETERS = {name: (f"{section}.{slope}", f"{section}.{offset}")
                   for name, (section, slope, offset) in _KEYS.items()}
"""Each line's (slope, offset) as ``pocket_pdr``'s parameters: the configuration's
``section.key`` (units as the module docstring's)."""


def line_parameters(fit: SavedFit, min_pairs: int = 1) -> dict[str, float]:
    """The lines of ``fit`` fitted from at least ``min_pairs`` pairs as parameter -> value
    (:data:`LINE_PARAMETERS`); a line not walked, or from fewer pairs, gives none."""
    values = {}
    for name, line in fit.lines.items():
        if line.fit is not None and line.fit.pairs >= max(min_pairs, 1):
            slope, offset = LINE_PARAMETERS[name]
            values[slope], values[offset] = line.slope, line.offset
    return values


def lines_text(step_length: StepLengthConfig, stairs: StairsConfig) -> str:
    """The three lines in one line of a log."""
    return (f"level s = {_line(step_length.a_h_m_per_deg, step_length.b_h_m)} m, "
            f"up v = {_line(stairs.a_u_cm_per_deg, stairs.b_u_cm)} cm, "
            f"down v = {_line(stairs.a_d_cm_per_deg, stairs.b_d_cm)} cm (Δθ in deg)")


def _line(slope: float, offset: float) -> str:
    return f"{slope:.5g}·Δθ {'-' if offset < 0 else '+'} {abs(offset):.4g}"


def taken_lines(step_length: StepLengthConfig, stairs: StairsConfig,
                values: dict[str, float]) -> tuple[StepLengthConfig, StairsConfig]:
    """``step_length`` and ``stairs`` with the lines' ``values`` by parameter
    (:data:`LINE_PARAMETERS`; the others kept); a level line that changes is the person's
    (``calibrated`` true: not scaled to a height). ValueError naming the parameter for an
    unknown one, a value not finite, or a slope not above 0."""
    known = {p for pair in LINE_PARAMETERS.values() for p in pair}
    changes: dict[str, dict[str, float]] = {"step_length": {}, "stairs": {}}
    for name, value in values.items():
        if name not in known:
            raise ValueError(f"{name}: not a line's parameter ({', '.join(sorted(known))})")
        if not math.isfinite(value):
            raise ValueError(f"{name}: {value} is not finite")
        section, key = name.split(".")
        changes[section][key] = float(value)
    for slope, _ in LINE_PARAMETERS.values():
        if slope in values and not values[slope] > 0.0:
            raise ValueError(f"{slope}: a slope must be above 0, got {values[slope]}")
    level = changes["step_length"]
    if any(value != getattr(step_length, key) for key, value in level.items()):
        level["calibrated"] = True
    return replace(step_length, **level), replace(stairs, **changes["stairs"])


def write_fit(path: str | Path, fit: SavedFit, written_by: str = WRITTEN_BY) -> Path:
    """``fit`` as YAML at ``path`` (module docstring), its first line naming what wrote it
    (``written_by``: the CLI, or the node ``stride_calibrator``); returns the path."""
    data: dict = {"step_length": {"calibrated": fit.lines[LEVEL].fit is not None},
                  "stairs": {}}
    blocks: dict = {}
    for name in LINES:
        line = fit.lines[name]
        section, slope_key, offset_key = _KEYS[name]
        data[section][slope_key] = line.slope
        data[section][offset_key] = line.offset
        blocks[name] = None if line.fit is None else {
            "pairs": line.fit.pairs, "covariance": [list(row) for row in line.fit.covariance],
            _SIGMA_KEY[name]: line.fit.residual_sigma}
    data["fit"] = {**blocks, "forgetting": fit.forgetting, "refused": dict(fit.refused),
                   "sources": dict(fit.sources)}
    path = Path(path)
    text = yaml.safe_dump(data, sort_keys=False, allow_unicode=True, default_flow_style=None)
    path.write_text(FIT_HEADER.format(written_by) + text)
    return path


def read_fit(path: str | Path) -> SavedFit:
    """The fit :func:`write_fit` saved at ``path``; InputError naming the file and the key
    for anything else."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise InputError(path, f"cannot read the saved fit ({exc.strerror})") from None
    where = f"{path}:"
    data = check_keys(parse_yaml(text, path), _SavedFitKeys, where,
                      ("step_length", "stairs", "fit"))
    step_length = _section(data["step_length"], StepLengthConfig, key_path(where, "step_length"),
                           ("a_h_m_per_deg", "b_h_m", "calibrated"))
    stairs = _section(data["stairs"], StairsConfig, key_path(where, "stairs"),
                      ("a_u_cm_per_deg", "b_u_cm", "a_d_cm_per_deg", "b_d_cm"))
    fit_where = key_path(where, "fit")
    blocks = check_keys(data["fit"], _FitKeys, fit_where, (*LINES, "forgetting", "refused"))
    values = {**step_length, **stairs}
    lines = {name: LineEstimate(values[_KEYS[name][1]], values[_KEYS[name][2]],
                                _stats(blocks[name], name, key_path(fit_where, name)))
             for name in LINES}
    if step_length["calibrated"] != (lines[LEVEL].fit is not None):
        raise InputError(key_path(where, "step_length.calibrated"),
                         "true exactly when fit.level is given (the person's level line)")
    forgetting = typed_value(blocks["forgetting"], "float", key_path(fit_where, "forgetting"))
    if not 0.0 < forgetting <= 1.0:
        raise InputError(key_path(fit_where, "forgetting"), f"must be within (0, 1], got "
                                                            f"{forgetting}")
    return SavedFit(lines, forgetting, _refused(blocks["refused"], key_path(fit_where, "refused")),
                    _sources(blocks.get("sources") or {}, key_path(fit_where, "sources")))


def fitted(fit: SavedFit) -> tuple[str, ...]:
    """The lines of ``fit`` that were walked (:data:`LINES` names, in their order)."""
    return tuple(name for name in LINES if fit.lines[name].fit is not None)


def applied(config: PocketConfig, fit: SavedFit, where: str | Path = "saved fit"
            ) -> PocketConfig:
    """``config`` with the person's lines of ``fit``: a fitted level line replaces
    ``step_length``'s a_H and b_H and marks it ``calibrated`` (the person's, not scaled by
    height), fitted stairs lines ``stairs``' a_U, b_U, a_D, b_D; a line not walked (``fit``
    None) keeps the configured one. InputError naming ``where`` (the file) when a line is
    none the configuration takes (a slope not positive)."""
    sections = {"step_length": config.step_length, "stairs": config.stairs}
    try:
        for name in fitted(fit):
            section, slope_key, offset_key = _KEYS[name]
            sections[section] = replace(sections[section], **{
                slope_key: fit.lines[name].slope, offset_key: fit.lines[name].offset})
    except ValueError as exc:
        raise InputError(where, f"its {name} line does not fit the configuration: {exc}"
                         ) from None
    if fit.lines[LEVEL].fit is not None:
        sections["step_length"] = replace(sections["step_length"], calibrated=True)
    return replace(config, **sections)


# the keys of the file's mappings, as dataclasses for pdr_core.config_files.check_keys
@dataclass(frozen=True)
class _SavedFitKeys:
    step_length: dict
    stairs: dict
    fit: dict


@dataclass(frozen=True)
class _FitKeys:
    level: dict | None
    up: dict | None
    down: dict | None
    forgetting: float
    refused: dict
    sources: dict


def _section(data, cls: type, where: str, keys: tuple[str, ...]) -> dict:
    """The ``keys`` of a configuration section, each of its field's type and all given."""
    values = check_keys(data, cls, where, keys)
    kinds = {name: str(cls.__dataclass_fields__[name].type) for name in keys}
    unknown = set(values) - set(keys)
    if unknown:
        raise InputError(key_path(where, sorted(unknown)[0]), "not part of a saved fit")
    return {name: typed_value(values[name], kinds[name], key_path(where, name)) for name in keys}


def _stats(block, name: str, where: str) -> FitStats | None:
    """A line's ``fit`` block: None (not walked), or pairs ≥ 1, a 2×2 covariance and a
    residual σ ≥ 0."""
    if block is None:
        return None
    values = check_keys(block, _StatsKeys[name], where,
                        tuple(_StatsKeys[name].__dataclass_fields__))
    pairs = typed_value(values["pairs"], "int", key_path(where, "pairs"))
    if pairs < 1:
        raise InputError(key_path(where, "pairs"), f"must be >= 1 (a line not walked is "
                                                   f"null), got {pairs}")
    cov_where = key_path(where, "covariance")
    rows = values["covariance"]
    if not (isinstance(rows, list) and len(rows) == 2
            and all(isinstance(row, list) and len(row) == 2 for row in rows)):
        raise InputError(cov_where, f"expected a 2×2 list of lists, got {rows!r}")
    matrix = np.array([[typed_value(v, "float", cov_where) for v in row] for row in rows])
    if not (np.allclose(matrix, matrix.T) and np.all(np.linalg.eigvalsh(matrix) >= 0.0)):
        raise InputError(cov_where, "not a covariance (symmetric, positive semi-definite)")
    sigma_key = _SIGMA_KEY[name]
    sigma = typed_value(values[sigma_key], "float", key_path(where, sigma_key))
    if not sigma >= 0.0:
        raise InputError(key_path(where, sigma_key), f"must be >= 0, got {sigma}")
    return FitStats(pairs, _pair_of_pairs(matrix), sigma)


@dataclass(frozen=True)
class _LevelStats:
    pairs: int
    covariance: list
    residual_sigma_m: float


@dataclass(frozen=True)
class _StairsStats:
    pairs: int
    covariance: list
    residual_sigma_cm: float


_StatsKeys = {LEVEL: _LevelStats, UP: _StairsStats, DOWN: _StairsStats}


def _refused(data, where: str) -> dict[str, int]:
    if not isinstance(data, dict):
        raise InputError(where, f"expected a mapping, got {data!r}")
    counts = {}
    for reason, count in data.items():
        if reason not in REASONS:
            raise InputError(key_path(where, str(reason)),
                             f"unknown reason (known: {', '.join(REASONS)})")
        counts[reason] = typed_value(count, "int", key_path(where, reason))
        if counts[reason] < 0:
            raise InputError(key_path(where, reason), f"must be >= 0, got {count}")
    return counts


def _sources(data, where: str) -> dict[str, str]:
    if not isinstance(data, dict):
        raise InputError(where, f"expected a mapping, got {data!r}")
    return {str(k): typed_value(v, "str", key_path(where, str(k))) for k, v in data.items()}
