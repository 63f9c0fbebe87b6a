"""One message builder for the live node and the recorders.

The message classes come in as an argument: rosbags' typestore (``get_typestore(...).types``)
or rclpy's generated classes (``{"sensor_msgs/msg/JointState": JointState, ...}``). The two
differ in what they accept for primitive sequences (rosbags wants float64 numpy arrays, rclpy
``array.array('d')`` or lists of Python floats) and in nothing else this builder uses;
:class:`MessageTypes` hides the difference.

The topics (relative names) and their types are in :mod:`.topics` (re-exported here). All
messages of one frame carry the same header (stamp and frame_id). Planar scenes have z = 0.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from .engine import Engine
from .frame import STATUS_BEHIND, STATUS_INPUT_DROPPED, STATUS_NEAR_SINGULAR, STATUS_OK, Frame
from .load_messages import LoadMessages, tree_effort_joints
from .msgtypes import TYPE_NAMES, MessageTypes
from .topics import (
    DIAGNOSTICS,
    EFFORT_COMMANDS,
    ENERGIES,
    ENERGY_LABELS,
    FIXED_TOPIC_TYPES,
    FRICTION_POWER,
    FRICTION_POWER_TYPE,
    INPUT_JOINT_STATES,
    INPUT_TYPES,
    JOINT_KINEMATICS,
    JOINT_STATES,
    LOAD_LABELS_NAMESPACE,
    LOADS_NAMESPACE,
    MARKER_NAMESPACES,
    MARKERS,
    NS_PER_S,
    ROBOT_DESCRIPTION,
    WRENCH_STAMPED,
    load_topic_types,
    point_topics,
    stamp_parts,
    topic_types,
)
from .urdf import TreeJointStates, exportable_model, frame_tree_joint_states

__all__ = [
    "DIAGNOSTICS",
    "EFFORT_COMMANDS",
    "ENERGIES",
    "ENERGY_LABELS",
    "FIXED_TOPIC_TYPES",
    "FRICTION_POWER",
    "FRICTION_POWER_TYPE",
    "INPUT_JOINT_STATES",
    "INPUT_TYPES",
    "JOINT_KINEMATICS",
    "JOINT_STATES",
    "LOADS_NAMESPACE",
    "LOAD_LABELS_NAMESPACE",
    "MARKERS",
    "MARKER_NAMESPACES",
    "NS_PER_S",
    "PATH_PERIOD",
    "ROBOT_DESCRIPTION",
    "TYPE_NAMES",
    "WRENCH_STAMPED",
    "MessageBuilder",
    "MessageTypes",
    "build_messages",
    "load_topic_types",
    "point_topics",
    "stamp_parts",
    "topic_types",
]

#: Seconds of frame time between two markers messages that carry the paths (0: every one).
PATH_PERIOD = 1.0

# Colours (r, g, b, a).
_LINK_COLOUR = (0.20, 0.45, 0.85, 1.0)
_JOINT_COLOUR = (0.95, 0.60, 0.10, 1.0)
_FIXED_COLOUR = (0.55, 0.10, 0.10, 1.0)
_PATH_COLOURS = (
    (0.20, 0.70, 0.30, 0.9),
    (0.80, 0.20, 0.60, 0.9),
    (0.10, 0.65, 0.75, 0.9),
    (0.55, 0.45, 0.10, 0.9),
)


class MessageBuilder:
    """Builds the messages of one frame for ``engine``'s scene.

    The path markers (constant) are built once; they are sent on the first frame and then at
    most every ``path_period`` seconds of frame time (RViz and Foxglove keep markers of lifetime
    0 until replaced), which keeps the markers message small at high rates. ``path_period=0``
    sends them with every frame.
    """

    def __init__(
        self,
        engine: Engine,
        types: Mapping[str, Any] | MessageTypes,
        *,
        frame_id: str = "world",
        path_period: float = PATH_PERIOD,
        diagnostic_name: str | None = None,
        omit_joints: Iterable[str] = (),
    ) -> None:
        if not isinstance(types, MessageTypes):
            types = MessageTypes(types)
        if not (math.isfinite(path_period) and path_period >= 0.0):
            raise ValueError(f"path_period must be a finite number >= 0, got {path_period!r}")
        self.engine = engine
        self.types = types
        self.frame_id = str(frame_id)
        self.path_period = float(path_period)
        scene = engine.scene
        self.diagnostic_name = diagnostic_name or f"linkage_ros: {scene.name}"
        self.topics = topic_types(engine)
        self._point_topics = [(p, point_topics(p)) for p in engine.published_points]
        self._fixed = {name: np.asarray(v, dtype=np.float64) for name, v in scene.fixed_points.items()}
        self._moving = tuple(p for p in engine.point_names if p not in self._fixed)
        self._segments = [
            (a, b) for link in scene.links for a, b in zip(tuple(link.points)[:-1], tuple(link.points)[1:])
        ]
        size = _characteristic_length(engine, self._fixed)
        self.line_width = size / 150.0
        self.joint_diameter = size / 40.0
        self._last_paths_t: float | None = None
        c = types.classes
        self._Time = c["builtin_interfaces/msg/Time"]
        self._Duration = c["builtin_interfaces/msg/Duration"]
        self._Header = c["std_msgs/msg/Header"]
        self._Point = c["geometry_msgs/msg/Point"]
        self._Vector3 = c["geometry_msgs/msg/Vector3"]
        self._PointStamped = c["geometry_msgs/msg/PointStamped"]
        self._Vector3Stamped = c["geometry_msgs/msg/Vector3Stamped"]
        self._JointState = c["sensor_msgs/msg/JointState"]
        self._JointTrajectory = c["trajectory_msgs/msg/JointTrajectory"]
        self._JointTrajectoryPoint = c["trajectory_msgs/msg/JointTrajectoryPoint"]
        self._Marker = c["visualization_msgs/msg/Marker"]
        self._MarkerArray = c["visualization_msgs/msg/MarkerArray"]
        self._DiagnosticArray = c["diagnostic_msgs/msg/DiagnosticArray"]
        self._DiagnosticStatus = c["diagnostic_msgs/msg/DiagnosticStatus"]
        self._KeyValue = c["diagnostic_msgs/msg/KeyValue"]
        self._path_points = [[self._point(xyz) for xyz in engine.paths[p]] for p in engine.published_points]
        self._fixed_point_by_name = {name: self._point(v) for name, v in self._fixed.items()}
        self._fixed_points = list(self._fixed_point_by_name.values())
        self._joint_names = tuple(engine.joint_names)
        self._inputs = tuple(getattr(engine, "inputs", ()) or (scene.input_joint,))
        # joints left out of joint_states (topic mode: the driver publishes the input joint)
        self.omit_joints = frozenset(omit_joints)
        #: ``() -> [(key, text)]``: KeyValues added to every diagnostics status after the frame's
        #: own (the runtime's dynamic mode: the drive state); None: none
        self.diagnostic_values: Callable[[], Sequence[tuple[str, str]]] | None = None
        # the URDF tree's joints (linkage-urdf) ride along on joint_states, so that
        # robot_state_publisher moves the closed chain; None for scenes without a URDF export
        self._tree = exportable_model(scene)
        self._zero_duration = self._Duration(sec=0, nanosec=0)
        self._empty = types.float64s(())
        self._styles()
        #: The force messages (None: the scene has no forces, and no message changes).
        self.loads = LoadMessages(self, size=size, tree_joints=tree_effort_joints(self._tree, self._inputs)
                                  ) if getattr(engine, "forces", False) else None
        #: The ``friction_power`` entries (:func:`linkage_ros.forces.friction_names`; empty: no topic).
        self.friction_names: tuple[str, ...] = tuple(getattr(engine, "friction_names", ()))
        if self.friction_names:
            n = len(self.friction_names)
            dim = c["std_msgs/msg/MultiArrayDimension"](label="W: " + " ".join(self.friction_names), size=n, stride=n)
            self._friction_layout = c["std_msgs/msg/MultiArrayLayout"](dim=[dim], data_offset=0)
            self._Float64MultiArray = c[FRICTION_POWER_TYPE]

    # ------------------------------------------------------------------ public
    def build(self, frame: Frame, stamp: int, *, include_paths: bool | None = None) -> list[tuple[str, Any]]:
        """``[(topic, message)]`` of ``frame``, stamped ``stamp`` (integer ns), in the order of
        :attr:`topics`.

        ``include_paths``: whether the markers carry the paths; default: the periodic rule
        (:meth:`wants_paths`). Messages of one call may share sub-messages (the header, a point):
        treat them as read-only.
        """
        return self.build_topics(frame, stamp, None, include_paths=include_paths)

    def build_topics(
        self,
        frame: Frame,
        stamp: int,
        topics: Iterable[str] | None,
        *,
        include_paths: bool | None = False,
        tree: TreeJointStates | None = None,
        load_tips: Sequence[float] | None = None,
    ) -> list[tuple[str, Any]]:
        """Like :meth:`build`, for the topics in ``topics`` only (None: all). The path timing of
        the markers changes only when they are built with the paths. ``tree``: the URDF tree's
        joint states to put on ``joint_states`` (default: :meth:`tree_states` of ``frame``; the
        byte templates of :mod:`linkage_ros.serialize` pass sentinels); ``load_tips`` likewise
        for the tips of the load arrows (default: :meth:`load_tips` of ``frame``)."""
        wanted = None if topics is None else set(topics)
        sec, nanosec = stamp_parts(stamp)
        header = self._Header(stamp=self._Time(sec=sec, nanosec=nanosec), frame_id=self.frame_id)
        tick = _Tick(self, frame)
        out: list[tuple[str, Any]] = []
        if wanted is None or JOINT_STATES in wanted or JOINT_KINEMATICS in wanted:
            js, jk = self._joints(frame, header, tree)
            if wanted is None or JOINT_STATES in wanted:
                out.append((JOINT_STATES, js))
            if wanted is None or JOINT_KINEMATICS in wanted:
                out.append((JOINT_KINEMATICS, jk))
        for name, (pos, vel, acc) in self._point_topics:
            if wanted is not None and not {pos, vel, acc} & wanted:
                continue
            ps = frame.points[name]
            if wanted is None or pos in wanted:
                out.append((pos, self._PointStamped(header=header, point=tick.point(name))))
            if wanted is None or vel in wanted:
                out.append((vel, self._Vector3Stamped(header=header, vector=self._vector(ps.velocity))))
            if wanted is None or acc in wanted:
                out.append((acc, self._Vector3Stamped(header=header, vector=self._vector(ps.acceleration))))
        if self.loads is not None:
            out += self.loads.wrenches(frame, header, wanted)
        if self.friction_names and (wanted is None or FRICTION_POWER in wanted):
            out.append((FRICTION_POWER, self.friction_power(frame)))
        if wanted is None or MARKERS in wanted:
            if include_paths is None:
                include_paths = self.wants_paths(frame.t)
            out.append((MARKERS, self._markers(tick, header, include_paths, load_tips)))
        if wanted is None or DIAGNOSTICS in wanted:
            out.append((DIAGNOSTICS, self._diagnostics(frame, header)))
        return out

    def wants_paths(self, t: float) -> bool:
        """Whether the markers of a frame at ``t`` carry the paths (first frame, then periodic)."""
        last = self._last_paths_t
        return last is None or t < last or t - last >= self.path_period

    # ------------------------------------------------------------------ pieces
    def _point(self, xyz: Any) -> Any:
        c = _floats(xyz)
        return self._Point(x=c[0], y=c[1], z=c[2] if len(c) > 2 else 0.0)

    def _vector(self, xyz: Any) -> Any:
        c = _floats(xyz)
        return self._Vector3(x=c[0], y=c[1], z=c[2] if len(c) > 2 else 0.0)

    @property
    def tree_joint_names(self) -> tuple[str, ...]:
        """Names of the URDF tree's joints on ``joint_states`` (empty without a URDF export)."""
        return () if self._tree is None else tuple(self._tree.joint_names)

    def tree_states(self, frame: Frame) -> TreeJointStates | None:
        """The URDF tree's joint states that ride along on ``joint_states`` (None: the scene has
        no URDF export)."""
        return None if self._tree is None else frame_tree_joint_states(self._tree, frame)

    def _joints(self, frame: Frame, header: Any, tree: TreeJointStates | None = None) -> tuple[Any, Any]:
        """joint_states and joint_kinematics (they share the position and velocity arrays)."""
        joints = [frame.joints[n] for n in self._joint_names]
        positions, velocities, accelerations = self.types.float64_rows(
            [
                [j.position for j in joints],
                [j.velocity for j in joints],
                [j.acceleration for j in joints],
            ]
        )
        names = list(self._joint_names)
        loads = self.loads
        if self._tree is None and not self.omit_joints:
            effort = self._empty if loads is None else loads.efforts(frame, names)
            state = self._JointState(
                header=header, name=names, position=positions, velocity=velocities, effort=effort
            )
        else:
            if tree is None:
                tree = self.tree_states(frame)
            all_names = [*names, *(tree.names if tree else ())]
            all_q = [*(j.position for j in joints), *(tree.position if tree else ())]
            all_dq = [*(j.velocity for j in joints), *(tree.velocity if tree else ())]
            if self.omit_joints:
                keep = [n not in self.omit_joints for n in all_names]
                all_names, all_q, all_dq = ([v for v, k in zip(row, keep) if k] for row in (all_names, all_q, all_dq))
            tree_q, tree_dq = self.types.float64_rows([all_q, all_dq])
            effort = self._empty if loads is None else loads.efforts(frame, all_names)
            state = self._JointState(
                header=header, name=all_names, position=tree_q, velocity=tree_dq, effort=effort
            )
        point = self._JointTrajectoryPoint(
            positions=positions,
            velocities=velocities,
            accelerations=accelerations,
            effort=self._empty if loads is None else loads.efforts(frame, names),
            time_from_start=self._zero_duration,
        )
        return state, self._JointTrajectory(header=header, joint_names=names, points=[point])

    def _marker_style(
        self, ns: str, marker_id: int, kind: int, colour: tuple[float, float, float, float], scale: float
    ) -> dict[str, Any]:
        """Every field of a marker but its header and points (shared by all frames; never mutated)."""
        c = self.types.classes
        r, g, b, a = colour
        return {
            "ns": ns,
            "id": marker_id,
            "type": kind,
            "action": self._Marker.ADD,
            "pose": c["geometry_msgs/msg/Pose"](
                position=self._Point(x=0.0, y=0.0, z=0.0),
                orientation=c["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
            ),
            "scale": self._Vector3(x=scale, y=scale, z=scale),
            "color": c["std_msgs/msg/ColorRGBA"](r=r, g=g, b=b, a=a),
            "lifetime": self._zero_duration,
            "frame_locked": False,
            "colors": [],
            "texture_resource": "",
            "texture": c["sensor_msgs/msg/CompressedImage"](
                header=self._Header(stamp=self._Time(sec=0, nanosec=0), frame_id=""),
                format="",
                data=self.types.uint8s(),
            ),
            "uv_coordinates": [],
            "text": "",
            "mesh_resource": "",
            "mesh_file": c["visualization_msgs/msg/MeshFile"](filename="", data=self.types.uint8s()),
            "mesh_use_embedded_materials": False,
        }

    def _styles(self) -> None:
        M = self._Marker
        w, d = self.line_width, self.joint_diameter
        self._link_style = self._marker_style("links", 0, M.LINE_LIST, _LINK_COLOUR, w)
        self._joint_style = self._marker_style("joints", 0, M.SPHERE_LIST, _JOINT_COLOUR, d)
        self._fixed_style = self._marker_style("fixed_pivots", 0, M.CUBE_LIST, _FIXED_COLOUR, 1.5 * d)
        self._path_styles = [
            self._marker_style("paths", i, M.LINE_STRIP, _PATH_COLOURS[i % len(_PATH_COLOURS)], 0.5 * w)
            for i in range(len(self._path_points))
        ]

    def load_tips(self, frame: Frame) -> tuple[float, ...]:
        """(x, y) of the tip of each load arrow in the markers, flat (derived from the frame's
        points and loads, as :meth:`tree_states` are; empty without forces)."""
        return () if self.loads is None else self.loads.tips(frame)

    def _markers(self, tick: _Tick, header: Any, include_paths: bool,
                 load_tips: Sequence[float] | None = None) -> Any:
        M = self._Marker
        point = tick.point
        link_points = []
        for a, b in self._segments:
            link_points.append(point(a))
            link_points.append(point(b))
        joint_points = [point(n) for n in self._moving]
        markers = [
            M(header=header, points=link_points, **self._link_style),
            M(header=header, points=joint_points, **self._joint_style),
            M(header=header, points=self._fixed_points, **self._fixed_style),
        ]
        if self.loads is not None:
            markers += self.loads.arrows(tick, header, load_tips)
        if include_paths:
            self._last_paths_t = tick.frame.t
            for points, style in zip(self._path_points, self._path_styles):
                markers.append(M(header=header, points=points, **style))
        return self._MarkerArray(markers=markers)

    def friction_power(self, frame: Frame) -> Any:
        """The ``friction_power`` message of ``frame`` (scenes with friction): the power friction
        dissipates, W, in the order of :attr:`friction_names` (NaN for a frame without it)."""
        friction = frame.friction
        values = [friction.get(name, math.nan) for name in self.friction_names]
        return self._Float64MultiArray(layout=self._friction_layout, data=self.types.float64s(values))

    def energies(self, values: Sequence[float]) -> Any:
        """The ``energies`` row of a dynamic-mode tick (:mod:`linkage_ros._runtime_dynamic`): a
        ``std_msgs/Float64MultiArray`` whose one dimension's label names the entries."""
        c = self.types.classes
        dim = c["std_msgs/msg/MultiArrayDimension"](label="J: " + " ".join(ENERGY_LABELS), size=len(values),
                                                      stride=len(values))
        layout = c["std_msgs/msg/MultiArrayLayout"](dim=[dim], data_offset=0)
        return c["std_msgs/msg/Float64MultiArray"](layout=layout, data=self.types.float64s(values))

    def _diagnostics(self, frame: Frame, header: Any) -> Any:
        S = self._DiagnosticStatus
        if frame.status == STATUS_OK:
            level, text = S.OK, "ok"
        elif frame.status == STATUS_NEAR_SINGULAR:
            level, text = S.WARN, frame.message or "near singular"
        elif frame.status == STATUS_BEHIND:
            level, text = S.WARN, frame.message or "falls behind real time"
        elif frame.status == STATUS_INPUT_DROPPED:
            level, text = S.WARN, frame.message or "input message dropped"
        else:
            level, text = S.ERROR, frame.message or "cannot be assembled"
        KV = self._KeyValue
        values = [KV(key="status", value=frame.status), KV(key="t", value=f"{frame.t:.9f}")]
        for key, row in (("phi", frame.phi), ("omega", frame.omega), ("epsilon", frame.epsilon)):
            if isinstance(row, tuple):  # several inputs: phi/<input>, omega/<input>, epsilon/<input>
                values += [KV(key=f"{key}/{name}", value=repr(v)) for name, v in zip(self._inputs, row)]
            else:
                values.append(KV(key=key, value=repr(row)))
        values.append(KV(key="conditioning", value=f"{frame.conditioning:.6g}"))
        # a dynamic law's run time per second of computing its ticks (< 1: it cannot keep up)
        factor = getattr(self.engine.motion, "realtime_factor", None)
        if factor is not None:
            values.append(KV(key="compute_factor", value=f"{factor:.3g}"))
            # and the share of the rate_hz ticks it was asked for over that window (the node's own count)
            share = getattr(self.engine.motion, "tick_share", math.nan)
            values.append(KV(key="tick_share", value=f"{share:.4f}"))
        if self.diagnostic_values is not None:  # e.g. the dynamic mode's drive state (runtime)
            values += [KV(key=key, value=value) for key, value in self.diagnostic_values()]
        status = S(
            level=level,
            name=self.diagnostic_name,
            message=text,
            hardware_id=str(self.engine.scene.name),
            values=values,
        )
        return self._DiagnosticArray(header=header, status=[status])


class _Tick:
    """One Point message per point per frame, shared by the messages that draw it."""

    __slots__ = ("builder", "frame", "points")

    def __init__(self, builder: MessageBuilder, frame: Frame) -> None:
        self.builder = builder
        self.frame = frame
        self.points: dict[str, Any] = {}

    def point(self, name: str) -> Any:
        found = self.points.get(name)
        if found is None:
            b = self.builder
            if name in b._fixed_point_by_name:
                found = b._fixed_point_by_name[name]
            else:
                found = b._point(self.frame.points[name].position)
            self.points[name] = found
        return found


def _floats(xyz: Any) -> Sequence[float]:
    """Python floats of a point: tuples from the per-tick path pass as they are."""
    if type(xyz) is tuple:
        return xyz
    return xyz.tolist() if isinstance(xyz, np.ndarray) else [float(v) for v in xyz]


def build_messages(
    frame: Frame,
    types: Mapping[str, Any] | MessageTypes,
    *,
    frame_id: str,
    stamp: int,
    engine: Engine,
    include_paths: bool = True,
) -> list[tuple[str, Any]]:
    """``[(topic, message)]`` for one frame (a one-off :class:`MessageBuilder`; loops should keep
    a builder, which also sends the paths only periodically)."""
    builder = MessageBuilder(engine, types, frame_id=frame_id)
    return builder.build(frame, stamp, include_paths=include_paths)


def _characteristic_length(engine: Engine, fixed: Mapping[str, np.ndarray]) -> float:
    """Size of the drawing: the diagonal of the box around paths and fixed points."""
    chunks = [np.atleast_2d(v) for v in engine.paths.values() if np.size(v)]
    chunks += [np.atleast_2d(v) for v in fixed.values()]
    if not chunks:
        return 1.0
    dims = max(c.shape[1] for c in chunks)
    stacked = np.vstack([np.pad(c, ((0, 0), (0, dims - c.shape[1]))) for c in chunks])
    size = float(np.linalg.norm(stacked.max(axis=0) - stacked.min(axis=0)))
    return size if math.isfinite(size) and size > 0.0 else 1.0
