"""The force part of the one message builder: efforts on the joint topics, a wrench per load,
arrows in the markers.

:class:`~linkage_ros.messages.MessageBuilder` owns one :class:`LoadMessages` when its engine's
scene has forces (:mod:`linkage_ros.forces`), and none otherwise (every message then stays as
it was, byte for byte). What it adds (docs/ros.md, "Forces")::

    pin_loads/<K>     geometry_msgs/msg/WrenchStamped   force (N, world frame) on the pin's first
                                                        body from the other; torque 0
    slide_loads/<K>   geometry_msgs/msg/WrenchStamped   force of the guide on the slider block
                                                        (normal to the guide) and its couple
                                                        (torque.z, N·m) about the block's point
    joint_states      effort: each input joint's effort (and the URDF tree joint that turns the
                      input link against the frame: the same number), 0.0 for every other joint
    joint_kinematics  points[0].effort: the same, for every joint of the scene
    markers           namespace ``loads``: one ARROW per load (id = its index), from the pair's
                      point along the force, length = |F| × ``scale`` (m/N), or above a knee
                      by the log rule of :class:`~linkage_ros.forces.LoadArrows` (the same
                      rule as the rerun view, with its floor); its ``text`` says which load and
                      the rule (:meth:`LoadMessages.label`); namespace ``load_labels``: one
                      TEXT_VIEW_FACING per load at its arrow's tip, ``R_<key>``

Every number comes from the frame (``frame.efforts``, ``frame.loads``), but the arrows' tips: the
pair's point plus the force times the rule's factor (fixed when the scene is loaded), derived
like the URDF tree's joint states
(:meth:`MessageBuilder.load_tips <linkage_ros.messages.MessageBuilder.load_tips>`; a byte
template passes sentinels for them through ``build_topics(..., load_tips=...)``). A frame without
forces gives NaN in their place, so that a template taken from it can never match a real frame.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any, Protocol

from solver.tracing import TRACE

from .forces import KIND_PIN, LoadArrows, LoadPair, load_arrows
from .msgtypes import MessageTypes
from .topics import LOAD_LABELS_NAMESPACE, LOADS_NAMESPACE, WRENCH_STAMPED, load_topic_types
from .urdf import BASE_LINK

__all__ = ["LOADS_NAMESPACE", "LOAD_LABELS_NAMESPACE", "WRENCH_STAMPED", "LoadMessages", "load_topic_types",
           "tree_effort_joints"]

_LOAD_COLOUR = (0.80, 0.25, 0.85, 1.0)
#: Arrow shaft diameter, head diameter and head length, in line widths of the drawing.
_ARROW_SHAPE = (1.5, 4.0, 5.0)
#: Height of an arrow's label (``R_<key>``, at its tip), in line widths of the drawing.
_LABEL_HEIGHT = 6.0
_NAN = math.nan


class MessageBuilder(Protocol):
    """What :class:`LoadMessages` reads of :class:`linkage_ros.messages.MessageBuilder` (named
    here, not imported: the builder owns this module's class, so the import points one way)."""

    engine: Any
    types: MessageTypes
    line_width: float

    def _marker_style(self, ns: str, marker_id: int, kind: int, colour: tuple[float, float, float, float],
                      scale: float) -> dict[str, Any]: ...


class _Tick(Protocol):
    """What :meth:`LoadMessages.arrows` reads of the builder's tick: the frame and its points'
    Point messages."""

    frame: Any

    def point(self, name: str) -> Any: ...


def tree_effort_joints(tree: Any, inputs: Iterable[str]) -> list[tuple[str, str]]:
    """``(tree joint, input)`` for each URDF tree joint (``linkage-urdf``) that turns an input
    crank against the frame: its coordinate is the input angle plus a constant, so its effort is
    the input's; and each actuator's rod slide, whose coordinate is the stroke (effort: the
    cylinder's force, N)."""
    if tree is None:
        return []
    inputs = set(inputs)
    return [(j.name, str(j.data[0])) for j in tree.joints
            if j.rule == "planar_pin" and j.parent == BASE_LINK and j.data and j.data[0] in inputs] + [
        (j.name, str(j.data[2])) for j in tree.joints
        if j.rule == "planar_slide" and len(j.data) > 2 and j.data[2] in inputs]


class LoadMessages:
    """The force messages of ``builder``'s engine (which must have forces)."""

    def __init__(self, builder: MessageBuilder, *, size: float, tree_joints: Sequence[tuple[str, str]]) -> None:
        engine = builder.engine
        c = builder.types.classes
        self.types = builder.types
        self.pairs = tuple(engine.load_pairs)
        self.topics = [p.topic for p in self.pairs]
        self._Vector3 = c["geometry_msgs/msg/Vector3"]
        self._Point = c["geometry_msgs/msg/Point"]
        self._Wrench = c["geometry_msgs/msg/Wrench"]
        self._WrenchStamped = c[WRENCH_STAMPED]
        self._Marker = c["visualization_msgs/msg/Marker"]
        self._zero = self._Vector3(x=0.0, y=0.0, z=0.0)
        #: How long a load's arrow is (:func:`~linkage_ros.forces.load_arrows` over one cycle at
        #: the starting motion): ``scale`` m per N, above ``knee`` N ``rule.step`` m per tenfold.
        self.rule: LoadArrows = load_arrows(engine.load_samples, size)
        self.scale: float = self.rule.scale
        bent = math.isfinite(self.rule.knee) or self.rule.floor > 0.0
        self._bent = self.rule.planar_factor if bent else None
        self._inputs = frozenset(engine.inputs)
        #: joint name → the input whose effort it carries (None: a passive joint, 0.0)
        self._carrier = {name: (name if name in self._inputs else None) for name in engine.joint_names}
        self._carrier.update(tree_joints)
        w = builder.line_width
        style = builder._marker_style(LOADS_NAMESPACE, 0, self._Marker.ARROW, _LOAD_COLOUR, w)
        shaft, head, length = (f * w for f in _ARROW_SHAPE)
        style["scale"] = self._Vector3(x=shaft, y=head, z=length)
        self._styles = [{**style, "id": i, "text": self.label(p)} for i, p in enumerate(self.pairs)]
        label = builder._marker_style(LOAD_LABELS_NAMESPACE, 0, self._Marker.TEXT_VIEW_FACING, _LOAD_COLOUR,
                                      _LABEL_HEIGHT * w)
        del label["pose"]  # at the arrow's tip: set per tick
        self._label_styles = [{**label, "id": i, "text": f"R_{p.key}"} for i, p in enumerate(self.pairs)]
        self._Pose = c["geometry_msgs/msg/Pose"]
        self._upright = c["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)
        fixed = engine.scene.fixed_points
        self._fixed = [(float(fixed[p.point][0]), float(fixed[p.point][1])) if p.point in fixed else None
                       for p in self.pairs]

    def label(self, pair: LoadPair) -> str:
        """The arrow marker's ``text``: what it shows and its scale, e.g. ``pin_loads/B: force on
        coupler from rocker; arrow 0.005 m per N``."""
        return f"{pair.topic}: force on {pair.body} from {pair.other}; arrow {self.rule.describe(per='m per N')[2:]}"

    def efforts(self, frame: Any, names: Iterable[str]) -> Any:
        """The effort array of ``names`` (joint_states, joint_kinematics) at ``frame``."""
        efforts = frame.efforts
        row = []
        for name in names:
            q = self._carrier.get(name)
            row.append(0.0 if q is None else efforts.get(q, _NAN))
        return self.types.float64_rows([row])[0]

    def wrenches(self, frame: Any, header: Any, wanted: set[str] | None) -> list[tuple[str, Any]]:
        """``[(topic, WrenchStamped)]`` of the loads in ``wanted`` (None: all)."""
        loads = frame.loads
        out = []
        for pair, topic in zip(self.pairs, self.topics):
            if wanted is not None and topic not in wanted:
                continue
            fx, fy, m = loads.get(pair.key, (_NAN, _NAN, _NAN))
            torque = self._zero if pair.kind == KIND_PIN else self._Vector3(x=0.0, y=0.0, z=m)
            wrench = self._Wrench(force=self._Vector3(x=fx, y=fy, z=0.0), torque=torque)
            out.append((topic, self._WrenchStamped(header=header, wrench=wrench)))
        return out

    def tips(self, frame: Any) -> tuple[float, ...]:
        """(x, y) of each arrow's tip, flat: the pair's point + the force × the rule's factor
        (:attr:`scale` up to the knee)."""
        loads, points, s = frame.loads, frame.points, self.scale
        out: list[float] = []
        for pair, fixed in zip(self.pairs, self._fixed):
            x, y = fixed if fixed is not None else points[pair.point].position[:2]
            fx, fy, _ = loads.get(pair.key, (_NAN, _NAN, _NAN))
            if self._bent is not None:  # an opaque call, so that the traced fast path keeps it
                s = TRACE.call(self._bent, fx, fy)
            out += (x + s * fx, y + s * fy)
        return tuple(out)

    def arrows(self, tick: _Tick, header: Any, tips: Sequence[float] | None = None) -> list[Any]:
        """One ARROW marker per load, from its point to its tip (:meth:`tips`), then one
        TEXT_VIEW_FACING marker per load at its tip, ``R_<key>`` (namespace ``load_labels``): which
        pin each arrow belongs to, in RViz and Foxglove alike."""
        if tips is None:
            tips = self.tips(tick.frame)
        out = []
        for i, (pair, style) in enumerate(zip(self.pairs, self._styles)):
            start = tick.point(pair.point)
            end = self._Point(x=tips[2 * i], y=tips[2 * i + 1], z=0.0)
            out.append(self._Marker(header=header, points=[start, end], **style))
        for i, style in enumerate(self._label_styles):
            at = self._Point(x=tips[2 * i], y=tips[2 * i + 1], z=0.0)
            out.append(self._Marker(header=header, pose=self._Pose(position=at, orientation=self._upright),
                                    points=[], **style))
        return out
