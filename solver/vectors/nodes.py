"""The vector model's other groups: the input, output points and output joints.

Input (driving group)
    seed 004's "input with an offset": every angle declared ``input`` is α = φ + Δ. The group
    provides the input joint (φ, 1, 0) and the unit jet (e^{jφ}, 1, 0) the angles read.
Points
    P = O + Σ σ_s·z_s from a fixed origin O; P' and P'' are the sums of the terms' jets
    (:func:`~solver.vectors.terms.vector_jet`). No loop equation, no branch.
Joints
    ``angle: V`` — α_V in (−π, π] (atan2 of e^{jα}), with α' and α'' of its base;
    ``length: V`` — r_V with its jet. Read directly; no loop equation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..groups.base import Context, Group
from ..jet import Jet
from .terms import Ref, Term, length_jet, signed_sum, unit_jet

__all__ = ["VectorInput", "VectorPoint", "VectorJoint"]


@dataclass(frozen=True)
class VectorInput(Group):
    kind = "vector_input"
    drives = True
    joint: str
    unit: str  # internal name of e^{jφ}
    drawn: tuple[tuple[str, ...], ...] = ()  # the model's extra polylines (``draw:``), for viewers

    def links(self) -> tuple[tuple[str, ...], ...]:
        return self.drawn

    def requires(self) -> tuple[str, ...]:
        return ()

    def provides(self) -> tuple[str, ...]:
        return (self.joint, self.unit)

    def joints(self) -> tuple[str, ...]:
        return (self.joint,)

    def hidden(self) -> tuple[str, ...]:
        return (self.unit,)

    def input_joint(self) -> str:
        return self.joint

    def solve(self, ctx: Context) -> None:
        phi = ctx.phi
        ctx.values[self.joint] = Jet(phi, 1.0, 0.0)
        ctx.values[self.unit] = Jet(ctx.xp.cis(phi), 1.0, 0.0)


@dataclass(frozen=True)
class VectorPoint(Group):
    kind = "vector_point"
    point: str
    origin: str
    origin_value: complex
    terms: tuple[Term, ...]
    parent: str | None  # the named point (or the origin) this one extends by one vector, for drawing
    #: Every term of the sum, in the file's order, constants included (for exporters); not solved.
    chain: tuple[Term, ...] = ()

    def requires(self) -> tuple[str, ...]:
        names = [self.origin, *(b for t in self.terms for b in t.bases())]
        return tuple(dict.fromkeys(names))

    def provides(self) -> tuple[str, ...]:
        return (self.point,)

    def links(self) -> tuple[tuple[str, ...], ...]:
        return () if self.parent is None else ((self.parent, self.point),)

    def solve(self, ctx: Context) -> None:
        ctx.values[self.point] = signed_sum(self.terms, ctx.values, self.origin_value)


@dataclass(frozen=True)
class VectorJoint(Group):
    kind = "vector_joint"
    expression: str  # "angle" | "length"
    ref: Ref

    def requires(self) -> tuple[str, ...]:
        return () if self.ref.base is None else (self.ref.base,)

    def provides(self) -> tuple[str, ...]:
        return (self.name,)

    def joint_units(self) -> dict[str, str]:
        return {self.name: "rad" if self.expression == "angle" else "m"}

    def joints(self) -> tuple[str, ...]:
        return (self.name,)

    def solve(self, ctx: Context) -> None:
        if self.expression == "length":
            ctx.values[self.name] = length_jet(self.ref, ctx.values)
            return
        if self.ref.base is None:
            u = self.ref.rot
            ctx.values[self.name] = Jet(math.atan2(u.imag, u.real), 0.0, 0.0)
            return
        j = unit_jet(self.ref, ctx.values)
        u = j.value
        ctx.values[self.name] = Jet(ctx.xp.arg(u), j.d1, j.d2)
