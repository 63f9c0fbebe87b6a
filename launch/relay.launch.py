"""The node as the exact closed-chain state publisher behind a driver's JointState topic.

    ros2 launch linkage_ros relay.launch.py scene:=four_bar
    ros2 launch linkage_ros relay.launch.py scene:=gripper_finger input_joint:=finger_joint \
        urdf:=gripper_finger.urdf frame_id:=palm
    ros2 launch linkage_ros relay.launch.py topic_epsilon:=difference topic_max_gap:=0.05

Graph (docs/relay.md)::

    driver ──/joint_states (input joint)──┬──────────────────────────► robot_state_publisher ─► /tf
                                          └─► mechanism_node (topic) ─┘ /joint_states (passive joints)
                                               input_joint_states:=/joint_states

The driver (hardware, ros2_control's joint_state_broadcaster, a test publisher) publishes the
input joint on ``input_topic``; mechanism_node runs with ``input_source: topic``, its
``input_joint_states`` remapped there, answers every message with the same topics as in clock
mode, and puts the passive joints only on ``joint_states`` (its own messages coming back on a
shared topic are ignored). robot_state_publisher hears both streams and poses every link.
``urdf``: the user's URDF (a path, or a file name under share/linkage_ros/config/urdf/); empty:
the URDF that ``linkage-urdf`` generates for the scene. ``topic_epsilon`` and ``topic_max_gap``
set the node parameters of the same names (how ε is read, and the largest gap between two
messages that are differenced; docs/relay.md), with the defaults of config/params.yaml.
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
    "scene": ("four_bar", "scene file, or the name of a shipped scene"),
    "input_topic": ("/joint_states", "the driver's sensor_msgs/JointState topic (the node's input_joint_states)"),
    "input_joint": ("", "the joint the driver publishes; empty: the scene's input joint"),
    "urdf": ("", "the user's URDF (path, or a file under share/linkage_ros/config/urdf); empty: generated"),
    "frame_id": ("world", "root frame: the node's frame_id and the generated URDF's root link"),
    "topic_epsilon": ("zero", "the input's angular acceleration: zero, or difference (of successive velocities)"),
    "topic_max_gap": ("0.25", "s, in [0.001, 60]: two messages further apart are not differenced"),
    "rviz": ("false", "start RViz with config/linkage.rviz"),
}


def robot_description(scene: str, urdf: str, frame_id: str, share: str) -> str:
    """The URDF text for robot_state_publisher: the user's file, or the scene's generated tree."""
    if not urdf:
        from linkage_ros.urdf import generate_urdf

        return generate_urdf(scene, frame_id=frame_id)
    path = urdf if os.path.isabs(urdf) or os.path.exists(urdf) else os.path.join(share, "config", "urdf", urdf)
    with open(path, encoding="utf-8") as f:
        return f.read()


def seconds(name: str, text: str) -> float:
    """A launch argument given in seconds, as the node's double parameter; one line if it is not
    a number (the node checks the range)."""
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"{name} must be a number of seconds, got {text!r}") from None


def _nodes(context: LaunchContext) -> list[Node]:
    """Read the URDF, then start the node in topic mode, robot_state_publisher and RViz."""
    scene = LaunchConfiguration("scene").perform(context)
    frame_id = LaunchConfiguration("frame_id").perform(context)
    input_joint = LaunchConfiguration("input_joint").perform(context)
    input_topic = LaunchConfiguration("input_topic").perform(context)
    share = get_package_share_directory("linkage_ros")
    description = robot_description(scene, LaunchConfiguration("urdf").perform(context), frame_id, share)
    overrides: dict[str, str | float] = {
        "scene": scene,
        "frame_id": frame_id,
        "input_source": "topic",
        "topic_epsilon": LaunchConfiguration("topic_epsilon").perform(context),
        "topic_max_gap": seconds("topic_max_gap", LaunchConfiguration("topic_max_gap").perform(context)),
    }
    if input_joint:
        overrides["input_joint"] = input_joint
    mechanism = Node(
        package="linkage_ros",
        executable="mechanism_node",
        name="mechanism_node",
        output="screen",
        parameters=[os.path.join(share, "config", "params.yaml"), overrides],
        # robot_state_publisher publishes /robot_description (the URDF it poses): the node's own
        # (the generated tree) goes to its private name, so the two never share a topic
        remappings=[("input_joint_states", input_topic), ("robot_description", "~/robot_description")],
    )
    state_publisher = Node(
        package="robot_state_publisher",
        executable="robot_state_publisher",
        name="robot_state_publisher",
        output="screen",
        parameters=[{"robot_description": ParameterValue(description, value_type=str)}],
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
