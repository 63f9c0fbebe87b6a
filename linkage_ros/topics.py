"""The topics a mechanism publishes: their names (relative, resolved in the node's namespace)
and ROS types, in the order :class:`~linkage_ros.messages.MessageBuilder` builds them::

    joint_states               sensor_msgs/msg/JointState
    joint_kinematics           trajectory_msgs/msg/JointTrajectory
    points/<P>/position        geometry_msgs/msg/PointStamped
    points/<P>/velocity        geometry_msgs/msg/Vector3Stamped
    points/<P>/acceleration    geometry_msgs/msg/Vector3Stamped
    pin_loads/<K>              geometry_msgs/msg/WrenchStamped   (scenes with forces only,
    slide_loads/<K>            geometry_msgs/msg/WrenchStamped    :mod:`.load_messages`)
    friction_power             std_msgs/msg/Float64MultiArray    (scenes with friction only:
                                                                  W, total then per element)
    markers                    visualization_msgs/msg/MarkerArray
    diagnostics                diagnostic_msgs/msg/DiagnosticArray

No message classes here: the table is what the recorders declare and the node advertises before
any message is built.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

from .engine import Engine

__all__ = [
    "DIAGNOSTICS",
    "EFFORT_COMMANDS",
    "ENERGIES",
    "ENERGY_LABELS",
    "FRICTION_POWER",
    "FRICTION_POWER_TYPE",
    "INPUT_JOINT_STATES",
    "INPUT_TYPES",
    "ROBOT_DESCRIPTION",
    "FIXED_TOPIC_TYPES",
    "JOINT_KINEMATICS",
    "JOINT_STATES",
    "LOADS_NAMESPACE",
    "LOAD_LABELS_NAMESPACE",
    "MARKERS",
    "MARKER_NAMESPACES",
    "NS_PER_S",
    "WRENCH_STAMPED",
    "load_topic_types",
    "point_topics",
    "stamp_parts",
    "topic_types",
]

#: Nanoseconds per second (stamps are integer ns).
NS_PER_S = 1_000_000_000

JOINT_STATES = "joint_states"
JOINT_KINEMATICS = "joint_kinematics"
MARKERS = "markers"
DIAGNOSTICS = "diagnostics"
#: What the node receives (topic mode: the driver's JointStates; dynamic mode: effort commands)
#: and, in dynamic mode, the energies of each tick: recorded beside what it publishes (issue 30).
INPUT_JOINT_STATES = "input_joint_states"
EFFORT_COMMANDS = "effort_commands"
ENERGIES = "energies"
#: The scene's URDF, latched (std_msgs/String): published once per scene and recorded with it.
ROBOT_DESCRIPTION = "robot_description"
#: The entries of one ``energies`` row, in order (J; :mod:`linkage_ros._runtime_dynamic`).
ENERGY_LABELS = ("kinetic", "gravity", "springs", "total")
INPUT_TYPES: dict[str, str] = {
    INPUT_JOINT_STATES: "sensor_msgs/msg/JointState",
    EFFORT_COMMANDS: "std_msgs/msg/Float64MultiArray",
    ENERGIES: "std_msgs/msg/Float64MultiArray",
    ROBOT_DESCRIPTION: "std_msgs/msg/String",
}

#: Topics that every engine publishes, with their types.
FIXED_TOPIC_TYPES: dict[str, str] = {
    JOINT_STATES: "sensor_msgs/msg/JointState",
    JOINT_KINEMATICS: "trajectory_msgs/msg/JointTrajectory",
    MARKERS: "visualization_msgs/msg/MarkerArray",
    DIAGNOSTICS: "diagnostic_msgs/msg/DiagnosticArray",
}

#: Marker namespaces in the markers topic.
MARKER_NAMESPACES = ("links", "joints", "fixed_pivots", "paths")
#: The markers' namespaces of the load arrows and of their labels (scenes with forces,
#: :mod:`.load_messages`).
LOADS_NAMESPACE = "loads"
LOAD_LABELS_NAMESPACE = "load_labels"
#: Scenes with friction: the power (W) friction dissipates at the tick, ``total`` first, then per
#: element (a pin by its point, a slider block, an actuator's seal), the one dimension's label
#: naming them (``W: total O A C B``; :func:`linkage_ros.forces.friction_names`).
FRICTION_POWER = "friction_power"
FRICTION_POWER_TYPE = "std_msgs/msg/Float64MultiArray"
#: The type of every ``pin_loads/<K>`` and ``slide_loads/<K>`` topic.
WRENCH_STAMPED = "geometry_msgs/msg/WrenchStamped"

_NAME_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def point_topics(point: str) -> tuple[str, str, str]:
    """``(position, velocity, acceleration)`` topic names of point ``point``."""
    if not _NAME_TOKEN.match(point):
        raise ValueError(
            f"point name {point!r} cannot be part of a ROS topic name "
            "(letters, digits and underscores, not starting with a digit)"
        )
    base = f"points/{point}"
    return (f"{base}/position", f"{base}/velocity", f"{base}/acceleration")


def load_topic_types(pairs: Sequence[Any]) -> list[tuple[str, str]]:
    """``(topic, type)`` of every load (:class:`~linkage_ros.forces.LoadPair`), in the order of
    ``pairs``."""
    return [(p.topic, WRENCH_STAMPED) for p in pairs]


def topic_types(engine_or_points: Engine | Sequence[str]) -> list[tuple[str, str]]:
    """Every ``(topic, type name)`` published for an engine (or a list of published points),
    in the order :func:`~linkage_ros.messages.build_messages` returns them."""
    points = engine_or_points.published_points if isinstance(engine_or_points, Engine) else tuple(engine_or_points)
    out = [
        (JOINT_STATES, FIXED_TOPIC_TYPES[JOINT_STATES]),
        (JOINT_KINEMATICS, FIXED_TOPIC_TYPES[JOINT_KINEMATICS]),
    ]
    for p in points:
        pos, vel, acc = point_topics(p)
        out += [
            (pos, "geometry_msgs/msg/PointStamped"),
            (vel, "geometry_msgs/msg/Vector3Stamped"),
            (acc, "geometry_msgs/msg/Vector3Stamped"),
        ]
    out += load_topic_types(getattr(engine_or_points, "load_pairs", ()))
    if getattr(engine_or_points, "friction_names", ()):
        out.append((FRICTION_POWER, FRICTION_POWER_TYPE))
    out += [(MARKERS, FIXED_TOPIC_TYPES[MARKERS]), (DIAGNOSTICS, FIXED_TOPIC_TYPES[DIAGNOSTICS])]
    return out


def stamp_parts(stamp_ns: int) -> tuple[int, int]:
    """``(sec, nanosec)`` of a time in integer nanoseconds (nanosec in [0, 10⁹))."""
    sec, nanosec = divmod(int(stamp_ns), NS_PER_S)
    return sec, nanosec
