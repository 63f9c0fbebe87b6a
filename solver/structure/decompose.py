"""The Assur decomposition of a drawing: the groups, in order, that place every point.

Known at the start: the ground's points. The inputs come first: a crank (an input link pinned to
the ground at its first point) places its second point. Then, repeatedly, the smallest group
whose outer joints are all known and which adds no freedom is taken — a dyad:

===========  ===============================================================  ==============
group        in the drawing                                                   emitted as
===========  ===============================================================  ==============
actuator     a cylinder between a known point and a point of a link with one  ``actuator``
             known point (the pushed link's pivot)
RRR          a point on two unplaced links, each with one known point         ``rrr``
RRP          a slide on a ground line whose point is on an unplaced link      ``rrp``
             with one known point (the rod)
RPR          a slide, its point known, on an unplaced link with one known     ``slotted``
             point on the slide's line (the link's pivot)
===========  ===============================================================  ==============

— and every point of a link that a group has placed follows as an ``attached`` point (distance
and angle from the link's first two placed points). When several groups are ready, they are
taken in the order of their kind (the table's) and then of their links' names, so the plan is
the same every time; the order does not change the result.

What stops the decomposition is named (:class:`Stall`): a link, slide or actuator whose points
are all placed by other groups over-constrains the mechanism; unplaced links left over form
sub-chains whose own count (3 per link, −2 per pin to a placed body or to each other) says
whether they are free (> 0: too few inputs), over-constrained (< 0), or need a group of class 3
or more (= 0: a triad, which is one more entry in ``_CANDIDATES``).

Modes from the pose (the group scenes' ``M`` conventions, docs/scenes.md): an RRR dyad's mode
is the sign of the signed area of A, B, C; an RRP's the sign of (B − A)·e; an actuator's the
sign of the area of A, C, O. A dyad drawn within ``tolerances.SINGULAR`` of its toggle
(conditioning |sin| of the angle between its links) has no mode: refused.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from functools import partial
from typing import Any

from ..tolerances import SINGULAR
from .drawing import GROUND, Drawing
from .graph import body_points

__all__ = ["Step", "Stall", "decompose", "cross", "dot", "ON_LINE"]

#: A slide's point farther than this from its line, relative to the drawing's size, is off it.
ON_LINE = 1e-9


def cross(a: complex, b: complex) -> float:
    return a.real * b.imag - a.imag * b.real


def dot(a: complex, b: complex) -> float:
    return a.real * b.real + a.imag * b.imag


@dataclass(frozen=True)
class Step:
    """One group of the decomposition: ``kind`` (a group type of the scene files), its ``name``,
    the drawn bodies it places (``links``), the points it provides, its ``fields`` as a group
    entry in the file's units (without ``type`` and ``name``), its assembly mode and its
    conditioning at the drawn pose (1 well conditioned, 0 a toggle), where it has them."""

    kind: str
    name: str
    links: tuple[str, ...]
    provides: tuple[str, ...]
    fields: dict[str, Any]
    mode: int | None = None
    conditioning: float | None = None
    #: the input's value at the drawn pose (rad for a crank, file length unit for an actuator)
    drawn: float | None = None

    def entry(self) -> dict[str, Any]:
        """The group entry of a scene file: ``{type, name, **fields}``."""
        return {"type": self.kind, "name": self.name, **self.fields}


@dataclass
class Stall:
    """Why the decomposition stopped: over-constrained bodies (name, count, reason) and the
    sub-chains left unplaced (their links and count)."""

    over: list[tuple[str, int, str]] = field(default_factory=list)
    left: list[tuple[tuple[str, ...], int]] = field(default_factory=list)

    def __bool__(self) -> bool:
        return bool(self.over or self.left)


class _State:
    def __init__(self, drawing: Drawing) -> None:
        self.d = drawing
        self.known: set[str] = set(drawing.ground)
        self.placed: set[str] = {GROUND}
        self.steps: list[Step] = []
        self.names: set[str] = set()
        self.stall = Stall()
        self.flagged: set[str] = set()
        self.done_slides: set[str] = set()
        self.done_actuators: set[str] = set()

    def unique(self, name: str) -> str:
        out, i = name, 2
        while out in self.names:
            out, i = f"{name}_{i}", i + 1
        self.names.add(out)
        return out

    def known_on(self, link: str) -> list[str]:
        return [q for q in self.d.links[link] if q in self.known]

    def add(self, step: Step) -> None:
        self.steps.append(step)
        self.known.update(step.provides)
        self.placed.update(step.links)


def decompose(drawing: Drawing) -> tuple[list[Step], Stall]:
    """The groups that place every point of ``drawing``, in order, and what stalled (empty when
    everything is placed). Raises a SceneError for a dyad drawn at its toggle or a slide point
    off its line."""
    st = _State(drawing)
    for inp in drawing.inputs:
        _crank(st, inp)
    while True:
        _attach_all(st)
        _flag_over(st)
        ready = sorted(_candidates(st), key=lambda c: (c[0], c[1]))
        if not ready:
            break
        ready[0][2]()
    _leftover(st)
    return st.steps, st.stall


# -- inputs -----------------------------------------------------------------------------------

def _crank(st: _State, inp: Any) -> None:
    d = st.d
    pts = d.links[inp.link]
    o, a = pts[0], pts[1]
    arm = d.points[a] - d.points[o]
    phi = math.atan2(arm.imag, arm.real)
    fields: dict[str, Any] = {"center": o, "point": a, "length": abs(arm), "joint": inp.joint}
    kind = "crank"
    if inp.follows is not None:
        kind = "coupled_crank"
        lead = next(i for i in d.inputs if i.joint == inp.follows)
        lp = d.links[lead.link]
        lead_arm = d.points[lp[1]] - d.points[lp[0]]
        offset = inp.offset
        if offset is None:
            offset = phi - inp.ratio * math.atan2(lead_arm.imag, lead_arm.real)
        fields.update(follows=inp.follows, ratio=inp.ratio, offset=offset / d.units.angle)
    if a in st.known:
        st.stall.over.append((inp.link, -1, f"input {inp.link} drives {a}, which another input already places"))
        return
    st.add(Step(kind, st.unique(inp.link), (inp.link,), (a,), fields, drawn=phi))


# -- attached points ----------------------------------------------------------------------------

def _attach_all(st: _State) -> None:
    for link, pts in st.d.links.items():
        if link not in st.placed:
            continue
        frame = st.known_on(link)[:2]
        for q in pts:
            if q not in st.known:
                _attach(st, link, frame, q)


def _attach(st: _State, link: str, frame: list[str], p: str) -> None:
    d = st.d
    r, q = frame
    base = r
    if abs(d.points[p] - d.points[r]) <= 1e-12 * d.size:
        base = q
    along = d.points[q] - d.points[r]
    arm = d.points[p] - d.points[base]
    turn = arm / along
    angle = math.atan2(turn.imag, turn.real)
    fields: dict[str, Any] = {"point": p, "base": base, "along": [r, q], "distance": abs(arm),
                              "angle": angle / d.units.angle}
    st.add(Step("attached", st.unique(f"{link}_{p}"), (), (p,), fields))


# -- over-constraint ------------------------------------------------------------------------------

def _flag_over(st: _State) -> None:
    d = st.d
    for link in d.links:
        if link in st.placed or link in st.flagged:
            continue
        k = st.known_on(link)
        if len(k) >= 2:
            st.flagged.add(link)
            st.placed.add(link)
            st.stall.over.append((link, 3 - 2 * len(k), f"{link} [{', '.join(d.links[link])}] has "
                                  f"{', '.join(k)} placed by other groups"))
    for s in d.slides.values():
        if s.name in st.done_slides or s.name in st.flagged:
            continue
        if s.point in st.known and s.on in st.placed:
            st.flagged.add(s.name)
            st.stall.over.append((s.name, -1, f"slide {s.name}: {s.point} and the line of {s.on} are both "
                                  "placed by other groups"))
    for a in d.actuators.values():
        if a.name in st.done_actuators or a.name in st.flagged:
            continue
        if all(q in st.known for q in a.between):
            st.flagged.add(a.name)
            st.stall.over.append((a.name, -1, f"actuator {a.name}: both its ends {a.between[0]}, "
                                  f"{a.between[1]} are placed by other groups"))


# -- dyads --------------------------------------------------------------------------------------

Candidate = tuple[int, tuple[str, ...], Callable[[], None]]


def _candidates(st: _State) -> Iterator[Candidate]:
    yield from _actuator_candidates(st)
    yield from _rrr_candidates(st)
    yield from _slide_candidates(st)


def _one_known(st: _State, link: str) -> str | None:
    if link in st.placed:
        return None
    k = st.known_on(link)
    return k[0] if len(k) == 1 else None


def _actuator_candidates(st: _State) -> Iterator[Candidate]:
    d = st.d
    for a in d.actuators.values():
        if a.name in st.done_actuators or a.name in st.flagged:
            continue
        ends = [q for q in a.between if q in st.known]
        if len(ends) != 1:
            continue
        base = ends[0]
        eye = a.between[1] if base == a.between[0] else a.between[0]
        for link in d.links:
            if eye in d.links[link]:
                pivot = _one_known(st, link)
                if pivot is not None and pivot != base:
                    yield 0, (a.name, link), partial(_actuator, st, a, base, eye, link, pivot)
                    break


def _actuator(st: _State, a: Any, base: str, eye: str, link: str, pivot: str) -> None:
    d = st.d
    pa, pc, po = d.points[base], d.points[eye], d.points[pivot]
    p, q = pc - pa, pc - po
    s, length = abs(p), abs(q)
    cond = abs(cross(p, q)) / (s * length)
    _toggle(st, cond, f"actuators.{a.name}", f"actuator {a.name} is drawn aligned with the link {link} it pushes "
            f"({base}, {eye}, {pivot} in a line)")
    mode = 1 if cross(pc - pa, po - pa) > 0.0 else -1
    lo, hi = a.stroke
    if not lo <= s <= hi:
        raise d.error(f"drawn at the length {s:.6g} between {base} and {eye}, outside its stroke [{lo:g}, {hi:g}]: "
                      "move a point or widen the stroke", f"actuators.{a.name}.stroke")
    fields: dict[str, Any] = {"base": base, "point": eye, "pivot": pivot, "length": length, "M": mode,
                              "joint": a.joint, "stroke": [lo, hi]}
    st.done_actuators.add(a.name)
    st.add(Step("actuator", st.unique(a.name), (link,), (eye,), fields, mode, cond, drawn=s))


def _rrr_candidates(st: _State) -> Iterator[Candidate]:
    d = st.d
    links = list(d.links)
    for i, l1 in enumerate(links):
        a = _one_known(st, l1)
        if a is None:
            continue
        for l2 in links[i + 1 :]:
            c = _one_known(st, l2)
            if c is None or c == a:
                continue
            common = [q for q in d.links[l1] if q in d.links[l2] and q not in st.known]
            if len(common) == 1:
                b = common[0]
                yield 1, (l1, l2), partial(_rrr, st, l1, l2, a, b, c)


def _rrr(st: _State, l1: str, l2: str, a: str, b: str, c: str) -> None:
    d = st.d
    pa, pb, pc = d.points[a], d.points[b], d.points[c]
    p, q = pb - pa, pb - pc
    l_1, l_2 = abs(p), abs(q)
    cond = abs(cross(p, q)) / (l_1 * l_2)
    _toggle(st, cond, f"links.{l2}", f"the dyad {l1}–{l2} is drawn at its toggle ({a}, {b}, {c} in a line)")
    mode = 1 if cross(pb - pa, pc - pa) > 0.0 else -1
    fields = {"ends": [a, c], "point": b, "lengths": [l_1, l_2], "M": mode}
    st.add(Step("rrr", st.unique(f"{l1}_{l2}"), (l1, l2), (b,), fields, mode, cond))


def _slide_candidates(st: _State) -> Iterator[Candidate]:
    d = st.d
    for s in d.slides.values():
        if s.name in st.done_slides or s.name in st.flagged:
            continue
        if s.on == GROUND and s.point not in st.known:
            for link in d.links:
                if s.point in d.links[link]:
                    end = _one_known(st, link)
                    if end is not None:
                        yield 2, (link, s.name), partial(_rrp, st, s, link, end)
                        break
        elif s.on != GROUND and s.point in st.known:
            pivot = _one_known(st, s.on)
            if pivot is not None:
                yield 3, (s.on, s.name), partial(_slotted, st, s, pivot)


def _off_line(st: _State, g0: str, g1: str, p: str) -> float:
    d = st.d
    e = d.points[g1] - d.points[g0]
    return cross(e / abs(e), d.points[p] - d.points[g0])


def _rrp(st: _State, s: Any, link: str, end: str) -> None:
    d = st.d
    g0, g1 = s.along
    miss = _off_line(st, g0, g1, s.point)
    if abs(miss) > ON_LINE * d.size:
        raise d.error(f"{s.point} is drawn {abs(miss):.3g} off the line {g0}–{g1} it slides on: move it onto the "
                      "line", f"slides.{s.name}.point")
    e = d.points[g1] - d.points[g0]
    e /= abs(e)
    pa, pb = d.points[end], d.points[s.point]
    p = pb - pa
    length = abs(p)
    cond = abs(dot(e, p)) / length
    _toggle(st, cond, f"slides.{s.name}", f"the rod {link} is drawn perpendicular to the line of slide {s.name} "
            "(its toggle)")
    mode = 1 if dot(p, e) >= 0.0 else -1
    angle = math.atan2(e.imag, e.real)
    fields: dict[str, Any] = {"end": end, "point": s.point, "length": length,
                              "guide": {"through": g0, "angle": angle / d.units.angle}, "M": mode}
    if s.joint is not None:
        fields["joint"] = s.joint
    st.done_slides.add(s.name)
    st.add(Step("rrp", st.unique(link), (link, s.name), (s.point,), fields, mode, cond))


def _slotted(st: _State, s: Any, pivot: str) -> None:
    d = st.d
    g0, g1 = s.along
    if abs(_off_line(st, g0, g1, pivot)) > ON_LINE * d.size:
        raise d.error(f"the line {g0}–{g1} does not pass through {pivot}, the pin {s.on} turns about: a slot offset "
                      "from the pivot has no group yet; draw the slot through the pivot", f"slides.{s.name}.along")
    po, pb = d.points[pivot], d.points[s.point]
    if abs(_off_line(st, g0, g1, s.point)) > ON_LINE * d.size:
        raise d.error(f"{s.point} is drawn off the line {g0}–{g1} it slides on: move it onto the line",
                      f"slides.{s.name}.point")
    r = pb - po
    rho = abs(r)
    u = r / rho if rho > 0.0 else 0j
    on_line: list[tuple[str, float]] = []
    for q in d.links[s.on]:
        if q == pivot:
            continue
        if abs(_off_line(st, g0, g1, q)) <= ON_LINE * d.size:
            on_line.append((q, dot(d.points[q] - po, u)))
    scale = max(abs(x) for _, x in on_line)
    cond = min(rho / scale, 1.0)
    _toggle(st, cond, f"slides.{s.name}", f"{s.point} is drawn on the pivot {pivot} of {s.on}")
    fields = {"pivot": pivot, "through": s.point, "points": dict(on_line)}
    st.done_slides.add(s.name)
    st.add(Step("slotted", st.unique(s.on), (s.on, s.name), tuple(q for q, _ in on_line), fields, None, cond))


def _toggle(st: _State, cond: float, entry: str, what: str) -> None:
    if not cond >= SINGULAR:
        raise st.d.error(f"{what}: its assembly mode is undefined there (conditioning {cond:.2g}); draw it in the "
                         "assembly it is meant to run in", entry)


# -- what is left ---------------------------------------------------------------------------------

def _leftover(st: _State) -> None:
    """The unplaced bodies, in sub-chains joined by unplaced points, with their own counts."""
    d = st.d
    bodies = body_points(d)
    slides_left = [s for s in d.slides.values() if s.name not in st.done_slides and s.name not in st.flagged]
    acts_left = [a for a in d.actuators.values() if a.name not in st.done_actuators and a.name not in st.flagged]
    free: list[str] = [ln for ln in d.links if ln not in st.placed]
    free += [f"{s.name}.block" for s in slides_left]
    for a in acts_left:
        free += [f"{a.name}.barrel", f"{a.name}.rod"]
    if not free:
        return
    parent = {b: b for b in free}

    def find(b: str) -> str:
        while parent[b] != b:
            parent[b] = parent[parent[b]]
            b = parent[b]
        return b

    at: dict[str, str] = {}
    for b in free:
        for q in bodies[b]:
            if q in st.known:
                continue
            if q in at:
                ra, rb = find(at[q]), find(b)
                if ra != rb:
                    parent[max(ra, rb)] = min(ra, rb)
            else:
                at[q] = b
    for s in slides_left:
        if s.on in parent:
            ra, rb = find(f"{s.name}.block"), find(s.on)
            parent[max(ra, rb)] = min(ra, rb)
    for a in acts_left:
        ra, rb = find(f"{a.name}.barrel"), find(f"{a.name}.rod")
        parent[max(ra, rb)] = min(ra, rb)
    chains: dict[str, list[str]] = {}
    for b in free:
        chains.setdefault(find(b), []).append(b)
    for members in chains.values():
        count = 3 * len(members)
        holders: dict[str, int] = {}
        for b in members:
            for q in bodies[b]:
                holders[q] = holders.get(q, 0) + 1
        for q, k in holders.items():
            count -= 2 * (k if q in st.known else k - 1)  # a placed point pins each body to what placed it
        for s in slides_left:
            if f"{s.name}.block" in members:
                count -= 2
        for a in acts_left:
            if f"{a.name}.barrel" in members:
                count -= 3  # the rod's slide in the barrel, and its stroke: an input
        names = tuple(dict.fromkeys(b.split(".")[0] for b in members))
        st.stall.left.append((names, count))
