"""A laid-out model (solver.models.planar) → the equivalent group scene, as scene-file data.

Mobility (Grübler–Kutzbach, /work/shared/structure.md): F = 3·n − 2·(hinges + closures) −
couplings, n the moving rigid bodies; it must equal the number of inputs. The inputs are hinges
on the ground: each is a ``crank`` whose joint is the model's joint value (θ = θ₀ + σ·q, groups
crank.py); a hinge tied to an input by a coupling is a crank that ``follows`` it. Then, until
every body is placed: a body with two known points carries its other points (``attached``);
two bodies pinned together at an unknown point B, each with one known point (A, C), are an
``rrr`` dyad, its mode the side of A→C on which the model's pose has B (the sign of the signed
area of A, B, C). A structure that needs another group is refused, naming the bodies left.

Every other hinge is published in the model's own convention, under its own name: a
``revolute`` joint between the frames of its two bodies with sign σ and offset
q₀ = q_pose − σ·Δ_pose, so that it reads the model's joint value (MJCF qpos, URDF position).
Masses, centres and the moments of inertia about the plane's normal become ``bodies``; gravity's
in-plane part becomes ``gravity``.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Sequence
from typing import Any

from ..errors import SceneError
from .planar import PlanarModel
from .spatial import GROUND_BODY, Coupling, Joint

__all__ = ["scene_data", "free_inputs"]

#: |signed area| / size² below which an RRR dyad is at its toggle in the model's pose.
TOGGLE = 1e-9


def _wrap(a: float) -> float:
    w = math.remainder(a, 2.0 * math.pi)
    return math.pi if w == -math.pi else w


def free_inputs(lay: PlanarModel) -> tuple[int, str]:
    """The mobility F and how it was counted."""
    model = lay.model
    n = len(model.bodies) - 1
    h = sum(1 for j in model.joints if j.kind == "hinge")
    c = sum(1 for p in lay.pins if p.closure is not None)
    k = len(model.couplings)
    f = 3 * n - 2 * (h + c) - k
    return f, f"{n} moving bodies, {h} hinges, {c} loop closures, {k} coupling(s): F = 3·{n} − 2·{h + c} − {k} = {f}"


def _couplings(lay: PlanarModel, inputs: Sequence[str]) -> dict[str, Coupling]:
    """Each coupled joint → its coupling to an input (inverted where the model ties the input to it)."""
    out: dict[str, Coupling] = {}
    file = lay.model.file
    for c in lay.model.couplings:
        if c.joint in inputs and c.source in inputs:
            raise SceneError(f"{c.what} ties '{c.joint}' to '{c.source}': both cannot be inputs", file=file)
        if c.source in inputs:
            out[c.joint] = c
        elif c.joint in inputs:
            out[c.source] = Coupling(c.source, c.joint, 1.0 / c.ratio, -c.offset / c.ratio, c.what)
        else:
            raise SceneError(
                f"{c.what} ties '{c.joint}' to '{c.source}', neither of them an input ({', '.join(inputs)}): "
                "make one of them an input",
                file=file,
            )
    return out


def scene_data(lay: PlanarModel, inputs: Sequence[str] | None = None) -> dict[str, Any]:
    """Scene-file data (SI units) for the laid-out model, driven by ``inputs`` (model joint names;
    default: the joints the model's actuators drive, less those a coupling makes dependent)."""
    model, file = lay.model, lay.model.file
    joints = {j.name: j for j in model.joints}
    if inputs is None:
        order = {j: i for i, j in enumerate(model.actuated)}
        dependent = {max(c.joint, c.source, key=order.__getitem__) for c in model.couplings
                     if c.joint in order and c.source in order}
        inputs = [j for j in model.actuated if j not in dependent]
    inputs = list(inputs)
    for name in inputs:
        j = joints.get(name)
        if j is None:
            raise SceneError(f"input '{name}' is not a joint of the model; joints: {', '.join(joints)}", file=file,
                             entry="inputs")
        if j.parent != GROUND_BODY:
            raise SceneError(
                f"input '{name}' turns '{j.child}' on '{j.parent}', a moving body: an input turns a body on the "
                "ground (a crank)",
                file=file,
                entry="inputs",
            )
    coupled = _couplings(lay, inputs)
    f, counted = free_inputs(lay)
    if f != len(inputs):
        grounded = [j.name for j in model.joints if j.parent == GROUND_BODY and j.name not in inputs
                    and j.name not in coupled]
        hint = (f"; name {f} inputs: hinges on the ground not yet inputs: {', '.join(grounded) or 'none'}"
                if f > len(inputs) else f"; name {f}")
        raise SceneError(
            f"the model has {f} freedoms ({counted}) but {len(inputs)} input(s) ({', '.join(inputs) or 'none'})"
            + hint,
            file=file,
            entry="inputs",
        )
    pts = lay.points
    fixed = dict(pts[GROUND_BODY])
    if len(fixed) < 2:
        for extra, z in (("world.origin", 0j), ("world.x", complex(lay.size, 0.0))):
            if len(fixed) < 2 and all(abs(z - w) > 1e-9 * lay.size for w in fixed.values()):
                fixed[extra] = z
                pts[GROUND_BODY][extra] = z
    known: dict[str, complex] = dict(fixed)
    frame: dict[str, tuple[str, str]] = {GROUND_BODY: tuple(list(fixed)[:2])}  # type: ignore[dict-item]
    groups: list[dict[str, Any]] = []
    crank_joints: set[str] = set()

    def second_point(body: str, center: str) -> str:
        others = [p for p in pts[body] if p != center]
        shared = [p for p in others if sum(p in b for b in pts.values()) > 1]
        if not (shared or others):
            raise SceneError(f"body '{body}' has one point only: give it a second (a child body or a site)",
                             file=file)
        return (shared or others)[0]

    def crank(j: Joint, follows: Coupling | None) -> None:
        center = next(p.point for p in lay.pins if p.joint is j)
        a = second_point(j.child, center)
        arm = pts[j.child][a] - pts[j.child][center]
        sg = lay.sign[j.name]
        g: dict[str, Any] = {
            "type": "crank", "name": j.child, "center": center, "point": a, "length": abs(arm), "joint": j.name,
            "offset": _wrap(cmath.phase(arm) - sg * j.value), "sign": int(sg),
        }
        if follows is not None:
            expect = follows.offset + follows.ratio * joints[follows.source].value
            if abs(expect - j.value) > 1e-9:
                raise SceneError(
                    f"{follows.what}: '{j.name}' = {j.value:.9g} at the model's pose, the coupling gives "
                    f"{expect:.9g}", file=file)
            g["follows"] = {"joint": follows.source, "ratio": follows.ratio, "offset": follows.offset}
        groups.append(g)
        crank_joints.add(j.name)
        place(j.child, (center, a))

    def place(body: str, pair: tuple[str, str]) -> None:
        frame[body] = pair
        p0, p1 = pair
        z0, z1 = pts[body][p0], pts[body][p1]
        for name in pair:
            known[name] = pts[body][name]
        for name, z in pts[body].items():
            if name in known:
                continue
            base = p0 if abs(z - z0) >= abs(z - z1) else p1
            zb = pts[body][base]
            groups.append({
                "type": "attached", "name": f"{body}.{name}", "point": name, "base": base, "along": [p0, p1],
                "distance": abs(z - zb), "angle": cmath.phase((z - zb) / (z1 - z0)),
            })
            known[name] = z

    for name in inputs:
        crank(joints[name], None)
    for name, c in coupled.items():
        j = joints[name]
        if j.parent != GROUND_BODY:
            raise SceneError(f"{c.what}: the coupled joint '{name}' turns a moving body: a coupled input is a "
                             "hinge on the ground", file=file)
        crank(j, c)
    todo = [b for b in pts if b not in frame]
    while todo:
        for b in todo:
            have = [p for p in pts[b] if p in known]
            if len(have) >= 2:
                place(b, (have[0], have[1]))
                break
        else:
            if not _dyad(lay, todo, known, groups, place):
                raise SceneError(
                    f"bodies {', '.join(todo)} are not placed by cranks, RRR dyads and points on links "
                    "(a structure of another class, or too few inputs there)",
                    file=file,
                )
        todo = [b for b in pts if b not in frame]
    named: dict[str, Any] = {}
    for j in model.joints:
        if j.name in crank_joints:
            continue
        parent, child = frame[j.parent], frame[j.child]
        sg = lay.sign[j.name]
        delta = cmath.phase((pts[j.child][child[1]] - pts[j.child][child[0]])
                            / (pts[j.parent][parent[1]] - pts[j.parent][parent[0]]))
        named[j.name] = {"revolute": {"parent": list(parent), "child": list(child),
                                      "offset": _wrap(j.value - sg * delta), "sign": int(sg)}}
    bodies = {}
    for body in model.bodies.values():
        if body.name == GROUND_BODY or body.mass <= 0.0:
            continue
        p0, p1 = frame[body.name]
        z0, z1 = pts[body.name][p0], pts[body.name][p1]
        u = (z1 - z0) / abs(z1 - z0)
        cz = (lay.plane.of(body.com) - z0) * u.conjugate()
        n = lay.plane.normal
        bodies[body.name] = {"points": [p0, p1], "mass": body.mass, "center": [cz.real, cz.imag],
                             "inertia": float(n @ body.inertia @ n)}
    g = model.gravity
    moving = [p for b, ps in pts.items() if b != GROUND_BODY for p in ps]
    data: dict[str, Any] = {
        "scene": model.name,
        "provenance": f"{model.provenance}; plane: {lay.plane.describe()}",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {k: [v.real, v.imag] for k, v in fixed.items()},
        "groups": groups,
        "joints": named,
        "outputs": {"points": list(dict.fromkeys(moving)), "joints": [j.name for j in model.joints]},
    }
    if bodies:
        data["bodies"] = bodies
        data["gravity"] = [float(g @ lay.plane.ex), float(g @ lay.plane.ey)]
    return data


def _dyad(lay: PlanarModel, todo: list[str], known: dict[str, complex], groups: list[dict[str, Any]],
          place: Any) -> bool:
    pts = lay.points
    for pin in lay.pins:
        b1, b2 = pin.bodies
        if b1 not in todo or b2 not in todo or pin.point in known:
            continue
        k1 = [p for p in pts[b1] if p in known]
        k2 = [p for p in pts[b2] if p in known]
        if len(k1) != 1 or len(k2) != 1 or k1[0] == k2[0]:
            continue
        a, c, b = k1[0], k2[0], pin.point
        za, zb, zc = known[a], pts[b1][b], known[c]
        area = ((zb - za).conjugate() * (zc - za)).imag / 2.0
        if abs(area) <= TOGGLE * lay.size**2:
            raise SceneError(
                f"dyad {b1}–{b2} (ends {a}, {c}, pin {b}) is at its toggle in the model's pose: its assembly mode "
                "is undefined there; import the model at another pose (keyframe=)",
                file=lay.model.file,
            )
        groups.append({"type": "rrr", "name": f"{b1}+{b2}", "ends": [a, c], "point": b,
                       "lengths": [abs(zb - za), abs(zb - zc)], "M": 1 if area > 0 else -1})
        known[b] = zb
        place(b1, (a, b))
        place(b2, (c, b))
        return True
    return False
