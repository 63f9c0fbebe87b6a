"""mechanism_node: the thin rclpy shell around :class:`linkage_ros.runtime.Runtime`.

    ros2 run linkage_ros mechanism_node --ros-args -p scene:=four_bar -p omega:=2.0

Declares the parameters of :data:`linkage_ros.runtime.PARAMETERS` with descriptors, ticks a
timer at ``rate_hz`` with t from the node clock (``use_sim_time`` works), publishes the messages
the runtime builds (QoS depth 10, reliable) and validates parameter changes in a callback. This
is the only module of the package that imports rclpy.
"""

from __future__ import annotations

import gc
import importlib
from collections.abc import Sequence
from typing import Any

import rclpy
import rclpy.logging
from rcl_interfaces.msg import (
    FloatingPointRange,
    ParameterDescriptor,
    ParameterType,
    SetParametersResult,
)
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

import solver
from solver.errors import SolverError

from .messages import TYPE_NAMES
from .runtime import PARAMETERS, ParameterSpec, Recorder, Runtime

__all__ = ["MechanismNode", "QOS_DEPTH", "main", "message_classes", "qos_profile"]

QOS_DEPTH = 10

_PARAMETER_TYPES = {
    "string": ParameterType.PARAMETER_STRING,
    "double": ParameterType.PARAMETER_DOUBLE,
    "string_array": ParameterType.PARAMETER_STRING_ARRAY,
}


def qos_profile() -> QoSProfile:
    """Depth 10, reliable, volatile: what the recorder's offered_qos_profiles also say."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=QOS_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE,
    )


def message_classes(names: Sequence[str] = TYPE_NAMES) -> dict[str, Any]:
    """The generated rclpy classes of the message types, by ROS type name."""
    out = {}
    for name in names:
        package, _, cls = name.split("/")
        out[name] = getattr(importlib.import_module(f"{package}.msg"), cls)
    return out


def descriptor(spec: ParameterSpec) -> ParameterDescriptor:
    """The ParameterDescriptor of one parameter (type, description, constraints, range)."""
    kwargs: dict[str, Any] = {
        "name": spec.name,
        "type": _PARAMETER_TYPES[spec.kind],
        "description": spec.description,
        "additional_constraints": spec.constraints,
        "read_only": False,
    }
    if spec.float_range is not None:
        lo, hi = spec.float_range
        kwargs["floating_point_range"] = [FloatingPointRange(from_value=lo, to_value=hi, step=0.0)]
    return ParameterDescriptor(**kwargs)


def mcap_recorder(namespace: str) -> Any:
    """A recorder factory for Runtime: rosbag2-profile MCAP with rclpy's serialisation."""

    def factory(path: str, topics: Sequence[tuple[str, str]]) -> Recorder:
        from rclpy.serialization import serialize_message

        from .record.mcap import Recorder as McapRecorder

        return McapRecorder(
            path,
            topics,
            namespace=namespace,
            serialize=lambda message, _type: serialize_message(message),
        )

    return factory


class MechanismNode(Node):
    """Publishes the kinematics of one mechanism at ``rate_hz``."""

    def __init__(self, *, node_name: str = "mechanism_node", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        values: dict[str, Any] = {}
        for spec in PARAMETERS:
            if spec.name == "points":
                continue  # its default depends on the scene
            self.declare_parameter(spec.name, spec.default, descriptor(spec))
            values[spec.name] = self.get_parameter(spec.name).value
        scene_outputs = _scene_outputs(values["scene"])
        points_spec = next(spec for spec in PARAMETERS if spec.name == "points")
        # A non-empty default makes the type a string array ([""] when the scene has no outputs:
        # rclpy would read an empty list as a byte array).
        self.declare_parameter("points", list(scene_outputs) or [""], descriptor(points_spec))
        values["points"] = list(self.get_parameter("points").value or ())
        self.runtime = Runtime(
            values, message_classes(), recorder_factory=mcap_recorder(self.get_namespace())
        )
        self._qos = qos_profile()
        self._publishers: dict[str, Any] = {}
        self._sync_publishers()
        self._timer = self.create_timer(self.runtime.period_s, self._on_timer)
        self._pending: list[Any] = []
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.get_logger().info(
            f"scene {self.runtime.engine.scene.name}: publishing {len(self._publishers)} topics "
            f"at {self.runtime.settings['rate_hz']:g} Hz"
        )

    # ------------------------------------------------------------------ callbacks
    def _on_timer(self) -> None:
        now_ns = self.get_clock().now().nanoseconds
        messages = self.runtime.tick(now_ns)
        for topic, message in messages:
            self._publishers[topic].publish(message)
        for event in self.runtime.take_events():
            self.get_logger().warning(event)
        if self._pending:
            pending, self._pending = self._pending, []
            self.set_parameters(pending)

    def _on_set_parameters(self, parameters: Sequence[Any]) -> SetParametersResult:
        changes = {p.name: p.value for p in parameters}
        old_rate = self.runtime.settings["rate_hz"]
        old_points = list(self.runtime.settings["points"])
        now_ns = self.get_clock().now().nanoseconds
        reason = self.runtime.update(changes, now_ns)
        if reason is not None:
            self.get_logger().warning(f"parameter change rejected: {reason}")
            return SetParametersResult(successful=False, reason=reason)
        self._sync_publishers()
        if self.runtime.settings["rate_hz"] != old_rate:
            self.destroy_timer(self._timer)
            self._timer = self.create_timer(self.runtime.period_s, self._on_timer)
        points = list(self.runtime.settings["points"])
        if "points" not in changes and points != old_points:
            # The points followed a change of scene: show it in the parameter (next tick).
            self._pending.append(Parameter("points", value=points))
        return SetParametersResult(successful=True, reason="")

    # ------------------------------------------------------------------ helpers
    def _sync_publishers(self) -> None:
        classes = self.runtime.types.classes
        wanted = dict(self.runtime.topics)
        for topic in [t for t in self._publishers if t not in wanted]:
            self.destroy_publisher(self._publishers.pop(topic))
        for topic, typename in wanted.items():
            if topic not in self._publishers:
                self._publishers[topic] = self.create_publisher(classes[typename], topic, self._qos)

    def destroy_node(self) -> None:
        self.runtime.close()
        super().destroy_node()


def _scene_outputs(scene: str) -> tuple[str, ...]:
    return tuple(solver.load_scene(scene).output_points)


def main(args: Sequence[str] | None = None) -> int:
    """Entry point of ``ros2 run linkage_ros mechanism_node``; 1 when the start values are
    unusable (unknown scene, unassemblable phi0, ...)."""
    try:
        with rclpy.init(args=args):
            try:
                node = MechanismNode()
            except (SolverError, ValueError) as error:
                rclpy.logging.get_logger("mechanism_node").error(f"cannot start: {error}")
                return 1
            # the scene, plan, typestore and message classes live as long as the node: move them
            # out of the collector's way, so its passes at 1 kHz only see the tick's own objects
            gc.collect()
            gc.freeze()
            try:
                rclpy.spin(node)
            finally:
                node.destroy_node()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
