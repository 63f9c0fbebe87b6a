"""Show a closed linkage in RViz: mechanism_node, robot_state_publisher and RViz.

    ros2 launch linkage_ros display.launch.py scene:=harvester_finger omega:=1.0

The URDF is generated when the launch starts (``linkage_ros.urdf.generate_urdf``, the same as
``linkage-urdf SCENE``) and handed to robot_state_publisher as ``robot_description``. The node
publishes the tree joints of that URDF on ``joint_states`` together with the scene's joints, so
robot_state_publisher gives TF for every link; RViz shows the robot model, the node's markers
and TF (config/linkage.rviz). ``rviz:=false`` leaves RViz out (e.g. to use Foxglove instead).
"""

from __future__ import annotations

import os

from ament_index_python.packages import get_package_share_directory
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue

from launch import LaunchContext, LaunchDescription

#: Launch arguments and their defaults.
ARGUMENTS = {
    "scene": ("harvester_finger", "scene file, or the name of a shipped scene"),
    "omega": ("1.0", "angular velocity of the input joint, rad/s"),
    "epsilon": ("0.0", "angular acceleration of the input joint, rad/s^2"),
    "rate_hz": ("50.0", "publishing rate, Hz"),
    "frame_id": ("world", "root frame: the node's frame_id and the URDF's root link"),
    "rviz": ("true", "start RViz with config/linkage.rviz"),
}


def _nodes(context: LaunchContext) -> list[Node]:
    """Generate the URDF for the chosen scene, then start the three nodes."""
    from linkage_ros.urdf import generate_urdf

    scene = LaunchConfiguration("scene").perform(context)
    frame_id = LaunchConfiguration("frame_id").perform(context)
    share = get_package_share_directory("linkage_ros")
    robot_description = generate_urdf(scene, frame_id=frame_id)
    mechanism = Node(
        package="linkage_ros",
        executable="mechanism_node",
        name="mechanism_node",
        output="screen",
        parameters=[
            os.path.join(share, "config", "params.yaml"),
            {
                "scene": scene,
                "frame_id": frame_id,
                "omega": ParameterValue(LaunchConfiguration("omega"), value_type=float),
                "epsilon": ParameterValue(LaunchConfiguration("epsilon"), value_type=float),
                "rate_hz": ParameterValue(LaunchConfiguration("rate_hz"), value_type=float),
            },
        ],
        # robot_state_publisher publishes /robot_description: the node's own goes to its private name
        remappings=[("robot_description", "~/robot_description")],
    )
    state_publisher = Node(
        package="robot_state_publisher",
        executable="robot_state_publisher",
        name="robot_state_publisher",
        output="screen",
        parameters=[
            {
                "robot_description": ParameterValue(robot_description, value_type=str),
                # TF at the node's rate (robot_state_publisher throttles to publish_frequency).
                "publish_frequency": ParameterValue(LaunchConfiguration("rate_hz"), value_type=float),
            }
        ],
    )
    rviz = Node(
        package="rviz2",
        executable="rviz2",
        name="rviz2",
        arguments=["-d", os.path.join(share, "config", "linkage.rviz"), "-f", frame_id],
        condition=IfCondition(LaunchConfiguration("rviz")),
    )
    return [mechanism, state_publisher, rviz]


def generate_launch_description() -> LaunchDescription:
    """Declare the arguments; the nodes are made once their values are known."""
    declared = [
        DeclareLaunchArgument(name, default_value=default, description=text)
        for name, (default, text) in ARGUMENTS.items()
    ]
    return LaunchDescription([*declared, OpaqueFunction(function=_nodes)])
