"""What ``ros2 param list/get/dump`` print, from rcl_interfaces ParameterValue messages
(no rclpy: the calls are in ``param_verbs``).

Copies ros2cli's ``ros2param/ros2param/api/__init__.py`` (``get_value``,
``get_parameter_type_string``) and ``verb/get.py``, ``verb/list.py``, ``verb/dump.py``:
``get`` prints ``print(label, value)`` with the message's raw field (``0.25``, ``True``,
``array('d', [1.0, 2.0])`` for numeric arrays, ``['a', 'b']`` for strings); ``list`` two
spaces and the name, ``(type: double)`` under ``--param-type``; ``dump`` PyYAML's default
``yaml.dump(..., default_flow_style=False)`` (keys sorted, block lists) of
``{'/node': {'ros__parameters': {...}}}`` with dotted names nested.
"""
from __future__ import annotations

import yaml
from rcl_interfaces.msg import ParameterType

PARAMETER_SEPARATOR = "."           # rclpy.parameter.PARAMETER_SEPARATOR_STRING
NOT_SET_LABEL = "Parameter not set."
# type -> (ros2param get's label, the ParameterValue field, param list's type name)
KINDS = {
    ParameterType.PARAMETER_BOOL: ("Boolean value is:", "bool_value", "boolean"),
    ParameterType.PARAMETER_INTEGER: ("Integer value is:", "integer_value", "integer"),
    ParameterType.PARAMETER_DOUBLE: ("Double value is:", "double_value", "double"),
    ParameterType.PARAMETER_STRING: ("String value is:", "string_value", "string"),
    ParameterType.PARAMETER_BYTE_ARRAY: ("Byte values are:", "byte_array_value",
                                         "byte array"),
    ParameterType.PARAMETER_BOOL_ARRAY: ("Boolean values are:", "bool_array_value",
                                         "boolean array"),
    ParameterType.PARAMETER_INTEGER_ARRAY: ("Integer values are:", "integer_array_value",
                                            "integer array"),
    ParameterType.PARAMETER_DOUBLE_ARRAY: ("Double values are:", "double_array_value",
                                           "double array"),
    ParameterType.PARAMETER_STRING_ARRAY: ("String values are:", "string_array_value",
                                           "string array"),
}
ARRAY_TYPES = {ParameterType.PARAMETER_BYTE_ARRAY, ParameterType.PARAMETER_BOOL_ARRAY,
               ParameterType.PARAMETER_INTEGER_ARRAY, ParameterType.PARAMETER_DOUBLE_ARRAY,
               ParameterType.PARAMETER_STRING_ARRAY}


def type_name(parameter_type: int) -> str:
    """``get_parameter_type_string``: ``double``, ``string array``, ``not set``, ..."""
    if parameter_type == ParameterType.PARAMETER_NOT_SET:
        return "not set"
    return KINDS[parameter_type][2]


def get_text(value, hide_type: bool = False) -> str:
    """The line ``ros2 param get`` prints for a ParameterValue (``Double value is: 0.25``;
    only the value under ``--hide-type``); ValueError ``Unknown parameter type 'N'``."""
    if value.type == ParameterType.PARAMETER_NOT_SET:
        return "None" if hide_type else NOT_SET_LABEL
    if value.type not in KINDS:
        raise ValueError(f"Unknown parameter type '{value.type}'")
    label, field, _ = KINDS[value.type]
    raw = getattr(value, field)
    return str(raw) if hide_type else f"{label} {raw}"


def python_value(value):
    """``get_value``: the ParameterValue as Python (bool, int, float, str, a list for an
    array), None when not set or of an unknown type."""
    if value.type not in KINDS:
        return None
    raw = getattr(value, KINDS[value.type][1])
    return list(raw) if value.type in ARRAY_TYPES else raw


def list_lines(names: list[str], types: dict[str, int] | None = None) -> list[str]:
    """``ros2 param list``'s lines of one node: sorted names indented by two spaces, each
    with ``(type: T)`` when ``types`` (name -> ParameterType) is given."""
    if types is None:
        return [f"  {name}" for name in sorted(names)]
    return [f"  {name} (type: {type_name(types[name])})" for name in sorted(names)]


def nested(values: dict[str, object]) -> dict:
    """``verb/dump.py``'s ``insert_dict``: ``{'a.b': 1}`` -> ``{'a': {'b': 1}}``."""
    tree: dict = {}
    for name, value in values.items():
        *groups, leaf = name.split(PARAMETER_SEPARATOR)
        branch = tree
        for group in groups:
            branch = branch.setdefault(group, {})
        branch[leaf] = value
    return tree


def dump_text(full_name: str, values: dict[str, object]) -> str:
    """``ros2 param dump``'s YAML (without the newline ``print`` adds) of a node's
    parameters (name -> Python value, :func:`python_value`)."""
    return yaml.dump({full_name: {"ros__parameters": nested(values)}},
                     default_flow_style=False)
