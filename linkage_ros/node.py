"""mechanism_node: the thin rclpy shell around :class:`linkage_ros.runtime.Runtime`.

    mechanism_node --ros-args -p scene:=four_bar -p omega:=2.0          # from the venv
    ros2 run linkage_ros mechanism_node --ros-args -p scene:=four_bar    # from a colcon install

Declares the parameters of :data:`linkage_ros.parameters.PARAMETERS` with descriptors, ticks a
timer at ``rate_hz`` with t from the node clock (``use_sim_time`` works), publishes the CDR bytes
the runtime renders (``Publisher.publish(bytes)``; QoS depth 10, reliable; a topic without a
subscriber is neither published nor, on an ordinary tick, rendered — which topics have one is
read every 50 ms, :data:`SUBSCRIBERS_CHECK_NS` — while the recording gets every topic) and validates
parameter changes in a callback. Integer values for double parameters (``-p omega:=2``, or
``ros2 param set ... omega 3``) are converted to doubles, at start and at run time. Every
rejected change is logged, rclpy's own descriptor checks included; so are the start and the end
of a recording, with the file name. The recording holds the topics under their names on the
wire (``resolve_topic_name``: namespace and remaps).

Topic mode (``-p input_source:=topic``, switchable at run time): the timer stops, and every
``sensor_msgs/JointState`` on the relative topic ``input_joint_states`` (best-effort subscription,
so reliable and best-effort publishers both reach it) is answered with the same topics, under
the message's ``header.stamp`` (:meth:`Runtime.answer`); dropped and unassemblable messages are
logged as warnings, at most one of each kind a second (:class:`~linkage_ros._throttle.Throttle`),
and a dropped one gets diagnostics WARN. The subscription is raw: names, positions,
velocities and stamp are read straight off the CDR bytes
(:func:`~linkage_ros.serialize.read_joint_state`; rclpy's deserialiser for anything unusual),
without building the message object.

Dynamic mode (``-p mode:=dynamic``, issue 22): the timer ticks as in clock mode, but φ(t) comes
from the equation of motion (:mod:`linkage_ros.dynamic`), and the ticks lie on the timer's period
grid: a callback that comes more than a period late renders the periods rcl's timer skipped too,
each stamped and solved at its grid time (:mod:`linkage_ros._tick_grid`, at most 20 a callback;
not under ``use_sim_time``), and an effort command first renders the grid times already due;
the node subscribes to the relative topic ``effort_commands`` (``std_msgs/Float64MultiArray``,
one value per input; best effort, so reliable and sensor-data publishers both match; raw,
recorded as received) and hands each command to :meth:`Runtime.command_efforts`; a refused one
is logged as one warning (at most one of its kind a second).

``robot_description`` (std_msgs/String, transient local) carries the scene's URDF (``linkage-urdf``)
from the start and after every change of scene or frame_id. ``mechanism_node --help`` prints the
usage and the parameters without starting a node.

The spin loop runs rclpy's ``EventsExecutor`` (C++, ``rclpy.experimental``, in Jazzy's rclpy
7.1): at 1 kHz it takes about a third of the CPU of the ``SingleThreadedExecutor``, whose Python
wait-set and task machinery costs ≈ 240 µs per timer tick here. ``LINKAGE_ROS_EXECUTOR=single``
selects the SingleThreadedExecutor (also used where rclpy has no EventsExecutor).

SIGINT and SIGTERM end the node between two ticks: the MCAP recording is finished, the exit
status is 0. Every tick ends (a dynamic law's advance cannot crawl: solver.dynamics._guard), and
a long one (a node fallen far behind real time) ends between two steps of the law on the signal
(:data:`~linkage_ros.dynamic.INTERRUPT`), so the spin loop sees it promptly; during the start-up
(the scene, its compiled instant and the message templates being built: seconds on a loaded
machine) the signal ends the node at once, with exit status 0 and nothing to finish. This module
and :mod:`linkage_ros.echo` are the ones that import rclpy.
"""

from __future__ import annotations

import gc
import importlib
import os
import signal
import sys
import time
from collections.abc import Callable, Sequence
from types import FrameType
from typing import Any

import rclpy
import rclpy.logging
from rcl_interfaces.msg import (
    FloatingPointRange,
    ParameterDescriptor,
    ParameterType,
    SetParametersResult,
)
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from rclpy.signals import SignalHandlerOptions
from std_msgs.msg import String

from solver.errors import SolverError

from ._throttle import Throttle
from .dynamic import INTERRUPT
from .messages import TYPE_NAMES
from .parameters import PARAMETERS, SPECS, ParameterSpec, for_scene, start_scene, validate_parameter
from .runtime import Recorder, Runtime
from .serialize import read_joint_state

__all__ = [
    "MechanismNode",
    "QOS_DEPTH",
    "coerce_parameter",
    "description_qos_profile",
    "input_qos_profile",
    "main",
    "make_executor",
    "message_classes",
    "qos_profile",
]

QOS_DEPTH = 10
#: Topic mode: the incoming JointState topic (relative, so it can be remapped), its queue depth.
INPUT_TOPIC = "input_joint_states"
INPUT_QOS_DEPTH = 100
#: The scene's URDF (std_msgs/String, latched): relative, as robot_state_publisher's.
DESCRIPTION_TOPIC = "robot_description"
#: Dynamic mode: the effort command topic (relative), std_msgs/Float64MultiArray, one value per
#: input (as ros2_control's effort controllers command them); its queue depth.
EFFORT_TOPIC = "effort_commands"
EFFORT_QOS_DEPTH = 10
#: At most one warning of a kind (dropped input, unassemblable input, a refused effort command,
#: ...) per this many seconds; each kind has its own window (:class:`~linkage_ros._throttle.Throttle`).
WARNING_THROTTLE_S = 1.0
#: Longest wait of the spin loop (s): how soon a signal is acted on when no timer is due.
SPIN_TIMEOUT_S = 0.1
#: How often (ns of monotonic time, checked per tick) the node reads which of its topics have a
#: subscriber (``Publisher.get_subscription_count``, ≈ 3 µs each): a topic nobody subscribes to is
#: not published (≈ 8 µs a topic and tick at 1 kHz) and, but while recording, not rendered on an
#: ordinary tick (:meth:`Runtime.publish_only <linkage_ros.runtime.Runtime.publish_only>`).
#: A subscriber matched meanwhile gets its first message at most this long after discovery.
SUBSCRIBERS_CHECK_NS = 50_000_000
#: A new publisher (at start, a change of scene or points) is published for this long (ns)
#: whatever its subscriber count, and every publisher for this long from the run's first tick
#: (under ``use_sim_time`` the first /clock may come much later): discovery matches the
#: subscribers already there meanwhile, so they get the first messages as before (not up to
#: 50 ms later, one topic after another).
FRESH_PUBLISHER_NS = 2_000_000_000

_PARAMETER_TYPES = {
    "string": ParameterType.PARAMETER_STRING,
    "double": ParameterType.PARAMETER_DOUBLE,
    "double_array": ParameterType.PARAMETER_DOUBLE_ARRAY,
    "string_array": ParameterType.PARAMETER_STRING_ARRAY,
}


#: Array parameters declared by type (rclpy would read an empty default as a byte array).
_ARRAY_TYPES = {"double_array": Parameter.Type.DOUBLE_ARRAY, "string_array": Parameter.Type.STRING_ARRAY}


def qos_profile() -> QoSProfile:
    """Depth 10, reliable, volatile: what the recorder's offered_qos_profiles also say."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=QOS_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE,
    )


def description_qos_profile() -> QoSProfile:
    """Depth 1, reliable, transient local: ``robot_description`` is latched, as
    robot_state_publisher publishes it (a late subscriber gets the last one)."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=1,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )


def input_qos_profile(depth: int = INPUT_QOS_DEPTH) -> QoSProfile:
    """Best effort, keep last ``depth`` (100): matches reliable and best-effort publishers (a
    JointState driver; an effort controller with ``qos_profile_sensor_data``)."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.BEST_EFFORT,
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
    if spec.float_range is not None and spec.kind == "double":  # rclpy checks ranges of doubles only
        lo, hi = spec.float_range
        kwargs["floating_point_range"] = [FloatingPointRange(from_value=lo, to_value=hi, step=0.0)]
    return ParameterDescriptor(**kwargs)


def coerce_parameter(name: str, value: Any) -> Any:
    """An integer given for one of our double parameters, as a float; for a double array
    (``input_omegas``, ...) integers or an empty list of any type (rclpy reads ``[]`` as a byte
    array; ``[]`` in a params file arrives as None), as a list of floats; other values unchanged."""
    spec = SPECS.get(name)
    if spec is not None and spec.kind == "double" and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if spec is not None and spec.kind == "string_array" and spec.name != "points" and not isinstance(value, str):
        if value is None:  # `[]` in a params file arrives unset
            return []
        try:
            items = list(value)
        except TypeError:
            return value
        return [str(v) for v in items] if all(isinstance(v, str) for v in items) else value
    if spec is not None and spec.kind == "double_array" and not isinstance(value, str):
        if value is None:  # `[]` in a params file arrives unset
            return []
        try:
            items = list(value)
        except TypeError:
            return value
        if not items or all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in items):
            return [float(v) for v in items]
    return value


def mcap_recorder(where: str | Callable[[str], str]) -> Any:
    """A recorder factory for Runtime: rosbag2-profile MCAP of the published bytes under the
    names on the wire (``where``: the node's ``resolve_topic_name``, so namespace and remaps
    apply; or a namespace), with the ``linkage_ros`` scene metadata that ``linkage-view`` uses to
    name what the markers draw and to find the (possibly remapped) topics."""
    from .record.rosbag2 import absolute_topic

    resolve = where if callable(where) else (lambda name: absolute_topic(name, where))

    def factory(path: str, topics: Sequence[tuple[str, str]], *, engine: Any, frame_id: str) -> Recorder:
        from .record.mcap import Recorder as McapRecorder
        from .record.replay import METADATA_NAME, scene_metadata

        wire = {name: resolve(name) for name, _ in topics}
        return McapRecorder(path, topics, resolve=resolve,
                            metadata={METADATA_NAME: scene_metadata(engine, frame_id=frame_id, topics=wire)})

    return factory


class MechanismNode(Node):
    """Publishes the kinematics of one mechanism at ``rate_hz``.

    Raises ValueError (a reason) or :class:`solver.SolverError` for unusable start values.
    """

    def __init__(self, *, node_name: str = "mechanism_node", **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        # rclpy's parsed start values (-p, --params-file, parameter_overrides); read, not changed
        overrides: dict[str, Parameter] = dict(getattr(self, "_parameter_overrides", {}))
        values: dict[str, Any] = {}
        scene = overrides.get("scene")
        units, defaults = start_scene(None if scene is None else scene.value)  # an actuator's: m, m/s, m/s²
        for spec in (for_scene(spec, units) for spec in PARAMETERS):
            given = overrides.get(spec.name)
            value = defaults.get(spec.name, spec.default) if given is None else coerce_parameter(spec.name, given.value)
            if spec.name == "points":
                values["points"] = value
                continue
            reason = validate_parameter(spec.name, value)
            if reason:
                raise ValueError(reason)
            kind = _ARRAY_TYPES.get(spec.kind) if spec.name != "points" else None
            if kind is not None:  # declared by type: rclpy reads an empty list as bytes
                self.declare_parameter(spec.name, kind, descriptor(spec), ignore_override=True)
                self.set_parameters([Parameter(spec.name, kind, list(value))])
            else:
                self.declare_parameter(spec.name, value, descriptor(spec), ignore_override=True)
            values[spec.name] = self.get_parameter(spec.name).value
        self.runtime = Runtime(values, recorder_factory=mcap_recorder(self.resolve_topic_name))
        self._recording: Any = None
        self._log_recording()
        # A non-empty default makes the type a string array ([""] when the scene has no outputs:
        # rclpy would read an empty list as a byte array).
        points = list(self.runtime.settings["points"]) or [""]
        self.declare_parameter("points", points, descriptor(SPECS["points"]), ignore_override=True)
        self._qos_profile = qos_profile()
        self._topic_publishers: dict[str, Any] = {}
        #: topic → its publisher's bound ``publish`` (one look-up per message and tick), or
        #: :func:`_unread` while nobody subscribes to it (:meth:`_check_subscribers`)
        self._publish: dict[str, Callable[[Any], None]] = {}
        self._next_check_ns = 0
        #: topic → until when (monotonic ns) its new publisher is published whatever its count
        #: (armed again at the run's first tick: the time before a first /clock does not count)
        self._fresh: dict[str, int] = {}
        self._first_tick = True
        self._sync_publishers()
        self._description_publisher = self.create_publisher(String, DESCRIPTION_TOPIC, description_qos_profile())
        self._description: str | None = None
        self._described_recorder: Any = None
        #: the node clock's handle (ROS time: the system's, or /clock under use_sim_time), read
        #: per tick without a Time object (``_now_ns``: 1.2 µs against 2.5 for ``now().nanoseconds``)
        self._node_clock: Any = self.get_clock()  # a ROSClock (Node's own attribute is _clock: not assigned here)
        self._clock_handle = self._node_clock.handle
        self._publish_description()
        self._tick_timer = self.create_timer(self.runtime.period_s, self._on_timer)
        self._input_subscription: Any = None
        self._input_type: Any = None
        self._effort_subscription: Any = None
        self._effort_type: Any = None
        self._sync_input()
        self._pending_parameters: list[Parameter] = []
        self._throttle = Throttle(WARNING_THROTTLE_S)
        self.add_pre_set_parameters_callback(self._coerce_parameters)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        where = (f"answering {self.resolve_topic_name(INPUT_TOPIC)}" if self.runtime.topic_mode
                 else f"at {self.runtime.settings['rate_hz']:g} Hz")
        if self._effort_subscription is not None:
            where += (f", dynamic mode (drive {self.runtime.engine.motion.kind}; effort commands on "  # type: ignore[union-attr]
                      f"{self.resolve_topic_name(EFFORT_TOPIC)})")
        self.get_logger().info(
            f"scene {self.runtime.engine.scene.name}: publishing {len(self._topic_publishers)} topics {where}"
        )

    # ------------------------------------------------------------------ callbacks
    def _now_ns(self) -> int:
        """The node clock's time in ns: ``get_clock().now().nanoseconds``, without the Time object."""
        with self._clock_handle:
            return int(self._clock_handle.get_now().nanoseconds)

    def _on_timer(self) -> None:
        handle = self._clock_handle  # _now_ns, without its call: this runs rate_hz times a second
        with handle:
            now_ns = handle.get_now().nanoseconds
        grid = self.runtime.grid
        if grid is None or self._node_clock.ros_time_is_active:
            self._tick(now_ns)
        else:  # dynamic mode: every period of the timer's grid, those rcl skipped too (_tick_grid)
            until = self._tick_timer.time_until_next_call()
            with handle:
                read_ns = handle.get_now().nanoseconds
            for stamp in grid.due(now_ns, grid.next_due(now_ns, until, read_ns)):
                self._tick(stamp)
        if self._pending_parameters:
            pending, self._pending_parameters = self._pending_parameters, []
            self.set_parameters(pending)

    def _tick(self, now_ns: int) -> None:
        """One tick at clock time ``now_ns``: solved, rendered and published."""
        runtime = self.runtime
        if time.monotonic_ns() >= self._next_check_ns:
            self._check_subscribers()
        messages = runtime.tick(now_ns)
        if self._first_tick and messages:  # the run's first tick (under use_sim_time: the first /clock)
            self._first_tick = False
            self._freshen()
        publish = self._publish
        for topic, data in messages:
            publish[topic](data)
        if runtime.events:
            for event in runtime.take_events():
                self.get_logger().warning(event)

    def _on_input(self, data: bytes) -> None:
        """A JointState's CDR bytes (raw subscription): read off the bytes
        (:func:`~linkage_ros.serialize.read_joint_state`), else deserialised the ordinary way."""
        fields = read_joint_state(data)
        if fields is None:
            try:
                message = deserialize_message(data, self._input_type)
            except (RuntimeError, ValueError) as error:  # rclpy's RCLError is a RuntimeError
                self._warn(f"JointState dropped: cannot deserialise it ({error})")
                return
            stamp = message.header.stamp
            fields = (message.name, message.position, message.velocity, stamp.sec * 1_000_000_000 + stamp.nanosec)
        runtime = self.runtime
        if runtime.recorder is not None:
            runtime.record_input(INPUT_TOPIC, fields[3], data)
        if time.monotonic_ns() >= self._next_check_ns:
            self._check_subscribers()
        publish = self._publish
        for topic, payload in runtime.answer(*fields):
            publish[topic](payload)
        if runtime.input_warnings:
            for warning in runtime.take_input_warnings():
                self._warn(warning)

    def _on_effort_command(self, data: bytes) -> None:
        """Dynamic mode: an effort command's CDR bytes (raw subscription: recorded as received);
        a refused one is logged (one line, at most one of its kind a second) and the last good
        command stays in force."""
        now_ns = self._now_ns()
        grid = self.runtime.grid
        if grid is not None and not self._node_clock.ros_time_is_active:
            for stamp in grid.due(now_ns):  # the periods due before it (a late timer's) without it
                self._tick(stamp)
        self.runtime.record_input(EFFORT_TOPIC, now_ns, data)
        try:
            values = deserialize_message(data, self._effort_type).data
        except (RuntimeError, ValueError) as error:  # rclpy's RCLError is a RuntimeError
            self._warn(f"effort command dropped: cannot deserialise it ({error})")
            return
        reason = self.runtime.command_efforts(values, now_ns)
        if reason is not None:
            self._warn(reason)

    def _coerce_parameters(self, parameters: list[Parameter]) -> list[Parameter]:
        out = []
        for p in parameters:
            value = coerce_parameter(p.name, p.value)
            spec = SPECS.get(p.name)
            kind = (_ARRAY_TYPES.get(spec.kind, Parameter.Type.DOUBLE) if spec is not None and isinstance(value, list)
                    else Parameter.Type.DOUBLE)
            out.append(p if value is p.value else Parameter(p.name, kind, value))
        return out

    def _on_set_parameters(self, parameters: Sequence[Any]) -> SetParametersResult:
        changes = {p.name: p.value for p in parameters}
        old_rate = self.runtime.settings["rate_hz"]
        old_points = list(self.runtime.settings["points"])
        reason = self.runtime.update(changes, self._now_ns())
        if reason is not None:
            return SetParametersResult(successful=False, reason=reason)
        self._log_recording()
        self._sync_publishers()
        self._publish_description()
        if "scene" in changes:
            self.get_logger().info(
                f"scene {self.runtime.engine.scene.name}: publishing {len(self._topic_publishers)} topics"
            )
        if self.runtime.settings["rate_hz"] != old_rate:
            self.destroy_timer(self._tick_timer)
            self._tick_timer = self.create_timer(self.runtime.period_s, self._on_timer)
        self._sync_input()
        points = list(self.runtime.settings["points"])
        if "points" not in changes and points != old_points:
            # The points followed a change of scene: show it in the parameter (next tick).
            self._pending_parameters.append(Parameter("points", value=points))
        return SetParametersResult(successful=True, reason="")

    def set_parameters_atomically(self, parameter_list: list[Parameter]) -> SetParametersResult:
        """rclpy's, with every rejection logged: ours (:meth:`_on_set_parameters`) and rclpy's
        own checks of the descriptors (type, range), which return before any callback. The
        parameter services call this method."""
        try:
            result = super().set_parameters_atomically(parameter_list)
        except ParameterException as error:  # e.g. an undeclared parameter
            self.get_logger().warning(f"parameter change rejected: {error}")
            raise
        if not result.successful:
            names = ", ".join(p.name for p in parameter_list)
            self.get_logger().warning(f"parameter change rejected ({names}): {result.reason}")
        return result

    # ------------------------------------------------------------------ helpers
    def _warn(self, text: str) -> None:
        """One warning, at most one of its kind (:func:`~linkage_ros._throttle.warning_kind`) per
        :data:`WARNING_THROTTLE_S` seconds: a flood of one kind does not hide another."""
        if self._throttle.allow(text, time.monotonic()):
            self.get_logger().warning(text)

    def _publish_description(self) -> None:
        """The scene's URDF on the latched ``robot_description`` (std_msgs/String, transient
        local): at start and whenever the scene or frame_id changes (RViz's RobotModel display
        reads it; with /tf from robot_state_publisher, or the node's own where tf2_msgs exists)."""
        runtime = self.runtime
        text = runtime.robot_description()
        if text is None:
            return
        if text != self._description:
            self._description = text
            self._description_publisher.publish(String(data=text))
        elif runtime.recorder is self._described_recorder:
            return
        self._described_recorder = runtime.recorder  # a new recording gets the description too
        runtime.record_description(self._now_ns())

    def _log_recording(self) -> None:
        """Log where the recording starts and that the previous one is finished."""
        recorder = self.runtime.recorder
        if recorder is self._recording:
            return
        if self._recording is not None:
            self._log_finished(self._recording)
        if recorder is not None:
            self.get_logger().info(f"recording to {getattr(recorder, 'path', '?')}")
        self._recording = recorder

    def _log_finished(self, recorder: Any) -> None:
        count = getattr(recorder, "message_count", None)
        messages = f" ({count} messages)" if count is not None else ""
        self.get_logger().info(f"recording finished: {getattr(recorder, 'path', '?')}{messages}")

    def _sync_publishers(self) -> None:
        wanted = dict(self.runtime.topics)
        classes = message_classes(sorted(set(wanted.values())))
        for topic in [t for t in self._topic_publishers if t not in wanted]:
            self.destroy_publisher(self._topic_publishers.pop(topic))
        now = time.monotonic_ns()
        for topic, typename in wanted.items():
            if topic not in self._topic_publishers:
                self._topic_publishers[topic] = self.create_publisher(
                    classes[typename], topic, self._qos_profile
                )
                self._fresh[topic] = now + FRESH_PUBLISHER_NS
        self._check_subscribers()

    def _freshen(self) -> None:
        """Every topic published for FRESH_PUBLISHER_NS from now on, whatever its count."""
        until = time.monotonic_ns() + FRESH_PUBLISHER_NS
        self._fresh = dict.fromkeys(self._topic_publishers, until)
        self._check_subscribers()

    def _check_subscribers(self) -> None:
        """Publish (from the next tick on) the topics with a subscriber; drop the rest unsent."""
        now = time.monotonic_ns()
        self._next_check_ns = now + SUBSCRIBERS_CHECK_NS
        if self._fresh:  # a new publisher's subscribers are still being discovered: published meanwhile
            self._fresh = {topic: until for topic, until in self._fresh.items() if until > now}
        read = {topic for topic, publisher in self._topic_publishers.items()
                if topic in self._fresh or publisher.get_subscription_count()}
        self._publish = {topic: publisher.publish if topic in read else _unread
                         for topic, publisher in self._topic_publishers.items()}
        self.runtime.publish_only(read)  # an ordinary tick renders those only (every topic while recording)

    def _sync_input(self) -> None:
        """Topic mode: the input subscription, no timer; clock mode: the timer, no subscription."""
        if self.runtime.topic_mode:
            self._tick_timer.cancel()
            if self._input_subscription is None:
                from sensor_msgs.msg import JointState

                self._input_type = JointState
                self._input_subscription = self.create_subscription(
                    JointState, INPUT_TOPIC, self._on_input, input_qos_profile(), raw=True
                )
        else:
            if self._input_subscription is not None:
                self.destroy_subscription(self._input_subscription)
                self._input_subscription = None
            if self._tick_timer.is_canceled():
                self._tick_timer.reset()
        dynamic = self.runtime.settings.get("mode") == "dynamic"
        if dynamic and self._effort_subscription is None:
            from std_msgs.msg import Float64MultiArray

            self._effort_type = Float64MultiArray
            self._effort_subscription = self.create_subscription(
                Float64MultiArray, EFFORT_TOPIC, self._on_effort_command, input_qos_profile(EFFORT_QOS_DEPTH),
                raw=True)
        elif not dynamic and self._effort_subscription is not None:
            self.destroy_subscription(self._effort_subscription)
            self._effort_subscription = None

    def destroy_node(self) -> None:
        recorder = self.runtime.recorder
        self.runtime.close()
        if recorder is not None:
            self._log_finished(recorder)
        super().destroy_node()


#: Environment variable that chooses the executor: ``events`` (default) or ``single``.
EXECUTOR_ENV = "LINKAGE_ROS_EXECUTOR"
EXECUTORS = ("events", "single")


def _unread(data: Any) -> None:
    """What a tick's message on a topic without subscribers is handed to: nothing."""


def make_executor(kind: str | None = None) -> Any:
    """The spin loop's executor: ``"events"`` (rclpy's EventsExecutor; the SingleThreadedExecutor
    where rclpy has none) or ``"single"``; default from :data:`EXECUTOR_ENV`. ValueError for
    anything else."""
    kind = kind if kind is not None else os.environ.get(EXECUTOR_ENV, "events") or "events"
    if kind not in EXECUTORS:
        raise ValueError(f"{EXECUTOR_ENV} must be one of {', '.join(EXECUTORS)}, got {kind!r}")
    if kind == "events":
        try:
            from rclpy.experimental import EventsExecutor
        except ImportError:  # rclpy before 7.1
            return SingleThreadedExecutor()
        return EventsExecutor()
    return SingleThreadedExecutor()


class _StopRequest:
    """SIGINT / SIGTERM handler: asks the spin loop to stop after the current tick; before the
    loop spins (the start-up), stops at once (KeyboardInterrupt, caught by ``_run``)."""

    def __init__(self) -> None:
        self.requested = False
        self.spinning = False

    def __call__(self, signum: int, frame: FrameType | None) -> None:
        self.requested = True
        INTERRUPT.set()  # a dynamic law's advance in progress ends between two steps
        if not self.spinning:
            raise KeyboardInterrupt


def usage() -> str:
    """What ``mechanism_node --help`` prints: how to start it, its topics and its parameters."""
    lines = [
        "usage: mechanism_node [-h] [--ros-args -p NAME:=VALUE ... [--params-file FILE] [-r FROM:=TO ...]]",
        "",
        "Publishes the exact kinematics (and forces, dynamics) of one linkage scene over ROS 2:",
        "joint_states, joint_kinematics, points/<P>/..., pin_loads/..., markers, diagnostics, tf,",
        "robot_description (docs/ros.md). Topic mode answers input_joint_states; dynamic mode",
        "takes effort_commands. SIGINT / SIGTERM end it between two ticks (exit status 0).",
        "",
        "parameters (-p NAME:=VALUE; all can be set at run time):",
    ]
    for spec in PARAMETERS:
        default = "the scene's outputs" if spec.default is None else repr(spec.default)
        lines.append(f"  {spec.name:<20} {spec.kind:<12} default {default}")
        lines.append(f"      {spec.description}")
    lines += ["", "e.g.  mechanism_node --ros-args -p scene:=four_bar -p omega:=2.0 -p rate_hz:=100.0"]
    return "\n".join(lines) + "\n"


def main(args: Sequence[str] | None = None) -> int:
    """Entry point of ``mechanism_node``: 0 after SIGINT / SIGTERM (the recording finished), 1
    with one ``cannot start: ...`` line when the start values are unusable; ``-h`` / ``--help``
    (before ``--ros-args``) prints :func:`usage` and returns 0 without starting a node."""
    argv = list(sys.argv[1:] if args is None else args)
    ours = argv[:argv.index("--ros-args")] if "--ros-args" in argv else argv
    if "-h" in ours or "--help" in ours:
        sys.stdout.write(usage())
        return 0
    stop = _StopRequest()
    previous = {sig: signal.signal(sig, stop) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        try:
            rclpy.init(args=None if args is None else list(args),
                       signal_handler_options=SignalHandlerOptions.NO)
        except RuntimeError as error:  # rclpy's RCLError: unparsable --ros-args
            rclpy.logging.get_logger("mechanism_node").error(f"cannot start: {error}")
            return 1
        try:
            return _run(stop)
        finally:
            rclpy.try_shutdown()
    except KeyboardInterrupt:  # SIGINT / SIGTERM during the start-up, outside _run
        return 0
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _run(stop: _StopRequest) -> int:
    try:
        executor = make_executor()
        node = MechanismNode()
    except (SolverError, ValueError, ParameterException) as error:
        rclpy.logging.get_logger("mechanism_node").error(f"cannot start: {error}")
        return 1
    except KeyboardInterrupt:  # SIGINT / SIGTERM during the start-up
        return 0
    # the scene, plan, typestore and templates live as long as the node: move them out of the
    # collector's way, so its passes at 1 kHz only see the tick's own objects
    gc.collect()
    gc.freeze()
    executor.add_node(node)
    stop.spinning = True
    try:
        while not stop.requested and executor.context.ok():
            executor.spin_once(timeout_sec=SPIN_TIMEOUT_S)
    except ExternalShutdownException:
        pass
    finally:
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
