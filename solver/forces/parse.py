"""``bodies``, ``gravity`` and ``loads`` of a scene file → :class:`~.spec.ForceSpec`.

Every fault is one SceneError line naming the key and the reason (docs/forces.md): a negative or
non-finite mass or inertia, a body whose points are not one link, two bodies for one link, a
load on an unknown body or at a point not on it, gravity of the wrong length, a bad table.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from .._fields import Entry, Units, show, suggest
from ..groups import Actuator, Group
from ..plan import order_groups
from .friction_spec import parse_friction
from .parse_drive import DRIVE_KEYS, parse_drive
from .spec import Body, ForceSpec, Load, PointForce, Spring, TableForce, Torque
from .structure import GROUND, Link, StructureFault, derive_structure

__all__ = ["FORCE_KEYS", "parse_forces", "MASS_MAX", "FORCE_MAX"]

#: The top-level keys of the force layer (with the drive's: motor, flywheel, damping).
FORCE_KEYS = ("bodies", "gravity", "loads", *DRIVE_KEYS, "friction")

#: Largest mass (kg), inertia (kg·m²), |force| (N), |torque| (N·m), stiffness (N/m), |gravity|
#: (m/s²): far beyond any machine, small enough that products with lengths ≤ 1e9 m and their
#: analogs stay finite in float64.
MASS_MAX = 1e12
FORCE_MAX = 1e12

_BODY_KEYS = ("points", "mass", "center", "inertia")
_LOAD_KEYS = ("body", "point", "force", "torque", "spring", "stiffness", "free_length", "direction", "table")


def parse_forces(top: Entry, units: Units, fixed: Mapping[str, Any], groups: Sequence[Group]) -> ForceSpec | None:
    """The force layer of a scene, or None when it names none of ``bodies``, ``gravity``, ``loads``
    (then nothing else is done: a scene without them loads as before)."""
    if not any(k in top.data for k in FORCE_KEYS):
        return None
    present = [k for k in FORCE_KEYS if k in top.data]
    joints = {n: u for g in groups for n, u in g.joint_units().items()}
    try:
        structure = derive_structure(order_groups(groups, fixed, file=top.file), fixed)
    except StructureFault as exc:
        raise top.error(str(exc), present[0]) from None
    bodies, names = _bodies(top, structure.links, units, structure.massless)
    gravity = _gravity(top)
    motors, flywheels, bodies, dampers = parse_drive(top, groups, bodies)
    spec = ForceSpec(structure, bodies, gravity, (), names)
    loads = _loads(top, spec, units, joints)
    actuators = {g.name: g.joint for g in groups if isinstance(g, Actuator)}
    friction = parse_friction(top, units, structure, names, actuators)
    return ForceSpec(structure, bodies, gravity, (*loads, *dampers), names, motors, flywheels, friction)


def _nonnegative(e: Entry, key: str, limit: float) -> float:
    value = e.number(key, 0.0)
    if value < 0.0:
        raise e.error(f"must not be negative, got {value}", key)
    if value > limit:
        raise e.error(f"{value:g} is beyond {limit:g}", key)
    return value


def _vector(e: Entry, key: str, limit: float) -> complex:
    raw = e.raw(key)
    if not isinstance(raw, (list, tuple)) or len(raw) != 2:
        raise e.error(f"must be [x, y] (a planar vector), got {show(raw)}", key)
    xy = e.child(key, {"x": raw[0], "y": raw[1]})  # a bad component is named: force.x, center.y
    x, y = xy.number("x"), xy.number("y")
    if abs(x) > limit or abs(y) > limit:
        raise e.error(f"{show(raw)} has a component beyond ±{limit:g}", key)
    return complex(x, y)


def _unknown_body(body: str, known: Sequence[str]) -> str:
    """``unknown body 'rockr' (did you mean 'rocker'?); bodies: …``."""
    near = suggest(body, known)
    hint = f" (did you mean '{near[0]}'?)" if near else ""
    return f"unknown body '{body}'{hint}; bodies: {', '.join(known)}"


def _links_text(links: Sequence[Link]) -> str:
    return "; ".join(f"{ln.name} [{', '.join(ln.points)}]" for ln in links)


def _bodies(
    top: Entry, links: Sequence[Link], units: Units, massless: frozenset[str] = frozenset()
) -> tuple[tuple[Body, ...], dict[str, str]]:
    raw = top.raw("bodies", {}) or {}
    b = top.child("bodies", raw)
    named: dict[str, Body] = {}  # link name → body
    names: dict[str, str] = {}
    defaults = {ln.name for ln in links}
    for key in b.data:
        name = str(key)
        e = b.child(name, b.raw(key))
        b.check_name(name, name)
        e.expect(_BODY_KEYS)
        if name == GROUND:
            raise b.error("'ground' is the frame: it carries the fixed points and is never solved", name)
        pts = e.names("points")
        if not pts:
            raise e.error("name the body's points: two (origin, x axis), or a slider block's one point", "points")
        link = _find_link(e, pts, links)
        if link.name in named:
            raise e.error(f"two bodies for one link ({_links_text([link])}): '{named[link.name].name}' and '{name}'",
                          "points")
        if name in defaults and name != link.name:
            raise b.error(f"'{name}' is the default name of another link ({_links_text(links)})", name)
        center = _vector(e, "center", math.inf) if "center" in e.data else 0j
        cx = e.length_value(center.real, "center", units, positive=False)
        cy = e.length_value(center.imag, "center", units, positive=False)
        mass = _nonnegative(e, "mass", MASS_MAX)
        inertia = _nonnegative(e, "inertia", MASS_MAX)
        if link.name in massless and (mass or inertia):
            raise e.error(f"{_links_text([link])} is an actuator's cylinder, a massless two-force member: lump "
                          "its barrel's and rod's masses into the links it is pinned to", "mass")
        e.done()
        frame = pts[:2] if len(pts) >= 2 else pts
        named[link.name] = Body(name, link, frame, mass, complex(cx, cy), inertia)
        names[link.name] = name
    out = tuple(named.get(ln.name) or Body(ln.name, ln, ln.points[:1] if ln.block else ln.points[:2]) for ln in links)
    return out, names


def _find_link(e: Entry, pts: Sequence[str], links: Sequence[Link]) -> Link:
    if len(set(pts)) != len(pts):
        raise e.error(f"names a point twice: {show(list(pts))}", "points")
    if len(pts) == 1:
        blocks = [ln for ln in links if ln.block and ln.points[0] == pts[0]]
        if not blocks:
            raise e.error(
                f"a body named by one point is a slider block; '{pts[0]}' is the pin of none (links: "
                f"{_links_text(links)})",
                "points",
            )
        return blocks[0]
    found = [ln for ln in links if not ln.block and set(pts) <= set(ln.points)]
    if not found:
        raise e.error(f"{show(list(pts))} are not points of one link of the scene; links: {_links_text(links)}",
                      "points")
    return found[0]


def _gravity(top: Entry) -> complex:
    if "gravity" not in top.data:
        return 0j
    raw = top.raw("gravity")
    if not isinstance(raw, (list, tuple)) or len(raw) != 2:
        n = f"{len(raw)} components" if isinstance(raw, (list, tuple)) else show(raw)
        raise top.error(f"must be [gx, gy] in m/s² (planar scenes), got {n}", "gravity")
    sub = top.child("gravity", {"x": raw[0], "y": raw[1]})
    g = complex(sub.number("x"), sub.number("y"))
    if abs(g) > FORCE_MAX:
        raise top.error(f"|g| = {abs(g):g} m/s² is beyond {FORCE_MAX:g}", "gravity")
    return g


def _loads(top: Entry, spec: ForceSpec, units: Units, joints: Mapping[str, str]) -> tuple[Load, ...]:
    raw = top.raw("loads", []) or []
    if not isinstance(raw, list):
        raise top.error(f"must be a list of loads, got {show(raw)}", "loads")
    out: list[Load] = []
    for i, item in enumerate(raw):
        e = top.child(f"loads[{i}]", item)
        e.expect(_LOAD_KEYS)
        kinds = [k for k in ("force", "torque", "spring", "table") if k in e.data]
        if len(kinds) != 1:
            raise e.error(f"a load is one of force, torque, spring or table; got {', '.join(kinds) or 'none'}")
        out.append(_LOAD_READERS[kinds[0]](e, spec, units, joints))
        e.done()
    return tuple(out)


def _body_point(e: Entry, spec: ForceSpec, body: str, point: str | None, key: str = "body") -> None:
    known = [b.name for b in spec.bodies]
    if body == GROUND:
        if point is None or not spec.carries(GROUND, point):
            raise e.error("ground is never solved: a load on it changes nothing (springs may end on it, at a "
                          "fixed point)", key)
        return
    b = spec.body(body)
    if b is None:
        raise e.error(_unknown_body(body, known), key)
    if point is not None and point not in b.points:
        raise e.error(f"'{point}' is not a point of body '{body}' ({', '.join(b.points)})", "point")
    if b.link.name in spec.structure.massless:
        raise e.error(f"body '{body}' is an actuator's cylinder, a massless two-force member: put the load on "
                      "a link it is pinned to", key)


def _force(e: Entry, spec: ForceSpec, units: Units, joints: Mapping[str, str]) -> Load:
    body, point = e.name("body"), e.name("point")
    if body == GROUND:
        raise e.error("ground is never solved: a force on it changes nothing", "body")
    _body_point(e, spec, body, point)
    return PointForce(body, point, _vector(e, "force", FORCE_MAX))


def _torque(e: Entry, spec: ForceSpec, units: Units, joints: Mapping[str, str]) -> Load:
    body = e.name("body")
    if body == GROUND:
        raise e.error("ground is never solved: a torque on it changes nothing", "body")
    _body_point(e, spec, body, None)
    t = e.number("torque")
    if abs(t) > FORCE_MAX:
        raise e.error(f"{t:g} N·m is beyond ±{FORCE_MAX:g}", "torque")
    return Torque(body, t)


def _spring(e: Entry, spec: ForceSpec, units: Units, joints: Mapping[str, str]) -> Load:
    raw = e.raw("spring")
    ok = isinstance(raw, (list, tuple)) and len(raw) == 2
    ok = ok and all(isinstance(x, (list, tuple)) and len(x) == 2 and all(isinstance(s, str) for s in x) for x in raw)
    if not ok:
        raise e.error(f"must be [[body, point], [body, point]] (its two ends), got {show(raw)}", "spring")
    ends = ((str(raw[0][0]), str(raw[0][1])), (str(raw[1][0]), str(raw[1][1])))
    for body, point in ends:
        b = spec.body(body)
        if body != GROUND and b is None:
            raise e.error(_unknown_body(body, [*(x.name for x in spec.bodies), GROUND]), "spring")
        if not spec.carries(body, point):
            raise e.error(f"'{point}' is not a point of body '{body}'", "spring")
    if ends[0][0] == ends[1][0]:
        raise e.error(f"both ends on body '{ends[0][0]}': a spring within one rigid body does nothing", "spring")
    k = _nonnegative(e, "stiffness", FORCE_MAX)
    free = e.length("free_length", units, positive=False, default=0.0)
    if free < 0.0:
        raise e.error(f"must not be negative, got {free / units.length:g}", "free_length")
    return Spring(ends, k, free)


def _table(e: Entry, spec: ForceSpec, units: Units, joints: Mapping[str, str]) -> Load:
    body, point = e.name("body"), e.name("point")
    _body_point(e, spec, body, point)
    direction = _vector(e, "direction", math.inf)
    if direction == 0:
        raise e.error("must not be [0, 0]: the force's direction", "direction")
    t = e.child("table", e.raw("table"))
    t.expect(("of", "at", "force", "period"))
    joint = t.name("of")
    if joint not in joints:
        near = suggest(joint, sorted(joints))
        hint = f" (did you mean '{near[0]}'?)" if near else ""
        raise t.error(f"unknown joint '{joint}'{hint}; joints: {', '.join(sorted(joints))}", "of")
    at_raw, f_raw = t.raw("at"), t.raw("force")
    for key, value in (("at", at_raw), ("force", f_raw)):
        if not isinstance(value, (list, tuple)) or len(value) < 2:
            raise t.error(f"must be a list of at least two numbers, got {show(value)}", key)
    if len(at_raw) != len(f_raw):
        raise t.error(f"has {len(f_raw)} values for {len(at_raw)} positions in 'at'", "force")
    angle = joints[joint] == "rad"
    scale = units.angle if angle else units.length
    at = tuple(t.as_number(v, "at") * scale for v in at_raw)
    force = tuple(t.as_number(v, "force") for v in f_raw)
    if any(b <= a for a, b in zip(at, at[1:])):
        raise t.error("positions must increase strictly", "at")
    if any(abs(f) > FORCE_MAX for f in force):
        raise t.error(f"a force beyond ±{FORCE_MAX:g} N", "force")
    period = _period(t, at, scale) if angle else None
    t.done()
    return TableForce(body, point, direction / abs(direction), joint, at, force, period)


def _period(t: Entry, at: tuple[float, ...], scale: float) -> float:
    """A table of an angle repeats every ``period`` (the scene's angle unit; one turn unless said:
    a four-stroke engine's cycle is 720°); its entries must lie within one period."""
    if "period" not in t.data:
        return 2.0 * math.pi
    period = t.number("period") * scale
    if not period > 0.0 or not math.isfinite(period):
        raise t.error(f"must be a positive angle, got {t.raw('period')!r}", "period")
    if at[-1] - at[0] > period:
        raise t.error(f"the table spans {(at[-1] - at[0]) / scale:g}, more than one period", "period")
    return period


_LOAD_READERS = {"force": _force, "torque": _torque, "spring": _spring, "table": _table}
