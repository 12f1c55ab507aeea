"""Configuration files: typed dataclasses from YAML mappings (units in the key names).

- :func:`read_config_file`: a YAML file's mapping; ``base: OTHER.yaml`` (relative to the
  file) is read first and the file's own keys override it, mapping by mapping.
- :func:`dataclass_from_mapping`: a dataclass from a mapping, each value checked against
  its field's type, the keys not given at their defaults; unknown keys and bad values
  raise InputError naming the key's path.
- :func:`check_keys`: the key check alone (unknown and required keys), for mappings whose
  values need more than a type check (scenarios, nested configurations).
- :func:`parse_yaml`: YAML text as data, invalid YAML an InputError naming its source.
- :func:`shipped_config_dir`: a package's installed ``config/`` folder, where each
  navigator's default configuration lies (``foot_ekf.yaml``, ``pocket_pdr.yaml``,
  ``landmark_drift.yaml``).

Used by the navigators' and the drift estimator's configurations (pdr_ins_ekf.config,
pdr_pocket.config, pdr_drift.config) and the simulator's scenarios (pdr_sim.scenario,
pdr_sim.pocket_scenario).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import fields, replace
from pathlib import Path
from typing import Any

import yaml

from pdr_core.errors import InputError


def typed_value(value: Any, kind: str, where: str) -> Any:
    """``value`` as the field's type; numbers written like 1.0e6, which YAML 1.1 reads
    as strings, are accepted."""
    if kind in ("float", "int"):
        if isinstance(value, str):
            try:
                value = float(value)
            except ValueError:
                raise InputError(where, f"expected a number, got {value!r}") from None
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise InputError(where, f"expected a number, got {value!r}")
        if kind == "int":
            if value != int(value):
                raise InputError(where, f"expected an integer, got {value!r}")
            return int(value)
        return float(value)
    if kind == "bool" and not isinstance(value, bool):
        raise InputError(where, f"expected true or false, got {value!r}")
    if kind == "str" and not isinstance(value, str):
        raise InputError(where, f"expected a string, got {value!r}")
    return value


def check_positive(config: Any, names: tuple[str, ...]) -> None:
    """ValueError naming the first of the fields ``names`` of ``config`` that is not > 0."""
    for name in names:
        if not getattr(config, name) > 0:
            raise ValueError(f"{name} must be > 0, got {getattr(config, name)}")


def key_path(where: str, key: str) -> str:
    """``FILE: a.b`` paths: the file is followed by a colon, nested keys by dots."""
    return f"{where} {key}" if where.endswith(":") else f"{where}.{key}"


def check_keys(data: Any, cls: type, where: str, required: tuple[str, ...] = ()) -> dict:
    """``data`` as a dict, refused unless it is a mapping whose keys are all fields of the
    dataclass ``cls`` and holds the ``required`` ones."""
    if not isinstance(data, Mapping):
        raise InputError(where, f"expected a mapping, got {data!r}")
    known = {f.name for f in fields(cls)}
    for key in data:
        if key not in known:
            raise InputError(key_path(where, key),
                             f"unknown key (known: {', '.join(sorted(known))})")
    for key in required:
        if key not in data:
            raise InputError(key_path(where, key), "required")
    return dict(data)


def dataclass_from_mapping(cls: type, values: dict, where: str, defaults: Any = None) -> Any:
    """``cls(**values)`` with every key known and every value of its field's type; with
    ``defaults`` (a ``cls``), the keys not given keep its values instead of the class's."""
    values = check_keys(values, cls, where)
    kinds = {f.name: str(f.type) for f in fields(cls)}
    typed = {k: typed_value(v, kinds[k], f"{where}.{k}") for k, v in values.items()}
    try:
        return cls(**typed) if defaults is None else replace(defaults, **typed)
    except (TypeError, ValueError) as exc:
        raise InputError(where, str(exc)) from exc


def merged(base: dict, override: dict) -> dict:
    """``base`` with ``override`` on top, mapping by mapping."""
    out = dict(base)
    for key, value in override.items():
        out[key] = (merged(out[key], value) if isinstance(value, dict)
                    and isinstance(out.get(key), dict) else value)
    return out


def parse_yaml(text: str, where: str | Path) -> Any:
    """The data of YAML ``text``; invalid YAML is an InputError at ``where``."""
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise InputError(where, f"invalid YAML ({exc})") from exc


def shipped_config_dir(package: str) -> Path:
    """The installed ``config/`` folder of ``package`` (its ament share directory)."""
    from ament_index_python.packages import get_package_share_directory

    return Path(get_package_share_directory(package)) / "config"


def read_config_file(path: Path, seen: tuple[Path, ...] = ()) -> dict:
    """A configuration file's mapping; ``base: FILE`` (relative to the file) is read first
    and the file's own keys override it."""
    if not path.is_file():
        raise InputError(path, "no such configuration file")
    if path.resolve() in seen:
        raise InputError(path, "base files include each other")
    data = parse_yaml(path.read_text(), path) or {}
    if not isinstance(data, dict):
        raise InputError(path, "expected a mapping at the top level")
    base = data.pop("base", None)
    if base is None:
        return data
    return merged(read_config_file(path.parent / str(base), (*seen, path.resolve())), data)
