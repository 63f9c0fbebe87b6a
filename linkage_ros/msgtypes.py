"""Message classes by ROS type name, with the conventions of the library they come from.

rosbags' type store (``get_typestore(Stores.ROS2_JAZZY).types``) gives dataclasses that need
every field and numpy arrays for primitive sequences; rclpy's generated classes take
``array.array`` (or lists of Python floats) and reject numpy arrays. :class:`MessageTypes`
wraps either so that one builder serves both.
"""

from __future__ import annotations

import array
import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

__all__ = ["TYPE_NAMES", "MessageTypes"]

#: Every message type the builder constructs (nested ones included).
TYPE_NAMES: tuple[str, ...] = (
    "builtin_interfaces/msg/Time",
    "builtin_interfaces/msg/Duration",
    "std_msgs/msg/Header",
    "std_msgs/msg/ColorRGBA",
    "geometry_msgs/msg/Point",
    "geometry_msgs/msg/Vector3",
    "geometry_msgs/msg/Quaternion",
    "geometry_msgs/msg/Pose",
    "geometry_msgs/msg/PointStamped",
    "geometry_msgs/msg/Vector3Stamped",
    "geometry_msgs/msg/Wrench",
    "geometry_msgs/msg/WrenchStamped",
    "sensor_msgs/msg/JointState",
    "sensor_msgs/msg/CompressedImage",
    "trajectory_msgs/msg/JointTrajectory",
    "trajectory_msgs/msg/JointTrajectoryPoint",
    "visualization_msgs/msg/Marker",
    "visualization_msgs/msg/MarkerArray",
    "visualization_msgs/msg/MeshFile",
    "diagnostic_msgs/msg/DiagnosticArray",
    "diagnostic_msgs/msg/DiagnosticStatus",
    "diagnostic_msgs/msg/KeyValue",
    "std_msgs/msg/MultiArrayDimension",
    "std_msgs/msg/MultiArrayLayout",
    "std_msgs/msg/Float64MultiArray",
    "std_msgs/msg/String",
)


class MessageTypes:
    """Message classes by type name, with the sequence conventions of their library.

    ``flavour`` is ``"rosbags"`` (dataclasses that need every field and numpy arrays for
    primitive sequences) or ``"rclpy"`` (generated classes: ``array.array`` sequences); it is
    detected from the classes when not given.
    """

    def __init__(self, types: Mapping[str, Any], *, flavour: str | None = None) -> None:
        missing = [name for name in TYPE_NAMES if name not in types]
        if missing:
            raise KeyError(f"message classes missing for {', '.join(missing)}")
        self.classes = {name: types[name] for name in TYPE_NAMES}
        if flavour is None:
            flavour = "rosbags" if dataclasses.is_dataclass(self.classes[TYPE_NAMES[0]]) else "rclpy"
        if flavour not in ("rosbags", "rclpy"):
            raise ValueError(f"flavour must be 'rosbags' or 'rclpy', got {flavour!r}")
        self.flavour = flavour

    def __getitem__(self, name: str) -> Any:
        return self.classes[name]

    def float64s(self, values: Sequence[float] | np.ndarray) -> Any:
        """A float64[] field value."""
        data = np.ascontiguousarray(values, dtype=np.float64).reshape(-1)
        if self.flavour == "rosbags":
            return data
        return array.array("d", data.tobytes())

    def float64_rows(self, rows: Sequence[Sequence[float]]) -> list[Any]:
        """Several float64[] field values (rows of Python floats)."""
        if self.flavour == "rosbags":
            return [np.array(row, dtype=np.float64) for row in rows]
        return [array.array("d", row) for row in rows]

    def uint8s(self) -> Any:
        """An empty uint8[] field value."""
        if self.flavour == "rosbags":
            return np.zeros(0, dtype=np.uint8)
        return array.array("B")
