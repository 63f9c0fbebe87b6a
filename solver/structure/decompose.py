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
taken in the order of their kind (the table's) and then of their links' names — names, not the
order the file lists them in, so the plan (and an RRR's ends: the lower-named link's first) is
the same whatever the order of the drawing's mappings; the order does not change the result.

What stops the decomposition is named (:class:`Stall`): a link, slide or actuator whose points
are all placed by other groups over-constrains the mechanism; unplaced links left over form
sub-chains whose own count (3 per link, −2 per pin to a placed body or to each other) says
whether they are free (> 0: too few inputs), over-constrained (< 0), or need a group of class 3
or more (= 0, a group of class 4 or more: the triad is a candidate, solver.structure.triad_step).

Modes from the pose (the group scenes' ``M`` conventions, docs/scenes.md): an RRR dyad's mode
is the sign of the signed area of A, B, C; an RRP's the sign of (B − A)·e; an actuator's the
sign of the area of A, C, O. A dyad drawn within ``tolerances.SINGULAR`` of its toggle
(conditioning |sin| of the angle between its links) has no mode: refused.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from functools import partial
from typing import Any, TypeVar

from .drawing import GROUND, Drawing
from .graph import body_points
from .slider_triad_step import slider_triad_candidates
from .step import ON_LINE, Step, cross, dot
from .step import refuse_toggle as _toggle
from .triad_step import triad_candidates

__all__ = ["Step", "Stall", "decompose", "cross", "dot", "ON_LINE"]

T = TypeVar("T")

@dataclass
class Stall:
    """Why the decomposition stopped: over-constrained bodies (name, count, reason) and the
    sub-chains left unplaced (their links, slides and actuators; their count; how many bodies)."""

    over: list[tuple[str, int, str]] = field(default_factory=list)
    left: list[tuple[tuple[str, ...], int, int]] = field(default_factory=list)

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
        #: the points that became known since the candidates were last looked at
        self.fresh: set[str] = set(drawing.points)
        #: which links carry each point (by name), and what to look at again when a point is placed
        self.point_links: dict[str, list[str]] = {q: [] for q in drawing.points}
        for link in sorted(drawing.links):
            for q in drawing.links[link]:
                self.point_links[q].append(link)
        self.watch: dict[str, set[tuple[str, str]]] = {q: set() for q in drawing.points}
        for link, pts in drawing.links.items():
            for q in pts:
                self.watch[q].add(("link", link))
        for sl in drawing.slides.values():
            near = {sl.point, *(q for ln in self.point_links[sl.point] for q in drawing.links[ln])}
            near.update(drawing.links.get(sl.on, ()))
            for q in near:
                self.watch[q].add(("slide", sl.name))
        for act in drawing.actuators.values():
            near = set(act.between)
            for end in act.between:
                near.update(q for ln in self.point_links[end] for q in drawing.links[ln])
            for q in near:
                self.watch[q].add(("actuator", act.name))

    def unique(self, name: str) -> str:
        out, i = name, 2
        while out in self.names:
            out, i = f"{name}_{i}", i + 1
        self.names.add(out)
        return out

    def known_on(self, link: str) -> list[str]:
        return [q for q in self.d.links[link] if q in self.known]

    def add(self, step: Step) -> None:
        """Take a group: its points are known, its links placed, and their other points follow
        as attached points."""
        self.steps.append(step)
        self.known.update(step.provides)
        self.fresh.update(step.provides)
        self.placed.update(step.links)
        for link in sorted(ln for ln in step.links if ln in self.d.links):
            _attach_link(self, link)

    def touched(self) -> list[tuple[str, str]]:
        """The links, slides and actuators whose candidates may have changed, by name."""
        out: set[tuple[str, str]] = set()
        for q in self.fresh:
            out.update(self.watch[q])
        self.fresh.clear()
        return sorted(out)


def _by_name(items: Mapping[str, T]) -> list[T]:
    """The values of a drawing's mapping in the order of their names (not the file's)."""
    return [items[k] for k in sorted(items)]


def decompose(drawing: Drawing) -> tuple[list[Step], Stall]:
    """The groups that place every point of ``drawing``, in order, and what stalled (empty when
    everything is placed). Raises a SceneError for a dyad drawn at its toggle or a slide point
    off its line.

    Incremental: a candidate group is (re)considered only when a point of what it joins becomes
    known, kept in a heap by (kind, names), and checked again when its turn comes — so a
    drawing of n links is decomposed in about n·log n steps, not n³."""
    st = _State(drawing)
    for inp in drawing.inputs:
        _crank(st, inp)
    heap: list[tuple[int, tuple[str, ...], str, str]] = []
    while True:
        for what, name in st.touched():
            _flag_over(st, what, name)
            for rank, names, _ in _candidates_of(st, what, name):
                heapq.heappush(heap, (rank, names, what, name))
        while heap:
            rank, names, what, name = heapq.heappop(heap)
            take = next((c for r, n, c in _candidates_of(st, what, name) if (r, n) == (rank, names)), None)
            if take is not None:  # (still ready: nothing it joins was placed meanwhile)
                take()
                break
        else:
            break
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

def _attach_link(st: _State, link: str) -> None:
    """Every point of a placed link not yet known: attached to its first two known points."""
    frame = st.known_on(link)[:2]
    for q in st.d.links[link]:
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

def _flag_over(st: _State, what: str, name: str) -> None:
    """A link with two placed points that no group placed, a slide whose point and line are both
    placed, an actuator with both ends placed: each over-constrains the mechanism."""
    d = st.d
    if name in st.flagged:
        return
    if what == "link" and name not in st.placed:
        k = st.known_on(name)
        if len(k) >= 2:
            st.flagged.add(name)
            st.placed.add(name)
            st.stall.over.append((name, 3 - 2 * len(k), f"{name} [{', '.join(d.links[name])}] has "
                                  f"{', '.join(k)} placed by other groups"))
            _attach_link(st, name)
    elif what == "slide" and name not in st.done_slides:
        s = d.slides[name]
        if s.point in st.known and s.on in st.placed:
            st.flagged.add(name)
            st.stall.over.append((name, -1, f"slide {name}: {s.point} and the line of {s.on} are both "
                                  "placed by other groups"))
    elif what == "actuator" and name not in st.done_actuators:
        a = d.actuators[name]
        if all(q in st.known for q in a.between):
            st.flagged.add(name)
            st.stall.over.append((name, -1, f"actuator {name}: both its ends {a.between[0]}, "
                                  f"{a.between[1]} are placed by other groups"))


# -- dyads --------------------------------------------------------------------------------------

Candidate = tuple[int, tuple[str, ...], Callable[[], None]]


def _candidates_of(st: _State, what: str, name: str) -> Iterator[Candidate]:
    """The groups ready now that involve the link, slide or actuator ``name``."""
    if what == "actuator":
        yield from _actuator_candidates(st, st.d.actuators[name])
    elif what == "slide":
        yield from _slide_candidates(st, st.d.slides[name])
    else:
        yield from _rrr_candidates(st, name)

        yield from triad_candidates(st, name)
        yield from slider_triad_candidates(st, name)


def _one_known(st: _State, link: str) -> str | None:
    if link in st.placed:
        return None
    k = st.known_on(link)
    return k[0] if len(k) == 1 else None


def _actuator_candidates(st: _State, a: Any) -> Iterator[Candidate]:
    if a.name in st.done_actuators or a.name in st.flagged:
        return
    ends = [q for q in a.between if q in st.known]
    if len(ends) != 1:
        return
    base = ends[0]
    eye = a.between[1] if base == a.between[0] else a.between[0]
    for link in st.point_links[eye]:
        pivot = _one_known(st, link)
        if pivot is not None and pivot != base:
            yield 0, (a.name, link), partial(_actuator, st, a, base, eye, link, pivot)
            return


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


def _rrr_candidates(st: _State, link: str) -> Iterator[Candidate]:
    """The RRR dyads of ``link`` with another link: each has one placed point, and they share one
    point not yet placed. The ends are ordered by the links' names."""
    d = st.d
    a = _one_known(st, link)
    if a is None:
        return
    for b in d.links[link]:
        if b in st.known:
            continue
        for other in st.point_links[b]:
            c = _one_known(st, other) if other != link else None
            if c is None or c == a:
                continue
            common = [q for q in d.links[link] if q in d.links[other] and q not in st.known]
            if len(common) == 1:
                l1, l2, e1, e2 = (link, other, a, c) if link < other else (other, link, c, a)
                yield 1, (l1, l2), partial(_rrr, st, l1, l2, e1, b, e2)


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


def _slide_candidates(st: _State, s: Any) -> Iterator[Candidate]:
    if s.name in st.done_slides or s.name in st.flagged:
        return
    if s.on == GROUND and s.point not in st.known:
        for link in st.point_links[s.point]:
            end = _one_known(st, link)
            if end is not None:
                yield 2, (link, s.name), partial(_rrp, st, s, link, end)
                return
    elif s.on != GROUND and s.point in st.known:
        pivot = _one_known(st, s.on)
        if pivot is not None:
            yield 3, (s.on, s.name), partial(_slotted, st, s, pivot)


def _off_line(st: _State, g0: str, g1: str, p: str) -> float:
    d = st.d
    e = d.points[g1] - d.points[g0]
    return cross(e / abs(e), d.points[p] - d.points[g0])


def _foot(st: _State, g0: str, g1: str, p: str) -> str:
    """The point of the line g0–g1 nearest p, as ``[x, y]`` for a message."""
    d = st.d
    a, e = d.points[g0], d.points[g1] - d.points[g0]
    z = a + e * (dot(d.points[p] - a, e) / dot(e, e))
    return f"[{z.real:.17g}, {z.imag:.17g}]"


def _rrp(st: _State, s: Any, link: str, end: str) -> None:
    d = st.d
    g0, g1 = s.along
    miss = _off_line(st, g0, g1, s.point)
    if abs(miss) > ON_LINE * d.size:
        raise d.error(f"{s.point} is drawn {abs(miss):.3g} off the line {g0}–{g1} it slides on: move it onto the "
                      f"line (to {_foot(st, g0, g1, s.point)})", f"slides.{s.name}.point")
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
    miss = _off_line(st, g0, g1, s.point)
    if abs(miss) > ON_LINE * d.size:
        raise d.error(f"{s.point} is drawn {abs(miss):.3g} off the line {g0}–{g1} it slides on: move it onto the "
                      f"line (to {_foot(st, g0, g1, s.point)})", f"slides.{s.name}.point")
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


# -- what is left ---------------------------------------------------------------------------------

def _leftover(st: _State) -> None:
    """The unplaced bodies, in sub-chains joined by unplaced points, with their own counts."""
    d = st.d
    bodies = body_points(d)
    slides_left = [s for s in _by_name(d.slides) if s.name not in st.done_slides and s.name not in st.flagged]
    acts_left = [a for a in _by_name(d.actuators) if a.name not in st.done_actuators and a.name not in st.flagged]
    free: list[str] = [ln for ln in sorted(d.links) if ln not in st.placed]
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
        st.stall.left.append((names, count, len(members)))
