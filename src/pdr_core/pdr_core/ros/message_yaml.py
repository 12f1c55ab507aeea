"""A message as ``ros2 topic echo`` prints it: YAML or a CSV line (no rclpy import).

The rules are those of Jazzy's rosidl_runtime_py (``rosidl_runtime_py/convert.py``:
``message_to_ordereddict``, ``_convert_value``, ``message_to_yaml``, ``message_to_csv``)
as ros2cli's ``ros2topic/verb/echo.py`` calls them, written again here because neither
package is on PyPI (docs/ros2.md):

- Fields in the order of the message's ``get_fields_and_field_types()``; a field whose
  value has that method is a nested message.
- numpy scalars become Python numbers (``.item()``: a float32 prints as the double it
  is, ``0.10000000149011612``); ``array.array``, numpy arrays and lists become lists.
- Sequences longer than ``truncate_length`` (ros2 topic echo's default 128, ``None`` =
  ``--full-length``) keep their first items and end with the string ``'...'``; strings
  and bytes are cut likewise, with ``...`` appended; bytes become the string of their
  characters.
- YAML: PyYAML's default ``Dumper`` with field order kept, block style, no line wrapping
  (``width=sys.maxsize``), so floats are spelt PyYAML's way (``1.0e-05``, ``.nan``,
  ``.inf``) and a list inside a map is not indented.
- CSV: every leaf in field order joined by ``,``, arrays flattened into the line, each
  value as Python's ``str`` (``1e-05``, ``True``, numpy's own ``str`` for array items).

``--no-arr``, ``--no-str`` and ``--flow-style`` are not supported.
"""
from __future__ import annotations

import array
import sys
from typing import Any

import numpy as np
import yaml

ECHO_TRUNCATE_LENGTH = 128   # ros2 topic echo's --truncate-length default
TRUNCATED = "..."            # what replaces the cut-off items and characters
SEPARATOR = "---"            # the line ros2 topic echo prints after each YAML message
SEQUENCES = (list, tuple, array.array, np.ndarray)


class _FieldOrderDumper(yaml.Dumper):
    """PyYAML's default Dumper, with a message's fields kept in their order (what
    rosidl_runtime_py registers for its OrderedDict on the default Dumper)."""


def _represent_fields(dumper: yaml.Dumper, fields: dict) -> yaml.MappingNode:
    return yaml.MappingNode("tag:yaml.org,2002:map",
                            [(dumper.represent_data(k), dumper.represent_data(v))
                             for k, v in fields.items()])


class _Fields(dict):
    """A message's fields as a mapping that the dumper writes in insertion order."""


_FieldOrderDumper.add_representer(_Fields, _represent_fields)


def message_fields(msg: Any, truncate_length: int | None = ECHO_TRUNCATE_LENGTH) -> dict:
    """``msg``'s fields by name, in the message's field order, as plain Python values
    (nested messages as such mappings), truncated to ``truncate_length``."""
    return _Fields((name, _plain(getattr(msg, name), truncate_length))
                   for name in msg.get_fields_and_field_types())


def _plain(value: Any, truncate_length: int | None) -> Any:
    """One field's value as rosidl_runtime_py's ``_convert_value`` gives it."""
    if isinstance(value, bytes):
        return "".join(map(chr, _cut(value, truncate_length))) + _ellipsis(value,
                                                                          truncate_length)
    if isinstance(value, str):
        return _cut(value, truncate_length) + _ellipsis(value, truncate_length)
    if isinstance(value, SEQUENCES):
        items = [_plain(v, truncate_length) for v in _cut(value, truncate_length)]
        items += [TRUNCATED] if _ellipsis(value, truncate_length) else []
        return tuple(items) if isinstance(value, tuple) else items
    if isinstance(value, np.number):
        return value.item()
    if isinstance(value, (bool, float, int)):
        return value
    return message_fields(value, truncate_length)


def _cut(value, truncate_length: int | None):
    return value if truncate_length is None else value[:truncate_length]


def _ellipsis(value, truncate_length: int | None) -> str:
    """``...`` when ``value`` is longer than ``truncate_length``, else ''."""
    return TRUNCATED if truncate_length is not None and len(value) > truncate_length else ""


def message_yaml(msg: Any, truncate_length: int | None = ECHO_TRUNCATE_LENGTH) -> str:
    """``msg`` as YAML, as ``message_to_yaml`` writes it (ends with a newline; ros2
    topic echo prints :data:`SEPARATOR` on the next line)."""
    return yaml.dump(message_fields(msg, truncate_length), Dumper=_FieldOrderDumper,
                     allow_unicode=True, width=sys.maxsize, default_flow_style=False)


def message_csv(msg: Any, truncate_length: int | None = ECHO_TRUNCATE_LENGTH) -> str:
    """``msg`` as one line of comma-separated values, as ``message_to_csv`` writes it
    (no newline)."""
    return ",".join(_csv_value(getattr(msg, name), truncate_length)
                    for name in msg.get_fields_and_field_types())


def _csv_value(value: Any, truncate_length: int | None) -> str:
    """One field's value in the CSV line: sequences flattened, leaves as ``str``."""
    if isinstance(value, SEQUENCES):
        items = [_csv_value(v, truncate_length) for v in _cut(value, truncate_length)]
        return ",".join(items + ([TRUNCATED] if _ellipsis(value, truncate_length) else []))
    if isinstance(value, bytes):
        return str(_cut(value, truncate_length)
                   + _ellipsis(value, truncate_length).encode())
    if isinstance(value, str):
        return _cut(value, truncate_length) + _ellipsis(value, truncate_length)
    if isinstance(value, (bool, float, int, np.number)):
        return str(value)
    return message_csv(value, truncate_length)
