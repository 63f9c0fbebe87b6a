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
        xp, phi = ctx.xp, ctx.phi
        o = ctx.values[self.center].value
        arm = xp.cis(phi)
        arm *= self.length  # in place on the fresh e^{jφ} (the same product as L·e^{jφ})
        ctx.values[self.point] = Jet(o + arm, 1j * arm, xp.negative(arm))
        ctx.values[self.joint] = Jet(phi, 1.0, 0.0)

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
