"""From a drawn scene to the equivalent group scene: the structure found, then written as groups.

:func:`find_structure` reads the drawing, checks that it is connected and that its mobility
equals its inputs, and decomposes it (solver.structure.decompose); :func:`scene_dict_from_drawing`
writes the result as a group scene mapping — ``fixed`` (the ground points), ``groups`` (the
inputs first, in the order listed, then the decomposition's groups) — with every other
top-level key passed on, translated where the drawn form names links:

* ``bodies: {LINK: {mass, center, inertia}}`` without ``points`` gets the link's first two
  points (its frame: origin at the first, x toward the second); a slide's name its block's point;
* a link named in ``loads`` (``body``, a spring's ends) that has no body entry gets a massless one;
* a revolute read-out may name links instead of point pairs (``parent: ground`` is the first two
  ground points), and either read-out may give ``at: q₀`` — its value at the drawn pose — from
  which the offset is computed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .._fields import Entry, read_units, show
from ..errors import SceneError
from ..groups import GROUP_TYPES
from .decompose import Stall, Step, decompose, dot
from .drawing import GROUND, Drawing, read_drawing
from .graph import Mobility, check_connected, mobility

__all__ = ["Structure", "find_structure", "scene_dict_from_drawing"]

#: The top-level keys that come first in an emitted scene (the rest keep the file's order).
_HEAD = ("scene", "provenance", "description", "units")


@dataclass(frozen=True)
class Structure:
    """A drawing's structure: the drawing, its mobility count and the groups that place it."""

    drawing: Drawing
    mobility: Mobility
    steps: tuple[Step, ...]

    @property
    def drivers(self) -> tuple[Step, ...]:
        """The input groups in the scene's input order: as ``inputs:`` lists them, then the
        actuators it does not list, in the drawing's order."""
        d = self.drawing
        by: dict[str, Step] = {s.links[0]: s for s in self.steps if s.kind in ("crank", "coupled_crank")}
        joints = {a.joint: a.name for a in d.actuators.values()}
        by.update({joints[s.fields["joint"]]: s for s in self.steps if s.kind == "actuator"})
        names = [*d.order, *(a for a in d.actuators if a not in d.order)]
        return tuple(by[n] for n in names if n in by)

    @property
    def ordered(self) -> tuple[Step, ...]:
        """Every group as emitted: the inputs first, then the rest in the decomposition's order."""
        drivers = self.drivers
        return (*drivers, *(s for s in self.steps if s not in drivers))

    @property
    def inputs_drawn(self) -> dict[str, float]:
        """Each input joint's value at the drawn pose, SI (rad for a crank, m for an actuator)."""
        scale = self.drawing.units.length
        return {s.fields["joint"]: float(s.drawn or 0.0) * (scale if s.kind == "actuator" else 1.0)
                for s in self.drivers}


def find_structure(scene: Mapping[str, Any], *, source: str | None = None) -> Structure:
    """The structure of a drawn scene mapping (one with ``drawing:``); a SceneError line for
    every fault (docs/scenes.md, "The drawn form")."""
    top = Entry(scene, file=source, where="")
    for key in ("fixed", "groups"):
        if key in top.data:
            raise top.error(f"a drawn scene has no '{key}': its ground points and groups come from the drawing", key)
    units = read_units(top, done=False)
    drawing = read_drawing(top, units)
    check_connected(drawing)
    mob = mobility(drawing)
    steps, stall = decompose(drawing)
    if mob.count != mob.inputs or stall:
        raise _fault(drawing, mob, stall)
    return Structure(drawing, mob, tuple(steps))


def _fault(d: Drawing, mob: Mobility, stall: Stall) -> SceneError:
    """One line: the count against the inputs, and which parts are free, over-constrained, or
    need a group of class 3 or more."""
    names = [i.link for i in d.inputs] + list(d.actuators)
    coupled = f", {mob.coupled} coupled" if mob.coupled else ""
    head = f"mobility {mob.text()} with {mob.inputs} input(s){coupled} ({', '.join(names) or 'none'})"
    parts: list[str] = []
    for name, count, reason in stall.over:
        what = "the slide" if name in d.slides else "the actuator" if name in d.actuators else "an input"
        parts.append(f"{reason}: over-constrained ({count:+d}), drop {what} or a link")
    for links, count, bodies in stall.left:
        shown = ", ".join(links)
        if count > 0:
            more = "an input" if count == 1 else f"{count} inputs"
            parts.append(f"{shown} free (sub-chain count {count:+d}): add {more} or a link")
        elif count < 0:
            parts.append(f"{shown} over-constrained (sub-chain count {count:+d}): drop a link or a pin")
        elif bodies == 2:
            parts.append(f"{shown} form a dyad of a kind with no group yet (a slide on a moving line whose block is "
                         "pinned to a link not yet placed: an RRP dyad on a moving guide); redraw it with the guide "
                         "on the ground or as a slotted link turning about a placed point")
        else:
            parts.append(f"{shown} form a group of class 3 or more (a triad: a ternary link and three binary links), "
                         "which no group of this solver solves yet; redraw it as dyads")
    if mob.count > mob.inputs and not parts:
        parts.append("add an input")
    if mob.count < mob.inputs and not parts:
        parts.append("drop an input")
    if not d.inputs and not d.actuators:
        parts.append("list the driven link(s) under drawing.inputs")
    verdict = "does not match" if mob.count != mob.inputs else "matches"
    return d.error(f"{head} {verdict}: {'; '.join(parts)}", "inputs" if mob.count != mob.inputs else "links")


def scene_dict_from_drawing(scene: Mapping[str, Any], *, source: str | None = None) -> dict[str, Any]:
    """The group scene mapping equivalent to a drawn scene mapping (one with ``drawing:``).

    The result loads with the ordinary loader (``solver._loader.parse_scene``) and solves
    bit-identically whether it is loaded from this mapping or from a file it was written to
    (floats written with ``repr``). A SceneError line for every fault of the drawing.
    """
    st = find_structure(scene, source=source)
    for step in st.steps:
        if step.kind not in GROUP_TYPES:
            what = f"input '{step.fields['joint']}' follows '{step.fields.get('follows')}': a coupled input"
            raise st.drawing.error(f"{what} needs the '{step.kind}' group, which this solver does not have yet "
                                   "(the model importers add it)", "inputs")
    return emit(scene, st)


def emit(scene: Mapping[str, Any], st: Structure) -> dict[str, Any]:
    """The group scene of a found structure (``scene``: the drawn mapping it came from)."""
    d = st.drawing
    out: dict[str, Any] = {k: scene[k] for k in _HEAD if k in scene}
    out["fixed"] = {g: [float(d.points[g].real), float(d.points[g].imag)] for g in d.ground}
    out["groups"] = [s.entry() for s in st.ordered]
    for key, value in scene.items():
        if key in out or key == "drawing":
            continue
        if key == "joints":
            value = _joints(d, value)
        elif key == "bodies":
            value = _bodies(d, value)
        out[key] = value
    _load_bodies(d, out)
    return out


def _link_line(d: Drawing, name: str, where: str) -> list[str]:
    if name == GROUND:
        if len(d.ground) < 2:
            raise d.error(f"{where}: the ground has one point ({d.ground[0]}): name its line by two points", "")
        return [d.ground[0], d.ground[1]]
    if name in d.links:
        return list(d.links[name][:2])
    raise d.error(f"{where}: '{name}' is not a link: {', '.join(d.links)}", "")


def _joints(d: Drawing, raw: Any) -> Any:
    if not isinstance(raw, Mapping):
        return raw
    out: dict[Any, Any] = {}
    for name, spec in raw.items():
        out[name] = spec
        if not isinstance(spec, Mapping) or len(spec) != 1:
            continue
        kind, body = next(iter(spec.items()))
        if kind not in ("revolute", "prismatic") or not isinstance(body, Mapping):
            continue
        new = dict(body)
        where = f"joints.{name}.{kind}"
        if kind == "revolute":
            for side in ("parent", "child"):
                if isinstance(new.get(side), str):
                    new[side] = _link_line(d, new[side], f"{where}.{side}")
        if "at" in new:
            new = _at(d, new, kind, where)
        out[name] = {kind: new}
    return out


def _number(d: Drawing, value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SceneError(f"must be a finite number, got {show(value)}", file=d.file, entry=where)
    return float(value)


def _point(d: Drawing, name: Any, where: str) -> complex:
    if not isinstance(name, str) or name not in d.points:
        raise SceneError(f"'{show(name)}' is not a drawn point", file=d.file, entry=where)
    return d.points[name]


def _at(d: Drawing, spec: dict[str, Any], kind: str, where: str) -> dict[str, Any]:
    """``at: q₀`` (the read-out's value at the drawn pose) → the offset that gives it."""
    if "offset" in spec:
        raise SceneError("give either 'at' (the value at the drawn pose) or 'offset', not both",
                         file=d.file, entry=f"{where}.at")
    at = _number(d, spec.pop("at"), f"{where}.at")
    sign = spec.get("sign", 1)
    sign = -1.0 if sign == -1 else 1.0
    if kind == "revolute":
        p, c = spec.get("parent"), spec.get("child")
        if not (isinstance(p, list) and isinstance(c, list) and len(p) == 2 and len(c) == 2):
            return spec  # the loader names the fault
        rp = _point(d, p[1], where) - _point(d, p[0], where)
        rc = _point(d, c[1], where) - _point(d, c[0], where)
        turn = rc * rp.conjugate()
        spec["offset"] = at - sign * math.atan2(turn.imag, turn.real) / d.units.angle
        return spec
    guide, point = spec.get("guide"), spec.get("point")
    w = _point(d, point, where)
    if isinstance(guide, list) and len(guide) == 2:
        g0 = _point(d, guide[0], where)
        u = _point(d, guide[1], where) - g0
        u /= abs(u) or 1.0
    elif isinstance(guide, Mapping):
        g0 = _point(d, guide.get("through"), where)
        a = _number(d, guide.get("angle", 0.0), f"{where}.guide.angle") * d.units.angle
        u = complex(math.cos(a), math.sin(a))
    else:
        return spec
    spec["offset"] = at - sign * dot(w - g0, u)
    return spec


def _body_points(d: Drawing, name: str) -> list[str] | None:
    if name in d.links:
        return list(d.links[name][:2])
    if name in d.slides:
        return [d.slides[name].point]
    return None


def _bodies(d: Drawing, raw: Any) -> Any:
    if not isinstance(raw, Mapping):
        return raw
    out: dict[Any, Any] = {}
    for name, spec in raw.items():
        pts = _body_points(d, str(name))
        if isinstance(spec, Mapping) and "points" not in spec and pts is not None:
            spec = {"points": pts, **spec}
        out[name] = spec
    return out


def _load_bodies(d: Drawing, out: dict[str, Any]) -> None:
    """A drawn link named in ``loads`` without a body entry becomes a massless body."""
    loads = out.get("loads")
    if not isinstance(loads, list):
        return
    named: list[str] = []
    for item in loads:
        if not isinstance(item, Mapping):
            continue
        if isinstance(item.get("body"), str):
            named.append(item["body"])
        spring = item.get("spring")
        if isinstance(spring, list):
            named += [end[0] for end in spring if isinstance(end, list) and end and isinstance(end[0], str)]
    bodies = out.get("bodies")
    have = set(bodies) if isinstance(bodies, Mapping) else set()
    add = {n: {"points": _body_points(d, n)} for n in dict.fromkeys(named) if n not in have and _body_points(d, n)}
    if add:
        out["bodies"] = {**(bodies if isinstance(bodies, Mapping) else {}), **add}

