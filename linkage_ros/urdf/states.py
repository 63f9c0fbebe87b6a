"""Exact positions and velocities of the tree joints, read off the solver's points and joints.

For robot_state_publisher: with these joint states the URDF tree puts every body where the solver
put it, so the two frames of every cut coincide (to rounding).

Planar bodies: a body's pose is its origin ``o`` (a point) and a direction ``r`` (a vector between
two points, or a constant); its angular velocity is ``ω = (r × ṙ)/|r|²``.

* pin (``planar_pin``): ``q = atan2(r_p × r_c, r_p · r_c)`` ∈ (−π, π] — the child's direction
  measured from the parent's; ``q̇ = ω_c − ω_p``. The driving crank is unwrapped to follow φ.
* slide (``planar_slide``): joint origin ``J = o_p + u_p·x₀``, axis ``a = u_p·e^{jβ}``
  (``u_p = r_p/|r_p|``): ``q = (o_c − J)·a``; since ``o_c − J`` stays along ``a`` and ``ȧ ⊥ a``,
  ``q̇ = (ȯ_c − J̇)·a`` with ``J̇ = ȯ_p + j·ω_p·u_p·x₀``.
* ``joint_value``: a scene joint's own coordinate (the spherical shaft φ and cage ψ).
* ``spherical_ring``: the bearing ring turns relative to the shaft about the groove normal
  ``n₀ = (cos α, sin α, 0)`` by ``θ = atan2(s, c)`` with ``s = −cos α·sin ψ − sin α·sin φ·cos ψ``
  and ``c = cos φ·cos ψ`` (the angle from the shaft's z axis to the rod direction
  ``k = (0, sin ψ, cos ψ)`` seen in the shaft frame ``R_y(φ)``, about ``n₀``);
  ``θ̇ = (c·ṡ − s·ċ)/(s² + c²)``.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable, Mapping
from typing import Any, NamedTuple

import numpy as np

from .tree import BASE_LINK, TreeModel

__all__ = ["TreeJointStates", "evaluate_tree", "tree_inputs", "tree_joint_states", "frame_tree_joint_states",
           "kinematics_tree_joint_states"]

TWO_PI = 2.0 * math.pi


class TreeJointStates(NamedTuple):
    """Names of the tree joints (URDF order) and their positions and velocities: tuples of
    floats for one frame, or ``(N, J)`` arrays for a sweep."""

    names: tuple[str, ...]
    position: Any
    velocity: Any


class _Functions(NamedTuple):
    """The elementary functions of one evaluation: :mod:`math` on floats, numpy on arrays."""

    atan2: Callable[[Any, Any], Any]
    sin: Callable[[Any], Any]
    cos: Callable[[Any], Any]
    floor: Callable[[Any], Any]


_SCALAR = _Functions(math.atan2, math.sin, math.cos, math.floor)
_ARRAYS = _Functions(np.arctan2, np.sin, np.cos, np.floor)
#: ``(o, ȯ, r, ṙ, ω)`` of the base: at the origin, x axis along x, at rest.
_BASE_POSE = (0j, 0j, 1 + 0j, 0j, 0.0)


class _Body(NamedTuple):
    """How to read one planar body's pose off the point and joint values (resolved once)."""

    name: str
    #: The x axis before the turn: two point names (tail, head), a scene joint's name (its
    #: position is the axis' absolute angle), or a constant complex direction.
    axis: tuple[str, str] | str | complex
    #: ``e^{j·turn}``; None when the body is not turned.
    turn: complex | None
    #: Whether the origin is needed (a slide's bodies; a pin reads directions only).
    locate: bool
    #: Whether the angular velocity is needed (a pin's bodies, a slide's parent, an anchor).
    spin: bool
    #: The point the origin is read at (``anchor`` None) or located from.
    origin: str | None
    #: A point of the body that locates the origin, and its place ``x`` in the body frame.
    anchor: str | None
    x: complex


class _Plan:
    """A model's tree joints resolved once: the bodies whose poses the joints read, each joint's
    rule with its constants, and which points and scene joints the evaluation reads."""

    def __init__(self, model: TreeModel) -> None:
        self.names = model.joint_names
        base = model.bodies[BASE_LINK].local
        self.fixed = {n: complex(v[0], v[1]) for n, v in base.items()}
        located: dict[str, bool] = {}  # body -> whether its origin is needed
        spinning: set[str] = set()  # bodies whose angular velocity a joint reads
        self.joints: list[tuple[str, tuple[Any, ...]]] = []
        joint_inputs: list[str] = []
        for j in model.joints:
            if j.rule == "planar_pin":
                unwrap = None if j.data[0] is None else str(j.data[0])
                for body in (j.parent, j.child):
                    located.setdefault(body, False)
                    spinning.add(body)
                joint_inputs += [unwrap] if unwrap is not None else []
                args: tuple[Any, ...] = (j.parent, j.child, unwrap)
            elif j.rule == "planar_slide":
                x0v, beta = j.data[:2]
                located[j.parent] = located[j.child] = True
                spinning.add(j.parent)
                args = (j.parent, j.child, complex(x0v[0], x0v[1]),  # type: ignore[index]
                        complex(math.cos(beta), math.sin(beta)))  # type: ignore[arg-type]
            elif j.rule == "joint_value":
                args = (str(j.data[0]),)
                joint_inputs += args
            elif j.rule == "spherical_ring":
                shaft, cage, alpha = j.data
                args = (str(shaft), str(cage), math.cos(alpha), math.sin(alpha))  # type: ignore[arg-type]
                joint_inputs += args[:2]
            else:  # pragma: no cover - the model only makes the rules above
                raise ValueError(f"unknown tree-joint rule {j.rule!r}")
            self.joints.append((j.rule, args))
        self.bodies = [_body(model, name, locate, name in spinning)
                       for name, locate in located.items() if name != BASE_LINK]
        points: list[str] = []
        for b in self.bodies:
            if isinstance(b.axis, tuple):
                points += b.axis
            elif isinstance(b.axis, str):
                joint_inputs.append(b.axis)
            if b.locate:
                points.append(b.anchor if b.anchor is not None else b.origin)  # type: ignore[arg-type]
        self.points = tuple(dict.fromkeys(points))
        self.joint_inputs = tuple(dict.fromkeys(joint_inputs))


def _body(model: TreeModel, name: str, locate: bool, spin: bool) -> _Body:
    b = model.bodies[name]
    assert b.origin is not None
    axis: tuple[str, str] | str | complex
    if isinstance(b.axis, (tuple, str)):
        axis = b.axis
    else:
        axis = complex(b.axis)  # type: ignore[arg-type]
    turn = complex(math.cos(b.turn), math.sin(b.turn)) if b.turn else None
    anchor = None if b.anchor is None or b.anchor == b.origin else b.anchor
    x = 0j if anchor is None else complex(b.local[anchor][0], b.local[anchor][1])
    return _Body(name, axis, turn, locate, spin or (locate and anchor is not None), b.origin, anchor, x)


#: Plans by ``id`` of their model, made on a model's first evaluation and dropped with the model
#: (models are not changed once built).
_PLANS: dict[int, _Plan] = {}


def _plan(model: TreeModel) -> _Plan:
    plan = _PLANS.get(id(model))
    if plan is None:
        plan = _PLANS[id(model)] = _Plan(model)
        weakref.finalize(model, _PLANS.pop, id(model), None)
    return plan


def _cross(a: Any, b: Any) -> Any:
    return a.real * b.imag - a.imag * b.real


def _dot(a: Any, b: Any) -> Any:
    return a.real * b.real + a.imag * b.imag


def _omega(r: Any, dr: Any) -> Any:
    """``ω = (r × ṙ)/|r|²`` (written out: it runs once per body and tick)."""
    return (r.real * dr.imag - r.imag * dr.real) / (r.real * r.real + r.imag * r.imag)


#: Position and velocity by name: complex numbers (arrays) for points, floats (arrays) for joints.
_Values = Mapping[str, tuple[Any, Any]]


def _pose(b: _Body, points: _Values, joints: _Values, f: _Functions) -> tuple[Any, Any, Any, Any, Any]:
    """``(o, ȯ, r, ṙ, ω)`` of a planar body: origin, a vector along its x axis and the angular
    velocity (``o, ȯ`` are ``None`` unless the body is located: a pin reads directions only;
    ``ω`` is ``None`` unless a joint or the anchor reads it).
    ``points``: position and velocity of each point as complex numbers (arrays); ``joints``: those
    of the scene joints."""
    axis = b.axis
    if isinstance(axis, tuple):
        (pt, vt), (ph, vh) = points[axis[0]], points[axis[1]]
        r, dr = ph - pt, vh - vt
    elif isinstance(axis, str):  # a scene joint: the absolute angle of the axis
        q, dq = joints[axis]
        r = f.cos(q) + 1j * f.sin(q)
        dr = 1j * dq * r
    else:
        r, dr = axis, 0j
    if b.turn is not None:
        r, dr = r * b.turn, dr * b.turn
    w = _omega(r, dr) if b.spin else None
    if not b.locate:
        return None, None, r, dr, w
    if b.anchor is None:
        o, do = points[b.origin]  # type: ignore[index]
    else:  # o = P − u·x, ȯ = Ṗ − j·ω·u·x with x the anchor's place in the body frame
        pa, va = points[b.anchor]
        assert w is not None  # an anchored body always spins (_body)
        u = r / abs(r)
        o, do = pa - u * b.x, va - 1j * w * u * b.x
    return o, do, r, dr, w


def _evaluate(plan: _Plan, points: _Values, joints: _Values, f: _Functions) -> tuple[list[Any], list[Any]]:
    """Positions and velocities of the tree joints, in URDF order (the rules: module docstring)."""
    poses = {BASE_LINK: _BASE_POSE}
    for b in plan.bodies:
        poses[b.name] = _pose(b, points, joints, f)
    qs: list[Any] = []
    dqs: list[Any] = []
    for rule, args in plan.joints:
        if rule == "planar_pin":
            parent, child, unwrap = args
            _, _, rp, _, wp = poses[parent]
            _, _, rc, _, wc = poses[child]
            q = f.atan2(_cross(rp, rc), _dot(rp, rc))
            if unwrap is not None:
                phi = joints[unwrap][0]
                q = q + TWO_PI * f.floor((phi - q) / TWO_PI + 0.5)
            dq = wc - wp
        elif rule == "planar_slide":
            parent, child, x0, turn = args
            op, dop, rp, _, wp = poses[parent]
            oc, doc, _, _, _ = poses[child]
            up = rp / abs(rp)
            a = up * turn
            q = _dot(oc - (op + up * x0), a)
            dq = _dot(doc - (dop + 1j * wp * up * x0), a)
        elif rule == "joint_value":
            q, dq = joints[args[0]]
        else:  # spherical_ring
            shaft, cage, ca, sa = args
            phi, dphi = joints[shaft]
            psi, dpsi = joints[cage]
            sf, cf, sp, cp = f.sin(phi), f.cos(phi), f.sin(psi), f.cos(psi)
            s = -ca * sp - sa * sf * cp
            c = cf * cp
            ds = -ca * cp * dpsi - sa * (cf * cp * dphi - sf * sp * dpsi)
            dc = -sf * cp * dphi - cf * sp * dpsi
            q = f.atan2(s, c)
            dq = (c * ds - s * dc) / (s * s + c * c)
        qs.append(q)
        dqs.append(dq)
    return qs, dqs


def frame_tree_joint_states(model: TreeModel, frame: Any) -> TreeJointStates:
    """Tree joint states of one engine frame (``frame.points[P].position/.velocity`` sequences of
    dim floats, ``frame.joints[J].position/.velocity`` floats): tuples of floats. The node calls
    this every tick: the model is resolved once (:class:`_Plan`), a call reads only the points
    and joints the rules need."""
    plan = _plan(model)
    frame_points: Mapping[str, Any] = frame.points
    frame_joints: Mapping[str, Any] = frame.joints
    points: dict[str, tuple[complex, complex]] = {}
    for n in plan.points:
        ps = frame_points.get(n)
        if ps is None:
            points[n] = (plan.fixed[n], 0j)
        else:
            p, v = ps.position, ps.velocity
            points[n] = (complex(p[0], p[1]), complex(v[0], v[1]))
    joints: dict[str, tuple[float, float]] = {}
    for n in plan.joint_inputs:
        js = frame_joints[n]
        joints[n] = (float(js.position), float(js.velocity))
    q, dq = _evaluate(plan, points, joints, _SCALAR)
    return TreeJointStates(plan.names, tuple(q), tuple(dq))  # floats: math on floats and complex


def kinematics_tree_joint_states(model: TreeModel, k: Any) -> TreeJointStates:
    """Tree joint states of a solve (:class:`solver.Kinematics` of the scene with every point and
    joint as outputs, e.g. ``scene.everything().solve(phi, omega=..., epsilon=...)``):
    ``(N, J)`` arrays (``(J,)`` for a scalar φ)."""
    plan = _plan(model)
    n = np.shape(k.valid)  # the samples' shape: φ's, or (N,) of (N, k) inputs (docs/inputs.md)
    known = set(k.points)

    def as_complex(xy: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy, dtype=np.float64)
        return xy[..., 0] + 1j * xy[..., 1]

    points: dict[str, tuple[Any, Any]] = {}
    for p in plan.points:
        if p not in known:
            points[p] = (np.full(n, plan.fixed[p]), np.zeros(n, complex))
        else:
            m = k.point(p)
            points[p] = (as_complex(m.position), as_complex(m.velocity))
    joints: dict[str, tuple[Any, Any]] = {}
    for j in plan.joint_inputs:
        m = k.joint(j)
        joints[j] = (np.asarray(m.position, dtype=np.float64), np.asarray(m.velocity, dtype=np.float64))
    q, dq = _evaluate(plan, points, joints, _ARRAYS)
    shape = n + (len(q),)
    position = np.empty(shape)
    velocity = np.empty(shape)
    for i, (a, b) in enumerate(zip(q, dq)):
        position[..., i] = a
        velocity[..., i] = b
    return TreeJointStates(model.joint_names, position, velocity)


def tree_joint_states(model: TreeModel, source: Any) -> TreeJointStates:
    """Tree joint states from an engine ``Frame`` (floats) or a ``solver.Kinematics`` (arrays)."""
    if hasattr(source, "points") and isinstance(source.points, Mapping):
        return frame_tree_joint_states(model, source)
    return kinematics_tree_joint_states(model, source)


def tree_inputs(model: TreeModel) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The points and the scene joints whose positions and velocities the tree joints read (for
    :func:`evaluate_tree`; ``linkage_ros._derived`` traces it into straight-line code)."""
    plan = _plan(model)
    return plan.points, plan.joint_inputs


def evaluate_tree(model: TreeModel, points: _Values, joints: _Values, *, atan2: Callable[[Any, Any], Any],
                  sin: Callable[[Any], Any], cos: Callable[[Any], Any],
                  floor: Callable[[Any], Any]) -> tuple[list[Any], list[Any]]:
    """Positions and velocities of the tree joints from the :func:`tree_inputs` (points: complex
    position and velocity; joints: position and velocity) with the given elementary functions:
    the one evaluation the frame and sweep paths run, on any number type (e.g. tracing values)."""
    return _evaluate(_plan(model), points, joints, _Functions(atan2, sin, cos, floor))
