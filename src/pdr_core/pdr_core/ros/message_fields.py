"""A message's fields set from a YAML mapping, as ``ros2 service call`` and ``ros2 topic
pub`` fill a request or a message (no rclpy import).

The rules are those of Jazzy's rosidl_runtime_py (``rosidl_runtime_py/set_message.py``:
``set_message_fields``) as ros2cli's ``ros2service/verb/call.py`` calls it, written again
because neither package is on PyPI (docs/ros2.md):

- The values are a mapping of field names (YAML, ``{}`` when none are given); a field
  not named keeps its default.
- A fixed array (numpy array) takes ``numpy.array(value, dtype)``, a sequence of numbers
  (``array.array``) ``array.array(typecode, value)``; a value of the field's own Python
  type is taken as it is; any other is converted by the field's type (``float(1)``,
  ``str(5)``, ``bool('false')`` is True as in rosidl_runtime_py), and where that type
  takes no argument, a nested message, the value is itself a mapping of its fields.
- A sequence of messages takes a list of such mappings, one message each.
- The generated setters check the rest (an array of the wrong size, an integer out of
  range) when the message is made with ``check_fields=True``, as the nested messages
  made here are; rosidl_runtime_py leaves that to the serialization, which fails with a
  SystemError.

Errors (:data:`FIELD_ERRORS`): an unknown field is an AttributeError saying
``'<Message> object has no attribute '<name>'``, as rosidl_runtime_py's ``getattr`` says
it; a value that is not a mapping where one is needed a TypeError with
rosidl_runtime_py's words; a value the field's type cannot take a ValueError or
TypeError of the type (``'int' object is not iterable`` for a sequence given a number,
where rosidl_runtime_py asks for a dictionary), an AssertionError of a checking setter.
ros2cli prints each after ``Failed to populate field: ``.
"""
from __future__ import annotations

import array
from typing import Any

import numpy as np
import yaml
from rosidl_parser.definition import AbstractNestedType, NamespacedType

from pdr_core.ros.ros_types import message_class

FIELD_ERRORS = (AttributeError, TypeError, ValueError, AssertionError)


def yaml_values(text: str) -> Any:
    """The values of a YAML text (``yaml.safe_load``, as ros2cli); ValueError with the
    problem and its place on one line when it is not YAML."""
    try:
        return yaml.safe_load(text)
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark
        raise ValueError(f"invalid YAML: {error.problem} (line {mark.line + 1}, column "
                         f"{mark.column + 1})") from None
    except yaml.YAMLError as error:
        raise ValueError(f"invalid YAML: {error}") from None


def set_message_fields(msg: Any, values: Any) -> None:
    """Set the fields of ``msg`` (a generated message or request) named in ``values``, a
    mapping, by the rules of the module's docstring; raises one of :data:`FIELD_ERRORS`."""
    if not isinstance(values, dict):
        raise TypeError(f"Value '{values}' is expected to be a dictionary but is a "
                        f"{type(values).__name__}")
    slot_types = dict(zip(msg.get_fields_and_field_types(), msg.SLOT_TYPES, strict=True))
    for name, value in values.items():
        if name not in slot_types:
            raise AttributeError(f"'{type(msg).__name__}' object has no attribute '{name}'")
        setattr(msg, name, _field_value(getattr(msg, name), value, slot_types[name]))


def _field_value(field: Any, value: Any, slot_type: Any) -> Any:
    """``value`` made into what the field ``field`` (of rosidl type ``slot_type``) holds."""
    field_type = type(field)
    if field_type is array.array:
        return array.array(field.typecode, value)
    if field_type is np.ndarray:
        return np.array(value, dtype=field.dtype)
    if type(value) is field_type:
        converted = value
    else:
        try:
            converted = field_type(value)
        except TypeError:
            if not hasattr(field_type, "SLOT_TYPES"):
                raise
            converted = _message(field_type, value)
    if isinstance(slot_type, AbstractNestedType) and \
            isinstance(slot_type.value_type, NamespacedType):
        element_class = message_class("/".join([*slot_type.value_type.namespaces,
                                                slot_type.value_type.name]))
        converted = [_message(element_class, item) for item in converted]
    return converted


def _message(msg_class: Any, values: Any) -> Any:
    """A new ``msg_class`` message, its setters checking, with the fields of the mapping
    ``values``."""
    msg = msg_class(check_fields=True)
    set_message_fields(msg, values)
    return msg
