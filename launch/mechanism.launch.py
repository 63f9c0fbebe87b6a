"""Start mechanism_node with the scene, omega, epsilon and rate_hz given as launch arguments.

    ros2 launch linkage_ros mechanism.launch.py scene:=four_bar omega:=2.0

Other parameters come from config/params.yaml (installed under share/linkage_ros/config).
"""

from __future__ import annotations

import os

from ament_index_python.packages import get_package_share_directory
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue

from launch import LaunchDescription

#: Launch arguments and their defaults (the same as config/params.yaml).
ARGUMENTS = {
    "scene": ("harvester_finger", "scene file, or the name of a shipped scene"),
    "omega": ("1.0", "angular velocity of the input joint, rad/s"),
    "epsilon": ("0.0", "angular acceleration of the input joint, rad/s^2"),
    "rate_hz": ("100.0", "publishing rate, Hz"),
}


def generate_launch_description() -> LaunchDescription:
    """Declare the arguments and start the node with them on top of params.yaml."""
    params_file = os.path.join(get_package_share_directory("linkage_ros"), "config", "params.yaml")
    declared = [
        DeclareLaunchArgument(name, default_value=default, description=text)
        for name, (default, text) in ARGUMENTS.items()
    ]
    overrides = {
        "scene": ParameterValue(LaunchConfiguration("scene"), value_type=str),
        "omega": ParameterValue(LaunchConfiguration("omega"), value_type=float),
        "epsilon": ParameterValue(LaunchConfiguration("epsilon"), value_type=float),
        "rate_hz": ParameterValue(LaunchConfiguration("rate_hz"), value_type=float),
    }
    node = Node(
        package="linkage_ros",
        executable="mechanism_node",
        name="mechanism_node",
        output="screen",
        parameters=[params_file, overrides],
    )
    return LaunchDescription([*declared, node])
