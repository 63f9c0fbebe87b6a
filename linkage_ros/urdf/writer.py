"""The URDF text of a :class:`~.model.TreeModel`: links with simple visuals, tree joints, and the
two fixed frames of every cut.

Visuals are sized from the scene: ``size`` is the longest distance between two points of one body
(the drum's diameter included); bars are cylinders of radius ``size/100``. Links the scene gives a
mass carry an ``<inertial>`` (:mod:`.inertial`).

Limits (``<limit>``; never 0, which a ros2_control or simulator reads as "cannot move"):

* position: a prismatic joint's travel over one turn of the input, widened by ``TRAVEL_MARGIN`` on
  each side; an actuator's rod exactly its stroke [closed, open]. Pins are ``continuous`` joints.
* effort and velocity of the joint an input's motor drives (the driving crank's pin, the
  actuator's rod): the motor's stall torque or force and its no-load speed (a table: its largest
  |torque| and the speed where it falls to zero); every other prismatic joint, and a driven joint
  without a motor, :data:`DEFAULT_EFFORT` and :data:`DEFAULT_VELOCITY` (the scene sets no limit;
  far above what the shipped scenes need). Passive pins carry no ``<limit>``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Sequence

import numpy as np

from solver.errors import AssemblyError, SceneError

from .inertial import tensor
from .states import kinematics_tree_joint_states
from .tree import BASE_LINK, Body, TreeJoint, TreeModel

__all__ = ["urdf_xml", "travel", "drive_limits", "CYCLE_SAMPLES", "BAR_RADIUS_PER_SIZE", "DEFAULT_EFFORT",
           "DEFAULT_VELOCITY"]

#: Samples of the input over one turn used to find the travel of the prismatic joints.
CYCLE_SAMPLES = 720
#: The sampled travel of a prismatic joint is widened by this fraction on each side, so that the
#: limits hold the extremes that fall between samples.
TRAVEL_MARGIN = 0.02
#: Bar radius as a fraction of the scene's size.
BAR_RADIUS_PER_SIZE = 1.0 / 100.0
#: The effort limit (N·m for a pin, N for a slide) of a joint whose effort the scene does not bound:
#: a megawatt-class figure, so that a controller clamping to it never limits a shipped scene (the
#: excavator's cylinders hold some 10⁴–10⁵ N).
DEFAULT_EFFORT = 1.0e6
#: The velocity limit (rad/s for a pin, m/s for a slide) of a joint whose speed the scene does not
#: bound (about 10⁴ rpm for a pin).
DEFAULT_VELOCITY = 1.0e3

_MATERIALS = {
    "frame": (0.45, 0.45, 0.48, 1.0),
    "crank": (0.95, 0.55, 0.10, 1.0),
    "bar": (0.20, 0.45, 0.85, 1.0),
    "slider": (0.20, 0.70, 0.30, 1.0),
    "drum": (0.85, 0.75, 0.40, 0.55),
    "ring": (0.80, 0.25, 0.60, 0.45),
}


def _f(x: float) -> str:
    text = repr(float(x)) if x != 0.0 else "0"
    return text[:-2] if text.endswith(".0") else text


def _vec(v: Sequence[float]) -> str:
    return " ".join(_f(x) for x in v)


def travel(scene: object, model: TreeModel, *, samples: int = CYCLE_SAMPLES) -> dict[str, tuple[float, float]]:
    """``{joint: (lowest, highest)}`` of every prismatic tree joint over one turn of the input
    (the assemblable samples of ``[0, 2π)``, or of an actuator's stroke); an actuator's rod
    travels exactly its stroke [closed, open]."""
    rods = {j.name: (model.bodies[j.child].size["length"], model.bodies[j.child].size["open"])
            for j in model.joints if j.type == "prismatic" and model.bodies[j.child].role == "rod"}
    slides = [i for i, j in enumerate(model.joints) if j.type == "prismatic" and j.name not in rods]
    if not slides:
        return rods
    span = getattr(scene, "input_ranges", (None,))[0]
    phi = (np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False) if span is None
           else np.linspace(float(span[0]), float(span[1]), samples))
    k = scene.everything().solve(phi, mask=True)  # type: ignore[attr-defined]
    valid = np.asarray(k.valid, dtype=bool)
    if not valid.any():
        raise AssemblyError(group="(all)", reason="cannot be assembled at any φ of one turn",
                            scene=str(getattr(scene, "name", "")))
    states = kinematics_tree_joint_states(model, k)
    out = {}
    for i in slides:
        q = states.position[valid, i]
        q = q[np.isfinite(q)]
        lo, hi = float(q.min()), float(q.max())
        pad = TRAVEL_MARGIN * (hi - lo) if hi > lo else TRAVEL_MARGIN * max(abs(hi), 1.0)
        out[model.joints[i].name] = (lo - pad, hi + pad)
    return {**out, **rods}


def drive_limits(scene: object, joint: str) -> tuple[float, float]:
    """``(effort, velocity)`` limits of the tree joint that input ``joint`` drives: its motor's
    stall torque (force) and no-load speed, a table's largest |torque| and the first speed at which
    it reaches zero; :data:`DEFAULT_EFFORT`, :data:`DEFAULT_VELOCITY` for what the scene leaves open."""
    forces = getattr(scene, "forces", None)
    motor = None if forces is None else forces.spec.motors.get(joint)
    if motor is None:
        return DEFAULT_EFFORT, DEFAULT_VELOCITY
    if motor.linear:
        effort, speed = abs(float(motor.stall)), abs(float(motor.no_load))
    else:
        effort, speed = max(abs(t) for t in motor.torques), 0.0
        pairs = list(zip(motor.speeds, motor.torques))
        for (w0, t0), (w1, t1) in zip(pairs, pairs[1:]):
            if w1 > 0.0 and t0 * t1 <= 0.0 and t0 != t1:
                speed = abs(w0 + (w1 - w0) * t0 / (t0 - t1))
                break
    return (effort if effort > 0.0 else DEFAULT_EFFORT), (speed if speed > 0.0 else DEFAULT_VELOCITY)


def _driven_by(scene: object, j: TreeJoint) -> str | None:
    """The input joint whose value this tree joint follows (the driving crank, an actuator's rod,
    the spherical shaft), or None for a passive joint."""
    name = {"planar_pin": j.data[:1], "planar_slide": j.data[2:3], "joint_value": j.data[:1]}.get(j.rule, ())
    inputs = tuple(getattr(scene, "inputs", ()))
    return str(name[0]) if name and name[0] is not None and name[0] in inputs else None


def _limit(scene: object, j: TreeJoint, slides: dict[str, tuple[float, float]]) -> dict[str, float] | None:
    driven = _driven_by(scene, j)
    if j.type != "prismatic" and driven is None:
        return None
    effort, velocity = drive_limits(scene, driven) if driven else (DEFAULT_EFFORT, DEFAULT_VELOCITY)
    out = {"effort": effort, "velocity": velocity}
    if j.type == "prismatic":
        lo, hi = slides[j.name]
        out = {"lower": lo, "upper": hi, **out}
    return out


def _size(model: TreeModel) -> float:
    size = 0.0
    for body in model.bodies.values():
        pts = [np.asarray(v) for v in body.local.values()]
        for i, p in enumerate(pts):
            for q in pts[i + 1:]:
                size = max(size, float(np.linalg.norm(p - q)))
        size = max(size, 2.0 * body.size.get("radius", 0.0))
    return size if size > 0.0 else 1.0


class _Doc:
    def __init__(self, name: str) -> None:
        self.robot = ET.Element("robot", name=name)
        for mat, rgba in _MATERIALS.items():
            m = ET.SubElement(self.robot, "material", name=mat)
            ET.SubElement(m, "color", rgba=_vec(rgba))

    def link(self, name: str) -> ET.Element:
        return ET.SubElement(self.robot, "link", name=name)

    def visual(self, link: ET.Element, shape: str, dims: dict[str, float | str], xyz: Sequence[float],
               rpy: Sequence[float], material: str) -> None:
        v = ET.SubElement(link, "visual")
        ET.SubElement(v, "origin", xyz=_vec(xyz), rpy=_vec(rpy))
        g = ET.SubElement(v, "geometry")
        ET.SubElement(g, shape, {k: (val if isinstance(val, str) else _f(val)) for k, val in dims.items()})
        ET.SubElement(v, "material", name=material)

    def joint(self, name: str, kind: str, parent: str, child: str, xyz: Sequence[float],
              rpy: Sequence[float], axis: Sequence[float] | None = None,
              limit: dict[str, float] | None = None) -> None:
        j = ET.SubElement(self.robot, "joint", name=name, type=kind)
        ET.SubElement(j, "parent", link=parent)
        ET.SubElement(j, "child", link=child)
        ET.SubElement(j, "origin", xyz=_vec(xyz), rpy=_vec(rpy))
        if axis is not None:
            ET.SubElement(j, "axis", xyz=_vec(axis))
        if limit is not None:
            ET.SubElement(j, "limit", {k: _f(v) for k, v in limit.items()})

    def inertial(self, link: ET.Element, body: Body, size: float) -> None:
        if body.inertial is None:
            return
        ixx, iyy, izz = tensor(body.inertial, size)
        el = ET.SubElement(link, "inertial")
        ET.SubElement(el, "origin", xyz=_vec(body.inertial.center), rpy="0 0 0")
        ET.SubElement(el, "mass", value=_f(body.inertial.mass))
        ET.SubElement(el, "inertia", ixx=_f(ixx), ixy="0", ixz="0", iyy=_f(iyy), iyz="0", izz=_f(izz))


def _bar(doc: _Doc, link: ET.Element, p: Sequence[float], q: Sequence[float], radius: float, material: str) -> None:
    d = np.asarray(q, float) - np.asarray(p, float)
    length = float(np.linalg.norm(d))
    if length == 0.0:
        return
    mid = 0.5 * (np.asarray(p, float) + np.asarray(q, float))
    yaw = math.atan2(d[1], d[0])
    pitch = math.atan2(math.hypot(d[0], d[1]), d[2])
    doc.visual(link, "cylinder", {"radius": radius, "length": length}, mid, (0.0, pitch, yaw), material)


def _body_visuals(doc: _Doc, link: ET.Element, body: Body, rb: float, slides: dict[str, tuple[float, float]],
                  model: TreeModel) -> None:
    driven = any(j.child == body.name and j.rule == "planar_pin" and j.data[0] is not None for j in model.joints)
    material = "crank" if driven else "bar"
    if body.role == "base":
        for p in body.local.values():
            doc.visual(link, "box", {"size": _vec((4 * rb, 4 * rb, 2 * rb))}, p, (0, 0, 0), "frame")
        for j in model.joints:
            if j.parent == BASE_LINK and j.type == "prismatic" and j.name in slides:
                lo, hi = slides[j.name]
                yaw = j.rpy[2] + math.atan2(j.axis[1], j.axis[0])
                mid = 0.5 * (lo + hi)
                centre = (j.xyz[0] + mid * math.cos(yaw), j.xyz[1] + mid * math.sin(yaw), -2 * rb)
                doc.visual(link, "box", {"size": _vec((hi - lo + 8 * rb, 5 * rb, rb))}, centre, (0, 0, yaw), "frame")
        return
    if body.role == "drum":
        disc: dict[str, float | str] = {"radius": body.size["radius"], "length": 2 * rb}
        doc.visual(link, "cylinder", disc, (0, 0, -2 * rb), (0, 0, 0), "drum")
    yaw = body.size.get("yaw", 0.0)  # the box along its slide, in the body frame
    if body.role == "slider":
        doc.visual(link, "box", {"size": _vec((8 * rb, 5 * rb, 4 * rb))}, (0, 0, 0), (0, 0, yaw), "slider")
    if body.role in ("barrel", "rod"):  # an actuator: the barrel ahead of A, the rod back from the eye C
        length = body.size["length"]
        x, radius = (0.5 * length, 2.6 * rb) if body.role == "barrel" else (-0.5 * length, 1.2 * rb)
        doc.visual(link, "cylinder", {"radius": radius, "length": length}, (x, 0, rb), (0, math.pi / 2, 0),
                   "slider" if body.role == "barrel" else "crank")
    if body.role == "eyelet":
        doc.visual(link, "box", {"size": _vec((5 * rb, 3.5 * rb, 3.5 * rb))}, (0, 0, 0), (0, 0, yaw), "slider")
    r = body.size.get("radius", 0.0)
    if body.role == "shaft":
        doc.visual(link, "cylinder", {"radius": r / 12, "length": 3 * r}, (0, 0, 0), (-math.pi / 2, 0, 0), "crank")
    if body.role == "ring":
        alpha = body.size["alpha"]
        doc.visual(link, "cylinder", {"radius": r, "length": r / 12}, (0, 0, 0), (0, math.pi / 2, alpha), "ring")
    if body.role == "cage":
        doc.visual(link, "cylinder", {"radius": r / 15, "length": 2.4 * r}, (0, 0, 0), (0, math.pi / 2, 0), "bar")
        doc.visual(link, "cylinder", {"radius": r / 20, "length": r}, (0, 0, r / 2), (0, 0, 0), "bar")
        doc.visual(link, "sphere", {"radius": r / 10}, (0, 0, r), (0, 0, 0), "slider")
    for start, end in body.bars:
        _bar(doc, link, body.local[start], body.local[end], rb, material)
    for pin in body.pins:
        doc.visual(link, "cylinder", {"radius": 1.6 * rb, "length": 3 * rb}, body.local[pin], (0, 0, 0), material)


def urdf_xml(scene: object, model: TreeModel, *, frame_id: str = "world", provenance: str = "") -> str:
    """The URDF document (text) of ``model``. ``frame_id`` names the root link; unless it is
    ``base_link`` it carries ``base_link`` by a fixed identity joint."""
    if not frame_id or frame_id in model.bodies and frame_id != BASE_LINK:
        raise SceneError(f"URDF export: frame_id {frame_id!r} is empty or the name of a body")
    slides = travel(scene, model)
    size = _size(model)
    rb = size * BAR_RADIUS_PER_SIZE
    doc = _Doc(str(model.scene_name).replace("/", "_"))
    doc.robot.insert(0, ET.Comment(
        f" Generated by linkage-urdf from scene '{model.scene_name}'. The mechanism is opened into a "
        "spanning tree; each cut joint is marked by two fixed frames <cut>_a and <cut>_b whose "
        "origins coincide when the joint states are the solver's. "
    ))
    if provenance:
        doc.robot.insert(1, ET.Comment(" " + " ".join(provenance.split()).replace("--", "-") + " "))
    if frame_id != BASE_LINK:
        doc.link(frame_id)
        doc.joint(f"{BASE_LINK}_joint", "fixed", frame_id, BASE_LINK, (0, 0, 0), (0, 0, 0))
    for body in model.bodies.values():
        link = doc.link(body.name)
        doc.inertial(link, body, size)
        _body_visuals(doc, link, body, rb, slides, model)
    for j in model.joints:
        doc.joint(j.name, j.type, j.parent, j.child, j.xyz, j.rpy, j.axis, _limit(scene, j, slides))
    for cut in model.cuts:
        doc.robot.append(ET.Comment(f" cut {cut.name}: {cut.why} "))
        for side, holder, local in (("a", cut.side_a, cut.local_a), ("b", cut.side_b, cut.local_b)):
            doc.link(f"{cut.name}_{side}")
            doc.joint(f"{cut.name}_{side}_joint", "fixed", holder, f"{cut.name}_{side}", local, (0, 0, 0))
    ET.indent(doc.robot, space="  ")
    return '<?xml version="1.0"?>\n' + ET.tostring(doc.robot, encoding="unicode") + "\n"
