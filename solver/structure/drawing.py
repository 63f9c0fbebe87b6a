"""The ``drawing:`` section of a scene file, read and validated into a :class:`Drawing`.

A drawing is the mechanism as drawn at one pose (docs/scenes.md, "The drawn form"):

```yaml
drawing:
  points: {O: [0, 0], A: [30, 40], B: [160, 120], C: [200, 0], P: [90, 150]}
  ground: [O, C]                       # the frame's points (fixed)
  links: {crank: [O, A], coupler: [A, B, P], rocker: [C, B]}
  inputs: [crank]                      # a link pinned to the ground at its first point
  slides: {piston: {point: B, on: ground, along: [G1, G2], joint: x}}
  actuators: {lift: {between: [E, F], stroke: [740, 1300], joint: stroke}}
```

``inputs`` items are a link name, or ``{link: NAME, joint: NAME}`` (the input joint's name,
default the link's), or a coupled input ``{link: NAME, follows: INPUT, ratio: r, offset: θ₀}``
whose angle is ``r·φ_INPUT + θ₀`` (``offset`` in the angle unit, default: the value that the
drawn pose gives). Every fault is one SceneError line naming the entry and what to change.
Coordinates stay in the file's length unit (the emitted group scene keeps the file's units).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

from .._fields import Entry, Units, show
from .._yaml import YamlMap
from ..errors import SceneError

__all__ = ["Drawing", "Input", "Slide", "Actuator", "read_drawing", "GROUND", "DRAWING_KEYS"]

#: The name of the frame in ``slides.on`` (and in bodies and loads): it carries the ground points.
GROUND = "ground"

#: The keys of ``drawing:``.
DRAWING_KEYS = ("points", "ground", "links", "inputs", "slides", "actuators")

_INPUT_KEYS = ("link", "joint", "follows", "ratio", "offset")
_SLIDE_KEYS = ("point", "on", "along", "joint")
_ACTUATOR_KEYS = ("between", "stroke", "joint")


@dataclass(frozen=True)
class Input:
    """A driven link: pinned to the ground at its first point; its angle (first → second point,
    from +x) is the input joint ``joint``. ``follows``: a coupled input, ``ratio·φ + offset``
    (``offset`` in rad, None: taken from the drawn pose)."""

    link: str
    joint: str
    follows: str | None = None
    ratio: float = 1.0
    offset: float | None = None


@dataclass(frozen=True)
class Slide:
    """A block pinned at ``point`` that slides on the line ``along`` of link ``on`` (or ground)."""

    name: str
    point: str
    on: str
    along: tuple[str, str]
    joint: str | None = None


@dataclass(frozen=True)
class Actuator:
    """A driven length (cylinder) between two points; the stroke |EF| is an input."""

    name: str
    between: tuple[str, str]
    stroke: tuple[float, float]  # file units
    joint: str


@dataclass(frozen=True)
class Drawing:
    """A validated drawing: coordinates in the file's length unit."""

    file: str | None
    units: Units
    points: Mapping[str, complex]
    ground: tuple[str, ...]
    links: Mapping[str, tuple[str, ...]]
    inputs: tuple[Input, ...]
    slides: Mapping[str, Slide]
    actuators: Mapping[str, Actuator]
    #: ``inputs:`` as listed: links and actuators (an actuator listed there takes that place among
    #: the scene's inputs; one not listed comes after those that are)
    order: tuple[str, ...] = ()
    #: the entries of the file, for messages with lines: ``entries["links.coupler"]``
    entries: Mapping[str, Entry] = field(default_factory=dict, compare=False, repr=False)

    @cached_property
    def size(self) -> float:
        """The drawing's size: the largest distance of a point from the first ground point."""
        o = self.points[self.ground[0]]
        return max((abs(p - o) for p in self.points.values()), default=0.0) or 1.0

    def bodies_at(self, point: str) -> list[str]:
        """The drawn links (and ground) that carry ``point``, in drawing order."""
        out = [GROUND] if point in self.ground else []
        return out + [name for name, pts in self.links.items() if point in pts]

    def error(self, message: str, entry: str = "") -> SceneError:
        """A SceneError at ``drawing.ENTRY`` (with the line where the file knows it)."""
        where = self.entries.get(entry)
        key: str | None = None
        if where is None:
            head, _, key = entry.rpartition(".")
            where = self.entries.get(head)
        if where is not None:
            return where.error(message, key or None)
        return SceneError(message, file=self.file, entry=f"drawing.{entry}" if entry else "drawing")


def read_drawing(top: Entry, units: Units) -> Drawing:
    """Validate ``top['drawing']`` (``top`` is the whole scene file's entry)."""
    d = top.child("drawing", top.raw("drawing"))
    d.expect(DRAWING_KEYS)
    entries: dict[str, Entry] = {"": d}
    points = _points(d, units, entries)
    ground = d.names("ground")
    if not ground:
        raise d.error("name at least one ground point (the frame the mechanism turns on)", "ground")
    for g in ground:
        if g not in points:
            raise d.error(f"'{g}' is not one of the points {_few(points)}", "ground")
    if len(set(ground)) != len(ground):
        raise d.error(f"names a point twice: {show(list(ground))}", "ground")
    links = _links(d, points, set(ground), entries)
    slides = _slides(d, points, set(ground), links, entries)
    actuators = _actuators(d, points, units, entries)
    names: dict[str, str] = {GROUND: "the ground"}
    for kind, group in (("link", links), ("slide", slides), ("actuator", actuators)):
        article = "an" if kind == "actuator" else "a"
        for name in group:
            if name in names:
                raise d.error(f"'{name}' names both {names[name]} and {article} {kind}: give each a name of its own",
                              kind + "s")
            names[name] = f"{article} {kind}"
    inputs, order = _inputs(d, links, actuators, set(ground), entries, units)
    _on_links(d, points, ground, links, slides, actuators)
    d.done()
    _joint_names(d, points, inputs, slides, actuators)
    return Drawing(top.file, units, points, tuple(ground), links, inputs, slides, actuators, order, entries)


def _joint_names(
    d: Entry, points: Mapping[str, complex], inputs: tuple[Input, ...], slides: Mapping[str, Slide],
    actuators: Mapping[str, Actuator],
) -> None:
    """The joints a drawing provides (inputs, slides' and actuators' joints) are named apart from
    its points and from each other (points and joints share one namespace in a scene)."""
    seen: dict[str, str] = {}
    named = [(i.joint, "inputs", f"input {i.link}") for i in inputs]
    named += [(s.joint, "slides", f"slide {s.name}") for s in slides.values() if s.joint is not None]
    named += [(a.joint, "actuators", f"actuator {a.name}") for a in actuators.values()]
    for joint, key, what in named:
        if joint in points:
            raise d.error(f"the joint '{joint}' of {what} is also a point: name the joint otherwise (joint: NAME)", key)
        if joint in seen:
            raise d.error(f"the joint '{joint}' of {what} is also the joint of {seen[joint]}: name it otherwise", key)
        seen[joint] = what


def _few(names: Any) -> str:
    shown = list(names)[:12]
    more = f" and {len(names) - 12} more" if len(names) > 12 else ""
    return ", ".join(shown) + more


def _points(d: Entry, units: Units, entries: dict[str, Entry]) -> dict[str, complex]:
    p = d.child("points", d.raw("points"))
    entries["points"] = p
    out: dict[str, complex] = {}
    for key in p.data:
        name = str(key)
        p.check_name(name, name)
        value = p.raw(key)
        if not isinstance(value, (list, tuple)) or len(value) != 2:
            raise p.error(f"must be [x, y] in the scene's length unit, got {show(value)}", name)
        xy = [p.length_value(p.as_number(v, name), name, units, positive=False) / units.length for v in value]
        out[name] = complex(xy[0], xy[1])
    if len(out) < 2:
        raise p.error("draw at least two points (a link joins two)")
    return out


def _links(
    d: Entry, points: Mapping[str, complex], ground: set[str], entries: dict[str, Entry]
) -> dict[str, tuple[str, ...]]:
    raw = d.raw("links")
    ln = d.child("links", raw)
    entries["links"] = ln
    out: dict[str, tuple[str, ...]] = {}
    apart = _coincident(points)
    for key in ln.data:
        name = str(key)
        ln.check_name(name, name)
        if name == GROUND:
            raise ln.error("'ground' is the frame: list its points under drawing.ground", name)
        pts = _point_names(ln, name, points)
        if len(pts) < 2:
            raise ln.error(
                f"a link joins at least two points, got {show(list(pts))}: add the point it is pinned at, or drop it",
                name,
            )
        if len(set(pts)) != len(pts):
            raise ln.error(f"names a point twice: {show(list(pts))}", name)
        if all(q in ground for q in pts):
            raise ln.error(
                f"joins ground points only ({', '.join(pts)}): it is part of the frame; drop it (its points are fixed)",
                name,
            )
        for i, a in enumerate(pts):
            for b in pts[i + 1 :]:
                if abs(points[a] - points[b]) <= apart:
                    raise ln.error(f"its points {a} and {b} are drawn at one place: a link's points are apart", name)
        out[name] = tuple(pts)
    if not out:
        raise ln.error("draw at least one link")
    return out


def _point_names(e: Entry, key: str, points: Mapping[str, complex]) -> tuple[str, ...]:
    """``e[key]`` as a list of drawn points (names checked once, as the points' keys)."""
    value = e.raw(key)
    if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
        raise e.error(f"must be a list of point names, got {show(value)}", key)
    for q in value:
        if q not in points:
            raise e.error(f"'{show(q, 40)}' is not one of the points {_few(points)}", key)
    return tuple(value)


def _coincident(points: Mapping[str, complex]) -> float:
    """Two points of one link closer than this are drawn at one place (1e-12 of the drawing)."""
    scale = max((abs(p) for p in points.values()), default=1.0) or 1.0
    return 1e-12 * scale


def _slides(
    d: Entry, points: Mapping[str, complex], ground: set[str], links: Mapping[str, tuple[str, ...]],
    entries: dict[str, Entry],
) -> dict[str, Slide]:
    raw = d.raw("slides", {}) or {}
    s = d.child("slides", raw)
    entries["slides"] = s
    out: dict[str, Slide] = {}
    for key in s.data:
        name = str(key)
        s.check_name(name, name)
        e = s.child(name, _on_key(s.raw(key)))
        entries[f"slides.{name}"] = e
        e.expect(_SLIDE_KEYS)
        point, on = e.name("point"), e.name("on")
        along = e.names("along", 2)
        joint = e.name("joint") if "joint" in e.data else None
        e.done()
        if point not in points:
            raise e.error(f"'{point}' is not one of the points {_few(points)}", "point")
        if on != GROUND and on not in links:
            raise e.error(f"'{on}' is neither 'ground' nor a link: {_few(links)}", "on")
        carriers = ground if on == GROUND else set(links[on])
        for g in along:
            if g not in carriers:
                what = "a ground point" if on == GROUND else f"a point of link '{on}' ({', '.join(links[on])})"
                raise e.error(f"'{g}' is not {what}: the line slid on is drawn through two points of it", "along")
        if abs(points[along[1]] - points[along[0]]) <= _coincident(points):
            raise e.error(f"{along[0]} and {along[1]} are drawn at one place: the line has no direction", "along")
        if point in carriers:
            raise e.error(f"'{point}' is a point of '{on}' itself: the block slides on it, it is not pinned to it",
                          "point")
        out[name] = Slide(name, point, on, (along[0], along[1]), joint)
    return out


def _on_key(raw: Any) -> Any:
    """``{point: B, on: ground}`` as YAML 1.1 reads it: the key ``on`` is the boolean true
    (PyYAML), taken back as ``on`` here (with its line)."""
    if not isinstance(raw, Mapping) or True not in raw or "on" in raw:
        return raw
    out = type(raw)() if isinstance(raw, YamlMap) else {}
    for k, v in raw.items():
        out["on" if k is True else k] = v
    if isinstance(raw, YamlMap) and isinstance(out, YamlMap):
        out.line = raw.line
        out.key_lines = {("on" if k is True else k): n for k, n in raw.key_lines.items()}
    return out


def _actuators(d: Entry, points: Mapping[str, complex], units: Units, entries: dict[str, Entry]) -> dict[str, Actuator]:
    raw = d.raw("actuators", {}) or {}
    a = d.child("actuators", raw)
    entries["actuators"] = a
    out: dict[str, Actuator] = {}
    for key in a.data:
        name = str(key)
        a.check_name(name, name)
        e = a.child(name, a.raw(key))
        entries[f"actuators.{name}"] = e
        e.expect(_ACTUATOR_KEYS)
        between = e.names("between", 2)
        for q in between:
            if q not in points:
                raise e.error(f"'{q}' is not one of the points {_few(points)}", "between")
        if between[0] == between[1]:
            raise e.error("an actuator joins two different points", "between")
        rs = e.raw("stroke")
        if not isinstance(rs, (list, tuple)) or len(rs) != 2:
            raise e.error(f"must be [closed, open] lengths of the actuator, got {show(rs)}", "stroke")
        sub = e.child("stroke", {"closed": rs[0], "open": rs[1]})
        lo = sub.length("closed", units) / units.length
        hi = sub.length("open", units) / units.length
        if not lo < hi:
            raise e.error(f"the closed length must be less than the open length, got [{lo:g}, {hi:g}]", "stroke")
        joint = e.name("joint", name)
        e.done()
        out[name] = Actuator(name, (between[0], between[1]), (lo, hi), joint)
    return out


def _inputs(
    d: Entry, links: Mapping[str, tuple[str, ...]], actuators: Mapping[str, Actuator], ground: set[str],
    entries: dict[str, Entry], units: Units,
) -> tuple[tuple[Input, ...], tuple[str, ...]]:
    raw = d.raw("inputs", [])
    if raw is None:
        raw = []
    if not isinstance(raw, list):
        raise d.error(f"must be a list of input links, got {show(raw)}", "inputs")
    out: list[Input] = []
    order: list[str] = []
    for i, item in enumerate(raw):
        where = f"inputs[{i}]"
        if isinstance(item, str) and item in actuators:  # its place among the inputs
            if item in order:
                raise d.error(f"'{item}' is listed twice", where)
            order.append(item)
            continue
        if isinstance(item, str) and item in links and links[item][0] in ground and links[item][1] not in ground:
            out.append(Input(item, item))  # (the plain form, checked without an entry of its own)
            order.append(item)
            continue
        if isinstance(item, str):
            e = d.child(where, {"link": item})
        else:
            e = d.child(where, item)
            e.expect(_INPUT_KEYS)
        entries[where] = e
        link = e.name("link")
        if link in actuators:
            raise e.error(f"'{link}' is an actuator: list it by its name alone (its stroke is the input)", "link")
        if link not in links:
            raise e.error(f"'{link}' is not a link: {_few(links)}", "link")
        pts = links[link]
        if pts[0] not in ground:
            raise e.error(
                f"an input link is pinned to the ground at its first point; '{pts[0]}' of {link} "
                f"[{', '.join(pts)}] is not a ground point ({', '.join(sorted(ground))}): list the ground pin first",
                "link",
            )
        if pts[1] in ground:
            raise e.error(f"the angle of {link} is read from {pts[0]} to {pts[1]}: both are ground points", "link")
        joint = e.name("joint", link)
        follows = e.name("follows") if "follows" in e.data else None
        ratio = e.number("ratio", 1.0) if follows is not None else 1.0
        offset = e.angle("offset", units, None) if follows is not None and "offset" in e.data else None
        if follows is None and ("ratio" in e.data or "offset" in e.data):
            raise e.error("a ratio or offset couples this input to another: add follows: INPUT", "follows")
        if follows is not None and not (math.isfinite(ratio) and ratio != 0.0):
            raise e.error(f"must be a non-zero number, got {show(e.raw('ratio'))}", "ratio")
        e.done()
        out.append(Input(link, joint, follows, ratio, offset))
        order.append(link)
    seen: dict[str, int] = {}
    for i, inp in enumerate(out):
        if inp.link in seen:
            raise d.error(f"'{inp.link}' is listed twice", f"inputs[{i}]")
        seen[inp.link] = i
    joints = {inp.joint for inp in out}
    for i, inp in enumerate(out):
        if inp.follows is not None and (inp.follows not in joints or inp.follows == inp.joint):
            raise d.error(f"follows '{inp.follows}', which is not another input joint: {sorted(joints)}",
                          f"inputs[{i}].follows")
    return tuple(out), tuple(order)


def _on_links(
    d: Entry, points: Mapping[str, complex], ground: tuple[str, ...], links: Mapping[str, tuple[str, ...]],
    slides: Mapping[str, Slide], actuators: Mapping[str, Actuator],
) -> None:
    """Every point is on the ground or a link (a slide's block or an actuator's end alone is
    not enough: a block carries only its pin)."""
    on = set(ground) | {q for pts in links.values() for q in pts}
    for name in points:
        if name not in on:
            used = [f"slide '{s.name}'" for s in slides.values() if name == s.point]
            used += [f"actuator '{a.name}'" for a in actuators.values() if name in a.between]
            hint = f" (it is an end of {', '.join(used)}, which needs a link to push)" if used else ""
            raise d.error(f"'{name}' is on no link{hint}: add it to a link (or to ground), or drop it", "points")
