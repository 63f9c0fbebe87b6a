"""The links and pins of a scene, read off its plan's groups (structure apart from solving).

Which group makes which body, and which pin joins which two bodies:

=========  ==========================================  =========================================
group      bodies (default name: points, frame)         pins (point: body ↔ other) and slides
=========  ==========================================  =========================================
crank      ``name``: [O, A]                             O: crank ↔ ground; A: joins what uses A
actuator   pushed link ``name``: [O, C]; cylinder        O: link ↔ owner(O); A: cylinder ↔
           ``name.cylinder``: [A, C] (massless)         owner(A); C: cylinder ↔ link
rrr        ``name.1``: [A, B];  ``name.2``: [C, B]      A: 1 ↔ owner(A); C: 2 ↔ owner(C); B: 1 ↔ 2
triad      ternary ``name``: [D, E, F]; binary            A: 1 ↔ owner(A); B: 2 ↔ owner(B); C: 3 ↔
           ``name.1``: [A, D], ``.2``: [B, E],          owner(C); D: 1 ↔ ternary; E: 2 ↔ ternary;
           ``.3``: [C, F]                               F: 3 ↔ ternary
slider_    ternary ``name``: [D, E, F]; block             B: 2 ↔ owner(B); C: 3 ↔ owner(C);
triad      ``name.block``: [D] (frame: the guide's);   E: 2 ↔ ternary; F: 3 ↔ ternary; D:
           binary ``name.2``: [B, E], ``.3``: [C, F]    block ↔ ternary; slide: block on ground
rrp        rod ``name``: [A, B]; block ``name.block``:  A: rod ↔ owner(A); B: rod ↔ block;
           [B] (frame: the guide's)                     slide: block on the ground's guide
slotted    link ``name``: [pivot, C, E, …];              pivot: link ↔ owner(pivot); B: block ↔
           block ``name.block``: [B] (frame: the link's) owner(B); slide: block along the link
attached   none: the point joins the link that carries  —
           its base and its ``along`` points
joints     none (read-outs)                             —
=========  ==========================================  =========================================

The *owner* of a point is the body a later group's pin at that point attaches to: ground for a
fixed point, the crank for its point, an actuator's pushed link for its eye C, the first link
(A–B) of an RRR for B, a triad's (or slider triad's) ternary link for D, E and F, the slider block of an RRP for B,
the slotted link for its points, the carrying link for an attached point (never a cylinder: it
carries no other point). A point that several bodies carry (B of an RRR is on both links) is
"on" each of them for loads.

Spherical groups (seed 001) and vector-loop scenes (seed 004) have no planar body structure
here: a scene of them with ``bodies``, ``gravity`` or ``loads`` is a one-line SceneError.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..groups import RRP, RRR, Actuator, Attached, Crank, Group, JointExpression, SliderTriad, Slotted, Triad

__all__ = ["GROUND", "Link", "Pin", "Slide", "Structure", "derive_structure", "StructureFault"]

#: The name of the frame: it carries the fixed points and is never solved.
GROUND = "ground"


class StructureFault(Exception):
    """A group the force layer cannot model; the caller turns it into a SceneError."""


@dataclass(frozen=True)
class Link:
    """A rigid body of the mechanism as the groups make it.

    ``points``: the scene points it carries (the first two set its default frame); ``block``:
    a slider block, named by its one point, whose frame is its guide's — the fixed unit
    direction ``guide`` (an RRP's) or the direction pivot → eyelet of the slotted link ``along``.
    """

    name: str
    group: str
    points: tuple[str, ...]
    block: bool = False
    guide: complex | None = None
    along: tuple[str, str] | None = None


@dataclass(frozen=True)
class Pin:
    """A revolute pair at ``point`` between ``body`` and ``other`` (a body or ``ground``)."""

    point: str
    body: str
    other: str


@dataclass(frozen=True)
class Slide:
    """A prismatic pair: the block ``body`` slides along ``guide`` (``ground`` or a slotted link);
    ``point`` is the block's pin, where the pair's normal force is taken to act."""

    body: str
    guide: str
    point: str


@dataclass(frozen=True)
class Structure:
    """Links, pins and slides in plan order, and the group that makes each."""

    links: tuple[Link, ...]
    pins: tuple[Pin, ...]
    slides: tuple[Slide, ...]
    owner: Mapping[str, str]  # point → the body a later pin at that point attaches to
    groups: tuple[Group, ...]  # the groups that make bodies (no read-out joints)
    rigid: Mapping[frozenset[str], float] = field(default_factory=dict)  # points at a fixed distance
    #: links that carry no mass and no load: an actuator's cylinder, a two-force member (its
    #: barrel's and rod's masses are lumped into the links it is pinned to)
    massless: frozenset[str] = frozenset()


def _carrier(group: str, points: tuple[str, str], links: Sequence[Link], extra: Mapping[str, list[str]],
             fixed: Mapping[str, Any], massless: set[str]) -> str:
    """The body that carries a slider triad's guide on the moving link through ``points`` (ground
    when both are fixed): the first link (not a block, not massless) holding both."""
    need = set(points)
    if need <= set(fixed):
        return GROUND
    for ln in links:
        if not ln.block and ln.name not in massless and need <= {*ln.points, *extra.get(ln.name, ())}:
            return ln.name
    raise StructureFault(f"slider_triad '{group}': its guide's points {points[0]}, {points[1]} are not points of one "
                         "link, so the guide is on no rigid body")


def derive_structure(ordered: Sequence[Group], fixed: Mapping[str, Any]) -> Structure:
    """Bodies and pins of the groups ``ordered`` (dependency order)."""
    owner: dict[str, str] = {name: GROUND for name in fixed}
    links: list[Link] = []
    extra: dict[str, list[str]] = {}  # attached points carried by a link
    pins: list[Pin] = []
    slides: list[Slide] = []
    makers: list[Group] = []
    massless: set[str] = set()
    for g in ordered:
        if isinstance(g, JointExpression):
            continue
        if isinstance(g, Crank):
            links.append(Link(g.name, g.name, (g.center, g.point)))
            pins.append(Pin(g.center, g.name, owner[g.center]))
            owner[g.point] = g.name
        elif isinstance(g, Actuator):
            cylinder = f"{g.name}.cylinder"
            links += [Link(g.name, g.name, (g.pivot, g.point)), Link(cylinder, g.name, (g.base, g.point))]
            pins += [Pin(g.pivot, g.name, owner[g.pivot]), Pin(g.base, cylinder, owner[g.base]),
                     Pin(g.point, cylinder, g.name)]
            owner[g.point] = g.name
            massless.add(cylinder)
        elif isinstance(g, RRR):
            (a, c), b = g.ends, g.point
            one, two = f"{g.name}.1", f"{g.name}.2"
            links += [Link(one, g.name, (a, b)), Link(two, g.name, (c, b))]
            pins += [Pin(a, one, owner[a]), Pin(c, two, owner[c]), Pin(b, one, two)]
            owner[b] = one
        elif isinstance(g, Triad):
            (a, b, c), (d, e, f) = g.ends, g.points
            arms = [f"{g.name}.{i}" for i in (1, 2, 3)]
            links += [Link(arms[0], g.name, (a, d)), Link(arms[1], g.name, (b, e)), Link(arms[2], g.name, (c, f)),
                      Link(g.name, g.name, (d, e, f))]
            pins += [Pin(a, arms[0], owner[a]), Pin(b, arms[1], owner[b]), Pin(c, arms[2], owner[c]),
                     Pin(d, arms[0], g.name), Pin(e, arms[1], g.name), Pin(f, arms[2], g.name)]
            owner[d] = owner[e] = owner[f] = g.name
        elif isinstance(g, SliderTriad):
            (b, c), (d, e, f) = g.ends, g.points
            two, three, block = f"{g.name}.2", f"{g.name}.3", f"{g.name}.block"
            links += [Link(two, g.name, (b, e)), Link(three, g.name, (c, f)), Link(g.name, g.name, (d, e, f))]
            pins += [Pin(b, two, owner[b]), Pin(c, three, owner[c]), Pin(e, two, g.name), Pin(f, three, g.name)]
            if g.block_at is not None:  # the swinging block: pinned at A, sliding along the ternary link
                links.append(Link(block, g.name, (g.block_at,), True, None, (d, e)))
                pins.append(Pin(g.block_at, block, owner[g.block_at]))
                slides.append(Slide(block, g.name, g.block_at))
            elif g.carrier is not None:  # the guide on the moving link through P, Q
                links.append(Link(block, g.name, (d,), True, None, g.carrier))
                pins.append(Pin(d, block, g.name))
                slides.append(Slide(block, _carrier(g.name, g.carrier, links, extra, fixed, massless), d))
            else:
                links.append(Link(block, g.name, (d,), True, g.direction))
                pins.append(Pin(d, block, g.name))
                slides.append(Slide(block, GROUND, d))
            owner[d] = owner[e] = owner[f] = g.name
        elif isinstance(g, RRP):
            block = f"{g.name}.block"
            links += [Link(g.name, g.name, (g.end, g.point)), Link(block, g.name, (g.point,), True, g.direction)]
            pins += [Pin(g.end, g.name, owner[g.end]), Pin(g.point, g.name, block)]
            slides.append(Slide(block, GROUND, g.point))
            owner[g.point] = block
        elif isinstance(g, Slotted):
            block = f"{g.name}.block"
            carried = (g.pivot, *(name for name, _ in g.points))
            links += [
                Link(g.name, g.name, carried),
                Link(block, g.name, (g.through,), True, None, (g.pivot, g.through)),
            ]
            pins += [Pin(g.pivot, g.name, owner[g.pivot]), Pin(g.through, block, owner[g.through])]
            slides.append(Slide(block, g.name, g.through))
            for name, _ in g.points:
                owner[name] = g.name
        elif isinstance(g, Attached):
            need = {g.base, *g.along}
            if need <= set(fixed):
                owner[g.point] = GROUND
                continue
            carriers = [
                ln for ln in links
                if not ln.block and ln.name not in massless and need <= {*ln.points, *extra.get(ln.name, ())}
            ]
            if not carriers:
                raise StructureFault(
                    f"attached '{g.name}': its base {g.base} and along [{', '.join(g.along)}] are not points of "
                    "one link, so the point is on no rigid body"
                )
            extra.setdefault(carriers[0].name, []).append(g.point)
            owner[g.point] = carriers[0].name
        elif getattr(g, "spatial", False):
            raise StructureFault(
                f"{g.kind} '{g.name}' is spatial (seed 001): 3-D forces and moments are not modelled; "
                "bodies, gravity and loads apply to planar scenes (docs/forces.md)"
            )
        else:
            raise StructureFault(
                f"{g.kind} '{g.name}': forces are modelled for the planar groups (crank, actuator, rrr, rrp, "
                "slotted, triad, slider_triad, attached); a vector-loop scene (seed 004) has no body structure here "
                "(docs/forces.md)"
            )
        if not isinstance(g, Attached):
            makers.append(g)
    full = tuple(
        Link(ln.name, ln.group, (*ln.points, *extra.get(ln.name, ())), ln.block, ln.guide, ln.along) for ln in links
    )
    rigid = {frozenset((p, q)): d for g in ordered for p, q, d in g.rigid_pairs() if p != q}
    return Structure(full, tuple(pins), tuple(slides), owner, tuple(makers), rigid, frozenset(massless))
