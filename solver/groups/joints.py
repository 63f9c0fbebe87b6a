"""Joint coordinates read off solved points: angles, distances and coordinates.

angle [P, Q]     θ = arg(Q − P) in (−π, π];  θ' = Im(r'/r),  θ'' = Im(r''/r − (r'/r)²).
distance [P, Q]  ρ = |Q − P|;  ρ' = ρ·Re(r'/r),  ρ'' = ρ·(Re((r'/r)') + Re(r'/r)²).
x P, y P         a coordinate of P and its analogs, read directly.
These are exact consequences of the points' jets (no loop equation of their own).

URDF-style joints (a coordinate named and measured the way the user's own URDF does it):

revolute   parent [P₀, P₁], child [C₀, C₁], offset q₀, sign s = ±1:
           q = wrap(s·Δ + q₀) in (−π, π], Δ = arg(r_c·conj(r_p)) the angle of the child's line
           r_c = C₁ − C₀ measured from the parent's r_p = P₁ − P₀ (counter-clockwise);
           q' = s·(θ_c' − θ_p'),  q'' = s·(θ_c'' − θ_p'')  with θ' = Im(r'/r), θ'' = Im((r'/r)').
prismatic  guide [G₀, G₁] (or through G₀ at a constant angle α), point P, offset q₀, sign s:
           q = s·d + q₀ with d = Re(w·conj(u)) the distance of P from G₀ along the unit vector u
           of the guide, w = P − G₀;  u' = jθ'·u, u'' = (jθ'' − θ'²)·u of the guide's angle θ;
           d' = Re(w'·ū + w·ū'),  d'' = Re(w''·ū + 2·w'·ū' + w·ū'')  (ū = conj(u)).
The sign says which way the URDF joint's axis points (+1: +z for a revolute, the guide's
direction for a prismatic; −1 the other way); the offset is the URDF joint's value when the two
lines are parallel (revolute) or P is at G₀ (prismatic).

When P and Q lie on one rigid body at the fixed distance L (a crank, a dyad's link, a point on a
slotted link), |r| = L identically, so r'/r = jθ' is purely imaginary and the angle's analogs
reduce to θ' = (r × r')/L², θ'' = (r × r'')/L²: the same values with a third of the arithmetic
(``rigid_length``, set by the loader from the groups' :meth:`~.base.Group.rigid_pairs`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._backend import Backend, cross
from .._fields import Entry, Units
from ..jet import Jet, angle_of, direction, length_of, sub
from .base import Context, Group

__all__ = ["JointExpression", "JOINT_KINDS", "URDF_JOINT_KINDS", "URDF_JOINT_KEYS"]

#: The kinds of joint expression and how many points each reads.
JOINT_KINDS: dict[str, int] = {"angle": 2, "distance": 2, "x": 1, "y": 1}

#: URDF-style joint kinds (``{revolute: {...}}``, ``{prismatic: {...}}``) and the keys each takes.
URDF_JOINT_KEYS: dict[str, tuple[str, ...]] = {
    "revolute": ("parent", "child", "offset", "sign"),
    "prismatic": ("guide", "point", "offset", "sign"),
}
URDF_JOINT_KINDS: tuple[str, ...] = tuple(URDF_JOINT_KEYS)

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class JointExpression(Group):
    kind = "joint"
    expression: str  # one of JOINT_KINDS or URDF_JOINT_KINDS
    points: tuple[str, ...]  # revolute: P₀, P₁, C₀, C₁; prismatic: G₀, G₁, P (or G₀, P with ``guide``)
    rigid_length: float | None = None  # |Q − P| when both lie on one rigid body
    offset: float = 0.0  # URDF-style joints: rad (revolute) or m (prismatic)
    sign: float = 1.0  # URDF-style joints: +1 or −1
    guide: complex | None = None  # prismatic through G₀ at a constant angle: the unit direction

    def requires(self) -> tuple[str, ...]:
        return self.points

    def provides(self) -> tuple[str, ...]:
        return (self.name,)

    def joints(self) -> tuple[str, ...]:
        return (self.name,)

    def joint_units(self) -> dict[str, str]:
        return {self.name: "rad" if self.expression in ("angle", "revolute") else "m"}

    @classmethod
    def from_urdf_entry(cls, name: str, kind: str, e: Entry, units: Units) -> JointExpression:
        """``{revolute: {parent: [P₀, P₁], child: [C₀, C₁], offset?, sign?}}`` or
        ``{prismatic: {guide: [G₀, G₁] | {through: G₀, angle: α}, point: P, offset?, sign?}}``."""
        e.expect(URDF_JOINT_KEYS[kind])  # a misspelt key first, with the closest known one
        sign = e.raw("sign", 1)
        if isinstance(sign, bool) or sign not in (1, -1):
            raise e.error(f"must be +1 or -1, got {sign!r}", "sign")
        if kind == "revolute":
            pts = (*e.names("parent", 2), *e.names("child", 2))
            offset = e.angle("offset", units, default=0.0)
            e.done()
            return cls(name=name, expression=kind, points=pts, offset=offset, sign=float(sign))
        raw_guide = e.raw("guide")
        guide: complex | None = None
        if isinstance(raw_guide, (list, tuple)):
            ends = e.names("guide", 2)
        elif not isinstance(raw_guide, Mapping):
            raise e.error(f"must be [G0, G1] or {{through: G0, angle: α}}, got {raw_guide!r:.60}", "guide")
        else:
            g = e.child("guide", raw_guide)
            g.expect(("through", "angle"))
            ends = (g.name("through"),)
            angle = g.angle("angle", units)
            guide = complex(math.cos(angle), math.sin(angle))
            g.done()
        pts = (*ends, e.name("point"))
        offset = e.length("offset", units, positive=False, default=0.0)
        e.done()
        return cls(name=name, expression=kind, points=pts, offset=offset, sign=float(sign), guide=guide)

    def solve(self, ctx: Context) -> None:
        vals, xp = ctx.values, ctx.xp
        if self.expression == "revolute":
            vals[self.name] = self._revolute(ctx)
            return
        if self.expression == "prismatic":
            vals[self.name] = self._prismatic(ctx)
            return
        if self.expression in ("x", "y"):
            p = vals[self.points[0]]
            part = (lambda z: z.real) if self.expression == "x" else (lambda z: z.imag)
            vals[self.name] = Jet(part(p.value), _part(part, p.d1), _part(part, p.d2))
            return
        r = sub(vals[self.points[1]], vals[self.points[0]])
        z = r.value
        if self.rigid_length is not None and self.expression == "angle":
            inv = 1.0 / (self.rigid_length * self.rigid_length)
            theta1, theta2 = cross(z, r.d1), cross(z, r.d2)
            theta1 *= inv  # in place on the fresh cross products
            theta2 *= inv
            vals[self.name] = Jet(xp.arg(z), theta1, theta2)
            return
        ctx.require(self, z.real * z.real + z.imag * z.imag > 0.0, reason="joins two coincident points")
        vals[self.name] = angle_of(r, xp) if self.expression == "angle" else length_of(r, xp)


    def _revolute(self, ctx: Context) -> Jet:
        vals, xp = ctx.values, ctx.xp
        p0, p1, c0, c1 = self.points
        rp = sub(vals[p1], vals[p0])
        rc = sub(vals[c1], vals[c0])
        for r, which in ((rp, "parent"), (rc, "child")):
            z = r.value
            ok = z.real * z.real + z.imag * z.imag > 0.0
            ctx.require(self, ok, reason=f"{which} line joins two coincident points")
        delta = xp.arg(rc.value * rp.value.conjugate())
        tc = angle_of(rc, xp)
        d1, d2 = tc.d1, tc.d2
        if not (_is_zero(rp.d1) and _is_zero(rp.d2)):
            tp = angle_of(rp, xp)
            d1, d2 = d1 - tp.d1, d2 - tp.d2
        s = self.sign
        q = delta if s == 1.0 and self.offset == 0.0 else _wrap(s * delta + self.offset, xp)
        return Jet(q, s * d1, s * d2)

    def _prismatic(self, ctx: Context) -> Jet:
        vals, xp = ctx.values, ctx.xp
        if self.guide is not None:
            g0, p = self.points
            u: Any = self.guide
            u1: Any = 0.0
            u2: Any = 0.0
        else:
            g0, g1, p = self.points
            r = sub(vals[g1], vals[g0])
            z = r.value
            ctx.require(self, z.real * z.real + z.imag * z.imag > 0.0, reason="guide joins two coincident points")
            if _is_zero(r.d1) and _is_zero(r.d2):
                u, u1, u2 = z / abs(z), 0.0, 0.0
            else:
                d = direction(r, xp)
                t1, t2 = d.w.imag, d.w1.imag
                u = d.unit
                u1 = 1j * t1 * u
                u2 = (1j * t2 - t1 * t1) * u
        w = sub(vals[p], vals[g0])
        ub, ub1, ub2 = _conj(u), _conj(u1), _conj(u2)
        q = (w.value * ub).real
        q1 = w.d1 * ub + w.value * ub1
        q2 = w.d2 * ub + 2.0 * (w.d1 * ub1) + w.value * ub2
        s = self.sign
        return Jet(s * q + self.offset, s * _real(q1), s * _real(q2))


def _is_zero(x: Any) -> bool:
    return isinstance(x, (int, float, complex)) and x == 0


def _conj(x: Any) -> Any:
    return x.conjugate() if hasattr(x, "conjugate") else x


def _real(x: Any) -> Any:
    return x.real if hasattr(x, "real") else x


def _wrap(x: Any, xp: Backend) -> Any:
    """``x`` wrapped to (−π, π] (exact for |x| ≤ π)."""
    if not xp.vectorised:
        return xp.call(_wrap_scalar, x)
    arr = np.asarray(x, dtype=np.float64)
    arr = arr - TWO_PI * np.round(arr / TWO_PI)
    return np.where(arr <= -math.pi, arr + TWO_PI, arr)


def _wrap_scalar(x: float) -> float:
    y = math.remainder(x, TWO_PI)
    return math.pi if y == -math.pi else y


def _part(part, value):  # type: ignore[no-untyped-def]
    return part(value) if hasattr(value, "real") else value
