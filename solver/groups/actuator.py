"""A driven length (hydraulic cylinder, electric ram): the RRR dyad whose one side is the input.

The cylinder is pinned at ``base`` A (a fixed point or a point of a link) and at its eye C, a
point of the link it pushes, which turns about ``pivot`` O at the fixed distance l = |C − O|.
The actuator's length s = |C − A| is the input joint (m), between the closed and open lengths
of ``stroke: [s_min, s_max]``.

Loop equation (seed 003's RRR dyad with l₁ = s, l₂ = l; solver.groups.rrr, ``circle_point``)
    |C − A| = s,  |C − O| = l,  with A and O known.
    With d = O − A and D = |d|: C = A + d·(a − j·M·h), a = (s² − l² + D²)/(2D²),
    4D⁴·h² = ((s + l)² − D²)(D² − (s − l)²).
Derivatives (exact): differentiate (C − A)·(C − A) = s² and (C − O)·(C − O) = l².
Linear system, with p = C − A, q = C − O (real dot products on complex numbers):
    C'·p = A'·p + s·s',                          C'·q = O'·q,
    C''·p = A''·p − |C' − A'|² + s'² + s·s'',    C''·q = O''·q − |C' − O'|²,
    solved by Cramer's rule as the RRR dyad's (``dyad_analogs`` with ``grow = (s·s', s'² + s·s'')``).
    One input: s' = 1, s'' = 0 (the analogs d/ds, d²/ds²); several inputs: the stroke's directional
    jet (s, u, σ) of solver.multi, so that every point downstream carries J·u and uᵀHu + J·σ.
Branch rule (seed 003)
    M = +1 when A → C → O is traversed counter-clockwise (as ``rrr``'s A → B → C), −1
    clockwise; it holds for every stroke (a cylinder does not pass its change points in service).
Conditioning
    |p × q| / (s·l) = |sin| of the angle between the cylinder and the pushed link: 0 where they are
    aligned (the cylinder pushes through the pivot, a toggle). There the analogs are the limit
    along the stroke where it exists, else NaN, and the sample is flagged (solver.singular).
Limits
    s outside [s_min, s_max] (the cylinder's closed and open lengths), and |s − l| ≤ D ≤ s + l
    violated: an AssemblyError naming the strokes (solver.errors); with fixed A and O the
    unassemblable strokes are closed-form intervals (``stroke_intervals``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .._fields import Entry, Units
from ..jet import Jet
from .base import Context, Group
from .rrr import circle_point, dyad_analogs

__all__ = ["Actuator", "stroke_intervals"]


@dataclass(frozen=True)
class Actuator(Group):
    kind = "actuator"
    drives = True
    base: str  # A: the cylinder's barrel pin
    point: str  # C: the rod's eye, on the pushed link
    pivot: str  # O: the pushed link's pin
    length: float  # l = |C − O|
    mode: int  # M = ±1
    joint: str  # the input joint: the stroke s (m)
    stroke: tuple[float, float]  # (closed, open) lengths, m

    def requires(self) -> tuple[str, ...]:
        return (self.base, self.pivot)

    def provides(self) -> tuple[str, ...]:
        return (self.point, self.joint)

    def joints(self) -> tuple[str, ...]:
        return (self.joint,)

    def joint_units(self) -> dict[str, str]:
        return {self.joint: "m"}

    def input_joint(self) -> str:
        return self.joint

    def input_range(self) -> tuple[float, float]:
        """The strokes the input may take (m): the closed and open lengths."""
        return self.stroke

    def rigid_pairs(self) -> tuple[tuple[str, str, float], ...]:
        return ((self.pivot, self.point, self.length),)

    def links(self) -> tuple[tuple[str, ...], ...]:
        return ((self.base, self.point), (self.pivot, self.point))

    def singular_names(self) -> tuple[str, ...]:
        return (self.point,)

    def solve(self, ctx: Context) -> None:
        vals = ctx.values
        if ctx.seeds is not None:
            stroke = ctx.seeds[self.joint]
        else:
            stroke = Jet(ctx.phi, 1.0, 0.0)
        s, u, acc = stroke
        lo, hi = self.stroke
        if ctx.xp.vectorised:  # two reductions when every stroke is inside; per sample otherwise
            inside = not np.size(s) or (bool(np.min(s) >= lo) and bool(np.max(s) <= hi))
            if not inside:
                inside = s >= lo
                inside &= s <= hi
        else:  # (per tick, traced: two guards)
            inside = lo <= s <= hi
        ctx.require(self, inside, reason=self._outside)
        ja, jo = vals[self.base], vals[self.pivot]
        c, p, q, jdet, cond = circle_point(ctx, self, ja.value, jo.value, (s, self.length), self._mode)
        grow: tuple[Any, Any] | None
        if u.__class__ is float and u == 0.0 and acc.__class__ is float and acc == 0.0:
            grow = None  # another input's direction (solver.multi): the stroke does not move
        elif u.__class__ is float and u == 1.0 and acc.__class__ is float and acc == 0.0:
            grow = (s, 1.0)  # d/ds: s·s' = s, s'² + s·s'' = 1
        else:
            e2 = u * u
            if not (acc.__class__ is float and acc == 0.0):
                e2 = e2 + s * acc
            grow = (s * u, e2)
        c1, c2 = dyad_analogs(p, q, jdet, ja, jo, grow)
        vals[self.point] = Jet(c, c1, c2)
        vals[self.joint] = stroke
        cond /= s * self.length
        ctx.conditioning[self.name] = cond

    def _mode(self, ctx: Context) -> int:
        return self.mode

    @cached_property
    def _outside(self) -> str:
        """The reason a stroke outside [s_min, s_max] cannot be assembled (made once)."""
        return f"is outside its stroke [{self.stroke[0]:g}, {self.stroke[1]:g}] m (closed and open lengths)"

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> Actuator:
        """``{type: actuator, name, base: A, point: C, pivot: O, length, M: ±1, joint?,
        stroke: [closed, open]}``; the joint defaults to the name."""
        name = e.name("name")
        raw = e.raw("stroke")
        if not isinstance(raw, (list, tuple)) or len(raw) != 2:
            raise e.error(f"must be [closed, open] lengths of the actuator, got {raw!r:.60}", "stroke")
        lo, hi = (e.as_number(v, "stroke") for v in raw)
        if not (lo > 0.0 and hi > 0.0):
            raise e.error(f"the closed and open lengths must be positive, got [{lo:g}, {hi:g}]", "stroke")
        if not lo < hi:
            raise e.error(f"the closed length must be less than the open length, got [{lo:g}, {hi:g}]", "stroke")
        sub = e.child("stroke", {"closed": lo, "open": hi})
        base, point, pivot = e.name("base"), e.name("point"), e.name("pivot")
        for key, other in (("pivot", base), ("point", base), ("point", pivot)):
            if e.raw(key) == other:
                raise e.error(f"'{other}' cannot be both the base, point or pivot of one actuator", key)
        return cls(
            name=name,
            base=base,
            point=point,
            pivot=pivot,
            length=e.length("length", units),
            mode=e.mode(),
            joint=e.name("joint", name),
            stroke=(sub.length("closed", units), sub.length("open", units)),
        )


def stroke_intervals(group: Actuator, base: complex, pivot: complex) -> list[tuple[float, float]]:
    """With fixed A and O: the strokes of [s_min, s_max] at which the actuator cannot be assembled
    (|s − l| ≤ D ≤ s + l violated: D − l ≤ s ≤ D + l and s ≥ l − D), as open intervals (m)."""
    lo, hi = group.stroke
    dist = abs(pivot - base)
    reach_lo, reach_hi = max(dist - group.length, group.length - dist), dist + group.length
    out: list[tuple[float, float]] = []
    if reach_lo > lo:
        out.append((lo, min(reach_lo, hi)))
    if reach_hi < hi:
        out.append((max(reach_hi, lo), hi))
    return out
