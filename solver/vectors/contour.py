"""One closed vector contour solved as a planar module (seed 004): a group of the plan.

The contour's terms are split at load time into a constant part (folded into one complex
number), moving terms that depend on no unknown (their sum is K, with its jet), and the terms
that depend on one of the two unknowns (``deps``). The module's own file gives the position in
closed form (:mod:`.pl1` … :mod:`.pl4`); the analogs come from one linear system for every
module (:mod:`.analogs`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..groups.base import Context, Group
from ..jet import Jet
from . import pl1, pl2, pl3, pl4
from .analogs import Dep, analogs
from .terms import Term, length_jet, signed_sum, sum_jets, unit_jet, vector_jet

__all__ = ["Contour", "DepSpec", "SOLUTIONS"]

Num = Any

#: Solutions of each module (seed 004, Tables 1–2) as solved here; see each module's docstring
#: for why Пл2s has one and Пл3s, Пл4s two.
SOLUTIONS = {"Пл1": 1, "Пл2": 1, "Пл3": 2, "Пл4": 2, "Пл1s": 2, "Пл2s": 1, "Пл3s": 2, "Пл4s": 2}


@dataclass(frozen=True)
class DepSpec:
    """A term that depends on unknown ``len_of`` through its length and/or ``ang_of`` through its angle."""

    term: Term
    len_of: int | None
    ang_of: int | None


@dataclass(frozen=True)
class Contour(Group):
    kind = "contour"
    module: str  # "Пл1" … "Пл4s"
    form: str  # "pl1" | "pl2" | "pl3" | "pl4": which closed form solves it
    unknowns: tuple[str, str]  # internal names, "AB.r" / "AB.alpha"
    mode: int  # M = ±1, or 0 for a module with one solution
    constant: complex
    known: tuple[Term, ...]
    deps: tuple[DepSpec, ...]
    #: Every term of the signed sum, in the file's order, constants included (for exporters that
    #: need the contour's chain of vectors, e.g. the URDF export); not used by the solve.
    chain: tuple[Term, ...] = ()

    def requires(self) -> tuple[str, ...]:
        names = [b for t in self.known for b in t.bases()]
        names += [b for d in self.deps for b in d.term.bases()]
        return tuple(n for n in dict.fromkeys(names) if n not in self.unknowns)

    def provides(self) -> tuple[str, ...]:
        return self.unknowns

    def hidden(self) -> tuple[str, ...]:
        return self.unknowns

    def closure(self, values: dict[str, Jet]) -> tuple[Jet, float]:
        """The jet of the contour's signed sum (zero when solved) and its scale Σ|z_s|."""
        terms = [*self.known, *(d.term for d in self.deps)]
        jets = [vector_jet(t.sign, length_jet(t.r, values), unit_jet(t.alpha, values)) for t in terms]
        total = sum_jets(jets, self.constant)
        scale = abs(self.constant) + sum(abs(j.value) for j in jets)
        return total, scale

    def solve(self, ctx: Context) -> None:
        vals, xp = ctx.values, ctx.xp

        def require(ok: Num, reason: str) -> None:
            ctx.require(self, ok, reason=reason)

        k = signed_sum(self.known, vals, self.constant)
        rj = [None if d.len_of is not None else length_jet(d.term.r, vals) for d in self.deps]
        uj = [None if d.ang_of is not None else unit_jet(d.term.alpha, vals) for d in self.deps]
        kpos = k.value
        solved: list[Num] = [None, None]
        if self.form == "pl4":
            p: list[Num] = [0j, 0j]
            for d, r in zip(self.deps, rj):
                p[d.ang_of] = p[d.ang_of] + d.term.sign * r.value * d.term.alpha.rot  # type: ignore[index,union-attr]
            u1, u2, _, _ = pl4.position(p[0], p[1], kpos, self.mode, xp, require)
            solved = [u1, u2]
        elif self.form == "pl2":
            dd: list[Num] = [0j, 0j]
            for d, u in zip(self.deps, uj):
                su = d.term.sign * u.value  # type: ignore[union-attr]
                dd[d.len_of] = dd[d.len_of] + su  # type: ignore[index]
                if d.term.r.offset:
                    kpos = kpos + d.term.r.offset * su
            solved = list(pl2.position(dd[0], dd[1], kpos, require))
        else:
            i_r = 0 if self.unknowns[0].endswith(".r") else 1
            i_a = 1 - i_r
            q: Num = None
            slide: Num = 0j
            for d, r, u in zip(self.deps, rj, uj):
                t = d.term
                if d.len_of is None:  # rotates with θ, known length
                    q = (0j if q is None else q) + t.sign * r.value * t.alpha.rot  # type: ignore[union-attr]
                elif d.ang_of is None:  # the slide of Пл3
                    slide = t.sign * u.value  # type: ignore[union-attr]
                    if t.r.offset:
                        kpos = kpos + t.r.offset * slide
                else:  # the rotating unknown vector of Пл1
                    slide = t.sign * t.alpha.rot
                    if t.r.offset:
                        q = (0j if q is None else q) + t.r.offset * slide
            if self.form == "pl3":
                rho, unit = pl3.position(slide, q, kpos, self.mode, xp, require)
            else:
                rho, unit = pl1.position(complex(slide), q, kpos, self.mode, xp, require)
            solved[i_r], solved[i_a] = rho, unit
        states = []
        for d, r, u in zip(self.deps, rj, uj):
            t = d.term
            dep = Dep(t.sign, 0.0, 0.0, d.len_of, d.ang_of)
            if d.len_of is None:
                dep.r, dep.r1, dep.r2 = r.value, r.d1, r.d2  # type: ignore[union-attr]
            else:
                dep.r = solved[d.len_of] + t.r.offset if t.r.offset else solved[d.len_of]
            if d.ang_of is None:
                dep.u, dep.a1, dep.a2 = u.value, u.d1, u.d2  # type: ignore[union-attr]
            else:
                dep.u = solved[d.ang_of] * t.alpha.rot if t.alpha.offset else solved[d.ang_of]
            states.append(dep)
        x, y, _, cond = analogs(k, states, xp)
        for i, name in enumerate(self.unknowns):
            vals[name] = Jet(solved[i], x[i], y[i])
        ctx.conditioning[self.name] = cond
