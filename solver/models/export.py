"""Any planar pin-jointed scene written as an MJCF model with ``<connect>`` loop closures.

The scene's links and pins (solver.forces.structure: which group makes which body) are opened
into a spanning tree from the ground, pins taken in plan order: a link reached through a pin is a
``<body>`` with a ``hinge`` about z at that pin, every other pin a ``<connect>`` equality (its
anchor in body1's frame; MuJoCo computes body2's, closed at the written pose). The pose is the
scene solved at the inputs ``phi`` (default: zero). Each body's frame has its origin at its
hinge and its x axis toward the link's next point; each hinge has ``ref`` = its angle at that
pose, so that qpos is the angle the scene measures: an input crank's qpos is the scene's φ (the
angle of O→A from +x), a passive hinge's the angle of its link from its parent's frame.

Every scene point is a ``<site>`` named after it, on the first body that carries it (a pin's
other body gets it through the hinge or the connect), so that importing the export
(solver.models.mjcf) gives back the same points under the same names. Masses, centres and
moments of inertia come from the scene's ``bodies`` (a planar body's Izz; Ixx = Iyy = Izz,
which keeps the triangle inequality); a link without a body gets ``MIN_MASS`` (MuJoCo needs a
mass on every moving body). Each input crank is a ``<motor>``; gravity is the scene's, in the
plane z = 0.

Exported: cranks, RRR dyads and attached points (pin-jointed planar linkages); a slider, a
slotted link, a cylinder or a spatial scene is one SceneError line.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Sequence
from typing import Any
from xml.sax.saxutils import quoteattr

import numpy as np

from ..errors import SceneError
from ..forces.structure import GROUND, derive_structure
from ..groups import RRR, Attached, Crank, JointExpression

__all__ = ["scene_to_mjcf", "MIN_MASS"]

#: kg (and MIN_MASS·1e-6 kg·m²): the mass given to a link the scene names no body for.
MIN_MASS = 1e-6


def _fit(name: str) -> str:
    return "".join(c if c.isalnum() or c in "_-" else "_" for c in name)


def _num(x: float) -> str:
    return repr(float(x))


def _quat(angle: float) -> str:
    return f"{_num(math.cos(angle / 2))} 0 0 {_num(math.sin(angle / 2))}"


def scene_to_mjcf(scene: Any, *, phi: Sequence[float] | None = None) -> str:
    """The MJCF text of a planar scene (module docstring), posed at the inputs ``phi``."""
    file = scene.path or scene.name
    if scene.dim != 2:
        raise SceneError("linkage-mjcf writes planar scenes; this one is spatial", file=file)
    for g in scene.ordered:
        if not isinstance(g, (Crank, RRR, Attached, JointExpression)):
            raise SceneError(f"{g.kind} '{g.name}': linkage-mjcf writes pin-jointed linkages (crank, rrr, "
                             "attached); sliders, slotted links and cylinders are not exported yet", file=file)
    fixed = scene._data.fixed
    st = derive_structure(scene.ordered, fixed)
    k = len(scene.inputs)
    q = tuple(float(x) for x in (phi if phi is not None else (0.0,) * k))
    if len(q) != k:
        raise SceneError(f"{k} input value(s) needed ({', '.join(scene.inputs)}), got {len(q)}", file=file)
    everything = scene.everything()
    kin = everything.solve(q[0] if k == 1 else q)
    where = {n: complex(*np.asarray(kin.point(n).position, float)) for n in everything.point_names}
    crank_joint = {g.name: g.joint for g in scene.ordered if isinstance(g, Crank) and g.drives}
    bodies = {b.name: b for b in scene.bodies} if scene.forces is not None else {}
    by_link = {b.link.name: b for b in bodies.values()}

    # the spanning tree from the ground, pins in plan order
    links = {ln.name: ln for ln in st.links}
    parent: dict[str, tuple[str, str]] = {}  # link → (parent body, pin point)
    reached = {GROUND}
    tree_pins: set[int] = set()
    changed = True
    while changed:
        changed = False
        for i, p in enumerate(st.pins):
            for a, b in ((p.other, p.body), (p.body, p.other)):
                if a in reached and b not in reached:
                    parent[b] = (a, p.point)
                    reached.add(b)
                    tree_pins.add(i)
                    changed = True
    loose = sorted(set(links) - reached)
    if loose:
        raise SceneError(f"links {', '.join(loose)} are pinned to nothing reachable from the ground", file=file)

    frame: dict[str, tuple[complex, float]] = {GROUND: (0j, 0.0)}
    for name in [n for n in links if n in parent]:
        _, pin = parent[name]
        others = [p for p in links[name].points if p != pin and abs(where[p] - where[pin]) > 0.0]
        angle = cmath.phase(where[others[0]] - where[pin]) if others else 0.0
        frame[name] = (where[pin], angle)

    def local(body: str, z: complex) -> complex:
        o, a = frame[body]
        return (z - o) * cmath.exp(-1j * a)

    sited: set[str] = set()
    children: dict[str, list[str]] = {}
    for name, (par, _) in parent.items():
        children.setdefault(par, []).append(name)
    names_used: set[str] = set()

    def unique(name: str) -> str:
        base, n = _fit(name), 1
        out = base
        while out in names_used:
            n += 1
            out = f"{base}_{n}"
        names_used.add(out)
        return out

    body_name = {GROUND: "world", **{n: unique(n) for n in links}}
    lines: list[str] = []

    def sites(body: str, pts: Sequence[str], indent: str) -> None:
        for p in pts:
            if p in sited:
                continue
            sited.add(p)
            z = local(body, where[p])
            lines.append(f'{indent}<site name={quoteattr(p)} pos="{_num(z.real)} {_num(z.imag)} 0"/>')

    def emit(body: str, indent: str) -> None:
        for child in children.get(body, []):
            o, a = frame[child]
            po, pa = frame[body]
            rel = local(body, o)
            lines.append(f'{indent}<body name="{body_name[child]}" pos="{_num(rel.real)} {_num(rel.imag)} 0" '
                         f'quat="{_quat(a - pa)}">')
            joint = crank_joint.get(child, f"{body_name[child]}_joint")
            lines.append(f'{indent}  <joint name={quoteattr(joint)} type="hinge" axis="0 0 1" ref="{_num(a - pa)}"/>')
            b = by_link.get(child)
            if b is not None and b.mass > 0:
                o0 = where[b.frame[0]]
                u = where[b.frame[1]] - o0
                c = local(child, o0 + b.center * u / abs(u))
                inertia = max(float(b.inertia), MIN_MASS * 1e-6)
                lines.append(f'{indent}  <inertial pos="{_num(c.real)} {_num(c.imag)} 0" mass="{_num(b.mass)}" '
                             f'diaginertia="{_num(inertia)} {_num(inertia)} {_num(inertia)}"/>')
            else:
                lines.append(f'{indent}  <inertial pos="0 0 0" mass="{_num(MIN_MASS)}" '
                             f'diaginertia="{_num(MIN_MASS * 1e-6)} {_num(MIN_MASS * 1e-6)} {_num(MIN_MASS * 1e-6)}"/>')
            sites(child, links[child].points, indent + "  ")
            emit(child, indent + "  ")
            lines.append(f"{indent}</body>")

    sites(GROUND, list(fixed), "    ")
    emit(GROUND, "    ")
    connects = []
    for i, p in enumerate(st.pins):
        if i in tree_pins:
            continue
        z = local(p.body, where[p.point])
        connects.append(f'    <connect name={quoteattr(_fit(p.point))} body1="{body_name[p.body]}" '
                        f'body2="{body_name[p.other]}" anchor="{_num(z.real)} {_num(z.imag)} 0"/>')
    g = scene.forces.spec.gravity if scene.forces is not None else 0j
    head = [
        f"<!-- written by linkage-mjcf from {quoteattr(str(file))[1:-1]} at inputs "
        f"{', '.join(f'{n} = {v!r}' for n, v in zip(scene.inputs, q))} (solver.models.export) -->",
        f"<mujoco model={quoteattr(_fit(scene.name))}>",
        '  <compiler angle="radian"/>',
        f'  <option gravity="{_num(g.real)} {_num(g.imag)} 0"/>',
        "  <worldbody>",
    ]
    tail = ["  </worldbody>"]
    if connects:
        tail += ["  <equality>", *connects, "  </equality>"]
    tail += ["  <actuator>", *(f'    <motor name={quoteattr(_fit(j) + "_motor")} joint={quoteattr(j)}/>'
                              for j in scene.inputs), "  </actuator>", "</mujoco>"]
    return "\n".join([*head, *lines, *tail]) + "\n"
