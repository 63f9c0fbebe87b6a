"""A group scene written as a drawing: its links and pins as drawn at one input value.

The reverse of :func:`~solver.structure.emit.scene_dict_from_drawing`: the bodies of the groups
(solver.forces.structure — the same table of which group makes which link) become drawn links,
slider blocks become slides, actuators' cylinders become ``actuators``, the fixed points the
ground, and every point is drawn where the scene puts it at the given inputs. Read back, the
drawing decomposes into the same groups and modes (lengths equal to round-off).

Not every group scene has a drawn form: a spherical or vector-loop scene (no planar links), an
RRR dyad with ``through_change_points: continuous`` (its mode changes along the motion, the
drawing holds one), and a point attached to the ground alone (it is a ground point in a
drawing) are refused with a SceneError naming the group.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from .._fields import LENGTH_UNITS
from ..errors import SceneError
from ..forces.structure import StructureFault, derive_structure
from ..groups import RRP, Actuator, Attached, Crank, Group, JointExpression, SliderTriad, Slotted, Triad

__all__ = ["drawing_from_groups"]

#: Keys of a group scene that the drawing replaces.
_REPLACED = ("fixed", "groups")


def _name(link: str) -> str:
    return link.replace(".", "_")


def drawing_from_groups(
    raw: Mapping[str, Any],
    groups: Sequence[Group],
    fixed: Mapping[str, Any],
    positions: Mapping[str, complex],
    *,
    file: str | None = None,
    input_order: Sequence[str] = (),
) -> dict[str, Any]:
    """The drawn scene mapping of a group scene: ``raw`` the scene file's mapping (its units and
    the keys passed on), ``groups`` its groups in dependency order, ``fixed`` its fixed points
    (SI), ``positions`` every point's position (SI) at the inputs to draw it at, ``input_order``
    the scene's input joints in its order (default: the groups')."""
    units = raw.get("units") if isinstance(raw.get("units"), Mapping) else None
    if units is None:
        raise SceneError("has no units: write it with units: {length: m, angle: rad}", file=file, entry="units")
    scale = LENGTH_UNITS[str(units["length"])]
    for g in groups:
        if getattr(g, "continuous", False):
            raise SceneError(f"rrr '{g.name}' follows change points (through_change_points: continuous): its mode "
                             "changes along the motion, a drawing holds one", file=file, entry="groups")
        if isinstance(g, Attached) and all(n in fixed for n in (g.base, *g.along)):
            raise SceneError(f"attached '{g.name}' is on the ground alone: give {g.point} as a fixed point",
                             file=file, entry="groups")
    try:
        st = derive_structure([g for g in groups if not isinstance(g, JointExpression)], fixed)
    except StructureFault as exc:
        raise SceneError(f"has no drawn form: {exc}", file=file, entry="groups") from None
    points: dict[str, list[float]] = {}

    def put(name: str) -> str:
        z = complex(positions[name]) / scale
        points[name] = [float(z.real), float(z.imag)]
        return name

    for name in fixed:
        put(name)
    ground = list(fixed)
    links: dict[str, list[str]] = {}
    slides: dict[str, dict[str, Any]] = {}
    actuators: dict[str, dict[str, Any]] = {}
    by_group = {g.name: g for g in groups}
    for ln in st.links:
        g = by_group[ln.group]
        if ln.name in st.massless:
            assert isinstance(g, Actuator)
            entry: dict[str, Any] = {"between": [g.base, g.point], "stroke": [s / scale for s in g.stroke]}
            if g.joint != g.name:
                entry["joint"] = g.joint
            actuators[g.name] = entry
            continue
        if ln.block:
            if isinstance(g, RRP):
                slides[_name(ln.name)] = _guide(g, g.point, g.length, g.joint, positions, ground, put, points, scale)
            elif isinstance(g, SliderTriad) and (g.block_at is not None or g.carrier is not None):
                slides[_name(ln.name)] = _moving_guide(g, st, positions, file)
            elif isinstance(g, SliderTriad):
                slides[_name(ln.name)] = _guide(g, g.points[0], max(g.lengths), g.slide, positions, ground, put,
                                                points, scale)
            elif isinstance(g, Slotted):
                slides[_name(ln.name)] = {"point": g.through, "on": _name(g.name), "along": [g.pivot, g.points[0][0]]}
            continue
        for q in ln.points:
            if q not in points:
                put(q)
        # (an actuator's pushed link is named by the actuator in the group scene: the drawing
        # names the actuator so, and its link after it)
        links[_name(ln.name) + ("_link" if isinstance(g, Actuator) else "")] = list(ln.points)
    drivers = {str(g.input_joint()): g for g in groups if g.drives}
    order = [drivers[j] for j in (input_order or drivers) if j in drivers]
    kinds = [isinstance(g, Actuator) for g in order]
    listed = kinds != sorted(kinds)  # an actuator before a crank: list the actuators in their place
    inputs: list[Any] = []
    for g in order:
        if isinstance(g, Crank):
            inputs.append(_name(g.name) if g.joint == _name(g.name) else {"link": _name(g.name), "joint": g.joint})
        elif isinstance(g, Actuator) and listed:
            inputs.append(g.name)
    drawing: dict[str, Any] = {"points": points, "ground": ground, "links": links}
    if inputs:
        drawing["inputs"] = inputs
    if slides:
        drawing["slides"] = slides
    if actuators:
        drawing["actuators"] = actuators
    # a triad's joint (the ternary link's angle arg(E − D)) is the drawing's read-out angle of D → E
    extra = {g.joint: {"angle": [g.points[0], g.points[1]]} for g in groups
             if isinstance(g, (Triad, SliderTriad)) and g.joint}
    if extra:
        raw = {**raw, "joints": {**(raw.get("joints") or {}), **extra}}
    out: dict[str, Any] = {}
    for key, value in raw.items():
        if key in _REPLACED:
            if "drawing" not in out:
                out["drawing"] = drawing
            continue
        out[key] = value
    out.setdefault("drawing", drawing)
    return out


def _moving_guide(g: SliderTriad, st: Any, positions: Mapping[str, complex], file: str | None) -> dict[str, Any]:
    """The slide of a slider triad's variant: D on the carrying link's line (a guide on a moving
    link), or the swinging block's pivot A on the ternary link's line — drawn through two points of
    that link that lie on the line (refused where none do: the line is not a drawn line of it)."""
    block = f"{g.name}.block"
    if g.block_at is not None:
        point, link, line = g.block_at, g.name, g.points
        d, e = (complex(positions[q]) for q in g.points[:2])
        w = (e - d) / abs(e - d)
        origin, direction = d + complex(g.origin) * w, complex(g.direction) * w
    else:
        assert g.carrier is not None
        point, link = g.points[0], next(x.guide for x in st.slides if x.body == block)
        line = next(ln.points for ln in st.links if ln.name == link)
        p, q = (complex(positions[n]) for n in g.carrier)
        w = (q - p) / abs(q - p)
        origin, direction = p + complex(g.origin) * w, complex(g.direction) * w
    size = max(abs(complex(positions[n])) for n in line) + 1.0
    on = [n for n in line if abs((direction.conjugate() * (complex(positions[n]) - origin)).imag) <= 1e-12 * size]
    if len(on) < 2:
        raise SceneError(f"has no drawn form: slider triad '{g.name}': its guide passes through fewer than two points "
                         f"of {_name(link)} (give the line through two of its points)", file=file, entry="groups")
    ends = sorted(on[:2], key=lambda n: (direction.conjugate() * complex(positions[n])).real)
    entry: dict[str, Any] = {"point": point, "on": _name(link), "along": ends}
    if g.slide is not None:
        entry["joint"] = g.slide
    return entry


def _guide(g: RRP | SliderTriad, point: str, length: float, joint: str | None, positions: Mapping[str, complex],
           ground: list[str], put: Any, points: dict[str, Any], scale: float) -> dict[str, Any]:
    """The guide of an RRP (or a slider triad) as two ground points of its line: the guide's
    origin (the named fixed point when there is no offset) and a point ``length`` along it; the
    slide of ``point`` on it, with the slide's ``joint``."""
    origin = complex(g.origin)
    names = []
    for i, z in enumerate((origin, origin + complex(g.direction) * length)):
        found = [n for n in ground if complex(positions[n]) == z]
        if found:
            names.append(found[0])
            continue
        name = f"{g.name}_guide{i}"
        while name in points:
            name += "_"
        positions = {**positions, name: z}
        points[name] = [float(z.real / scale), float(z.imag / scale)]
        ground.append(name)
        names.append(name)
    entry: dict[str, Any] = {"point": point, "on": "ground", "along": names}
    if joint is not None:
        entry["joint"] = joint
    return entry

