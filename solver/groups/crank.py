"""The input crank: seed 000's ``OA = TurnRI(1, φ, L)``.

Loop equation
    A = O + L·e^{jφ}, with O a fixed pivot and φ the generalised coordinate.
Derivatives (exact)
    A' = j·(A − O),  A'' = −(A − O).
Linear system
    none: the crank is driven.
Branch rule
    none: one solution for every φ.
The crank also provides the input joint, whose coordinate is φ itself: ``(φ, 1, 0)``.

Several inputs (docs/inputs.md): each crank is seeded with its input's directional jet
``(q, u, s)`` — the path q(t) = q₀ + u·t + s·t²/2 — so that A' = j(A − O)·u and
A'' = j(A − O)·s − (A − O)·u², and every group downstream yields J·u and uᵀHu + J·s.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .._fields import Entry, Units
from ..jet import Jet
from .base import Context, Group

__all__ = ["Crank"]


@dataclass(frozen=True)
class Crank(Group):
    kind = "crank"
    drives = True
    center: str
    point: str
    length: float
    joint: str

    def requires(self) -> tuple[str, ...]:
        return (self.center,)

    def provides(self) -> tuple[str, ...]:
        return (self.point, self.joint)

    def joints(self) -> tuple[str, ...]:
        return (self.joint,)

    def input_joint(self) -> str:
        return self.joint

    def rigid_pairs(self) -> tuple[tuple[str, str, float], ...]:
        return ((self.center, self.point, self.length),)

    def links(self) -> tuple[tuple[str, ...], ...]:
        return ((self.center, self.point),)

    def solve(self, ctx: Context) -> None:
        if ctx.seeds is not None:
            self._solve_seeded(ctx, ctx.seeds[self.joint])
            return
        xp, phi = ctx.xp, ctx.phi
        o = ctx.values[self.center].value
        arm = xp.cis(phi)
        arm *= self.length  # in place on the fresh e^{jφ} (the same product as L·e^{jφ})
        ctx.values[self.point] = Jet(o + arm, 1j * arm, xp.negative(arm))
        ctx.values[self.joint] = Jet(phi, 1.0, 0.0)

    def _solve_seeded(self, ctx: Context, seed: Jet) -> None:
        """One of several inputs, seeded with the directional jet ``(q, u, s)`` (solver.multi):
        A' = j·(A − O)·u,  A'' = j·(A − O)·s − (A − O)·u².  A zero ``u`` (the float 0.0, another
        input's direction) leaves A' and A'' the float 0.0, so no array work follows from it."""
        q, u, s = seed
        arm = ctx.xp.cis(q)
        arm *= self.length
        point = ctx.values[self.center].value + arm
        if u.__class__ is float and u == 0.0 and s.__class__ is float and s == 0.0:
            ctx.values[self.point] = Jet(point, 0.0, 0.0)
        elif u.__class__ is float and u == 1.0 and s.__class__ is float and s == 0.0:  # a unit direction
            ctx.values[self.point] = Jet(point, 1j * arm, ctx.xp.negative(arm))
        else:
            ja = 1j * arm
            acc = arm * (-(u * u))
            if not (s.__class__ is float and s == 0.0):
                acc += ja * s
            ctx.values[self.point] = Jet(point, ja * u, acc)
        ctx.values[self.joint] = Jet(q, u, s)

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> Crank:
        """``{type: crank, name, center, point, length, joint?}``; the joint defaults to the name."""
        name = e.name("name")
        center = e.name("center")
        if center not in fixed:
            raise e.error(f"the crank turns about a fixed point; '{center}' is not one of {sorted(fixed)}", "center")
        return cls(
            name=name,
            center=center,
            point=e.name("point"),
            length=e.length("length", units),
            joint=e.name("joint", name),
        )
