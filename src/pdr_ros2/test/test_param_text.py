"""``ros2 param get/list/dump`` text against ros2cli's ros2param (``verb/get.py``: ``print(label,
value)`` of the message's raw field; ``verb/list.py``: ``f'  {name}'``, ``(type: T)`` from
``api.get_parameter_type_string``; ``verb/dump.py``: ``yaml.dump(..., default_flow_style=
False)`` of ``{'/node': {'ros__parameters': ...}}``, dotted names nested by ``insert_dict``)."""
from __future__ import annotations

import pytest
from rcl_interfaces.msg import ParameterType, ParameterValue

from pdr_ros2.param_text import dump_text, get_text, list_lines, nested, python_value, type_name


def value(kind: int, **field) -> ParameterValue:
    return ParameterValue(type=kind, **field)


@pytest.mark.parametrize(("parameter", "line"), [
    (value(ParameterType.PARAMETER_BOOL, bool_value=True), "Boolean value is: True"),
    (value(ParameterType.PARAMETER_INTEGER, integer_value=5), "Integer value is: 5"),
    (value(ParameterType.PARAMETER_DOUBLE, double_value=0.25), "Double value is: 0.25"),
    (value(ParameterType.PARAMETER_DOUBLE, double_value=1e-05), "Double value is: 1e-05"),
    (value(ParameterType.PARAMETER_STRING, string_value="x"), "String value is: x"),
    (value(ParameterType.PARAMETER_STRING, string_value=""), "String value is: "),
    (value(ParameterType.PARAMETER_BOOL_ARRAY, bool_array_value=[True, False]),
     "Boolean values are: [True, False]"),
    (value(ParameterType.PARAMETER_INTEGER_ARRAY, integer_array_value=[1, 2]),
     "Integer values are: array('q', [1, 2])"),
    (value(ParameterType.PARAMETER_DOUBLE_ARRAY, double_array_value=[0.5, 2.0]),
     "Double values are: array('d', [0.5, 2.0])"),
    (value(ParameterType.PARAMETER_STRING_ARRAY, string_array_value=["a", "b"]),
     "String values are: ['a', 'b']"),
    (value(ParameterType.PARAMETER_BYTE_ARRAY, byte_array_value=[b"\x01"]),
     "Byte values are: [b'\\x01']"),
    (value(ParameterType.PARAMETER_NOT_SET), "Parameter not set."),
])
def test_get_prints_ros2params_label_and_the_raw_field(parameter, line):
    assert get_text(parameter) == line


def test_hide_type_prints_the_value_only():
    assert get_text(value(ParameterType.PARAMETER_DOUBLE, double_value=0.25), True) == "0.25"
    assert get_text(value(ParameterType.PARAMETER_NOT_SET), True) == "None"


def test_an_unknown_type_is_ros2params_error():
    with pytest.raises(ValueError, match=r"^Unknown parameter type '42'$"):
        get_text(ParameterValue(type=42))


def test_python_values_are_lists_for_arrays_and_none_when_not_set():
    assert python_value(value(ParameterType.PARAMETER_DOUBLE_ARRAY,
                              double_array_value=[0.5])) == [0.5]
    assert python_value(value(ParameterType.PARAMETER_INTEGER, integer_value=3)) == 3
    assert python_value(value(ParameterType.PARAMETER_NOT_SET)) is None


def test_list_lines_are_sorted_and_indented_with_types_on_request():
    names = ["use_sim_time", "block_s", "a.b"]
    assert list_lines(names) == ["  a.b", "  block_s", "  use_sim_time"]
    types = {"block_s": ParameterType.PARAMETER_DOUBLE,
             "use_sim_time": ParameterType.PARAMETER_BOOL,
             "a.b": ParameterType.PARAMETER_STRING_ARRAY}
    assert list_lines(names, types) == ["  a.b (type: string array)",
                                        "  block_s (type: double)",
                                        "  use_sim_time (type: boolean)"]
    assert type_name(ParameterType.PARAMETER_NOT_SET) == "not set"


def test_dotted_names_nest():
    assert nested({"a.b.c": 1, "a.d": 2, "e": 3}) == {"a": {"b": {"c": 1}, "d": 2}, "e": 3}


def test_dump_is_pyyamls_block_style_with_sorted_keys():
    text = dump_text("/pocket_pdr", {"use_sim_time": False, "block_s": 0.25,
                                     "filter.frames": ["map", "odom"], "config": "",
                                     "filter.gain": 2, "tiny": 1e-05})
    assert text == """\
/pocket_pdr:
  ros__parameters:
    block_s: 0.25
    config: ''
    filter:
      frames:
      - map
      - odom
      gain: 2
    tiny: 1.0e-05
    use_sim_time: false
"""
