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
from collections.abc import Callable, Mapping
from typing import Any, NamedTuple

import numpy as np

from .model import BASE_LINK, TreeModel

__all__ = ["TreeJointStates", "tree_joint_states", "frame_tree_joint_states", "kinematics_tree_joint_states"]

TWO_PI = 2.0 * math.pi


class TreeJointStates(NamedTuple):
    """Names of the tree joints (URDF order) and their positions and velocities: tuples of
    floats for one frame, or ``(N, J)`` arrays for a sweep."""

    names: tuple[str, ...]
    position: Any
    velocity: Any


class _Source:
    """Point and joint values of one frame (scalars) or a sweep (arrays).

    ``point(P)`` gives ``(position, velocity)`` of P as complex numbers (arrays), ``joint(J)``
    ``(position, velocity)`` of a scene joint; both are read once and cached."""

    def __init__(
        self,
        point: Callable[[str], tuple[Any, Any]],
        joint: Callable[[str], tuple[Any, Any]],
        vectorised: bool,
    ) -> None:
        self._point, self._joint = point, joint
        self._cache: dict[str, tuple[Any, Any]] = {}
        self.vectorised = vectorised
        self.atan2 = np.arctan2 if vectorised else math.atan2
        self.sin = np.sin if vectorised else math.sin
        self.cos = np.cos if vectorised else math.cos
        self.floor = np.floor if vectorised else math.floor

    def point(self, name: str) -> tuple[Any, Any]:
        hit = self._cache.get(name)
        if hit is None:
            hit = self._cache[name] = self._point(name)
        return hit

    def joint(self, name: str) -> tuple[Any, Any]:
        return self._joint(name)


def _cross(a: Any, b: Any) -> Any:
    return a.real * b.imag - a.imag * b.real


def _dot(a: Any, b: Any) -> Any:
    return a.real * b.real + a.imag * b.imag


def _pose(model: TreeModel, body: str, src: _Source, *, locate: bool = True) -> tuple[Any, Any, Any, Any]:
    """``(o, ȯ, r, ṙ)`` of a planar body: origin and a vector along its x axis (``o, ȯ`` are
    ``None`` unless ``locate``: a pin reads directions only)."""
    if body == BASE_LINK:
        return 0j, 0j, 1 + 0j, 0j
    b = model.bodies[body]
    assert b.origin is not None
    if isinstance(b.axis, tuple):
        (pt, vt), (ph, vh) = src.point(b.axis[0]), src.point(b.axis[1])
        r, dr = ph - pt, vh - vt
    elif isinstance(b.axis, str):  # a scene joint: the absolute angle of the axis
        q, dq = src.joint(b.axis)
        r = src.cos(q) + 1j * src.sin(q)
        dr = 1j * dq * r
    else:
        r, dr = complex(b.axis), 0j  # type: ignore[arg-type]
    if b.turn:
        rot = complex(math.cos(b.turn), math.sin(b.turn))
        r, dr = r * rot, dr * rot
    if not locate:
        return None, None, r, dr
    if b.anchor is None or b.anchor == b.origin:
        o, do = src.point(b.origin)
    else:  # o = P − u·x, ȯ = Ṗ − j·ω·u·x with x the anchor's place in the body frame
        pa, va = src.point(b.anchor)
        x = complex(b.local[b.anchor][0], b.local[b.anchor][1])
        u = r / abs(r)
        o, do = pa - u * x, va - 1j * _omega(r, dr) * u * x
    return o, do, r, dr


def _omega(r: Any, dr: Any) -> Any:
    return _cross(r, dr) / _dot(r, r)


def _evaluate(model: TreeModel, src: _Source) -> tuple[list[Any], list[Any]]:
    poses: dict[tuple[str, bool], tuple[Any, Any, Any, Any]] = {}

    def pose(name: str, locate: bool = True) -> tuple[Any, Any, Any, Any]:
        key = (name, locate)
        if key not in poses:
            poses[key] = _pose(model, name, src, locate=locate)
        return poses[key]

    qs: list[Any] = []
    dqs: list[Any] = []
    for j in model.joints:
        if j.rule == "planar_pin":
            _, _, rp, drp = pose(j.parent, False)
            _, _, rc, drc = pose(j.child, False)
            q = src.atan2(_cross(rp, rc), _dot(rp, rc))
            unwrap = j.data[0]
            if unwrap is not None:
                phi = src.joint(str(unwrap))[0]
                q = q + TWO_PI * src.floor((phi - q) / TWO_PI + 0.5)
            dq = _omega(rc, drc) - _omega(rp, drp)
        elif j.rule == "planar_slide":
            x0v, beta = j.data
            x0 = complex(x0v[0], x0v[1])  # type: ignore[index]
            op, dop, rp, drp = pose(j.parent)
            oc, doc, _, _ = pose(j.child)
            up = rp / abs(rp)
            wp = _omega(rp, drp)
            a = up * complex(math.cos(beta), math.sin(beta))  # type: ignore[arg-type]
            q = _dot(oc - (op + up * x0), a)
            dq = _dot(doc - (dop + 1j * wp * up * x0), a)
        elif j.rule == "joint_value":
            q, dq = src.joint(str(j.data[0]))
        elif j.rule == "spherical_ring":
            shaft, cage, alpha = j.data
            phi, dphi = src.joint(str(shaft))
            psi, dpsi = src.joint(str(cage))
            ca, sa = math.cos(alpha), math.sin(alpha)  # type: ignore[arg-type]
            sf, cf, sp, cp = src.sin(phi), src.cos(phi), src.sin(psi), src.cos(psi)
            s = -ca * sp - sa * sf * cp
            c = cf * cp
            ds = -ca * cp * dpsi - sa * (cf * cp * dphi - sf * sp * dpsi)
            dc = -sf * cp * dphi - cf * sp * dpsi
            q = src.atan2(s, c)
            dq = (c * ds - s * dc) / (s * s + c * c)
        else:  # pragma: no cover - the model only makes the rules above
            raise ValueError(f"unknown tree-joint rule {j.rule!r}")
        qs.append(q)
        dqs.append(dq)
    return qs, dqs


def _fixed_lookup(model: TreeModel) -> dict[str, complex]:
    base = model.bodies[BASE_LINK].local
    return {n: complex(v[0], v[1]) for n, v in base.items()}


def frame_tree_joint_states(model: TreeModel, frame: Any) -> TreeJointStates:
    """Tree joint states of one engine frame (``frame.points[P].position/.velocity`` sequences of
    dim floats, ``frame.joints[J].position/.velocity`` floats): tuples of floats."""
    points: Mapping[str, Any] = frame.points
    joints: Mapping[str, Any] = frame.joints

    def point(n: str) -> tuple[complex, complex]:
        ps = points.get(n)
        if ps is None:
            return _fixed_lookup(model)[n], 0j
        p, v = ps.position, ps.velocity
        return complex(p[0], p[1]), complex(v[0], v[1])

    def joint(n: str) -> tuple[float, float]:
        js = joints[n]
        return float(js.position), float(js.velocity)

    q, dq = _evaluate(model, _Source(point, joint, False))
    return TreeJointStates(model.joint_names, tuple(map(float, q)), tuple(map(float, dq)))


def kinematics_tree_joint_states(model: TreeModel, k: Any) -> TreeJointStates:
    """Tree joint states of a solve (:class:`solver.Kinematics` of the scene with every point and
    joint as outputs, e.g. ``scene.everything().solve(phi, omega=..., epsilon=...)``):
    ``(N, J)`` arrays (``(J,)`` for a scalar φ)."""
    fixed = _fixed_lookup(model)
    n = np.shape(k.valid)  # the samples' shape: φ's, or (N,) of (N, k) inputs (docs/inputs.md)
    known = set(k.points)

    def as_complex(xy: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy, dtype=np.float64)
        return xy[..., 0] + 1j * xy[..., 1]

    def point(p: str) -> tuple[Any, Any]:
        if p not in known:
            return np.full(n, fixed[p]), np.zeros(n, complex)
        m = k.point(p)
        return as_complex(m.position), as_complex(m.velocity)

    def joint(j: str) -> tuple[Any, Any]:
        m = k.joint(j)
        return np.asarray(m.position, dtype=np.float64), np.asarray(m.velocity, dtype=np.float64)

    src = _Source(point, joint, True)
    q, dq = _evaluate(model, src)
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
