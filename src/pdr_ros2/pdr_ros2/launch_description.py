"""A launch file of ROS 2's XML or YAML front end read into the processes it starts.

The elements and attributes read are those of ``launch_xml``/``launch_yaml`` (ROS 2
Jazzy) that a graph of nodes needs, each as the real parser reads it (``launch``'s
``actions/`` and ``launch_ros``'s ``actions/node.py``; docs/ros2.md lists them):

- ``<arg name default description>``, ``<let name value>``, ``<set_env name value>``;
- ``<node pkg exec name namespace args ros_args output on_exit exec_name>`` with
  ``<param name value [value-sep]>`` or ``<param from>`` (a ROS parameter file),
  ``<remap from to>`` and ``<env name value>`` children;
- ``<executable cmd name cwd output on_exit>`` with ``<env>`` children;
- ``<include file>`` with ``<arg name value>`` children, ``<group scoped>`` and
  ``<push_ros_namespace namespace>``;
- ``if`` and ``unless`` on every action (``true``/``false``/``1``/``0``).

As ``launch_xml`` does, an attribute or a child the element does not read is an error
that names it, so a file this reader accepts is also one the real parser accepts. Each
node's ``name``/``value`` parameters go to a parameter file with the ``/**`` key, typed
by YAML, as ``launch_ros`` writes them; a ``<param from>`` file is passed as it is.
"""
from __future__ import annotations

import os
import shlex
from dataclasses import dataclass, field, replace
from pathlib import Path
from xml.etree import ElementTree

import yaml

from pdr_ros2.launch_substitutions import LaunchError, Scope, substitute

ACTIONS = frozenset({"arg", "let", "node", "executable", "include", "group",
                     "push_ros_namespace", "set_env"})
CONDITIONS = frozenset({"if", "unless"})
ATTRIBUTES = {
    "launch": frozenset(),
    "arg": frozenset({"name", "default", "description"}),
    "let": frozenset({"name", "value"}) | CONDITIONS,
    "set_env": frozenset({"name", "value"}) | CONDITIONS,
    "node": frozenset({"pkg", "exec", "name", "namespace", "args", "ros_args", "output",
                       "on_exit", "exec_name"}) | CONDITIONS,
    "executable": frozenset({"cmd", "name", "cwd", "output", "on_exit"}) | CONDITIONS,
    "include": frozenset({"file"}) | CONDITIONS,
    "group": frozenset({"scoped"}) | CONDITIONS,
    "push_ros_namespace": frozenset({"namespace"}) | CONDITIONS,
    "param": frozenset({"name", "value", "value-sep", "from"}),
    "remap": frozenset({"from", "to"}),
    "env": frozenset({"name", "value"}),
    "include/arg": frozenset({"name", "value"}),
}
CHILDREN = {"launch": ACTIONS, "group": ACTIONS, "node": frozenset({"param", "remap", "env"}),
            "executable": frozenset({"env"}), "include": frozenset({"arg"})}
OUTPUTS = ("log", "screen", "both")     # launch's output modes; "log" is its default
SHUTDOWN = "shutdown"                   # the one on_exit value the front ends read
ROOT_NAMESPACE = "/"
LAUNCH_SUFFIXES = (".launch.xml", ".launch.yaml", ".launch.yml", ".xml", ".yaml", ".yml")


@dataclass
class LaunchProcess:
    """One process of a launch: the command, how its output goes and what its end does.

    ``parameters`` are a node's parameter sources in order: a mapping (written to a
    ``/**`` parameter file at start) or the path of a parameter file."""

    label: str                      # "<executable>-<n>", as ros2 launch prints it
    command: list[str]
    ros_arguments: list[str] = field(default_factory=list)
    parameters: list[dict | str] = field(default_factory=list)
    env: dict[str, str] = field(default_factory=dict)
    cwd: str | None = None
    output: str = "log"
    shutdown_on_exit: bool = False

    def argv(self, folder: Path) -> list[str]:
        """The full command line; each mapping of ``parameters`` written to ``folder``."""
        ros_args = list(self.ros_arguments)
        for index, source in enumerate(self.parameters):
            if isinstance(source, dict):
                path = folder / f"{self.label}_params_{index}.yaml"
                path.write_text(yaml.safe_dump({"/**": {"ros__parameters": source}}))
                source = str(path)
            ros_args += ["--params-file", source]
        return self.command + (["--ros-args", *ros_args] if ros_args else [])


@dataclass
class Context:
    """What the actions read so far set: configurations, namespace, environment."""

    variables: dict[str, str]
    folder: str
    namespace: str = ROOT_NAMESPACE
    env: dict[str, str] = field(default_factory=dict)

    def scope(self) -> Scope:
        return Scope(self.variables, self.folder)

    def copy(self) -> Context:
        return replace(self, variables=dict(self.variables), env=dict(self.env))


@dataclass
class Launch:
    """A launch file read: its processes and the arguments it (or an include) declares."""

    processes: list[LaunchProcess] = field(default_factory=list)
    declared: dict[str, tuple[str | None, str]] = field(default_factory=dict)


def read_launch(path: Path, arguments: dict[str, str]) -> Launch:
    """The processes of the launch file at ``path`` with the launch ``arguments``
    (``name:=value`` of the command line); LaunchError names the file and the problem,
    including an argument the file does not declare."""
    launch = Launch()
    context = Context(dict(arguments), str(path.parent))
    read_file(path, context, launch)
    unknown = sorted(set(arguments) - set(launch.declared))
    if unknown:
        raise LaunchError(f"{path}: unknown launch argument(s) {', '.join(unknown)} "
                          f"(declared: {', '.join(launch.declared) or 'none'})")
    return launch


def read_file(path: Path, context: Context, launch: Launch) -> None:
    """Read the launch file's actions in ``context`` into ``launch``."""
    try:
        root = load_root(path)
        if root.tag != "launch":
            raise LaunchError(f"the root element is <{root.tag}>, not <launch>")
        check(root, "launch")
        read_actions(root, context, launch)
    except LaunchError as error:
        message = str(error)
        raise LaunchError(message if message.startswith(f"{path}:") else
                          f"{path}: {message}") from None


def load_root(path: Path) -> ElementTree.Element:
    """The launch file's root element: XML as it is, YAML made into the same tree."""
    try:
        if path.suffix in (".yaml", ".yml"):
            content = yaml.safe_load(path.read_text())
            if not isinstance(content, dict) or list(content) != ["launch"]:
                raise LaunchError("a YAML launch file is a mapping with the one key 'launch'")
            return yaml_element("launch", content["launch"])
        return ElementTree.parse(path).getroot()
    except OSError as error:
        raise LaunchError(f"cannot be read: {error.strerror}") from None
    except (ElementTree.ParseError, yaml.YAMLError) as error:
        raise LaunchError(f"is not a launch file: {error}") from None


def yaml_element(tag: str, body) -> ElementTree.Element:
    """A YAML front-end entity as the XML element it stands for (``launch_yaml``):
    scalars are attributes, a list of scalars an attribute with ``<name>-sep=","``, a
    list of mappings children (``children:`` of a group or launch: one-key mappings)."""
    element = ElementTree.Element(tag)
    items = body.items() if isinstance(body, dict) else [("children", body or [])]
    for key, value in items:
        if key == "children":
            for entity in value:
                if not (isinstance(entity, dict) and len(entity) == 1):
                    raise LaunchError(f"<{tag}>'s children are one-key mappings, not {entity!r}")
                [(child_tag, child_body)] = entity.items()
                element.append(yaml_element(child_tag, child_body))
        elif isinstance(value, list) and all(isinstance(v, dict) for v in value):
            element.extend(yaml_element(key, child) for child in value)
        elif isinstance(value, list):
            element.set(key, ",".join(map(yaml_scalar, value)))
            element.set(f"{key}-sep", ",")
        else:
            element.set(key, yaml_scalar(value))
    return element


def yaml_scalar(value) -> str:
    """A YAML scalar as the text of an XML attribute."""
    return str(value).lower() if isinstance(value, bool) else str(value)


def check(element: ElementTree.Element, kind: str) -> None:
    """launch_xml's strictness: no attribute or child the element does not read."""
    unread = sorted(set(element.attrib) - ATTRIBUTES[kind])
    if unread:
        raise LaunchError(f"Unexpected attribute(s) found in `{element.tag}`: {unread}")
    children = {child.tag for child in element} - CHILDREN.get(kind, frozenset())
    if children:
        raise LaunchError(f"Unexpected nested tag(s) found in `{element.tag}`: "
                          f"{sorted(children)}")


def children(element: ElementTree.Element, tag: str) -> list[ElementTree.Element]:
    """The element's ``tag`` children, each checked as launch_xml checks it."""
    found = element.findall(tag)
    for child in found:
        check(child, tag)
    return found


def read_actions(parent: ElementTree.Element, context: Context, launch: Launch) -> None:
    """Each action child of ``parent`` in order."""
    for element in parent:
        check(element, element.tag)
        if not condition(element, context):
            continue
        ACTION_READERS[element.tag](element, context, launch)


def condition(element: ElementTree.Element, context: Context) -> bool:
    """The ``if``/``unless`` attributes: launch's true/false/1/0 (any case)."""
    for name, wanted in (("if", True), ("unless", False)):
        if name in element.attrib:
            text = attribute(element, name, context).strip().lower()
            if text not in ("true", "false", "1", "0"):
                raise LaunchError(f"<{element.tag} {name}=...>: '{text}' is not a boolean "
                                  "(true, false, 1 or 0)")
            if (text in ("true", "1")) != wanted:
                return False
    return True


def attribute(element: ElementTree.Element, name: str, context: Context,
              default: str | None = None) -> str:
    """An attribute's substituted text; LaunchError when it is required and missing."""
    if name not in element.attrib:
        if default is None:
            raise LaunchError(f"<{element.tag}> needs the attribute '{name}'")
        return default
    return substitute(element.attrib[name], context.scope())


def read_arg(element, context: Context, launch: Launch) -> None:
    """``<arg>``: a value given (command line, include) wins over the default."""
    name = attribute(element, "name", context)
    default = element.get("default")
    launch.declared.setdefault(name, (default, element.get("description", "")))
    if name in context.variables:
        return
    if default is None:
        raise LaunchError(f"required launch argument '{name}' not provided "
                          f"(give {name}:=VALUE)")
    context.variables[name] = substitute(default, context.scope())


def read_let(element, context: Context, launch: Launch) -> None:
    context.variables[attribute(element, "name", context)] = attribute(element, "value",
                                                                       context)


def read_set_env(element, context: Context, launch: Launch) -> None:
    context.env[attribute(element, "name", context)] = attribute(element, "value", context)


def read_push_namespace(element, context: Context, launch: Launch) -> None:
    context.namespace = namespace_of(attribute(element, "namespace", context),
                                     context.namespace)


def namespace_of(namespace: str, pushed: str) -> str:
    """``namespace`` under the pushed one (an absolute namespace stays as it is)."""
    if namespace.startswith("/"):
        return namespace
    joined = "/".join(part for part in (*pushed.split("/"), *namespace.split("/")) if part)
    return "/" + joined


def read_group(element, context: Context, launch: Launch) -> None:
    """``<group scoped>``: a scoped group (the default) keeps its settings inside."""
    scoped = attribute(element, "scoped", context, "true").lower() in ("true", "1")
    read_actions(element, context.copy() if scoped else context, launch)


def read_include(element, context: Context, launch: Launch) -> None:
    """``<include file>``: the file's actions with its ``<arg>`` values, in a scope of
    its own."""
    inner = context.copy()
    for child in element:
        check(child, "include/arg")
        inner.variables[attribute(child, "name", context)] = attribute(child, "value",
                                                                       context)
    path = Path(attribute(element, "file", context))
    inner.folder = str(path.parent)
    read_file(path, inner, launch)


def read_node(element, context: Context, launch: Launch) -> None:
    """``<node>``: ``<prefix of pkg>/lib/pkg/exec`` with its ROS arguments."""
    from pdr_ros2.cli_run import executable_path

    package, executable = attribute(element, "pkg", context), attribute(element, "exec",
                                                                        context)
    try:
        path = executable_path(package, executable)
    except ValueError as error:
        raise LaunchError(f"<node pkg='{package}' exec='{executable}'>: {error}") from None
    ros_args = shlex.split(attribute(element, "ros_args", context, ""))
    if "name" in element.attrib:
        ros_args += ["-r", f"__node:={attribute(element, 'name', context)}"]
    namespace = namespace_of(attribute(element, "namespace", context, ""), context.namespace)
    if namespace != ROOT_NAMESPACE:
        ros_args += ["-r", f"__ns:={namespace}"]
    for remap in children(element, "remap"):
        ros_args += ["-r", f"{attribute(remap, 'from', context)}:="
                           f"{attribute(remap, 'to', context)}"]
    label = attribute(element, "exec_name", context, executable)
    launch.processes.append(LaunchProcess(
        numbered(label, launch), [path, *shlex.split(attribute(element, "args", context, ""))],
        ros_args, parameters(element, context), {**context.env, **envs(element, context)},
        None, output(element, context), on_exit(element, context)))


def read_executable(element, context: Context, launch: Launch) -> None:
    """``<executable cmd>``: a command line of any program."""
    command = shlex.split(attribute(element, "cmd", context))
    if not command:
        raise LaunchError("<executable> has an empty cmd")
    label = attribute(element, "name", context, os.path.basename(command[0]))
    launch.processes.append(LaunchProcess(
        numbered(label, launch), command, env={**context.env, **envs(element, context)},
        cwd=attribute(element, "cwd", context, "") or None, output=output(element, context),
        shutdown_on_exit=on_exit(element, context)))


def numbered(label: str, launch: Launch) -> str:
    """ros2 launch's process label: the name and the process' number from 1."""
    return f"{label}-{len(launch.processes) + 1}"


def parameters(element, context: Context) -> list[dict | str]:
    """A node's parameter sources in order: runs of ``name``/``value`` gathered into a
    mapping (values typed by YAML, as launch_ros types them), ``from`` files as paths."""
    sources: list[dict | str] = []
    for param in children(element, "param"):
        if "from" in param.attrib:
            if set(param.attrib) != {"from"}:
                raise LaunchError("<param from> takes no other attribute")
            sources.append(attribute(param, "from", context))
            continue
        if not (sources and isinstance(sources[-1], dict)):
            sources.append({})
        sources[-1][attribute(param, "name", context)] = param_value(param, context)
    return sources


def param_value(param, context: Context):
    """A ``<param>``'s value: a list under ``value-sep``, each item (or the value)
    typed by YAML; text that YAML reads as a mapping stays text."""
    text = param.attrib.get("value")
    if text is None:
        raise LaunchError(f"<param name='{param.get('name')}'> needs 'value' or 'from'")
    if "value-sep" in param.attrib:
        separator = param.attrib["value-sep"]
        return [typed(substitute(item, context.scope())) for item in text.split(separator)]
    return typed(substitute(text, context.scope()))


def typed(text: str):
    """YAML's type of a parameter's text (``0`` int, ``0.0`` float, ``true`` bool,
    ``[a, b]`` a list); text that is no scalar or list stays a string."""
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        return text
    return text if value is None or isinstance(value, dict) else value


def envs(element, context: Context) -> dict[str, str]:
    return {attribute(env, "name", context): attribute(env, "value", context)
            for env in children(element, "env")}


def output(element, context: Context) -> str:
    mode = attribute(element, "output", context, OUTPUTS[0])
    if mode not in OUTPUTS:
        raise LaunchError(f"<{element.tag} output='{mode}'>: one of {', '.join(OUTPUTS)}")
    return mode


def on_exit(element, context: Context) -> bool:
    if "on_exit" not in element.attrib:
        return False
    if (value := attribute(element, "on_exit", context)) != SHUTDOWN:
        raise LaunchError(f"<{element.tag} on_exit='{value}'>: only 'shutdown' is read")
    return True


ACTION_READERS = {"arg": read_arg, "let": read_let, "set_env": read_set_env,
                  "push_ros_namespace": read_push_namespace, "group": read_group,
                  "include": read_include, "node": read_node, "executable": read_executable}
