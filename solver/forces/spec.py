"""What a scene says about masses and loads, validated, in SI (the force layer's data).

Masses in kg, inertias in kg·m² about the centre of mass (+z), gravity in m/s², forces in N,
torques in N·m, stiffness in N/m; lengths (a centre, a spring's free length, a table's slide
coordinate) are read in the scene's length unit and kept in metres.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property

from .friction_spec import FrictionSpec
from .structure import GROUND, Link, Pin, Slide, Structure

__all__ = ["Body", "PointForce", "Torque", "Spring", "TableForce", "Damper", "Load", "Motor", "ForceSpec"]


@dataclass(frozen=True)
class Body:
    """A link with its mass properties (all zero for a link the scene does not name).

    ``frame``: the frame's points — two (origin, then a point on its x axis) or, for a slider
    block, its one point (x along its guide). ``center``: the centre of mass in that frame, m.
    """

    name: str
    link: Link
    frame: tuple[str, ...]
    mass: float = 0.0
    center: complex = 0j
    inertia: float = 0.0

    @property
    def points(self) -> tuple[str, ...]:
        return self.link.points

    @property
    def inert(self) -> bool:
        """True when the body carries no inertia or gravity load (massless, no inertia)."""
        return self.mass == 0.0 and self.inertia == 0.0


@dataclass(frozen=True)
class PointForce:
    """A constant force ``force`` (N, world frame) on ``body`` at its point ``point``."""

    body: str
    point: str
    force: complex


@dataclass(frozen=True)
class Torque:
    """A constant pure torque (N·m, about +z) on ``body``."""

    body: str
    torque: float


@dataclass(frozen=True)
class Spring:
    """A linear spring between point ``ends[0][1]`` of body ``ends[0][0]`` and ``ends[1]``:
    tension k·(ℓ − ℓ₀) along the line between them (ℓ its length, m)."""

    ends: tuple[tuple[str, str], tuple[str, str]]
    stiffness: float
    free_length: float


@dataclass(frozen=True)
class TableForce:
    """A force of fixed direction ``direction`` (a unit vector) on ``body`` at ``point``, of
    magnitude f(q) interpolated linearly in the table (``at``, ``force``) of the joint ``joint``'s
    coordinate q (m or rad), constant beyond its ends; ``period`` (2π for an angle) first wraps
    q into [at₀, at₀ + period)."""

    body: str
    point: str
    direction: complex
    joint: str
    at: tuple[float, ...]
    force: tuple[float, ...]
    period: float | None = None


@dataclass(frozen=True)
class Damper:
    """Viscous damping in the revolute joint ``joint``: a couple −c·s·q̇ on ``body`` and +c·s·q̇ on
    ``other`` (``ground`` or a body), q̇ the joint's rate (rad/s), c ``coefficient`` (N·m·s/rad),
    s ``sign`` (−1 where the joint measures the other body against this one)."""

    joint: str
    body: str
    other: str
    coefficient: float
    sign: float = 1.0


Load = PointForce | Torque | Spring | TableForce | Damper


@dataclass(frozen=True)
class Motor:
    """The drive of one input: its torque (N·m; N for a length input) as a function of the
    input's rate ω (rad/s; m/s). A linear characteristic T = T_stall·(1 − ω/ω₀) (``stall`` and
    ``no_load`` given), or a table (``speeds`` increasing, ``torques``) linear between its entries
    and constant beyond them."""

    joint: str
    stall: float | None = None
    no_load: float | None = None
    speeds: tuple[float, ...] = ()
    torques: tuple[float, ...] = ()

    @property
    def linear(self) -> bool:
        return self.stall is not None


@dataclass(frozen=True)
class ForceSpec:
    """The scene's bodies (every link, named or not), gravity and loads, with its structure."""

    structure: Structure
    bodies: tuple[Body, ...]
    gravity: complex
    loads: tuple[Load, ...]
    names: Mapping[str, str] = field(default_factory=dict)  # a link's default name → its body name
    #: the drive of each input that has one (``motor:``; solver.dynamics), input joint → Motor
    motors: Mapping[str, Motor] = field(default_factory=dict)
    #: flywheels (``flywheel:``), input joint → inertia kg·m²; already added to its link's body
    flywheels: Mapping[str, float] = field(default_factory=dict)
    #: Coulomb friction in pins, slides and cylinder seals (``friction:``; solver.forces.friction)
    friction: FrictionSpec | None = None

    @cached_property  # read on every k.reaction (the node: every pin, every tick)
    def pins(self) -> tuple[Pin, ...]:
        """Every revolute pair as (point, body, other), with the scene's body names."""
        n = self.names
        return tuple(Pin(p.point, n.get(p.body, p.body), n.get(p.other, p.other)) for p in self.structure.pins)

    @cached_property
    def slides(self) -> tuple[Slide, ...]:
        n = self.names
        return tuple(Slide(n.get(s.body, s.body), n.get(s.guide, s.guide), s.point)
                     for s in self.structure.slides)

    def body(self, name: str) -> Body | None:
        return next((b for b in self.bodies if b.name == name), None)

    def carries(self, body: str, point: str) -> bool:
        if body == GROUND:
            return point in self.structure.owner and self.structure.owner[point] == GROUND
        b = self.body(body)
        return b is not None and point in b.points
