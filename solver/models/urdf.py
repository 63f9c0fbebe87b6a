"""A URDF read through yourdfpy into a :class:`~solver.models.spatial.SpatialModel`, its loops closed
by the conventions in use.

yourdfpy parses the file (links, joints with origins and axes, inertials, ``<mimic>``); the pose
is every joint at zero. Read from it:

* links joined by ``fixed`` joints are one rigid body; the root link and all fixed to it are the
  ground; masses, centres (``inertial/origin``) and inertias summed per rigid body;
* ``revolute`` and ``continuous`` joints are hinges, ``prismatic`` slides (``floating`` and
  ``planar`` are refused: spatial); the joint frame is the child link's frame, so the anchor is
  the child's origin and the axis the child's ``axis`` in the world;
* ``<mimic joint="p" multiplier="c₁" offset="c₀"/>`` on joint q: a coupling q = c₀ + c₁·p;
* loop closures, in either convention: onshape-to-robot's frame pairs, links (or the fixed joints
  to them) named ``closing_<name>_1`` and ``closing_<name>_2``, whose origins coincide — a pin
  between the bodies carrying them; and URDF+ ``<constraint name type="loop">`` (Chignoli et al.,
  2024) with ``<predecessor link>``, ``<successor link>`` and ``<origin xyz rpy>``, the loop frame
  in the predecessor's frame, which is the successor's frame — a pin at its origin. yourdfpy does
  not know ``<constraint>``; it is read from the same file with lxml (yourdfpy's own XML parser);
* the joints named in ``<transmission>`` elements are the actuated ones.

yourdfpy is an optional dependency, imported here only: a missing one is one SceneError line.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import SceneError
from .spatial import GROUND_BODY, Body, Closure, Coupling, Joint, SpatialModel

__all__ = ["read_urdf"]

_CLOSING = re.compile(r"^closing_(.+)_([12])$")


def _modules(file: str) -> tuple[Any, Any]:
    try:
        import yourdfpy
        from lxml import etree
    except ImportError:
        raise SceneError("reading URDF needs the yourdfpy package: pip install yourdfpy", file=file) from None
    return yourdfpy, etree


def _xyz_rpy(element: Any) -> np.ndarray:
    """A 4×4 transform from an ``<origin xyz rpy>`` element (identity without one)."""
    t = np.eye(4)
    if element is None:
        return t
    xyz = [float(v) for v in element.get("xyz", "0 0 0").split()]
    r, p, y = (float(v) for v in element.get("rpy", "0 0 0").split())
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    t[:3, :3] = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                 [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                 [-sp, cp * sr, cp * cr]]
    t[:3, 3] = xyz
    return t


def read_urdf(path: str | Path) -> SpatialModel:
    """The model at zero joint positions as plain data."""
    file = str(path)
    yourdfpy, etree = _modules(file)
    try:
        urdf = yourdfpy.URDF.load(file, build_scene_graph=True, load_meshes=False,
                                  build_collision_scene_graph=False, load_collision_meshes=False)
        tree = etree.parse(file)
    except Exception as exc:  # the parser's own faults, whatever their class: one line
        first = " ".join(str(exc).split("\n")[:2]).strip()
        raise SceneError(f"yourdfpy cannot read it: {first}", file=file) from None
    robot = urdf.robot
    root = urdf.base_link

    def world(link: str) -> np.ndarray:
        return np.asarray(urdf.get_transform(link, root), float)

    parent_of = {j.child: j for j in robot.joints}
    rigid: dict[str, str] = {}

    def rigid_of(link: str) -> str:
        if link not in rigid:
            j = parent_of.get(link)
            rigid[link] = GROUND_BODY if j is None else (rigid_of(j.parent) if j.type == "fixed" else link)
        return rigid[link]

    members: dict[str, list[str]] = {}
    for link in robot.links:
        members.setdefault(rigid_of(link.name), []).append(link.name)
    closing: dict[str, list[tuple[str, np.ndarray]]] = {}
    bodies: dict[str, Body] = {}
    for name in [GROUND_BODY, *(b for b in members if b != GROUND_BODY)]:
        links = members.get(name, [])
        points: dict[str, np.ndarray] = {}
        mass, weighted, parts = 0.0, np.zeros(3), []
        for ln in links:
            t = world(ln)
            match = _CLOSING.match(ln)
            if match:
                closing.setdefault(match.group(1), []).append((name, t[:3, 3].copy()))
                continue
            points[ln] = t[:3, 3].copy()
            inertial = urdf.link_map[ln].inertial
            if inertial is not None and inertial.mass:
                to = t @ (inertial.origin if inertial.origin is not None else np.eye(4))
                m = float(inertial.mass)
                inertia = np.asarray(inertial.inertia if inertial.inertia is not None else np.zeros((3, 3)), float)
                parts.append((m, to[:3, 3].copy(), to[:3, :3] @ inertia @ to[:3, :3].T))
                mass += m
                weighted += m * to[:3, 3]
        com = weighted / mass if mass > 0 else np.zeros(3)
        total = np.zeros((3, 3))
        for m, c, own in parts:
            r = c - com
            total += own + m * (float(r @ r) * np.eye(3) - np.outer(r, r))
        bodies[name] = Body(name, points, mass, com, total, frozenset(points))

    joints: list[Joint] = []
    couplings: list[Coupling] = []
    for j in robot.joints:
        if j.type == "fixed":
            continue
        if j.type not in ("revolute", "continuous", "prismatic"):
            raise SceneError(
                f"joint '{j.name}' is {j.type}: a spatial mechanism, not a planar one (revolute, continuous and "
                "prismatic joints only)",
                file=file,
                entry=f"joint {j.name}",
            )
        t = world(j.child)
        axis = t[:3, :3] @ np.asarray(j.axis if j.axis is not None else (1.0, 0.0, 0.0), float)
        rng = (float(j.limit.lower), float(j.limit.upper)) if j.limit is not None and j.type == "revolute" else None
        joints.append(Joint(j.name, "slide" if j.type == "prismatic" else "hinge", rigid_of(j.parent),
                            rigid_of(j.child), t[:3, 3].copy(), axis / np.linalg.norm(axis), 0.0, 0.0, rng))
        if j.mimic is not None:
            couplings.append(Coupling(j.name, j.mimic.joint, float(j.mimic.multiplier or 1.0),
                                      float(j.mimic.offset or 0.0), f"mimic of '{j.mimic.joint}' on '{j.name}'"))

    closures: list[Closure] = []
    for name, frames in closing.items():
        if len(frames) != 2:
            raise SceneError(f"closing_{name}_1 / closing_{name}_2: a closure needs both frames, found {len(frames)}",
                             file=file)
        (b1, p1), (b2, p2) = frames
        closures.append(Closure(name, b1, b2, p1, float(np.linalg.norm(p1 - p2))))
    for c in tree.getroot().iter("constraint"):
        cname = c.get("name", f"constraint{len(closures)}")
        if c.get("type") != "loop":
            raise SceneError(f"constraint '{cname}' of type {c.get('type')!r}: only type=\"loop\" closes a loop "
                             "(a coupling is a <mimic>)", file=file, entry=f"constraint {cname}")
        pred, succ = c.find("predecessor"), c.find("successor")
        ends = [None if e is None else e.get("link") for e in (pred, succ)]
        if not all(e in urdf.link_map for e in ends):
            raise SceneError(f"constraint '{cname}' needs <predecessor link> and <successor link> naming links of "
                             "the model", file=file, entry=f"constraint {cname}")
        loop = world(pred.get("link")) @ _xyz_rpy(c.find("origin"))
        there = world(succ.get("link"))[:3, 3]
        closures.append(Closure(cname, rigid_of(pred.get("link")), rigid_of(succ.get("link")), loop[:3, 3].copy(),
                                float(np.linalg.norm(loop[:3, 3] - there))))

    actuated = [j.get("name") for t in tree.getroot().iter("transmission") for j in t.iter("joint")]
    return SpatialModel(
        name=robot.name or Path(file).stem,
        file=file,
        kind="URDF",
        bodies=bodies,
        joints=tuple(joints),
        closures=tuple(closures),
        couplings=tuple(couplings),
        actuated=tuple(a for a in dict.fromkeys(actuated) if a),
        gravity=np.array([0.0, 0.0, -9.81]),
        pose="zero joint positions",
        provenance=f"imported from {Path(file).name} (URDF, read by yourdfpy) at zero joint positions",
    )
