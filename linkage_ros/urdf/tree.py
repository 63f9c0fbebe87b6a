"""The types of a mechanism opened into a tree: bodies, tree joints, cuts (no scene reading here).

:mod:`.model` (group scenes) and :mod:`.vectors` (vector-loop scenes) build a :class:`TreeModel`;
:mod:`.states` evaluates its joint coordinates and :mod:`.writer` writes it as URDF. The types sit
below all of them, so the package reads top-down: tree ← states, vector bodies ← vectors ← model.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

from solver.errors import SceneError

__all__ = ["BASE_LINK", "Body", "Cut", "Inertial", "TreeJoint", "TreeModel", "Vec3", "check_names"]

BASE_LINK = "base_link"

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class Inertial:
    """A link's mass (kg), centre of mass in the link frame (m) and inertia about it (kg·m², +z)
    (:mod:`.inertial`)."""

    mass: float
    center: Vec3
    izz: float


@dataclass
class Body:
    """A rigid body. Planar: frame origin at point ``origin``, x axis along ``axis`` (a pair of
    point names, a constant complex direction, or the name of a scene joint whose position is an
    absolute angle) turned by ``turn`` rad; ``local`` maps its points to frame coordinates.
    ``anchor``: a named point of ``local`` from which the origin is located when the origin is not
    itself a point the solver reports (vector scenes). ``role`` names the drawing: ``base``,
    ``bar``, ``drum``, ``slider``, ``eyelet``, ``shaft``, ``ring``, ``cage``, ``barrel``, ``rod``
    (an actuator's, ``size["length"]`` long: its closed length)."""

    name: str
    role: str
    origin: str | None = None
    axis: tuple[str, str] | complex | str | None = None
    local: dict[str, Vec3] = field(default_factory=dict)
    #: Bars to draw, as pairs of point names of ``local``.
    bars: list[tuple[str, str]] = field(default_factory=list)
    #: Pins to draw (point names of ``local``).
    pins: list[str] = field(default_factory=list)
    #: Free-form sizes for the drawing (e.g. ``radius`` of a drum, ``alpha`` of a ring, ``yaw``
    #: of a slider's box in the body frame).
    size: dict[str, float] = field(default_factory=dict)
    #: The body's x axis is the direction of ``axis`` turned by this angle (rad).
    turn: float = 0.0
    #: A named point of ``local`` that locates the origin (None: the origin is read directly).
    anchor: str | None = None
    #: Mass properties from the scene's ``bodies:`` (None: massless, no ``<inertial>``).
    inertial: Inertial | None = None


@dataclass(frozen=True)
class TreeJoint:
    """A joint of the tree. ``type`` is the URDF type (``continuous`` for a pin, ``prismatic``);
    ``xyz``/``rpy`` the joint frame in the parent's frame, ``axis`` in the joint frame.
    ``rule`` says how its coordinate is computed (see :mod:`.states`); ``data`` holds the names
    and constants the rule reads (an actuator's rod slide adds the input joint it follows)."""

    name: str
    type: str
    parent: str
    child: str
    xyz: Vec3
    rpy: Vec3
    axis: Vec3
    rule: str
    data: tuple[object, ...] = ()


@dataclass(frozen=True)
class Cut:
    """A joint left out of the tree: a point on each side, in that side's frame."""

    name: str
    kind: str  # "pin"
    point: str
    side_a: str
    local_a: Vec3
    side_b: str
    local_b: Vec3
    why: str


@dataclass
class TreeModel:
    """Bodies, tree joints (parents before children) and cuts of one scene."""

    scene_name: str
    dim: int
    input_joint: str
    bodies: dict[str, Body]
    joints: list[TreeJoint]
    cuts: list[Cut]
    owner: dict[str, str]

    @cached_property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)


def check_names(model: TreeModel, scene_joints: tuple[str, ...], error: Callable[[str], SceneError]) -> None:
    """Raise ``error(...)`` when two URDF links would share a name or a tree joint is named like
    a scene joint (``joint_states`` carries both)."""
    links = list(model.bodies)
    for cut in model.cuts:
        links += [f"{cut.name}_a", f"{cut.name}_b"]
    dup = sorted({n for n in links if links.count(n) > 1})
    if dup:
        raise error(f"URDF link names would clash: {', '.join(dup)}")
    clash = sorted(set(model.joint_names) & set(scene_joints))
    if clash:
        raise error(
            f"tree joint names {', '.join(clash)} are also scene joints; rename those scene joints "
            "(joint_states carries both)"
        )
