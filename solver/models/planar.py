"""A :class:`~solver.models.spatial.SpatialModel` laid into its plane: a drawing of links and pins.

Planarity: every hinge axis parallel to the first one, n (|a × n| ≤ ``AXIS_TOLERANCE``), every
slide axis across it (|a·n| ≤ the same). The plane's frame: z = n, x = the world axis most
nearly across n, projected onto the plane and normalised, y = z × x, origin the world origin
(points are projected along n: a linkage's layers may sit at different depths). A hinge whose
axis is −n turns clockwise in the plane: its sign σ = −1.

Points: each rigid body carries its model bodies' origins (named after them), each hinge's
anchor (the child body's origin's name when they coincide, else ``<joint>_pin``) and each
closure's point (body1's point there, else the closure's name). A slide joint's child is a
block (solver.models.build: the drawing's ``slides``); its axis, projected, is the guide. Points of one body closer than
``POINT_TOLERANCE`` × the model's size are one point. A point shared by two bodies is a pin.
Point names are made fit for ROS topic names (``points/<P>/position``): characters other than
letters, digits and ``_`` become ``_``, and a name that is also a joint's gains ``_point``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from ..errors import SceneError
from .spatial import GROUND_BODY, Closure, Joint, SpatialModel

__all__ = ["Plane", "PlanarModel", "Pin", "lay_out", "AXIS_TOLERANCE", "POINT_TOLERANCE"]

#: |sin| of the angle between two hinge axes still taken as parallel (and |cos| between a slide
#: axis and the normal still taken as across it): far below any drawn misalignment, far above
#: the rounding of a compiled model's quaternions (≈1e-16).
AXIS_TOLERANCE = 1e-9
#: Two points of one body closer than this times the model's size are one point.
POINT_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Plane:
    """The mechanism's plane in the model's world frame: p₃ = origin + x·ex + y·ey (+ depth·normal)."""

    origin: np.ndarray
    ex: np.ndarray
    ey: np.ndarray
    normal: np.ndarray

    def of(self, p: np.ndarray) -> complex:
        r = np.asarray(p, float) - self.origin
        return complex(float(r @ self.ex), float(r @ self.ey))

    def to_world(self, z: complex, depth: float = 0.0) -> np.ndarray:
        return self.origin + z.real * self.ex + z.imag * self.ey + depth * self.normal

    def describe(self) -> str:
        def v(a: np.ndarray) -> str:
            return "(" + ", ".join(f"{x:.6g}" for x in a) + ")"
        return f"origin {v(self.origin)}, x {v(self.ex)}, y {v(self.ey)}, normal {v(self.normal)}"


@dataclass(frozen=True)
class Pin:
    point: str
    bodies: tuple[str, str]
    joint: Joint | None  # a hinge; None for a closure
    closure: Closure | None = None


@dataclass
class PlanarModel:
    model: SpatialModel
    plane: Plane
    size: float
    #: body → {point: plane coordinate}; the ground is GROUND_BODY
    points: dict[str, dict[str, complex]] = field(default_factory=dict)
    pins: list[Pin] = field(default_factory=list)
    sign: dict[str, float] = field(default_factory=dict)  # hinge → σ
    slides: list[Joint] = field(default_factory=list)  # slide joints: the child is a block

    def where(self, name: str) -> complex:
        for pts in self.points.values():
            if name in pts:
                return pts[name]
        raise KeyError(name)


def _loops(model: SpatialModel) -> dict[str, list[Joint]]:
    """Each closure → the tree joints of its loop (the path body1 → … → body2 through the tree)."""
    up = {j.child: j for j in model.joints}

    def chain(body: str) -> list[Joint]:
        out = []
        while body in up:
            out.append(up[body])
            body = up[body].parent
        return out

    loops = {}
    for c in model.closures:
        a, b = chain(c.body1), chain(c.body2)
        common = {j.name for j in a} & {j.name for j in b}
        loops[c.name] = [j for j in a + b if j.name not in common]
    return loops


def _plane(model: SpatialModel) -> Plane:
    hinges = [j for j in model.joints if j.kind == "hinge"]
    if not hinges:
        raise SceneError("no hinge joint: a planar linkage turns on hinges", file=model.file)
    n = hinges[0].axis / np.linalg.norm(hinges[0].axis)
    loops = _loops(model)
    for j in model.joints:
        off = np.linalg.norm(np.cross(j.axis, n)) if j.kind == "hinge" else abs(float(j.axis @ n))
        if off > AXIS_TOLERANCE:
            where = [name for name, js in loops.items() if any(x.name == j.name for x in js)]
            loop = f"loop '{where[0]}'" if where else "an open chain"
            what = "not parallel to" if j.kind == "hinge" else "not across"
            axes = ", ".join(f"{x:.6g}" for x in j.axis)
            base = ", ".join(f"{x:.6g}" for x in n)
            ang = math.degrees(math.asin(min(1.0, off)))
            raise SceneError(
                f"spatial {loop}: {j.kind} '{j.name}' axis ({axes}) is {what} hinge '{hinges[0].name}' axis "
                f"({base}), {ang:.4g}° off: a planar linkage needs parallel hinge axes (and slides across them)",
                file=model.file,
                entry=f"joint {j.name}",
            )
    world = np.eye(3)
    k = int(np.argmin(np.abs(world @ n)))
    ex = world[k] - (world[k] @ n) * n
    ex /= np.linalg.norm(ex)
    ey = np.cross(n, ex)
    return Plane(np.zeros(3), ex, ey, n)


def lay_out(model: SpatialModel) -> PlanarModel:
    """The model's bodies as planar point sets joined by pins (module docstring)."""
    plane = _plane(model)
    joint_names = {j.name for j in model.joints}

    def fit(name: str) -> str:
        name = re.sub(r"[^A-Za-z0-9_]", "_", name) or "p"
        if name[0].isdigit():
            name = f"p{name}"
        return f"{name}_point" if name in joint_names else name

    coords = [plane.of(p) for b in model.bodies.values() for p in b.points.values()]
    coords += [plane.of(j.anchor) for j in model.joints] + [plane.of(c.point) for c in model.closures]
    size = max((abs(z) for z in coords), default=1.0) or 1.0
    tol = POINT_TOLERANCE * size
    out = PlanarModel(model, plane, size)
    origins: set[str] = set()  # points that are only a model body's origin (a site's name wins)
    for b in model.bodies.values():
        pts: dict[str, complex] = {}
        for name, p in b.points.items():
            z = plane.of(p)
            if not any(abs(z - w) <= tol for w in pts.values()):
                pts[fit(name)] = z
                if name in b.origins:
                    origins.add(fit(name))
        out.points[b.name] = pts

    def at(body: str, z: complex) -> str | None:
        return next((n for n, w in out.points[body].items() if abs(z - w) <= tol), None)

    def pin(a: str, b: str, z: complex, candidate: str) -> str:
        found = [n for n in (at(b, z), at(a, z)) if n is not None]
        name = next((n for n in found if n not in origins), found[0] if found else fit(candidate))
        for body in (a, b):
            have = at(body, z)
            if have is not None and have != name:
                if have in origins:  # a body origin at a named pin: the pin's name is kept
                    del out.points[body][have]
                else:
                    raise SceneError(
                        f"points '{have}' and '{name}' of body '{body}' coincide: one pin joins three bodies "
                        "there; give the model one body origin at that pin",
                        file=model.file,
                    )
            out.points[body][name] = z
        return name

    for j in model.joints:
        if j.kind != "hinge":
            out.slides.append(j)
            continue
        out.sign[j.name] = 1.0 if float(j.axis @ plane.normal) > 0 else -1.0
        name = pin(j.parent, j.child, plane.of(j.anchor), f"{j.name}_pin")
        out.pins.append(Pin(name, (j.parent, j.child), j))
    for c in model.closures:
        if c.gap > 1e3 * tol:
            raise SceneError(
                f"closure '{c.name}' is open by {c.gap:.3g} m at the model's pose: its two points must coincide",
                file=model.file,
            )
        if c.body1 == c.body2:
            continue
        name = pin(c.body1, c.body2, plane.of(c.point), c.name)
        out.pins.append(Pin(name, (c.body1, c.body2), None, c))
    if GROUND_BODY not in out.points:
        out.points[GROUND_BODY] = {}
    return out

