"""The slotted link (kulisa, RPR) of seed 000: a link pivoted at A that passes through B.

Loop equation
    The link's direction is u = (B − A)/|B − A|; each point P_k on it lies at a signed distance
    L_k from A:  P_k = A + L_k·u  (seed 000: AC = TurnRI(AB, 0, L_AC), C = A + AC).
Derivatives (exact), with r = B − A, ln r = ln ρ + jθ:
    θ' = Im(r'/r),  θ'' = Im(r''/r − (r'/r)²),
    P_k' = A' + jθ'·(P_k − A),  P_k'' = A'' + (jθ'' − θ'²)·(P_k − A).
    The slide of B along the link is ρ = |r|: ρ' = ρ·Re(r'/r).
Linear system
    none: explicit.
Branch rule
    none. B must not coincide with A (the link's direction is undefined there: AssemblyError).
Conditioning: ρ / ρ_max, the slide relative to the largest distance named on the link. Below
tolerances.SINGULAR the eyelet all but passes through the pivot: the link's direction turns by
about π within a tiny change of φ, the analogs have no limit there and are NaN, flagged
(solver.singular); exactly on the pivot it is an AssemblyError.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

from .._fields import Entry, Units
from ..jet import sub
from .attached import points_on_link
from .base import Context, Group, at_most_one

__all__ = ["Slotted"]


@dataclass(frozen=True)
class Slotted(Group):
    kind = "slotted"
    pivot: str
    through: str
    points: tuple[tuple[str, float], ...]  # (name, distance from the pivot)

    def requires(self) -> tuple[str, ...]:
        return (self.pivot, self.through)

    def provides(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.points)

    def rigid_pairs(self) -> tuple[tuple[str, str, float], ...]:
        return tuple((self.pivot, name, abs(d)) for name, d in self.points)

    def links(self) -> tuple[tuple[str, ...], ...]:
        far = max(self.points, key=lambda p: abs(p[1]))[0]
        return ((self.pivot, self.through, far),)

    def restricted(self, wanted: set[str]) -> Slotted:
        keep = tuple(p for p in self.points if p[0] in wanted)
        return self if len(keep) == len(self.points) or not keep else replace(self, points=keep)

    def solve(self, ctx: Context) -> None:
        vals = ctx.values
        r = sub(vals[self.through], vals[self.pivot])
        z = r.value
        ctx.require(self, z.real * z.real + z.imag * z.imag > 0.0, reason="has its eyelet on the pivot")
        jets, rho = points_on_link(vals[self.pivot], r, self._offsets, ctx.xp)
        for name, jet in zip(self._names, jets):
            vals[name] = jet
        ctx.conditioning[self.name] = at_most_one(rho / self._scale)

    def singular_names(self) -> tuple[str, ...]:
        return self._names

    @cached_property
    def _names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.points)

    @cached_property
    def _offsets(self) -> tuple[complex, ...]:
        return tuple(complex(d) for _, d in self.points)

    @cached_property
    def _scale(self) -> float:
        return max(abs(d) for _, d in self.points)

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> Slotted:
        """``{type: slotted, name, pivot, through, points: {C: L_AC, ...}}``."""
        raw = e.raw("points")
        if not isinstance(raw, Mapping) or not raw:
            raise e.error("must map point names to their distances from the pivot", "points")
        sub = e.child("points", raw)
        points = tuple((str(k), sub.length(str(k), units, positive=False)) for k in raw)
        if any(d == 0.0 for _, d in points):
            raise e.error("a point on the slotted link at distance 0 is the pivot itself", "points")
        return cls(name=e.name("name"), pivot=e.name("pivot"), through=e.name("through"), points=points)
