"""The scene's bodies on the tree: readable link names and ``<inertial>`` from ``bodies:``.

A scene that names its links (``bodies: {boom: {points: [O1, C1], mass: …}}``, docs/forces.md)
says which link is which better than the group that solves it does (group ``boom_cylinder``
solves the boom; RRR ``bucket_link`` the rod E–G and the bucket D–G). Each named body of the
scene is matched to the tree body that carries its points (a slider block: the tree's slider or
eyelet at its one point); that link, and the tree joint that hangs it (``<link>_joint``), take the
scene's name. The actuators' barrel and rod (``<g>_barrel``, ``<g>_rod``, ``<g>_rod_joint``) are
no scene bodies and keep their names, as do the cuts (``<group>_<point>``).

Inertial (URDF ``<inertial>``, in the link frame): the scene's mass; its centre of mass, given in
the body frame of docs/forces.md (origin at the first point, x toward the second; a block's x
along its guide), carried into the link frame: ``c_link = p₀ + c·(p₁ − p₀)/|p₁ − p₀|`` with the
frame points' link coordinates p₀, p₁ (a block: ``p₀ + c·e``, e its guide's direction in the link
frame); ``izz`` the scene's inertia about the centre (a flywheel on the input included, as the
dynamics use it). A planar body says nothing of ``ixx``, ``iyy``: they are written as a thin plate
in the plane of motion, ``ixx = iyy = izz/2`` (the perpendicular-axis theorem, so the triangle
inequalities hold), products zero. A point mass (mass, no inertia: a piston) gets a small
sphere's ``2/5·m·r²`` on every axis, r = :data:`POINT_MASS_RADIUS_PER_SIZE` of the scene's size,
so that simulators needing a positive-definite inertia load it; a massless link has no
``<inertial>``.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from .tree import BASE_LINK, Body, Cut, Inertial, TreeJoint, TreeModel, Vec3

__all__ = ["Inertial", "POINT_MASS_RADIUS_PER_SIZE", "name_and_weigh", "tensor"]

#: The radius of the small sphere given to a point mass (a body with mass and no inertia), as a
#: fraction of the scene's size (the bar radius of the drawing).
POINT_MASS_RADIUS_PER_SIZE = 1.0 / 100.0

_BLOCK_ROLES = ("slider", "eyelet")


def tensor(inertial: Inertial, size: float) -> tuple[float, float, float]:
    """``(ixx, iyy, izz)`` of the URDF inertia (products zero): see the module docstring."""
    if inertial.izz > 0.0:
        return 0.5 * inertial.izz, 0.5 * inertial.izz, inertial.izz
    r = POINT_MASS_RADIUS_PER_SIZE * size
    sphere = 0.4 * inertial.mass * r * r
    return sphere, sphere, sphere


def _c(v: Vec3) -> complex:
    return complex(v[0], v[1])


def _match(body: Any, tree: dict[str, Body]) -> Body | None:
    """The tree body carrying scene body ``body`` (a :class:`solver.forces.Body`)."""
    frame = set(body.frame)
    if body.link.block:
        return next((b for b in tree.values() if b.role in _BLOCK_ROLES and frame <= set(b.local)), None)
    fits = [b for b in tree.values() if b.name != BASE_LINK and b.role not in _BLOCK_ROLES and frame <= set(b.local)]
    return next((b for b in fits if set(body.points) <= set(b.local)), fits[0] if fits else None)


def _center(body: Any, link: Body) -> Vec3:
    p0 = _c(link.local[body.frame[0]])
    if body.link.block:  # x along the guide: the slider's frame is the guide's, the eyelet's its link's
        e = 1.0 + 0j
    else:
        d = _c(link.local[body.frame[1]]) - p0
        e = d / abs(d)
    c = p0 + complex(body.center) * e
    return (c.real, c.imag, 0.0)


def name_and_weigh(scene: Any, model: TreeModel, error: Any) -> TreeModel:
    """``model`` with the scene's named bodies as link names and their :class:`Inertial` in
    ``Body.inertial`` (unchanged for a scene without ``bodies:``). ``error(message)`` makes the
    :class:`~solver.errors.SceneError` for a body with mass that no link of the tree carries."""
    forces = getattr(scene, "forces", None)
    if forces is None:
        return model
    named = set(forces.spec.names.values())
    rename: dict[str, str] = {}
    weights: dict[str, Inertial] = {}
    for body in forces.spec.bodies:
        if body.inert and body.name not in named:
            continue
        link = _match(body, model.bodies)
        if link is None:
            if body.inert:
                continue
            raise error(f"body '{body.name}' (points {', '.join(body.points)}) is carried by no single link "
                        "of the tree; its mass cannot be written")
        if link.name in weights or link.name in rename:
            raise error(f"bodies '{body.name}' and '{rename.get(link.name, link.name)}' would both be link "
                        f"'{link.name}' of the tree")
        if not body.inert:
            weights[link.name] = Inertial(body.mass, _center(body, link), body.inertia)
        if body.name in named and link.role != "rod":
            rename[link.name] = body.name
    return _renamed(model, rename, weights)


def _renamed(model: TreeModel, rename: dict[str, str], weights: dict[str, Inertial]) -> TreeModel:
    def n(name: str) -> str:
        return rename.get(name, name)

    bodies = {}
    for name, b in model.bodies.items():
        bodies[n(name)] = replace(b, name=n(name), inertial=weights.get(name))
    joints: list[TreeJoint] = []
    for j in model.joints:
        name = f"{n(j.child)}_joint" if j.name == f"{j.child}_joint" else j.name
        joints.append(replace(j, name=name, parent=n(j.parent), child=n(j.child)))
    cuts: list[Cut] = [replace(c, side_a=n(c.side_a), side_b=n(c.side_b)) for c in model.cuts]
    owner = {p: n(b) for p, b in model.owner.items()}
    return replace(model, bodies=bodies, joints=joints, cuts=cuts, owner=owner)
