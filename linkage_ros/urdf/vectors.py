"""A vector-loop scene (seed 004, :mod:`solver.vectors`) opened into a spanning tree of bodies.

A vector scene names vectors, not bodies; the bodies follow from the vectors (docs/urdf.md,
"Vector scenes"):

* **Nodes.** Every vector runs from a tail node to a head node. Each contour's and each point's
  signed sum chains its vectors (``+V``: from tail to head; ``−V``: from head to tail), from a fixed
  point for a point, round to where it started for a contour; a vector used in several sums joins
  their nodes. Fixed points and named points name their nodes; a node that a constant vector puts
  on a fixed point is that point.
* **Bodies.** A vector's *class* is what its angle follows: the input φ, one unknown angle (the
  vectors linked to it by α_k = α_i + Δ share it), or nothing (a constant angle). Within one class,
  the vectors of constant length join their nodes rigidly; each connected set is one body. The
  constant-angle set that holds the fixed points is the frame, ``base_link``; other constant-angle
  sets translate (sliders).
* **Slides.** A vector of variable length is a prismatic joint, along the vector, between the
  body of its class that holds its tail and the one that holds its head.
* **Pins.** Bodies of different classes that share a node are pinned there.
* **Tree and cuts.** Slides are always on the tree (a cut slide would leave its two frames apart).
  Pins are added in the order the solver makes their bodies known — the frame, the input, then
  each contour's unknowns — and, among the pins of one contour, the pin joining two bodies that
  contour solves comes last; a pin that would close a loop is cut. So each contour is cut at the
  pin between two of the bodies it solves (the four-bar at B between coupler and rocker, the
  harvester finger at the eyelet pin B between eyelet and drum), as the group form is.

Every tree joint coordinate is read off the solver's points and joints (:mod:`.states`): a body's
direction from a scene joint ``{angle: V}`` of its class (or φ for the input), else from two named
points on one body of its class; a body located by a slide needs one named point. Where the scene
gives neither, the export says which body and what to add. After building, the tree is placed by
planar forward kinematics at a few φ and every named point compared with the solver's: a vector
used as a free vector (added somewhere it does not lie) is reported, not exported wrongly.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Iterable
from typing import Any

import numpy as np

from .states import kinematics_tree_joint_states
from .tree import BASE_LINK, Body, Cut, TreeJoint, TreeModel, Vec3, check_names
from .vector_bodies import TOL_PLACE, Comp, UnionFind, VectorBodies

__all__ = ["build_vector_model", "TOL_PLACE", "TOL_CHECK"]

#: The build-time check of the tree against the solver's points (relative to the scene's size):
#: loose, it catches a wrong structure, not rounding (the tests hold the closure to 1e-9 m).
TOL_CHECK = 1e-6
#: Input angles of the build-time check (rad).
CHECK_PHI = (0.3, 1.9, 3.7, 5.2)

_Z = 0j


def _v(z: complex) -> Vec3:
    return (float(z.real), float(z.imag), 0.0)


def _edges(b: VectorBodies) -> tuple[list[tuple[Comp, Comp, str]], list[tuple[tuple[int, int, int], str, Comp, Comp]]]:
    """Slides ``(tail side, head side, vector)`` and pins ``(key, node, holder, holder)``."""
    slides = []
    for v in b.vectors.values():
        if v.length is not None:
            t, h = (b.node[k] for k in b.ends(v.name))
            slides.append((b.comp_of[(v.cls, t)], b.comp_of[(v.cls, h)], v.name))
    holders: dict[str, list[Comp]] = {}
    for (_, n), comp in b.comp_of.items():
        if comp not in holders.setdefault(n, []):
            holders[n].append(comp)
    pins = []
    for n, hs in holders.items():
        hs.sort(key=lambda c: (c.rank, c.order))
        for other in hs[1:]:
            pins.append(((other.rank, hs[0].rank, b.node_order[n]), n, hs[0], other))
    pins.sort(key=lambda p: p[0])
    return slides, pins


def _axis_source(b: VectorBodies, cls: str, comps: Iterable[Comp]) -> tuple[str | tuple[str, str], float]:
    """How the tree joint states read the class's direction: ``(axis, turn)`` (see :class:`Body`)."""
    if cls == b.inp.unit:
        return str(b.inp.joint), 0.0
    for j in b.vjoints:
        if j.expression == "angle" and j.ref.base == cls:
            return str(j.name), -float(j.ref.offset)
    best: tuple[float, str, str, complex] | None = None
    for comp in comps:
        named = [n for n in comp.nodes if n in b.reported]
        for i, p in enumerate(named):
            for q in named[i + 1:]:
                d = comp.pos[q] - comp.pos[p]
                if best is None or abs(d) > best[0] * (1 + TOL_PLACE):
                    best = (abs(d), p, q, d)
    if best is None or best[0] <= TOL_PLACE * b.size:
        owner = cls.rsplit(".", 1)[0]
        raise b.error(
            f"the angle of vector '{owner}' ({cls}) cannot be read from the scene's outputs: no joint "
            f"{{angle: V}} follows it and no body of it holds two named points; add a joint "
            f"{{angle: {owner}}} to vector_model.joints (or name a second point on that body)",
            "vector_model",
        )
    _, p, q, d = best
    return (p, q), -cmath.phase(d)


def build_vector_model(scene: Any) -> TreeModel:
    """The spanning tree of a vector-loop scene (see the module docstring)."""
    b = VectorBodies(scene)
    b.collect()
    b.merge_onto_fixed_points()
    b.name_nodes()
    b.components()
    b.rank_and_name()
    slides, pins = _edges(b)

    # the tree: every slide, then the pins in order; a pin closing a loop is cut
    uf = UnionFind()
    adj: dict[str, list[tuple[Comp, str, Any]]] = {c.name: [] for c in b.comps}
    for a, c, v in slides:
        if not uf.union(a.name, c.name):
            raise b.error(f"the slide of vector '{v}' closes a loop of slides with no pin to cut")
        adj[a.name].append((c, "slide", (v, True)))
        adj[c.name].append((a, "slide", (v, False)))
    cut_pins: list[tuple[str, Comp, Comp]] = []
    for _, n, h0, h1 in pins:
        if uf.union(h0.name, h1.name):
            adj[h0.name].append((h1, "pin", n))
            adj[h1.name].append((h0, "pin", n))
        else:
            cut_pins.append((n, h0, h1))
    base = next(c for c in b.comps if c.is_base)
    loose = sorted(c.name for c in b.comps if uf.find(c.name) != uf.find(base.name))
    if loose:
        raise b.error(f"the bodies {', '.join(loose)} are joined to the frame by no pin or slide")

    # bodies and tree joints, depth first from the frame (parents before children)
    bodies: dict[str, Body] = {}
    joints: list[TreeJoint] = []
    owner: dict[str, str] = {}
    comp_by_name = {c.name: c for c in b.comps}
    axes = {
        cls: _axis_source(b, cls, [c for c in b.comps if c.cls == cls])
        for cls in dict.fromkeys(c.cls for c in b.comps if c.cls is not None)
    }
    frame = Body(BASE_LINK, "base")
    for n in base.nodes:
        frame.local[n] = _v(base.pos[n])
    bodies[BASE_LINK] = frame
    for n in base.nodes:
        owner[n] = BASE_LINK

    def add(comp: Comp, origin: str) -> Body:
        o = comp.pos[origin]
        axis: Any = 1 + 0j
        turn = 0.0
        if comp.cls is not None:
            axis, turn = axes[comp.cls]
        body = Body(comp.name, "bar", origin, axis, {n: _v(comp.pos[n] - o) for n in comp.nodes}, turn=turn)
        bodies[comp.name] = body
        for n in comp.nodes:
            owner.setdefault(n, comp.name)
        return body

    def visit(comp: Comp) -> None:
        nexts = sorted(adj[comp.name], key=lambda e: (e[0].rank, e[0].order))
        for child, kind, data in nexts:
            if child.name in bodies:
                continue
            parent = bodies[comp.name]
            if kind == "pin":
                body = add(child, data)
                unwrap = b.inp.joint if (comp.is_base and child.cls == b.inp.unit) else None
                joints.append(TreeJoint(f"{child.name}_joint", "continuous", parent.name, child.name,
                                        parent.local[data], (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), "planar_pin", (unwrap,)))
            else:
                vname, from_tail = data
                vec = b.vectors[vname]
                t, h = (b.node[k] for k in b.ends(vname))
                near, far = (t, h) if from_tail else (h, t)
                body = add(child, far)
                beta = vec.angle
                x0 = parent.local[near]
                joints.append(TreeJoint(f"{child.name}_joint", "prismatic", parent.name, child.name, x0,
                                        (0.0, 0.0, 0.0), (math.cos(beta), math.sin(beta), 0.0), "planar_slide",
                                        (x0, beta)))
                body.role = "eyelet" if child.cls is not None else "slider"
                body.size["yaw"] = beta
            visit(child)

    visit(base)
    _dress(b, bodies, slides, pins, cut_pins)
    cuts = [_cut(b, n, h0, h1, bodies) for n, h0, h1 in cut_pins]
    _locate(b, bodies, joints, comp_by_name)
    model = TreeModel(
        scene_name=str(scene.name),
        dim=int(scene.dim),
        input_joint=str(scene.input_joint),
        bodies=bodies,
        joints=joints,
        cuts=cuts,
        owner=owner,
    )
    check_names(model, tuple(scene.joint_names), b.error)
    _check_places(b, scene, model)
    return model


def _dress(b: VectorBodies, bodies: dict[str, Body], slides: list[tuple[Comp, Comp, str]],
           pins: list[tuple[tuple[int, int, int], str, Comp, Comp]],
           cut_pins: list[tuple[str, Comp, Comp]]) -> None:
    """Bars, pins and the drum of the visuals."""
    for v in b.vectors.values():
        if v.length is None and v.r != 0.0:
            t, h = (b.node[k] for k in b.ends(v.name))
            body = bodies[b.comp_of[(v.cls, t)].name]
            if body.name != BASE_LINK:
                body.bars.append((t, h))
    for _, n, h0, h1 in pins:
        for comp in (h0, h1):
            body = bodies[comp.name]
            if comp.name != BASE_LINK and n not in body.pins:
                body.pins.append(n)
    eyelets = {n for body in bodies.values() if body.role == "eyelet" for n in body.local}
    for comp in b.comps:
        if comp.cls == b.inp.unit and comp.name in bodies and eyelets & set(comp.nodes):
            body = bodies[comp.name]
            body.role = "drum"
            body.size["radius"] = max(abs(complex(x, y)) for x, y, _ in body.local.values())


def _cut(b: VectorBodies, n: str, h0: Comp, h1: Comp, bodies: dict[str, Body]) -> Cut:
    a, c = sorted((h0, h1), key=lambda x: (-x.rank, x.order))
    rank = max(h0.rank, h1.rank)
    contour = b.contours[rank - 2].name if rank >= 2 else b.inp.joint
    why = (f"pin {n} joins '{a.name}' and '{c.name}', the bodies contour '{contour}' makes known last; "
           "cutting it keeps every body on the tree") if rank >= 2 else (
           f"pin {n} joins '{a.name}' and '{c.name}'; cutting it keeps every body on the tree")
    return Cut(f"{contour}_{n}", "pin", n, a.name, bodies[a.name].local[n], c.name, bodies[c.name].local[n], why)


def _locate(b: VectorBodies, bodies: dict[str, Body], joints: list[TreeJoint], comps: dict[str, Comp]) -> None:
    """Give every body a slide touches a named point to locate its origin from."""
    readable = b.reported | set(bodies[BASE_LINK].local)
    for j in joints:
        if j.type != "prismatic":
            continue
        for name in (j.parent, j.child):
            body = bodies[name]
            if name == BASE_LINK or body.origin in readable:
                continue
            named = [n for n in comps[name].nodes if n in readable]
            if not named:
                raise b.error(
                    f"body '{name}' (nodes {', '.join(comps[name].nodes)}) carries the slide '{j.name}' but "
                    "holds no point the solver reports, so its place cannot be read; name one of its nodes "
                    "in vector_model.points",
                    "vector_model",
                )
            body.anchor = named[0]


def _check_places(b: VectorBodies, scene: Any, model: TreeModel) -> None:
    """Place the tree by planar forward kinematics at a few φ; compare with the solver's points."""
    k = scene.everything().solve(np.asarray(CHECK_PHI), mask=True)
    valid = np.flatnonzero(np.asarray(k.valid, bool))
    if valid.size == 0:
        return
    states = kinematics_tree_joint_states(model, k)
    tol = TOL_CHECK * b.size
    for i in valid:
        pose: dict[str, tuple[complex, complex]] = {BASE_LINK: (_Z, 1 + 0j)}
        for jn, j in enumerate(model.joints):
            o, u = pose[j.parent]
            q = float(states.position[i, jn])
            x = complex(j.xyz[0], j.xyz[1])
            if j.type == "prismatic":
                pose[j.child] = (o + u * (x + q * complex(j.axis[0], j.axis[1])), u)
            else:
                pose[j.child] = (o + u * x, u * cmath.exp(1j * q))
        for body in model.bodies.values():
            o, u = pose[body.name]
            for n, xyz in body.local.items():
                if n not in k.points:
                    continue
                p = k.point(n).position[i]
                here = o + u * complex(xyz[0], xyz[1])
                if abs(here - complex(p[0], p[1])) > tol:
                    raise b.error(
                        f"point '{n}' on body '{body.name}' does not follow the solver (off by "
                        f"{abs(here - complex(p[0], p[1])):.3g} m at φ = {k.phi[i]:.3g} rad): a vector's sum places "
                        "it where the vector does not lie (a vector used as a free vector in a point's or a "
                        "contour's sum)",
                        "vector_model",
                    )
