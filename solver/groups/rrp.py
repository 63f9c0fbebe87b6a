"""The RRP dyad (ВВП group): a link AB of length l whose end B slides on a fixed straight guide.

Loop equation
    B = P₀ + s·e,  |B − A| = l,  with A known, the guide through the fixed point P₀ (a named
    fixed point shifted by the offset along the guide's left normal) with unit direction e.
    With w = A − P₀, t = w·e (A's foot on the guide) and n = e × w (A's signed distance):
    s = t + M·√(l² − n²).
Derivatives (exact): differentiate (B − A)·(B − A) = l² with B' = s'·e, p = B − A:
    s'·(e·p) = A'·p,   s''·(e·p) = A''·p − |B' − A'|².
Linear system
    the scalar equations above; e·p = M·√(l² − n²).
Branch rule
    seed 003's reasoning applied to the RRP group: the closure fixes the sine of the angle from
    the guide to AB and leaves its cosine's sign free. M = +1 takes (B − A)·e ≥ 0 (B ahead of
    A's foot along the guide), M = −1 behind it; chosen once, it holds for every position.
Conditioning
    |e·p| / l = |cos| of the angle between AB and the guide: 0 where AB is perpendicular to it
    (a toggle). There the analogs returned are the limit along the branch where it exists, else
    NaN, and the sample is flagged (solver.singular).
Assembly fails where |n| > l (A farther from the guide than the link is long); the φ intervals
come from ``assembly_residual`` (solver.assembly).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .._backend import abs2, cross, dot
from .._fields import Entry, Units
from ..jet import Jet
from ..tolerances import ASSEMBLY_SLACK
from .base import Context, Group

__all__ = ["RRP"]


@dataclass(frozen=True)
class RRP(Group):
    kind = "rrp"
    end: str  # A
    point: str  # B
    length: float
    origin: complex  # P₀, offset applied
    direction: complex  # e, unit
    mode: int
    joint: str | None = None  # slide s of B along the guide, from P₀

    def requires(self) -> tuple[str, ...]:
        return (self.end,)

    def provides(self) -> tuple[str, ...]:
        return (self.point,) if self.joint is None else (self.point, self.joint)

    def joints(self) -> tuple[str, ...]:
        return () if self.joint is None else (self.joint,)

    def rigid_pairs(self) -> tuple[tuple[str, str, float], ...]:
        return ((self.end, self.point, self.length),)

    def joint_units(self) -> dict[str, str]:
        return {name: "m" for name in self.joints()}

    def links(self) -> tuple[tuple[str, ...], ...]:
        return ((self.end, self.point),)

    def singular_names(self) -> tuple[str, ...]:
        return self.provides()

    def restricted(self, wanted: set[str]) -> RRP:
        return self if self.joint is None or self.joint in wanted else replace(self, joint=None)

    def solve(self, ctx: Context) -> None:
        xp, vals = ctx.xp, ctx.values
        ja = vals[self.end]
        e, length = self.direction, self.length
        w = ja.value - self.origin
        t = dot(e, w)
        n = cross(e, w)
        h2 = (length - n) * (length + n)  # l² − n², exact to rounding at a toggle
        ctx.require(self, h2 >= -ASSEMBLY_SLACK * length * length)
        ep = self.mode * xp.sqrt(h2 * (h2 > 0.0))  # e·p
        s = t + ep
        b = self.origin + s * e
        p = b - ja.value
        if not xp.vectorised and ep == 0.0:  # an exact toggle on the scalar path: limit below
            ep = math.nan
        s1 = dot(ja.d1, p) / ep
        b1 = s1 * e
        s2 = (dot(ja.d2, p) - abs2(b1 - ja.d1)) / ep
        vals[self.point] = Jet(b, b1, s2 * e)
        if self.joint is not None:
            vals[self.joint] = Jet(s, s1, s2)
        ctx.conditioning[self.name] = abs(ep) / length if xp.vectorised or ep == ep else 0.0

    def assembly_residual(self, vals: Mapping[str, Jet]) -> tuple[Any, Any, float]:
        """``R = l² − n²`` (≥ 0 where assemblable, n = A's signed distance from the guide), R', scale."""
        ja = vals[self.end]
        n = cross(self.direction, ja.value - self.origin)
        n1 = cross(self.direction, ja.d1)
        return (self.length - n) * (self.length + n), -2.0 * n * n1, self.length**2

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> RRP:
        """``{type: rrp, name, end: A, point: B, length, guide: {through, angle, offset?}, M, joint?}``."""
        g = e.child("guide", e.raw("guide"))
        through = g.name("through")
        if through not in fixed:
            raise g.error(f"the guide is fixed; '{through}' is not a fixed point", "through")
        angle = g.angle("angle", units, 0.0)
        offset = g.length("offset", units, positive=False, default=0.0)
        g.done()
        if isinstance(angle, np.ndarray):  # a population of designs (solver.synthesis): one per row
            direction: Any = np.cos(angle) + 1j * np.sin(angle)
        else:
            direction = complex(math.cos(angle), math.sin(angle))
        at = fixed[through]
        origin = (at if isinstance(at, np.ndarray) else complex(at)) + offset * 1j * direction
        joint = e.raw("joint", None)
        return cls(
            name=e.name("name"),
            end=e.name("end"),
            point=e.name("point"),
            length=e.length("length", units),
            origin=origin,
            direction=direction,
            mode=e.mode(),
            joint=None if joint is None else e.name("joint"),
        )
