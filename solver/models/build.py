"""A laid-out model (solver.models.planar) → the equivalent group scene, as scene-file data.

Mobility (Grübler–Kutzbach, /work/shared/structure.md): F = 3·n − 2·(hinges + closures) −
couplings, n the moving rigid bodies; it must equal the number of inputs. The default inputs are
the joints the model's actuators drive (one of two coupled ones), completed when F is larger by
the model's other hinges on the ground in model order (an underactuated gripper's spring links). The inputs are hinges
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
from ..structure import GROUND
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
    sl = len(lay.slides)
    f = 3 * n - 2 * (h + sl + c) - k
    slides = f", {sl} slide(s)" if sl else ""
    return f, (f"{n} moving bodies, {h} hinges{slides}, {c} loop closures, {k} coupling(s): "
               f"F = 3·{n} − 2·{h + sl + c} − {k} = {f}")


def _complete(lay: PlanarModel, inputs: list[str]) -> list[str]:
    """The default inputs completed to the mobility: the model's other hinges on the ground, in
    model order (an underactuated gripper's spring-loaded links), neither coupled nor inputs."""
    f, _ = free_inputs(lay)
    tied = {c.joint for c in lay.model.couplings} | {c.source for c in lay.model.couplings}
    more = [j.name for j in lay.model.joints if j.parent == GROUND_BODY and j.kind == "hinge"
            and j.name not in inputs and j.name not in tied]
    return more[: max(0, f - len(inputs))]


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
        rank = {j: i for i, j in enumerate(model.actuated)}
        dependent = {max(c.joint, c.source, key=rank.__getitem__) for c in model.couplings
                     if c.joint in rank and c.source in rank}
        inputs = [j for j in model.actuated if j not in dependent]
        inputs += _complete(lay, inputs)
    inputs = list(inputs)
    for name in inputs:
        j = joints.get(name)
        if j is None:
            raise SceneError(f"input '{name}' is not a joint of the model; joints: {', '.join(joints)}", file=file,
                             entry="inputs")
        if j.kind != "hinge":
            raise SceneError(f"input '{name}' is a slide: a driven slide is a cylinder (an actuator group), not "
                             "imported yet; drive a hinge on the ground", file=file, entry="inputs")
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
    ground = pts[GROUND_BODY]
    for extra, z in (("world_origin", 0j), ("world_x", complex(lay.size, 0.0))):  # the ground's line
        if len(ground) < 2 and all(abs(z - w) > 1e-9 * lay.size for w in ground.values()):
            ground[extra] = z
    pin_of = {p.joint.name: p.point for p in lay.pins if p.joint is not None}
    blocks = {j.child: j for j in lay.slides}
    slides: dict[str, Any] = {}
    guides: dict[str, tuple[str, str]] = {}
    for body, j in blocks.items():
        shared = [p for p in pts[body] if sum(p in b for b in pts.values()) > 1]
        if len(shared) != 1:
            raise SceneError(f"slide '{j.name}': its block '{body}' must be pinned to one other body at one point, "
                             f"found {len(shared)} ({', '.join(shared) or 'none'})", file=file,
                             entry=f"joint {j.name}")
        b = shared[0]
        zb = pts[body][b]
        axis = complex(float(j.axis @ lay.plane.ex), float(j.axis @ lay.plane.ey))
        g0, g1 = f"{j.name}_guide0", f"{j.name}_guide1"
        pts[j.parent][g0] = zb
        pts[j.parent][g1] = zb + axis / abs(axis) * lay.size
        guides[j.name] = (g0, g1)
        slides[body] = {"point": b, "on": GROUND if j.parent == GROUND_BODY else j.parent, "along": [g0, g1]}
        pts[body] = {b: zb}
    fixed = dict(pts[GROUND_BODY])
    links: dict[str, list[str]] = {}
    for body, names in pts.items():
        if body == GROUND_BODY or body in blocks:
            continue
        order = list(names)
        pivot = next((pin_of[j.name] for j in model.joints if j.child == body and j.name in pin_of
                      and (j.name in inputs or j.name in coupled)), None)
        if pivot is not None:  # an input link: pinned to the ground at its first point
            shared = [p for p in order if p != pivot and sum(p in b for b in pts.values()) > 1]
            rest = [p for p in order if p != pivot and p not in shared]
            order = [pivot, *shared, *rest]
        if len(order) < 2:
            raise SceneError(f"body '{body}' has one point only ({', '.join(order)}): give it a second (a child "
                             "body, or a joint or closure on it)", file=file)
        links[body] = order
    child_of = {j.name: j.child for j in model.joints}
    taken = set(joints)

    def link_name(body: str) -> str:
        """The drawn link (and group) of a body: its name, unless a group's own joint name would be
        a model joint's (linkage-urdf names a crank's tree joint ``<group>_joint``)."""
        return f"{body}_link" if f"{body}_joint" in taken else body

    drawn_inputs: list[Any] = [{"link": link_name(child_of[name]), "joint": name} for name in inputs]
    for name, c in coupled.items():
        j = joints[name]
        if j.parent != GROUND_BODY or j.kind != "hinge":
            what = "is a slide" if j.kind != "hinge" else "turns a moving body"
            raise SceneError(f"{c.what}: the coupled joint '{name}' {what}: a coupled input is a hinge on the "
                             "ground", file=file)
        expect = c.offset + c.ratio * joints[c.source].value
        if abs(expect - j.value) > 1e-9:
            raise SceneError(f"{c.what}: '{name}' = {j.value:.9g} at the model's pose, the coupling gives "
                             f"{expect:.9g}", file=file)
        plane_ratio = lay.sign[name] * c.ratio * lay.sign[c.source]
        drawn_inputs.append({"link": link_name(j.child), "joint": name, "follows": c.source, "ratio": plane_ratio})
    drawn = {
        "scene": model.name,
        "units": {"length": "m", "angle": "rad"},
        "drawing": {
            "points": {n: [z.real, z.imag] for body in pts.values() for n, z in body.items()},
            "ground": list(fixed),
            "links": {link_name(body): order for body, order in links.items()},
            "inputs": drawn_inputs,
            **({"slides": {link_name(b): v | {"on": v["on"] if v["on"] == GROUND else link_name(v["on"])}
                           for b, v in slides.items()}} if slides else {}),
        },
        "outputs": {"points": list(fixed)[:1]},
    }
    from ..structure import scene_dict_from_drawing

    emitted = scene_dict_from_drawing(drawn, source=file)
    groups = [_model_convention(g, lay, joints, coupled) for g in emitted["groups"]]
    frame = {body: (order[0], order[1]) for body, order in links.items()}
    frame[GROUND_BODY] = (list(fixed)[0], list(fixed)[1])
    crank_joints = set(inputs) | set(coupled)
    named: dict[str, Any] = {}
    for body, j in blocks.items():  # a block turns with its guide: its frame is the guide line
        frame[body] = guides[j.name]
        pts[body].update({g: pts[j.parent][g] for g in guides[j.name]})
    for j in model.joints:
        if j.name in crank_joints:
            continue
        if j.kind == "slide":
            named[j.name] = {"prismatic": {"guide": list(guides[j.name]), "point": slides[j.child]["point"],
                                           "offset": j.value, "sign": 1}}
            continue
        parent, child = frame[j.parent], frame[j.child]
        sg = lay.sign[j.name]
        delta = cmath.phase((pts[j.child][child[1]] - pts[j.child][child[0]])
                            / (pts[j.parent][parent[1]] - pts[j.parent][parent[0]]))
        named[j.name] = {"revolute": {"parent": list(parent), "child": list(child),
                                      "offset": _wrap(j.value - sg * delta), "sign": int(sg)}}
    bodies = {}
    for rigid in model.bodies.values():
        if rigid.name == GROUND_BODY or rigid.mass <= 0.0:
            continue
        p0, p1 = frame[rigid.name]
        z0, z1 = pts[rigid.name][p0], pts[rigid.name][p1]
        u = (z1 - z0) / abs(z1 - z0)
        n = lay.plane.normal
        if rigid.name in blocks:  # a slider block: named by its point, its frame the guide's
            b = slides[rigid.name]["point"]
            cz = (lay.plane.of(rigid.com) - pts[rigid.name][b]) * u.conjugate()
            bodies[rigid.name] = {"points": [b], "mass": rigid.mass, "center": [cz.real, cz.imag],
                                  "inertia": float(n @ rigid.inertia @ n)}
            continue
        cz = (lay.plane.of(rigid.com) - z0) * u.conjugate()
        bodies[rigid.name] = {"points": [p0, p1], "mass": rigid.mass, "center": [cz.real, cz.imag],
                              "inertia": float(n @ rigid.inertia @ n)}
    g = model.gravity
    moving = [p for b, ps in pts.items() if b != GROUND_BODY for p in ps if p not in pts[GROUND_BODY]]
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


def _model_convention(g: dict[str, Any], lay: PlanarModel, joints: dict[str, Joint],
                      coupled: dict[str, Coupling]) -> dict[str, Any]:
    """An emitted crank (its joint the plane angle of O→A) made to read the model's joint value:
    θ = θ₀ + σ·q with θ₀ from the pose; a coupled one follows its input's model value."""
    if g["type"] not in ("crank", "coupled_crank"):
        return g
    j = joints[g["joint"]]
    pts = lay.points[j.child]
    arm = pts[g["point"]] - pts[g["center"]]
    sg = lay.sign[j.name]
    out = {k: g[k] for k in ("name", "center", "point", "length", "joint")}
    out = {"type": "crank", **out, "offset": _wrap(cmath.phase(arm) - sg * j.value), "sign": int(sg)}
    c = coupled.get(j.name)
    if c is not None:
        out["follows"] = {"joint": c.source, "ratio": c.ratio, "offset": c.offset}
    return out
