"""Start mechanism_node with any of its parameters given as launch arguments.

    ros2 launch linkage_ros mechanism.launch.py scene:=four_bar omega:=2.0
    ros2 launch linkage_ros mechanism.launch.py scene:=excavator input_source:=topic \
        input_joints:="[boom_cylinder_rod_joint, arm_cylinder_rod_joint, bucket_cylinder_rod_joint]"
    ros2 launch linkage_ros mechanism.launch.py params_file:=config/params.yaml rate_hz:=200.0

Every node parameter (linkage_ros.parameters.PARAMETERS) is a launch argument of the same name.
An argument left empty (the default) is not passed: the node takes its own default, which for a
scene driven by actuators follows the scene (the stroke's closed length, 0.1 m/s). Arrays are
written as YAML lists (``input_omegas:="[1.0, -2.0]"``). ``params_file`` (default: none) is a
parameter file loaded first (e.g. the installed config/params.yaml); the arguments given override
it. A value that is not of the parameter's type stops the launch with one line naming it; the node
checks ranges and names as at any start.
"""

from __future__ import annotations

from typing import Any

import yaml
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

from launch import LaunchContext, LaunchDescription
from linkage_ros.parameters import PARAMETERS

#: Launch arguments: every node parameter (default "": the node's own), and the parameter file.
ARGUMENTS: dict[str, tuple[str, str]] = {
    spec.name: ("", f"{spec.description} ({spec.kind}; empty: the node's default)") for spec in PARAMETERS
}
ARGUMENTS["params_file"] = ("", "a parameter file loaded before the arguments given (empty: none)")
KINDS = {spec.name: spec.kind for spec in PARAMETERS}


def parameter_value(name: str, text: str) -> Any:
    """A launch argument's text as the value of the node parameter ``name`` (its kind's type);
    ValueError with one line when it is not."""
    kind = KINDS[name]
    if kind == "string":
        return text
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        value = None
    if kind == "double" and isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    if kind == "double_array" and isinstance(value, list) and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        return [float(v) for v in value]
    if kind == "string_array" and isinstance(value, list):
        return [str(v) for v in value]
    expected = {"double": "a number", "double_array": "a list of numbers", "string_array": "a list of names"}[kind]
    raise ValueError(f"launch argument {name} must be {expected}, got {text!r}")


def overrides(values: dict[str, str]) -> dict[str, Any]:
    """The node parameters of the launch arguments that were given (non-empty)."""
    return {name: parameter_value(name, text) for name, text in values.items() if name in KINDS and text != ""}


def _nodes(context: LaunchContext) -> list[Node]:
    values = {name: LaunchConfiguration(name).perform(context) for name in ARGUMENTS}
    parameters: list[Any] = [values["params_file"]] if values["params_file"] else []
    given = overrides(values)
    if given:
        parameters.append(given)
    return [Node(package="linkage_ros", executable="mechanism_node", name="mechanism_node", output="screen",
                 parameters=parameters)]


def generate_launch_description() -> LaunchDescription:
    """Declare the arguments; the node is made once their values are known."""
    declared = [
        DeclareLaunchArgument(name, default_value=default, description=text)
        for name, (default, text) in ARGUMENTS.items()
    ]
    return LaunchDescription([*declared, OpaqueFunction(function=_nodes)])
