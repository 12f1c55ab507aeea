"""Node parameters declared one way by every node of the workspace.

:func:`declare` declares a parameter with its description (``ros2 param describe``) and
its type taken from the default, and reads what was given leniently where ROS's YAML
parsing surprises people: ``-p mag_wait_s:=2`` (an integer for a double) is 2.0, and a
number given for a string is that string. A value that cannot be the parameter's type,
or a choice outside the allowed values (``-p imu_durability:=reliable``), is refused with
an :class:`~pdr_core.errors.InputError` naming the parameter, the value and what it
takes: the node exits 2 with that one line (pdr_core.ros.node_main).

rclpy is imported inside the function (pdr_core stays importable without ROS).
"""
from __future__ import annotations

from collections.abc import Sequence

from pdr_core.errors import InputError

TYPE_NAMES = {bool: "a boolean (true or false)", int: "an integer", float: "a number",
              str: "a string"}


def declare(node, name: str, default: bool | int | float | str, description: str,
            choices: Sequence[str] = ()) -> bool | int | float | str:
    """Declare ``name`` on ``node`` with ``default`` (which gives its type) and
    ``description`` (its units and meaning), and return its value, converted to that
    type as the module docstring says; ``choices``: the values a string may take."""
    from rcl_interfaces.msg import ParameterDescriptor

    given = node.declare_parameter(name, default,
                                   ParameterDescriptor(dynamic_typing=True)).value
    node.undeclare_parameter(name)
    value = _converted(name, given, type(default))
    if choices and value not in choices:
        raise InputError(f"parameter {name}", f"{value!r} is not one of {', '.join(choices)} "
                         f"(-p {name}:={choices[0]})")
    allowed = f" One of: {', '.join(choices)}." if choices else ""
    node.declare_parameter(name, value,
                           ParameterDescriptor(description=description + allowed),
                           ignore_override=True)
    return value


def _converted(name: str, value, kind: type):
    """``value`` as ``kind``: an integer for a float, a number for a string; else the
    value itself when it is of that type, or an InputError."""
    if kind is float and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if kind is str and isinstance(value, int | float) and not isinstance(value, bool):
        return str(value)
    if isinstance(value, kind) and (kind is bool or not isinstance(value, bool)):
        return value
    raise InputError(f"parameter {name}", f"{value!r} is not {TYPE_NAMES[kind]}")


def refuse_removed(node, replaced: dict[str, str]) -> None:
    """Refuse a parameter that is gone when it is given (an InputError saying what
    replaced it), so an old launch file fails loudly instead of being ignored."""
    from rcl_interfaces.msg import ParameterDescriptor

    for name, instead in replaced.items():
        given = node.declare_parameter(name, None,
                                       ParameterDescriptor(dynamic_typing=True)).value
        node.undeclare_parameter(name)
        if given is not None:
            raise InputError(f"parameter {name}", f"is gone: use {instead}")
