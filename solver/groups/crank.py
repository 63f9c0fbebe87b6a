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

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .._fields import Entry, Units
from ..jet import Jet
from .base import Context, Group

__all__ = ["Crank", "CoupledCrank", "CoupledCrankEntry"]


@dataclass(frozen=True)
class Crank(Group):
    kind = "crank"
    drives = True
    center: str
    point: str
    length: float
    joint: str
    #: θ₀ (rad): the angle of O→A where the joint reads 0 (a model's own convention)
    offset: float = 0.0
    #: σ = ±1: the joint turns counter-clockwise (+1) or clockwise (−1) in the scene's plane
    sign: float = 1.0

    @property
    def plain(self) -> bool:
        """True for a scene's own crank: its joint is the angle of O→A itself."""
        return self.offset == 0.0 and self.sign == 1.0

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
        if not self.plain:
            self._solve_seeded(ctx, Jet(ctx.phi, 1.0, 0.0))
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
        input's direction) leaves A' and A'' the float 0.0, so no array work follows from it.
        A crank in a model's convention turns by θ = θ₀ + σ·q: its jet (θ₀ + σq, σu, σs)."""
        self._place(ctx, seed)
        ctx.values[self.joint] = seed

    def _place(self, ctx: Context, seed: Jet) -> None:
        """A from the joint's jet (q, u, s): the angle's jet, then the point's."""
        q, u, s = seed
        if not self.plain:
            sg = self.sign
            q = q * sg + self.offset if sg != 1.0 else q + self.offset
            u = u if sg == 1.0 else (-u if sg == -1.0 else u * sg)
            s = s if sg == 1.0 else (-s if sg == -1.0 else s * sg)
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

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> Crank:
        """``{type: crank, name, center, point, length, joint?, offset?, sign?, follows?}``; the
        joint defaults to the name; ``follows: {joint, ratio, offset?}`` makes a coupled crank."""
        name = e.name("name")
        center = e.name("center")
        if center not in fixed:
            raise e.error(f"the crank turns about a fixed point; '{center}' is not one of {sorted(fixed)}", "center")
        sign = e.raw("sign", 1)
        if isinstance(sign, bool) or sign not in (1, -1):
            raise e.error(f"must be +1 or -1, got {sign!r}", "sign")
        common = dict(
            name=name,
            center=center,
            point=e.name("point"),
            length=e.length("length", units),
            joint=e.name("joint", name),
            offset=e.angle("offset", units, default=0.0),
            sign=float(sign),
        )
        raw = e.raw("follows", None)
        if raw is None:
            return cls(**common)  # type: ignore[arg-type]
        f = e.child("follows", raw)
        source = f.name("joint")
        ratio = f.as_number(f.raw("ratio"), "ratio")
        if not (math.isfinite(ratio) and ratio != 0.0 and abs(ratio) <= 1e6):
            raise f.error(f"must be a non-zero finite ratio (|ratio| ≤ 1e6), got {ratio!r}", "ratio")
        shift = f.angle("offset", units, default=0.0)
        f.done()
        if source == common["joint"]:
            raise f.error(f"a crank cannot follow its own joint '{source}'", "joint")
        return CoupledCrank(**common, source=source, ratio=float(ratio), shift=shift)  # type: ignore[arg-type]


@dataclass(frozen=True)
class CoupledCrank(Crank):
    """A crank turned by another input: its joint q = ``shift`` + ``ratio``·p, p the input joint
    ``source`` (module docstring). Not an input of its own."""

    drives = False
    source: str = ""
    ratio: float = 1.0
    shift: float = 0.0

    def requires(self) -> tuple[str, ...]:
        return (self.center, self.source)

    def input_joint(self) -> None:  # type: ignore[override]
        return None

    def solve(self, ctx: Context) -> None:
        p, dp, ddp = ctx.values[self.source]
        c1 = self.ratio
        q = p * c1 + self.shift
        seed = Jet(q, dp * c1, ddp * c1)
        self._place(ctx, seed)
        ctx.values[self.joint] = seed


class CoupledCrankEntry:
    """``{type: coupled_crank, name, center, point, length, joint?, follows, ratio, offset?}``: the
    drawn form's coupled input (solver.structure), whose angle is ratio·φ_follows + offset — a
    :class:`CoupledCrank` with θ₀ = 0, σ = 1 (its joint is its angle)."""

    kind = "coupled_crank"
    fields = ("type", "name", "center", "point", "length", "joint", "follows", "ratio", "offset")

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> CoupledCrank:
        name = e.name("name")
        center = e.name("center")
        if center not in fixed:
            raise e.error(f"the crank turns about a fixed point; '{center}' is not one of {sorted(fixed)}", "center")
        ratio = e.as_number(e.raw("ratio"), "ratio")
        if not (math.isfinite(ratio) and ratio != 0.0 and abs(ratio) <= 1e6):
            raise e.error(f"must be a non-zero finite ratio (|ratio| ≤ 1e6), got {ratio!r}", "ratio")
        joint = e.name("joint", name)
        source = e.name("follows")
        if source == joint:
            raise e.error(f"a crank cannot follow its own joint '{source}'", "follows")
        return CoupledCrank(name=name, center=center, point=e.name("point"), length=e.length("length", units),
                            joint=joint, source=source, ratio=float(ratio),
                            shift=e.angle("offset", units, default=0.0))
