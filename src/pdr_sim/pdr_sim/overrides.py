"""``KEY=VALUE`` overrides of nested YAML mappings (``step.length_m=1.2``,
``segments[1].steps=20``), for the CLI's ``--set`` and ``--imu-set``."""
from __future__ import annotations

import copy
import itertools
import re
from collections.abc import Iterable
from typing import Any

import yaml

from pdr_core.errors import InputError

_TOKEN = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)|\[(\d+)\]")


def _path(key: str, option: str) -> list[str | int]:
    parts: list[str | int] = []
    pos = 0
    for match in _TOKEN.finditer(key):
        gap = key[pos:match.start()]
        if gap not in ("", ".") or (gap == "" and parts and match.group(1)):
            raise InputError(option, f"cannot parse key '{key}'")
        parts.append(match.group(1) if match.group(1) else int(match.group(2)))
        pos = match.end()
    if pos != len(key) or not parts:
        raise InputError(option, f"cannot parse key '{key}'")
    return parts


def with_overrides(data: dict, assignments: Iterable[str], option: str) -> dict:
    """A deep copy of ``data`` with each ``KEY=VALUE`` applied (VALUE parsed as YAML)."""
    out = copy.deepcopy(data)
    for assignment in assignments:
        key, sep, text = assignment.partition("=")
        if not sep:
            raise InputError(option, f"expected KEY=VALUE, got '{assignment}'")
        parts = _path(key.strip(), option)
        node: Any = out
        for part, following in itertools.pairwise(parts):
            try:
                if isinstance(part, int):
                    node = node[part]
                else:
                    node = node.setdefault(part, [] if isinstance(following, int) else {})
            except (IndexError, TypeError, AttributeError) as exc:
                raise InputError(option, f"'{key}' does not exist in the scenario") from exc
        try:
            node[parts[-1]] = yaml.safe_load(text)
        except (IndexError, TypeError) as exc:
            raise InputError(option, f"'{key}' does not exist in the scenario") from exc
    return out
