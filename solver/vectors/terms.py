"""Vector parameters and contour terms of seed 004's vector model, and their jets.

A vector i is ``r_i·e^{jα_i}``. Each parameter, after its links are followed, is a *base* plus a
constant offset (seed 004: α_k = α_i + Δα_ik, r_k = r_i + Δr_ik):

* base ``None``: a constant (the offset is the value);
* the input unit ``e^{jφ}`` (an angle "input with an offset");
* an unknown parameter, solved by one contour (``"AB.r"``, ``"AB.alpha"``).

At solve time a length parameter is a real jet ``(r, r', r'')`` and an angle parameter a *unit
jet* ``(e^{jα}, α', α'')``: the unit vector rather than the angle, so no group needs a
trigonometric call except the input's ``e^{jφ}`` and an output joint's ``atan2``.
A vector's jet follows from ``z = r·u`` (``u = e^{jα}``):
    z'  = (r' + j·r·α')·u,
    z'' = (r'' − r·α'² + j·(2·r'·α' + r·α''))·u.
"""

from __future__ import annotations

import cmath
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..jet import Jet

__all__ = ["Ref", "Term", "is_zero", "length_jet", "unit_jet", "vector_jet", "sum_jets", "term_jet", "signed_sum"]

Num = Any


def is_zero(x: Num) -> bool:
    """True for a Python float zero: a derivative that vanishes (structural zeros are ``0.0``).

    Skipping a term for it is exact, so a derivative that happens to be 0.0 on the per-tick
    path is no different from one that is zero by construction.
    """
    return x.__class__ is float and x == 0.0


@dataclass(frozen=True)
class Ref:
    """A resolved parameter: ``base + offset`` (``base is None``: the constant ``offset``).

    For an angle, ``offset`` is in rad and ``rot = e^{j·offset}``.
    """

    base: str | None
    offset: float
    angle: bool

    @property
    def rot(self) -> complex:
        return cmath.exp(1j * self.offset)


@dataclass(frozen=True)
class Term:
    """``sign · r·e^{jα}`` of vector ``vector`` in a contour's signed sum."""

    vector: str
    sign: float
    r: Ref
    alpha: Ref

    def bases(self) -> tuple[str, ...]:
        return tuple(b for b in (self.r.base, self.alpha.base) if b is not None)


def length_jet(ref: Ref, values: Mapping[str, Jet]) -> Jet:
    if ref.base is None:
        return Jet(ref.offset, 0.0, 0.0)
    j = values[ref.base]
    return j if ref.offset == 0.0 else Jet(j.value + ref.offset, j.d1, j.d2)


def unit_jet(ref: Ref, values: Mapping[str, Jet]) -> Jet:
    if ref.base is None:
        return Jet(ref.rot, 0.0, 0.0)
    j = values[ref.base]
    return j if ref.offset == 0.0 else Jet(j.value * ref.rot, j.d1, j.d2)


def vector_jet(sign: float, r: Jet, u: Jet) -> Jet:
    """Jet of ``sign·r·u`` from the jets of its length and unit vector."""
    r1, r2, a1, a2 = r.d1, r.d2, u.d1, u.d2
    if is_zero(r1) and is_zero(r2):
        z = (sign * r.value) * u.value if isinstance(r.value, float) else sign * r.value * u.value
        if is_zero(a1) and is_zero(a2):
            return Jet(z, 0.0, 0.0)
        if isinstance(a1, float) and a1 == 1.0 and is_zero(a2):  # the input: z' = jz, z'' = −z
            return Jet(z, 1j * z, -z)
        z2 = -(a1 * a1) * z if is_zero(a2) else (1j * a2 - a1 * a1) * z
        return Jet(z, 1j * a1 * z, z2)
    su = sign * u.value
    z = r.value * su
    if is_zero(a1) and is_zero(a2):  # a slide along a fixed direction
        return Jet(z, r1 * su, r2 * su)
    z1 = (r1 + 1j * (r.value * a1)) * su
    z2 = (r2 - r.value * a1 * a1 + 1j * (2.0 * r1 * a1 + r.value * a2)) * su
    return Jet(z, z1, z2)


def sum_jets(jets: list[Jet], start: complex = 0j) -> Jet:
    """Term-by-term sum, skipping scalar zeros."""
    v: Num = start
    d1: Num = 0.0
    d2: Num = 0.0
    for j in jets:
        v = v + j.value
        if not is_zero(j.d1):
            d1 = j.d1 if is_zero(d1) else d1 + j.d1
        if not is_zero(j.d2):
            d2 = j.d2 if is_zero(d2) else d2 + j.d2
    return Jet(v, d1, d2)


def term_jet(t: Term, values: Any) -> Jet:
    """Jet of vector ``t.vector`` (unsigned), computed once per evaluation.

    The jet is kept in the evaluation's namespace under the key ``("vector", name)`` — a tuple,
    so it can never clash with a point or joint name — because a contour and the points read
    the same vectors (the input crank, typically).
    """
    key = ("vector", t.vector)
    jet = values.get(key)
    if jet is None:
        jet = vector_jet(1.0, length_jet(t.r, values), unit_jet(t.alpha, values))
        values[key] = jet
    return jet


def signed_sum(terms: tuple[Term, ...] | list[Term], values: Any, start: complex = 0j) -> Jet:
    """``start + Σ σ_s·z_s`` term by term, skipping scalar zeros."""
    v: Num = start
    d1: Num = 0.0
    d2: Num = 0.0
    for t in terms:
        j = term_jet(t, values)
        neg = t.sign < 0
        v = v - j.value if neg else v + j.value
        if not is_zero(j.d1):
            d1 = (-j.d1 if neg else j.d1) if is_zero(d1) else (d1 - j.d1 if neg else d1 + j.d1)
        if not is_zero(j.d2):
            d2 = (-j.d2 if neg else j.d2) if is_zero(d2) else (d2 - j.d2 if neg else d2 + j.d2)
    return Jet(v, d1, d2)
