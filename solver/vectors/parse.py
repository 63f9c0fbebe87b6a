"""The ``vector_model:`` section of a scene file → groups (seed 004's vector model).

::

    vector_model:
      input: crank                      # the input joint; its coordinate is φ
      vectors:                          # r and alpha each: a number (scene units), unknown,
        OA: {r: 0.1, alpha: input}      #   input / {input: Δα} (α = φ + Δα), or
        AB: {r: 0.4, alpha: unknown}    #   {link: VECTOR, plus: Δ} (α_k = α_i + Δα, r_k = r_i + Δr)
        OC: {fixed: [O, C]}             # the constant vector between two fixed points
      contours:                         # signed sums that close; M where the module has 2 solutions
        dyad: {sum: [OA, AB, -CB, -OC], M: +1}
      points:                           # sums of vectors from a fixed origin
        B: {from: O, sum: [OA, AB]}
      joints:                           # a vector's angle (rad, (−π, π]) or length
        coupler: {angle: AB}
      draw: [[C, B]]                    # optional: polylines for viewers beyond the points' sums

Structural checks (all at load time, as SceneError naming the contour and its unknowns):
links are followed to their base (a cycle of links is an error); contours are put in dependency
order, each solving exactly two unknowns not solved before it; each is classified as Пл1–Пл4
(or Пл1s–Пл4s when a term is linked to the contour's own unknown) and rejected where seed 004
says the framework has no solution.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Mapping
from typing import Any

from .._fields import Entry, Units, show
from ..groups.base import Group
from ..tolerances import SINGULAR
from .contour import Contour, DepSpec
from .nodes import VectorInput, VectorJoint, VectorPoint
from .terms import Ref, Term

__all__ = ["parse_vector_model", "SECTION"]

SECTION = "vector_model"
_PARAM_FORMS = "a number, 'unknown', 'input', {input: offset} or {link: VECTOR, plus: offset}"
_RULES = {
    "pl1": "M = +1 takes the larger root of the unknown length",
    "pl3": "M = +1 takes the larger root of the unknown length (the RRP group's M for a slider-crank)",
    "pl4": "M = +1 when the two unknown-angle vectors, in the contour's order, turn counter-clockwise",
}


def parse_vector_model(e: Entry, units: Units, fixed: Mapping[str, Any]) -> list[Group]:
    """Groups of one vector model: the input, the contours in solving order, points, joints."""
    for n, v in fixed.items():
        if not isinstance(v, complex):
            raise e.error(f"the vector model is planar; fixed point '{n}' is not [x, y]")
    joint = e.name("input")
    unit_name = f"{joint}.input"
    model = _Model(e, units, fixed, unit_name)
    contours = model.contours(e.child("contours", e.raw("contours")))
    points = model.points(e.child("points", e.raw("points", {})))
    joints = model.joints(e.child("joints", e.raw("joints", {})))
    drawn = _drawn(e, {*fixed, *(p.point for p in points)})
    e.done()
    solved = {u for c in contours for u in c.unknowns}
    for g in (*points, *joints):
        for b in g.requires():
            if b.endswith((".r", ".alpha")) and b not in solved and b not in fixed and b != unit_name:
                raise e.error(f"'{g.name}' reads {b}, which is unknown and solved by no contour")
    return [VectorInput(name=joint, joint=joint, unit=unit_name, drawn=drawn), *contours, *points, *joints]


def _drawn(e: Entry, points: set[str]) -> tuple[tuple[str, ...], ...]:
    """``draw: [[C, B], ...]``: polylines through points that no point's sum already draws."""
    raw = e.raw("draw", [])
    if not isinstance(raw, list) or not all(
        isinstance(line, list) and len(line) >= 2 and all(isinstance(n, str) for n in line) for line in raw
    ):
        raise e.error(f"must be a list of polylines, each a list of two or more point names, got {show(raw)}", "draw")
    for line in raw:
        for n in line:
            if n not in points:
                raise e.error(f"unknown point '{n}'; points: {sorted(points)}", "draw")
    return tuple(tuple(line) for line in raw)


class _Model:
    def __init__(self, e: Entry, units: Units, fixed: Mapping[str, Any], unit_name: str) -> None:
        self.units, self.fixed, self.unit_name = units, fixed, unit_name
        ve = e.child("vectors", e.raw("vectors"))
        if not ve.data:
            raise ve.error("name at least one vector")
        self.entries: dict[str, Entry] = {}
        self.specs: dict[str, dict[str, tuple[Any, ...]]] = {}
        for name in ve.data:
            v = ve.child(str(name), ve.raw(name))
            self.entries[str(name)] = v
            if "fixed" in v.data:
                a, b = v.names("fixed", 2)
                for p in (a, b):
                    if p not in fixed:
                        raise v.error(f"'{p}' is not a fixed point; fixed: {sorted(fixed)}", "fixed")
                z = complex(fixed[b]) - complex(fixed[a])
                if z == 0:
                    raise v.error("joins two coincident fixed points", "fixed")
                self.specs[str(name)] = {"r": ("const", abs(z)), "alpha": ("const", cmath.phase(z))}
            else:
                self.specs[str(name)] = {"r": self._spec(v, "r"), "alpha": self._spec(v, "alpha")}
            v.done()

    # -- parameters ---------------------------------------------------------------------------
    def _spec(self, v: Entry, key: str) -> tuple[Any, ...]:
        raw = v.raw(key)
        angle = key == "alpha"
        if raw == "unknown":
            return ("unknown",)
        if raw == "input":
            if not angle:
                raise v.error("only an angle can be the input φ", key)
            return ("input", 0.0)
        if isinstance(raw, (int, float)) and not isinstance(raw, bool):
            return ("const", v.angle(key, self.units) if angle else v.length(key, self.units))
        if isinstance(raw, Mapping):
            sub = v.child(key, raw)
            if "input" in sub.data:
                if not angle:
                    raise v.error("only an angle can be the input φ", key)
                off = sub.angle("input", self.units)
                sub.done()
                return ("input", off)
            if "link" in sub.data:
                target = sub.name("link")
                plus = (
                    sub.angle("plus", self.units, 0.0)
                    if angle
                    else sub.length("plus", self.units, positive=False, default=0.0)
                )
                sub.done()
                return ("link", target, plus)
        raise v.error(f"must be {_PARAM_FORMS}, got {show(raw)}", key)

    def resolve(self, name: str, kind: str, chain: tuple[str, ...] = ()) -> Ref:
        """Follow links to the base: a constant, the input, or an unknown (seed 004: links first)."""
        here = f"{name}.{kind}"
        if here in chain:
            raise self.entries[name].error(f"links form a cycle: {' → '.join((*chain, here))}", kind)
        spec = self.specs[name][kind]
        angle = kind == "alpha"
        if spec[0] == "const":
            return Ref(None, float(spec[1]), angle)
        if spec[0] == "unknown":
            return Ref(here, 0.0, angle)
        if spec[0] == "input":
            return Ref(self.unit_name, float(spec[1]), True)
        target = spec[1]
        if target not in self.specs:
            known = sorted(self.specs)
            raise self.entries[name].error(f"links to '{target}', which is not a vector; vectors: {known}", kind)
        base = self.resolve(target, kind, (*chain, here))
        return Ref(base.base, base.offset + float(spec[2]), angle)

    def terms(self, e: Entry, key: str) -> list[Term]:
        raw = e.raw(key)
        if not isinstance(raw, (list, tuple)) or not raw or not all(isinstance(x, str) for x in raw):
            what = "a non-empty list of vector names, each optionally signed (-AB)"
            raise e.error(f"must be {what}, got {show(raw)}", key)
        out = []
        for item in raw:
            text = item.strip()
            sign = -1.0 if text.startswith("-") else 1.0
            name = text.lstrip("+-").strip()
            if name not in self.specs:
                raise e.error(f"'{name}' is not a vector; vectors: {sorted(self.specs)}", key)
            out.append(Term(name, sign, self.resolve(name, "r"), self.resolve(name, "alpha")))
        return out

    def _unknowns(self, terms: list[Term]) -> list[str]:
        names = [b for t in terms for b in t.bases() if b != self.unit_name]
        return list(dict.fromkeys(names))

    # -- contours -----------------------------------------------------------------------------
    def contours(self, ce: Entry) -> list[Contour]:
        if not ce.data:
            raise ce.error("name at least one contour")
        pending = []
        for cname in ce.data:
            c = ce.child(str(cname), ce.raw(cname))
            terms = self.terms(c, "sum")
            pending.append((str(cname), c, terms, self._unknowns(terms)))
        known: set[str] = set()
        out: list[Contour] = []
        while pending:
            ready = next((p for p in pending if len([u for u in p[3] if u not in known]) == 2), None)
            if ready is None:
                _stalled(ce, pending, known)
            assert ready is not None
            pending.remove(ready)
            cname, c, terms, unknowns = ready
            mine = [u for u in unknowns if u not in known]
            out.append(self._classify(cname, c, terms, (mine[0], mine[1])))
            known.update(mine)
        declared = {f"{n}.{k}" for n, s in self.specs.items() for k in ("r", "alpha") if s[k][0] == "unknown"}
        unsolved = sorted(declared - known)
        if unsolved:
            raise ce.error(f"no contour solves the unknown(s) {', '.join(unsolved)}")
        return out

    def _classify(self, cname: str, c: Entry, terms: list[Term], unknowns: tuple[str, str]) -> Contour:
        constant = 0j
        known: list[Term] = []
        deps: list[DepSpec] = []
        for t in terms:
            li = unknowns.index(t.r.base) if t.r.base in unknowns else None
            ai = unknowns.index(t.alpha.base) if t.alpha.base in unknowns else None
            if li is None and ai is None:
                if t.r.base is None and t.alpha.base is None:
                    constant += t.sign * t.r.offset * t.alpha.rot
                else:
                    known.append(t)
            else:
                deps.append(DepSpec(t, li, ai))
        kinds = tuple("r" if u.endswith(".r") else "alpha" for u in unknowns)
        owners = tuple(u.rsplit(".", 1)[0] for u in unknowns)
        base = {("r", "r"): "Пл2", ("alpha", "alpha"): "Пл4"}.get((kinds[0], kinds[1]))
        if base is None:
            base = "Пл1" if owners[0] == owners[1] else "Пл3"
        linked = {i for d in deps for i in (d.len_of, d.ang_of) if i is not None and d.term.vector != owners[i]}
        module = base + ("s" if linked else "")
        where = f"{module}({unknowns[0]}, {unknowns[1]})"
        if len(linked) == 2 and base != "Пл4":
            raise c.error(
                f"{where} has links from both of its unknowns: seed 004 gives no solution for a module "
                "with links from both of its functions, except Пл4s"
            )
        if base == "Пл2":
            form, solutions = "pl2", 1
            _check_slides(c, where, deps)
        elif base == "Пл4":
            form, solutions = "pl4", 2
        else:
            i_r = kinds.index("r")
            slides = [d for d in deps if d.len_of == i_r]
            if len(slides) > 1:
                linked_len = [d.term.vector for d in slides if d.term.vector != owners[i_r]]
                raise c.error(
                    f"{where}: the length of {', '.join(linked_len)} is linked to the contour's unknown "
                    f"length {unknowns[i_r]} (a length-on-length link to an unknown): seed 004 solves that "
                    "only in its 'inertial' model, from the previous position, not in a rigid closed form"
                )
            rotating = slides[0].ang_of is not None
            turning = [d for d in deps if d.len_of is None]
            if not rotating and not turning:
                raise c.error(f"{where}: the unknown angle {unknowns[1 - i_r]} turns no vector of known length")
            form = "pl1" if rotating else "pl3"
            solutions = 2 if (turning or slides[0].term.r.offset or not rotating) else 1
        mode = 0
        if solutions == 2:
            if "M" not in c.data:
                raise c.error(f"{where} has two solutions: give the assembly mode M: +1 or -1 ({_RULES[form]})")
            mode = c.mode()
        elif "M" in c.data:
            raise c.error(f"{where} has one solution; remove M")
        c.done()
        return Contour(
            name=cname,
            module=module,
            form=form,
            unknowns=unknowns,
            mode=mode,
            constant=constant,
            known=tuple(known),
            deps=tuple(deps),
            chain=tuple(terms),
        )

    # -- outputs --------------------------------------------------------------------------------
    def points(self, pe: Entry) -> list[VectorPoint]:
        out: list[VectorPoint] = []
        sums: dict[str, tuple[str, tuple[tuple[float, str], ...]]] = {}
        for pname in pe.data:
            p = pe.child(str(pname), pe.raw(pname))
            origin = p.name("from")
            if origin not in self.fixed:
                raise p.error(
                    f"points are sums of vectors from a fixed point; '{origin}' is not one of {sorted(self.fixed)}",
                    "from",
                )
            terms = self.terms(p, "sum")
            p.done()
            key = tuple((t.sign, t.vector) for t in terms)
            parent = origin if len(key) == 1 else None  # drawn: a point one vector beyond another
            for other, (o, k) in sums.items():
                if o == origin and len(k) == len(key) - 1 and key[: len(k)] == k:
                    parent = other
            sums[str(pname)] = (origin, key)
            value = complex(self.fixed[origin])
            moving = []
            for t in terms:
                if t.r.base is None and t.alpha.base is None:
                    value += t.sign * t.r.offset * t.alpha.rot
                else:
                    moving.append(t)
            out.append(
                VectorPoint(
                    name=str(pname),
                    point=str(pname),
                    origin=origin,
                    origin_value=value,
                    terms=tuple(moving),
                    parent=parent,
                    chain=tuple(terms),
                )
            )
        return out

    def joints(self, je: Entry) -> list[VectorJoint]:
        out = []
        for jname in je.data:
            j = je.child(str(jname), je.raw(jname))
            kinds = [k for k in ("angle", "length") if k in j.data]
            if len(kinds) != 1 or len(j.data) != 1:
                raise j.error(f"must be {{angle: VECTOR}} or {{length: VECTOR}}, got {show(j.data)}")
            vec = j.name(kinds[0])
            if vec not in self.specs:
                raise j.error(f"'{vec}' is not a vector; vectors: {sorted(self.specs)}", kinds[0])
            kind = "alpha" if kinds[0] == "angle" else "r"
            out.append(VectorJoint(name=str(jname), expression=kinds[0], ref=self.resolve(vec, kind)))
        return out


def _check_slides(c: Entry, where: str, deps: list[DepSpec]) -> None:
    """Пл2 with both slides at constant angles: refuse parallel slides (or a slide whose terms
    cancel) on load, where the closure ρ₁·D₁ + ρ₂·D₂ + K = 0 has no solution at any φ."""
    if any(d.term.alpha.base is not None for d in deps):
        return  # a slide that turns: parallel at some φ at most (an AssemblyError there)
    col = [0j, 0j]
    for d in deps:
        if d.len_of is not None:
            col[d.len_of] += d.term.sign * d.term.alpha.rot
    n1, n2 = abs(col[0]), abs(col[1])
    if n1 <= SINGULAR or n2 <= SINGULAR or abs((col[0].conjugate() * col[1]).imag) <= SINGULAR * n1 * n2:
        angles = ", ".join(f"{d.term.vector} at {math.degrees(d.term.alpha.offset):g}°" for d in deps)
        raise c.error(
            f"{where}: the two unknown lengths slide along parallel lines ({angles}): the contour "
            "cannot close at any φ (seed 004's Пл2 needs two slides at different angles)"
        )


def _stalled(ce: Entry, pending: list[tuple[str, Entry, list[Term], list[str]]], known: set[str]) -> None:
    """Raise the SceneError that says why no remaining contour can be solved next."""
    for _, c, _, unknowns in pending:
        mine = [u for u in unknowns if u not in known]
        if len(mine) < 2:
            before = [u for u in unknowns if u in known]
            solved = f" ({', '.join(before)} solved by earlier contours)" if before else ""
            raise c.error(
                f"has {len(mine)} unknown(s) ({', '.join(mine) or 'none'}){solved}: a contour, a planar "
                "module Пл1–Пл4, solves exactly two"
            )
    if len(pending) == 1:
        cname, c, _, unknowns = pending[0]
        mine = [u for u in unknowns if u not in known]
        raise c.error(
            f"has {len(mine)} unknowns ({', '.join(mine)}): a contour, a planar module Пл1–Пл4, solves exactly two"
        )
    listing = "; ".join(f"'{n}' has {', '.join(u for u in us if u not in known)}" for n, _, _, us in pending)
    raise ce.error(
        "the unknowns cannot be put in a solvable order (each contour must have exactly two left when its "
        f"turn comes): {listing}"
    )
