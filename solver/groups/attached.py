"""A point rigidly attached to a link: seed 000's ``TurnRI(r, α, L)`` in general.

Loop equation
    P = X + L·e^{jα}·r/|r|,  r = Q − R,
    where X is a point of the link (the base), R → Q a vector along the link, α the fixed angle
    from that vector to XP (counter-clockwise) and L = |XP|.
Derivatives (exact), from ln r = ln ρ + jθ:
    θ' = Im(r'/r),  θ'' = Im(r''/r − (r'/r)²),
    v = P − X:  P' = X' + jθ'·v,  P'' = X'' + (jθ'' − θ'²)·v.
Linear system
    none: explicit.
Branch rule
    none; the link's direction must be defined, |r| > 0 (else AssemblyError).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._backend import Backend
from .._fields import Entry, Units
from ..jet import Jet, direction, sub, turning
from .base import Context, Group

__all__ = ["Attached", "points_on_link"]


def points_on_link(base: Jet, r: Jet, offsets: tuple[complex, ...], xp: Backend) -> tuple[list[Jet], Any]:
    """Jets of ``base + c·r/|r|`` for each complex offset ``c = L·e^{jα}``; also ``|r|``."""
    d = direction(r, xp)
    theta1 = d.w.imag if hasattr(d.w, "imag") else 0.0
    theta2 = d.w1.imag if hasattr(d.w1, "imag") else 0.0
    out = []
    for c in offsets:
        v = c * d.unit
        v1, v2 = turning(v, theta1, theta2)
        out.append(Jet(base.value + v, base.d1 + v1, base.d2 + v2))
    return out, d.length


@dataclass(frozen=True)
class Attached(Group):
    kind = "attached"
    point: str
    base: str
    along: tuple[str, str]
    distance: float
    angle: float  # rad

    def requires(self) -> tuple[str, ...]:
        return tuple(dict.fromkeys((self.base, *self.along)))

    def provides(self) -> tuple[str, ...]:
        return (self.point,)

    def rigid_pairs(self) -> tuple[tuple[str, str, float], ...]:
        return ((self.base, self.point, self.distance),)

    def links(self) -> tuple[tuple[str, ...], ...]:
        return ((self.base, self.point),)

    def solve(self, ctx: Context) -> None:
        xp, vals = ctx.xp, ctx.values
        r = sub(vals[self.along[1]], vals[self.along[0]])
        z = r.value
        ctx.require(self, z.real * z.real + z.imag * z.imag > 0.0, reason="has a link of zero length")
        if isinstance(self.angle, np.ndarray):  # a population of designs (solver.synthesis): one per row
            offset = self.distance * (np.cos(self.angle) + 1j * np.sin(self.angle))
        else:
            offset = self.distance * complex(xp.cos(self.angle), xp.sin(self.angle))
        (p,), _ = points_on_link(vals[self.base], r, (offset,), xp)
        vals[self.point] = p

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> Attached:
        """``{type: attached, name, point, base, along: [R, Q], distance, angle?}``."""
        along = e.names("along", 2)
        return cls(
            name=e.name("name"),
            point=e.name("point"),
            base=e.name("base", along[0]),
            along=(along[0], along[1]),
            distance=e.length("distance", units),
            angle=e.angle("angle", units, 0.0),
        )
