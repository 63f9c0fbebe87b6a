"""Joint coordinates read off solved points: angles, distances and coordinates.

angle [P, Q]     θ = arg(Q − P) in (−π, π];  θ' = Im(r'/r),  θ'' = Im(r''/r − (r'/r)²).
distance [P, Q]  ρ = |Q − P|;  ρ' = ρ·Re(r'/r),  ρ'' = ρ·(Re((r'/r)') + Re(r'/r)²).
x P, y P         a coordinate of P and its analogs, read directly.
These are exact consequences of the points' jets (no loop equation of their own).

When P and Q lie on one rigid body at the fixed distance L (a crank, a dyad's link, a point on a
slotted link), |r| = L identically, so r'/r = jθ' is purely imaginary and the angle's analogs
reduce to θ' = (r × r')/L², θ'' = (r × r'')/L²: the same values with a third of the arithmetic
(``rigid_length``, set by the loader from the groups' :meth:`~.base.Group.rigid_pairs`).
"""

from __future__ import annotations

from dataclasses import dataclass

from .._backend import cross
from ..jet import Jet, angle_of, length_of, sub
from .base import Context, Group

__all__ = ["JointExpression", "JOINT_KINDS"]

#: The kinds of joint expression and how many points each reads.
JOINT_KINDS: dict[str, int] = {"angle": 2, "distance": 2, "x": 1, "y": 1}


@dataclass(frozen=True)
class JointExpression(Group):
    kind = "joint"
    expression: str  # one of JOINT_KINDS
    points: tuple[str, ...]
    rigid_length: float | None = None  # |Q − P| when both lie on one rigid body

    def requires(self) -> tuple[str, ...]:
        return self.points

    def provides(self) -> tuple[str, ...]:
        return (self.name,)

    def joints(self) -> tuple[str, ...]:
        return (self.name,)

    def joint_units(self) -> dict[str, str]:
        return {self.name: "rad" if self.expression == "angle" else "m"}

    def solve(self, ctx: Context) -> None:
        vals, xp = ctx.values, ctx.xp
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


def _part(part, value):  # type: ignore[no-untyped-def]
    return part(value) if hasattr(value, "real") else value
