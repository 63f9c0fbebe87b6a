"""Independent 50-digit Newton–Euler reference for the force layer (issue 17): mpmath + PyYAML only.

This module never imports the solver and shares none of its formulas. From a scene file it reads
the topology (fixed points, groups, bodies, gravity, loads) with plain PyYAML, then at
``mp.dps = 50``:

* positions in closed form, group by group (circle intersections, a line and a circle, points on
  a line), written here afresh;
* real accelerations by mpmath's numerical differentiation ``mp.diff`` in time along the motion
  q(t) = q₀ + ω·t + ε·t²/2 of every input (so several inputs need no Jacobian or Hessian);
* the Newton–Euler equations of EVERY moving body (force balance, moment balance about the body's
  frame origin, with m·a_G and I·α) as one linear system in all the unknowns at once: the pin
  forces, the normal force and couple of every prismatic pair, and the input effort of every
  crank; solved by LU at 50 digits.

Model (what a mechanism designer expects, and what issue 17 says): pins and slides are
frictionless; a slider block (rrp) is a body pinned to its rod at its point and sliding on the
fixed guide; a slotted link (slotted) carries a block pinned at ``through`` on the body that
carries that point and sliding along the link; each sliding pair acts on its block with a force
normal to the guide and a couple about the block's point (the opposite on the guide's body). A
link without a ``bodies`` entry is massless (a slot's block too, unless a body names its point).
An input effort is the torque about +z the actuator applies to its crank (the opposite torque on
the ground). ``R(P, on=X)`` is the force on body X at pin P from the other body. Unnamed links
take the solver's default names (a crank's or slotted link's group name, ``name.1`` / ``name.2``
for an RRR's links, ``name.block`` for a block; a triad's ternary link ``name`` and binary links
``name.1`` … ``name.3``; a slider triad's ternary link ``name``, binary links ``name.2``,
``name.3`` and block ``name.block``): topology is shared, formulas are not. A triad (one input, drawn by its
``shape`` at ``at``) is solved by ``findroot`` on its three loop equations, continued from the
drawn pose in steps of ≤ 0.25° of the input (the mode drawn, followed as the scene follows it);
a slider triad alike, on its two loop equations in (s, θ).

Loads: a force at a point, a torque, a spring ``[[body, point], [body, point]]`` (tension
k·(ℓ − ℓ₀), ends on ground allowed), a force of fixed direction whose size is read off a table of a
joint's coordinate (linear, constant beyond the ends; an angle wrapped into [at₀, at₀ + period),
``period`` in the scene's angle unit, one turn unless given: 720° for a four-stroke engine).

Drive (issue 22; ``motor`` is ignored: it moves the mechanism in forward dynamics, and an effort
is what the actuator must apply whoever it is): ``flywheel: {CRANK: I_F}`` is a massless disc
turning with the input crank, so it adds I_F (kg·m²) to that body's rotational inertia and nothing
else, wherever the body's centre is. ``damping: {JOINT: c}`` is a viscous couple in a revolute
joint: −c·q̇ on the joint's moving body and +c·q̇ on the other, q̇ the joint's rate (rad/s), for an
input crank (crank against ground), an ``angle`` joint (the link carrying both points against
ground) and a ``revolute`` joint (child line's link against the parent line's link, or ground when
the parent line is fixed; q = s·Δ + q₀ gives a couple −c·s·q̇ on the child, +c·s·q̇ on the parent).
Every solve checks its equilibrium residual; :func:`power_residual` checks the efforts against
an energy balance that uses no reaction and no moment equation (a damper's power is −c·q̇²).

Run ``python tests/reference/forces_mp.py SCENE.yaml [...]`` to (re)write
``tests/data/forces_<scene>.json`` (``--check`` compares with the stored files instead); the
sampling and the files are forces_mp_data.py's.
"""

from __future__ import annotations

import hashlib
import json
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import mpmath
import yaml
from mpmath import mp, mpf

__all__ = ["DPS", "GROUND", "Mechanism", "Solution", "digest", "load", "main", "positions", "power_residual", "solve"]

DPS = 50
"""Working precision (decimal digits)."""
CHECK_TOL = mpf("1e-28")
"""The equilibrium residual of every solve must be below this (relative)."""

ROOT = Path(__file__).resolve().parents[2]
LENGTH_UNITS = {"m": "1", "cm": "0.01", "mm": "0.001"}
GROUND = "ground"

Vec = tuple[mpf, mpf]


def _n(x: Any) -> mpf:
    return mpf(str(x))  # decimal text as written in the file (YAML 1.1 leaves 1e-3 as a string)


def _sub(a: Vec, b: Vec) -> Vec:
    return a[0] - b[0], a[1] - b[1]


def _cross(a: Vec, b: Vec) -> mpf:
    return a[0] * b[1] - a[1] * b[0]


def _root(x: mpf, what: str) -> mpf:
    if x < 0:
        raise ValueError(f"cannot be assembled: {what}")
    return mp.sqrt(x)


def _unit(a: Vec) -> Vec:
    r = mp.hypot(*a)
    return a[0] / r, a[1] / r


@dataclass
class Link:
    """A rigid body of the mechanism: its points; a slider block has one point and a guide."""

    name: str
    points: list[str]
    block: bool = False
    guide: Vec | None = None  # block on a fixed guide: its unit direction
    along: tuple[str, str] | None = None  # block in a slotted link: the link's pivot → eyelet
    mass: mpf = field(default_factory=lambda: mpf(0))
    center: Vec = field(default_factory=lambda: (mpf(0), mpf(0)))
    inertia: mpf = field(default_factory=lambda: mpf(0))
    frame: tuple[str, ...] = ()  # the points that set the body frame (first two, or a block's one)


@dataclass
class Mechanism:
    name: str
    file: Path
    length: mpf  # scene length unit in m
    angle: mpf  # scene angle unit in rad
    fixed: dict[str, Vec]
    groups: list[dict[str, Any]]
    inputs: list[str]  # crank joints, in scene order
    cranks: dict[str, str]  # joint -> crank body
    links: dict[str, Link]
    pins: dict[str, list[str]]  # point -> bodies meeting there (ground last)
    slides: dict[str, str]  # block -> the body it slides on (ground, or a slotted link)
    joints: dict[str, Any]  # the scene's read-out joints (for a table load's coordinate)
    gravity: Vec
    loads: list[dict[str, Any]]
    dampers: list[tuple[str, str, str, mpf]] = field(default_factory=list)  # (joint, body, other, c)
    #: per triad (group index): input q → solved (Dx, Dy, θ), the continuation's start points
    triad_memo: dict[int, dict[mpf, list]] = field(default_factory=dict)


def _links(groups: list[dict[str, Any]], fixed: dict[str, Vec], angle: mpf) -> tuple[dict, dict, dict]:
    """Links (default names as name, name.1/.2, name.block), slides and cranks of the groups."""
    links: dict[str, Link] = {}
    slides: dict[str, str] = {}
    cranks: dict[str, str] = {}
    for g in groups:
        kind, name = g["type"], str(g["name"])
        if kind == "crank":
            cranks[str(g.get("joint", name))] = name
            links[name] = Link(name, [g["center"], g["point"]])
        elif kind == "rrr":
            e1, e2 = g["ends"]
            links[f"{name}.1"] = Link(f"{name}.1", [e1, g["point"]])
            links[f"{name}.2"] = Link(f"{name}.2", [e2, g["point"]])
        elif kind == "rrp":
            a = _n(g["guide"].get("angle", 0)) * angle
            links[name] = Link(name, [g["end"], g["point"]])
            links[f"{name}.block"] = Link(f"{name}.block", [g["point"]], True, (mp.cos(a), mp.sin(a)))
            slides[f"{name}.block"] = GROUND
        elif kind == "slotted":
            links[name] = Link(name, [g["pivot"], *map(str, g["points"])])
            links[f"{name}.block"] = Link(f"{name}.block", [g["through"]], True, None, (g["pivot"], g["through"]))
            slides[f"{name}.block"] = name
        elif kind == "triad":  # binary links A–D, B–E, C–F and the ternary link D–E–F
            for i, (x, y) in enumerate(zip(g["ends"], g["points"]), 1):
                links[f"{name}.{i}"] = Link(f"{name}.{i}", [x, y])
            links[name] = Link(name, list(g["points"]))
        elif kind == "slider_triad":  # block at D on the guide, binary links B–E, C–F, ternary D–E–F
            a = _n(g["guide"].get("angle", 0)) * angle
            d, e, f = g["points"]
            links[f"{name}.2"] = Link(f"{name}.2", [g["ends"][0], e])
            links[f"{name}.3"] = Link(f"{name}.3", [g["ends"][1], f])
            links[name] = Link(name, list(g["points"]))
            links[f"{name}.block"] = Link(f"{name}.block", [d], True, (mp.cos(a), mp.sin(a)))
            slides[f"{name}.block"] = GROUND
        elif kind == "attached":
            need = {g.get("base", g["along"][0]), *g["along"]}
            if not need <= set(fixed):
                host = next(k for k, li in links.items() if need <= set(li.points) and not li.block)
                links[host].points.append(g["point"])
        else:
            raise ValueError(f"the reference knows no group type '{kind}'")
    return links, slides, cranks


def load(path: str | Path) -> Mechanism:
    """Read a planar scene's topology, bodies, gravity and loads (SI, at working precision)."""
    path = Path(path)
    raw = yaml.safe_load(path.read_text())
    units = raw.get("units", {})
    length = mpf(LENGTH_UNITS[units.get("length", "m")])
    angle = mpf(1) if units.get("angle", "deg") == "rad" else mp.pi / 180
    fixed = {str(k): (_n(v[0]) * length, _n(v[1]) * length) for k, v in raw["fixed"].items()}
    groups = [dict(g) for g in raw["groups"]]
    links, slides, cranks = _links(groups, fixed, angle)
    rename: dict[str, str] = {}
    for body, spec in (raw.get("bodies") or {}).items():
        pts = [str(p) for p in spec["points"]]
        link = next(
            k for k, li in links.items() if li.block == (len(pts) == 1) and set(pts) <= set(li.points)
        )  # a body names exactly one link: anything else is the solver's SceneError, not ours
        li = links[link]
        li.frame = tuple(pts)
        li.mass, li.inertia = _n(spec.get("mass", 0)), _n(spec.get("inertia", 0))
        c = spec.get("center", [0, 0])
        li.center = (_n(c[0]) * length, _n(c[1]) * length)
        rename[link] = str(body)
    named = {rename.get(k, k): li for k, li in links.items()}
    for name, li in named.items():
        li.name = name
        li.frame = li.frame or tuple(li.points[: 1 if li.block else 2])
    pins: dict[str, list[str]] = {}
    for point in dict.fromkeys(p for li in named.values() for p in li.points):
        at = [k for k, li in named.items() if point in li.points]
        at += [GROUND] if point in fixed else []
        if len(at) >= 2:
            pins[point] = at
    gravity = tuple(_n(x) for x in raw.get("gravity", [0, 0]))
    m = Mechanism(
        name=str(raw.get("scene", path.stem)), file=path, length=length, angle=angle, fixed=fixed, groups=groups,
        inputs=list(cranks), cranks={j: rename.get(c, c) for j, c in cranks.items()}, links=named, pins=pins,
        slides={rename.get(b, b): rename.get(g, g) for b, g in slides.items()}, joints=dict(raw.get("joints") or {}),
        gravity=(gravity[0], gravity[1]), loads=list(raw.get("loads") or []),
    )  # fmt: skip
    for joint, inertia in (raw.get("flywheel") or {}).items():  # a massless disc on the crank
        m.links[m.cranks[str(joint)]].inertia += _n(inertia)
    m.dampers = [(str(j), *_damped(m, str(j)), _n(c)) for j, c in (raw.get("damping") or {}).items()]
    return m


def _carrier(m: Mechanism, points: Sequence[str], ground_ok: bool = False) -> str:
    """The link (not a block) carrying all ``points``; ground for fixed points when allowed."""
    for name, li in m.links.items():
        if not li.block and set(points) <= set(li.points):
            return name
    if ground_ok and set(points) <= set(m.fixed):
        return GROUND
    raise ValueError(f"{m.file}: no one link carries {', '.join(points)}")


def _damped(m: Mechanism, joint: str) -> tuple[str, str]:
    """(moving body, other body or ground) of a damped revolute joint."""
    if joint in m.cranks:
        return m.cranks[joint], GROUND
    ((kind, arg),) = dict(m.joints[joint]).items()
    if kind == "angle":
        return _carrier(m, [str(p) for p in arg]), GROUND
    if kind == "revolute":
        return _carrier(m, [str(p) for p in arg["child"]]), _carrier(m, [str(p) for p in arg["parent"]], True)
    raise ValueError(f"{m.file}: the reference damps no joint of kind '{kind}'")


def positions(m: Mechanism, q: Sequence[mpf], upto: int | None = None) -> dict[str, Vec]:
    """Every point at input coordinates q (one per input, rad), in m (of the groups before the
    ``upto``-th, when given)."""
    pts: dict[str, Vec] = dict(m.fixed)
    qs = dict(zip(m.inputs, q))
    L, A = m.length, m.angle
    for index, g in enumerate(m.groups[:upto]):
        kind = g["type"]
        if kind == "triad":
            pts.update(_triad(m, index, list(q)))
        elif kind == "slider_triad":
            pts.update(_slider_triad(m, index, list(q)))
        elif kind == "crank":
            o, r, t = pts[g["center"]], _n(g["length"]) * L, qs[str(g.get("joint", g["name"]))]
            pts[g["point"]] = (o[0] + r * mp.cos(t), o[1] + r * mp.sin(t))
        elif kind == "rrr":  # circle ∩ circle; M = +1: E1 → P → E2 counter-clockwise
            e1, e2 = pts[g["ends"][0]], pts[g["ends"][1]]
            l1, l2 = (_n(x) * L for x in g["lengths"])
            d = mp.hypot(*_sub(e2, e1))
            u = _unit(_sub(e2, e1))
            along = (l1**2 - l2**2 + d**2) / (2 * d)
            h = _root(l1**2 - along**2, g["name"]) * int(g.get("M", 1))
            pts[g["point"]] = (e1[0] + along * u[0] + h * u[1], e1[1] + along * u[1] - h * u[0])
        elif kind == "rrp":  # line ∩ circle; M = +1: B ahead of A's foot along the guide
            gd = g["guide"]
            a = _n(gd.get("angle", 0)) * A
            e = (mp.cos(a), mp.sin(a))
            off = _n(gd.get("offset", 0)) * L
            p0 = pts[gd["through"]]
            p0 = (p0[0] - off * e[1], p0[1] + off * e[0])
            w = _sub(pts[g["end"]], p0)
            foot, dist = w[0] * e[0] + w[1] * e[1], _cross(e, w)
            s = foot + int(g.get("M", 1)) * _root((_n(g["length"]) * L) ** 2 - dist**2, g["name"])
            pts[g["point"]] = (p0[0] + s * e[0], p0[1] + s * e[1])
        elif kind == "slotted":
            a = pts[g["pivot"]]
            u = _unit(_sub(pts[g["through"]], a))
            for name, dist in g["points"].items():
                pts[str(name)] = (a[0] + _n(dist) * L * u[0], a[1] + _n(dist) * L * u[1])
        elif kind == "attached":
            r0, r1 = (pts[p] for p in g["along"])
            base = pts[g.get("base", g["along"][0])]
            u = _unit(_sub(r1, r0))
            t = _n(g.get("angle", 0)) * A
            c, s, d = mp.cos(t), mp.sin(t), _n(g["distance"]) * L
            pts[g["point"]] = (base[0] + d * (c * u[0] - s * u[1]), base[1] + d * (s * u[0] + c * u[1]))
    return pts


TRIAD_DRAWN = mpf("1e-9")
"""The drawn shape must close the loop at ``at`` to this (relative to the link lengths)."""


def _triad_loop(m: Mechanism, g: dict[str, Any], pts: dict[str, Vec]) -> tuple[Callable[..., list], Any, Any]:
    """The triad's three loop equations in (Dx, Dy, θ) with the ends at ``pts``, and the ternary
    link's shape u = E − D, v = F − D in its own frame (θ = arg(E − D))."""
    L = m.length
    sh = g["shape"]
    d0, e0, f0 = (mpmath.mpc(_n(sh[k][0]) * L, _n(sh[k][1]) * L) for k in g["points"])
    u = abs(e0 - d0)
    v = (f0 - d0) * abs(e0 - d0) / (e0 - d0)
    a_, b_, c_ = (mpmath.mpc(*pts[k]) for k in g["ends"])
    la, lb, lc = (_n(x) * L for x in g["lengths"])

    def f(x: mpf, y: mpf, t: mpf) -> list:
        d = mpmath.mpc(x, y)
        w = mpmath.mpc(mp.cos(t), mp.sin(t))
        return [abs(d - a_) ** 2 - la**2, abs(d + u * w - b_) ** 2 - lb**2, abs(d + v * w - c_) ** 2 - lc**2]

    return f, u, v


def _triad(m: Mechanism, index: int, q: list[mpf]) -> dict[str, Vec]:
    """D, E, F of the ``index``-th group, a triad, at q: its loop solved by findroot, continued in
    steps of at most 0.25° of the input from the drawn pose at ``at`` (the scene's ``shape`` is
    that pose, one input) — the mode is the one drawn, followed continuously, as the scene says."""
    g = m.groups[index]
    if len(m.inputs) != 1 or "shape" not in g or "at" not in g:
        raise NotImplementedError("the reference solves a triad of one input drawn by its shape at 'at'")
    memo = m.triad_memo.setdefault(index, {})
    if not memo:  # the drawn pose closes the loop at `at`
        at = _n(g["at"]) * m.angle
        sh = g["shape"]
        d0, e0 = (mpmath.mpc(_n(sh[k][0]), _n(sh[k][1])) * m.length for k in g["points"][:2])
        f, _, _ = _triad_loop(m, g, positions(m, [at], index))
        x0 = [d0.real, d0.imag, mpmath.arg(e0 - d0)]
        worst = max(abs(r) for r in f(*x0)) / max(_n(x) * m.length for x in g["lengths"]) ** 2
        if worst > TRIAD_DRAWN:
            raise NotImplementedError(f"triad '{g['name']}': its shape is not the pose drawn at 'at' ({worst})")
        memo[at] = x0
    target = q[0]
    start = min(memo, key=lambda k: abs(k - target))
    x = memo[start]
    steps = max(1, int(mp.ceil(abs(target - start) / (mpf("0.25") * mp.pi / 180))))
    prev = None
    for k in range(1, steps + 1):
        qk = start + (target - start) * k / steps
        f, _, _ = _triad_loop(m, g, positions(m, [qk], index))
        guess = x if prev is None else [2 * a - b for a, b in zip(x, prev)]
        sol = mpmath.findroot(f, guess, tol=mpf(10) ** (-2 * mp.dps + 10))
        prev, x = x, [sol[0], sol[1], sol[2]]
    memo[target] = x
    _, u, v = _triad_loop(m, g, positions(m, [target], index))
    d = mpmath.mpc(x[0], x[1])
    w = mpmath.mpc(mp.cos(x[2]), mp.sin(x[2]))
    return {name: (p.real, p.imag) for name, p in zip(g["points"], (d, d + u * w, d + v * w))}


def _slider_loop(m: Mechanism, g: dict[str, Any], pts: dict[str, Vec]) -> tuple[Callable[..., list], Any, Any, Any]:
    """The slider triad's two loop equations in (s, θ) with the ends at ``pts`` (D = O + s·e on the
    guide, O the guide's point shifted by its offset), and (O, e, u, v) with u = E − D, v = F − D
    in the ternary link's own frame."""
    L, A = m.length, m.angle
    gd = g["guide"]
    a = _n(gd.get("angle", 0)) * A
    e = mpmath.mpc(mp.cos(a), mp.sin(a))
    off = _n(gd.get("offset", 0)) * L
    o = mpmath.mpc(*pts[gd["through"]]) + off * mpmath.mpc(0, 1) * e
    sh = g["shape"]
    d0, e0, f0 = (mpmath.mpc(_n(sh[k][0]) * L, _n(sh[k][1]) * L) for k in g["points"])
    u = abs(e0 - d0)
    v = (f0 - d0) * abs(e0 - d0) / (e0 - d0)
    b_, c_ = (mpmath.mpc(*pts[k]) for k in g["ends"])
    lb, lc = (_n(x) * L for x in g["lengths"])

    def f(s: mpf, t: mpf) -> list:
        d = o + s * e
        w = mpmath.mpc(mp.cos(t), mp.sin(t))
        return [abs(d + u * w - b_) ** 2 - lb**2, abs(d + v * w - c_) ** 2 - lc**2]

    return f, (o, e), u, v


def _slider_triad(m: Mechanism, index: int, q: list[mpf]) -> dict[str, Vec]:
    """D, E, F of the ``index``-th group, a slider triad, at q: its loop solved by findroot in
    (s, θ), continued as :func:`_triad`'s from the drawn pose at ``at``."""
    g = m.groups[index]
    if len(m.inputs) != 1 or "shape" not in g or "at" not in g:
        raise NotImplementedError("the reference solves a slider triad of one input drawn by its shape at 'at'")
    memo = m.triad_memo.setdefault(index, {})
    if not memo:
        at = _n(g["at"]) * m.angle
        sh = g["shape"]
        d0, e0 = (mpmath.mpc(_n(sh[k][0]), _n(sh[k][1])) * m.length for k in g["points"][:2])
        f, (o, e), _, _ = _slider_loop(m, g, positions(m, [at], index))
        s0 = ((d0 - o) * mpmath.conj(e)).real
        x0 = [s0, mpmath.arg(e0 - d0)]
        worst = max(abs(r) for r in f(*x0)) / max(_n(x) * m.length for x in g["lengths"]) ** 2
        if worst > TRIAD_DRAWN:
            raise NotImplementedError(f"slider triad '{g['name']}': its shape is not the pose drawn at 'at' ({worst})")
        memo[at] = x0
    target = q[0]
    start = min(memo, key=lambda k: abs(k - target))
    x = memo[start]
    steps = max(1, int(mp.ceil(abs(target - start) / (mpf("0.25") * mp.pi / 180))))
    prev = None
    for k in range(1, steps + 1):
        qk = start + (target - start) * k / steps
        f, _, _, _ = _slider_loop(m, g, positions(m, [qk], index))
        guess = x if prev is None else [2 * a - b for a, b in zip(x, prev)]
        sol = mpmath.findroot(f, guess, tol=mpf(10) ** (-2 * mp.dps + 10))
        prev, x = x, [sol[0], sol[1]]
    memo[target] = x
    _, (o, e), u, v = _slider_loop(m, g, positions(m, [target], index))
    d = o + x[0] * e
    w = mpmath.mpc(mp.cos(x[1]), mp.sin(x[1]))
    return {name: (p.real, p.imag) for name, p in zip(g["points"], (d, d + u * w, d + v * w))}


def _frame(m: Mechanism, li: Link, pts: dict[str, Vec]) -> tuple[Vec, Vec]:
    """(origin, unit x axis) of a body's frame."""
    if li.guide is not None:
        return pts[li.frame[0]], li.guide
    if li.along is not None:
        return pts[li.frame[0]], _unit(_sub(pts[li.along[1]], pts[li.along[0]]))
    return pts[li.frame[0]], _unit(_sub(pts[li.frame[1]], pts[li.frame[0]]))


def _center(m: Mechanism, li: Link, pts: dict[str, Vec]) -> Vec:
    o, x = _frame(m, li, pts)
    c = li.center
    return o[0] + c[0] * x[0] - c[1] * x[1], o[1] + c[0] * x[1] + c[1] * x[0]


@dataclass
class Solution:
    """One instant: efforts, pin reactions and the sliding pairs' actions, SI."""

    effort: dict[str, mpf]
    reactions: dict[str, dict[str, Vec]]  # point -> body -> force on that body at the pin
    slides: dict[str, tuple[Vec, mpf]]  # block -> (force on it from its guide, couple about its point)
    conditioning: mpf


def _motion(m: Mechanism, q: Sequence[mpf], omega: Sequence[mpf], epsilon: Sequence[mpf]) -> Callable[[mpf], dict]:
    """Positions along q(t) = q + ω·t + ε·t²/2, memoised (mp.diff evaluates each t many times)."""
    memo: dict[tuple[int, mpf], dict[str, Vec]] = {}

    def at(t: mpf) -> dict[str, Vec]:
        key = (mp.prec, t)  # mp.diff raises the precision: never reuse a value computed at less
        if key not in memo:
            memo[key] = positions(m, [a + w * t + e * t * t / 2 for a, w, e in zip(q, omega, epsilon)])
        return memo[key]

    return at


def _accelerations(m: Mechanism, at: Callable[[mpf], dict]) -> dict[str, tuple[Vec, mpf]]:
    """(a_G, α) of every body, by mp.diff in time at t = 0."""
    out = {}
    for name, li in m.links.items():
        ax, ay, alpha = _rates(m, at, li, 2)
        out[name] = ((ax, ay), alpha)
    return out


def _joint(m: Mechanism, joint: str, pts: dict[str, Vec], q: Sequence[mpf]) -> mpf:
    """A joint's coordinate (rad or m): an input, or a read-out of the scene's ``joints`` (a
    ``revolute`` one s·Δ + q₀ in (−π, π], Δ the child line's angle from the parent line's)."""
    if joint in m.inputs:
        return q[m.inputs.index(joint)]
    ((kind, arg),) = dict(m.joints[joint]).items()
    if kind in ("x", "y"):
        return pts[arg][0 if kind == "x" else 1]
    if kind == "revolute":
        (p0, p1), (c0, c1) = arg["parent"], arg["child"]
        u, v = _sub(pts[p1], pts[p0]), _sub(pts[c1], pts[c0])
        turn = mp.atan2(_cross(u, v), u[0] * v[0] + u[1] * v[1])
        value = int(arg.get("sign", 1)) * turn + _n(arg.get("offset", 0)) * m.angle
        return value - 2 * mp.pi * mp.ceil((value - mp.pi) / (2 * mp.pi))  # into (−π, π], as read out
    d = _sub(pts[arg[1]], pts[arg[0]])
    if kind == "distance":
        return mp.hypot(*d)
    if kind == "angle":
        return mp.atan2(d[1], d[0])
    raise ValueError(f"{m.file}: the reference reads no joint of kind '{kind}'")


def _joint_rate(m: Mechanism, joint: str, at: Callable[[mpf], dict], q: Sequence[mpf], omega: Sequence[mpf]) -> mpf:
    """A joint's rate at t = 0: ω for an input, else mp.diff in time of its coordinate, unwound
    about its value at t = 0 (an angle jumps by 2π at ±π)."""
    if joint in m.inputs:
        return omega[m.inputs.index(joint)]
    q0 = _joint(m, joint, at(mpf(0)), q)

    def unwound(t: mpf) -> mpf:
        d = _joint(m, joint, at(t), q) - q0
        return d - 2 * mp.pi * mp.nint(d / (2 * mp.pi))

    return mp.diff(unwound, 0)


def _table(load: dict[str, Any], value: mpf, angle: bool, m: Mechanism) -> mpf:
    """Linear interpolation in the table, constant beyond its ends; an angle wrapped into
    [at₀, at₀ + period) first (``period`` in the scene's angle unit, one turn by default)."""
    scale = m.angle if angle else m.length
    at = [_n(x) * scale for x in load["table"]["at"]]
    force = [_n(x) for x in load["table"]["force"]]
    if angle:
        period = _n(load["table"]["period"]) * m.angle if "period" in load["table"] else 2 * mp.pi
        value = at[0] + mp.fmod(value - at[0], period)
        value += period if value < at[0] else 0
    if value <= at[0]:
        return force[0]
    for a0, a1, f0, f1 in zip(at, at[1:], force, force[1:]):
        if value <= a1:
            return f0 + (f1 - f0) * (value - a0) / (a1 - a0)
    return force[-1]


Term = tuple[str, Vec, "str | None", mpf]
"""(body, force, point of application or None, couple) — one action of a load on one body."""


def _load_terms(m: Mechanism, load: dict[str, Any], pts: dict[str, Vec], q: Sequence[mpf]) -> list[Term]:
    """A load as terms on bodies (a spring: one on each end's body; ground's dropped later)."""
    if "force" in load:
        f = load["force"]
        return [(str(load["body"]), (_n(f[0]), _n(f[1])), str(load["point"]), mpf(0))]
    if "torque" in load:
        return [(str(load["body"]), (mpf(0), mpf(0)), None, _n(load["torque"]))]
    if "spring" in load:  # tension k(ℓ − ℓ₀): pulls each end toward the other
        (b0, p0), (b1, p1) = ((str(b), str(p)) for b, p in load["spring"])
        d = _sub(pts[p1], pts[p0])
        ell = mp.hypot(*d)
        tension = _n(load.get("stiffness", 0)) * (ell - _n(load.get("free_length", 0)) * m.length)
        f = (tension * d[0] / ell, tension * d[1] / ell)
        return [(b0, f, p0, mpf(0)), (b1, (-f[0], -f[1]), p1, mpf(0))]
    if "table" in load:
        joint = str(load["table"]["of"])
        angle = joint in m.inputs or next(iter(dict(m.joints[joint]))) in ("angle", "revolute")
        size = _table(load, _joint(m, joint, pts, q), angle, m)
        u = _unit((_n(load["direction"][0]), _n(load["direction"][1])))
        return [(str(load["body"]), (size * u[0], size * u[1]), str(load["point"]), mpf(0))]
    raise ValueError(f"{m.file}: the reference knows no load {load}")


def _damper_terms(m: Mechanism, at: Callable[[mpf], dict], q: Sequence[mpf], omega: Sequence[mpf]) -> list[Term]:
    """Every damper as its two couples: −c·q̇ on the moving body, +c·q̇ on the other (of a
    ``revolute`` joint: the child's couple −c·s·q̇, the parent's +c·s·q̇)."""
    out: list[Term] = []
    zero = (mpf(0), mpf(0))
    for joint, body, other, c in m.dampers:
        spec = {} if joint in m.inputs else dict(m.joints[joint])
        sign = int(spec["revolute"].get("sign", 1)) if "revolute" in spec else 1
        couple = c * sign * _joint_rate(m, joint, at, q, omega)
        out += [(body, zero, None, -couple), (other, zero, None, couple)]
    return out


def solve(m: Mechanism, q: Sequence[mpf], omega: Sequence[mpf], epsilon: Sequence[mpf]) -> Solution:
    """Newton–Euler of every moving body at one instant, as one linear system."""
    at = _motion(m, q, omega, epsilon)
    pts = at(mpf(0))
    acc = _accelerations(m, at)
    bodies = list(m.links)
    row = {b: 3 * i for i, b in enumerate(bodies)}
    columns: list[tuple[str, ...]] = []
    terms: list[list[tuple[str, Vec, Vec, mpf]]] = []  # per unknown: (body, force, point, couple) per unit

    def unknown(label: tuple[str, ...], effect: list[tuple[str, Vec, Vec, mpf]]) -> None:
        columns.append(label)
        terms.append([t for t in effect if t[0] != GROUND])

    ex, ey, zero = (mpf(1), mpf(0)), (mpf(0), mpf(1)), (mpf(0), mpf(0))
    for point, at_pin in m.pins.items():  # F on at_pin[i], and −F on the last one
        p = pts[point]
        for body in at_pin[:-1]:
            for axis, u in (("x", ex), ("y", ey)):
                unknown(("pin", point, body, axis), [(body, u, p, mpf(0)), (at_pin[-1], (-u[0], -u[1]), p, mpf(0))])
    for block, guide in m.slides.items():  # normal force N·n and couple M on the block, −N·n and −M on the guide
        li = m.links[block]
        p, e = _frame(m, li, pts)
        n = (-e[1], e[0])
        unknown(("slide", block, "normal"), [(block, n, p, mpf(0)), (guide, (-n[0], -n[1]), p, mpf(0))])
        unknown(("slide", block, "couple"), [(block, zero, p, mpf(1)), (guide, zero, p, mpf(-1))])
    for joint in m.inputs:
        unknown(("effort", joint), [(m.cranks[joint], zero, zero, mpf(1))])
    size = 3 * len(bodies)
    if len(columns) != size:
        raise ValueError(f"{m.file}: {len(columns)} unknowns for {size} equations: not statically determinate")
    mat = mp.matrix(size, size)
    for j, effect in enumerate(terms):
        for body, f, p, couple in effect:
            r, o = row[body], _frame(m, m.links[body], pts)[0]
            mat[r, j] += f[0]
            mat[r + 1, j] += f[1]
            mat[r + 2, j] += _cross(_sub(p, o), f) + couple
    rhs = mp.matrix(size, 1)
    terms_applied = [t for load in m.loads for t in _load_terms(m, load, pts, q)] + _damper_terms(m, at, q, omega)
    applied = [(b, f, pts[p] if p is not None else zero, c) for b, f, p, c in terms_applied]
    for b in bodies:
        li, r = m.links[b], row[b]
        o = _frame(m, li, pts)[0]
        g_at = _sub(_center(m, li, pts), o)
        (ax, ay), alpha = acc[b]
        inertial = (li.mass * (ax - m.gravity[0]), li.mass * (ay - m.gravity[1]))  # m(a − g)
        rhs[r] += inertial[0]
        rhs[r + 1] += inertial[1]
        rhs[r + 2] += li.inertia * alpha + _cross(g_at, inertial)
        for body, f, p, couple in applied:
            if body == b != GROUND:
                rhs[r] -= f[0]
                rhs[r + 1] -= f[1]
                rhs[r + 2] -= _cross(_sub(p, o), f) + couple
    x = mp.lu_solve(mat, rhs)
    residual = mp.norm(mat * x - rhs) / max(mp.norm(rhs), mpf(1))
    assert residual < CHECK_TOL, f"equilibrium residual {residual}"
    norms = [mp.norm(mat[i, :]) for i in range(size)]
    conditioning = abs(mp.det(mat)) / mp.fprod(norms)
    sol = Solution({}, {}, {}, conditioning)
    value = dict(zip(columns, x))
    for point, at_pin in m.pins.items():
        forces = {b: (value[("pin", point, b, "x")], value[("pin", point, b, "y")]) for b in at_pin[:-1]}
        forces[at_pin[-1]] = (-sum(f[0] for f in forces.values()), -sum(f[1] for f in forces.values()))
        sol.reactions[point] = forces
    for block in m.slides:
        e = _frame(m, m.links[block], pts)[1]
        n = value[("slide", block, "normal")]
        sol.slides[block] = ((-e[1] * n, e[0] * n), value[("slide", block, "couple")])
    sol.effort = {j: value[("effort", j)] for j in m.inputs}
    return sol


def _rates(m: Mechanism, at: Callable[[mpf], dict], li: Link, order: int) -> tuple[mpf, mpf, mpf]:
    """d^order/dt^order at t = 0 of the body's centre (x, y) and of its angle."""
    x0 = _frame(m, li, at(mpf(0)))[1]

    def angle(t: mpf) -> mpf:  # continuous through t = 0
        x = _frame(m, li, at(t))[1]
        return mp.atan2(_cross(x0, x), x0[0] * x[0] + x0[1] * x[1])

    gx = mp.diff(lambda t: _center(m, li, at(t))[0], 0, order)
    gy = mp.diff(lambda t: _center(m, li, at(t))[1], 0, order)
    return gx, gy, (mp.diff(angle, 0, order) if li.guide is None else mpf(0))  # a fixed guide: no turn


def power_residual(m: Mechanism, q: Sequence[mpf], omega: Sequence[mpf], epsilon: Sequence[mpf], sol: Solution) -> mpf:
    """(Σ Q·ω + P_loads − dT/dt − dV/dt) / its largest term: zero for right efforts (ideal pins,
    and slides do no work). Uses no reaction and no moment equation: an energy check of the
    efforts, with dT/dt = Σ m·v_G·a_G + I·θ'·α and dV/dt = −Σ m·g·v_G."""
    at = _motion(m, q, omega, epsilon)
    pts = at(mpf(0))
    d_energy = mpf(0)
    for li in m.links.values():
        vx, vy, spin = _rates(m, at, li, 1)
        ax, ay, alpha = _rates(m, at, li, 2)
        d_energy += li.mass * (vx * ax + vy * ay) + li.inertia * spin * alpha
        d_energy -= li.mass * (m.gravity[0] * vx + m.gravity[1] * vy)
    load_power = mpf(0)
    applied = [t for load in m.loads for t in _load_terms(m, load, pts, q)] + _damper_terms(m, at, q, omega)
    for body, f, point, couple in applied:
        if body == GROUND:
            continue
        if point is not None:
            v = [mp.diff(lambda t, i=i, p=point: at(t)[p][i], 0) for i in range(2)]
            load_power += f[0] * v[0] + f[1] * v[1]
        if couple:
            load_power += couple * _rates(m, at, m.links[body], 1)[2]
    inputs = sum((sol.effort[j] * w for j, w in zip(m.inputs, omega)), mpf(0))
    scale = max(abs(inputs), abs(d_energy), abs(load_power), mpf(1))
    return (inputs + load_power - d_energy) / scale


MECHANICS_KEYS = ("units", "fixed", "groups", "joints", "bodies", "gravity", "loads")
"""What the forces depend on; descriptions, provenance and outputs do not."""
DRIVE_KEYS = ("flywheel", "damping")
"""Also mechanics (issue 22), counted only where a scene has them: the digests of scenes without
them stay what they were (``motor`` does not change an effort)."""


def digest(path: str | Path) -> str:
    """SHA-256 of the scene's mechanics (MECHANICS_KEYS and any DRIVE_KEYS, canonical JSON): a
    reference is stale when this changes, and only then."""
    raw = yaml.safe_load(Path(path).read_text())
    mechanics = {k: raw.get(k) for k in MECHANICS_KEYS} | {k: raw[k] for k in DRIVE_KEYS if k in raw}
    return hashlib.sha256(json.dumps(mechanics, sort_keys=True, default=str).encode()).hexdigest()


def main(argv: Sequence[str] | None = None) -> int:
    """Write (or ``--check``) tests/data/forces_<scene>.json: forces_mp_data.main."""
    import forces_mp_data

    return forces_mp_data.main(argv)


if __name__ == "__main__":
    sys.exit(main())
