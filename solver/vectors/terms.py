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

__all__ = ["Ref", "Term", "is_zero", "length_jet", "unit_jet", "vector_jet", "sum_jets"]

Num = Any


def is_zero(x: Num) -> bool:
    """True for a Python scalar zero (an exactly vanishing derivative known at load time)."""
    return isinstance(x, (int, float, complex)) and x == 0


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
    su = sign * u.value
    z = r.value * su
    r1, r2, a1, a2 = r.d1, r.d2, u.d1, u.d2
    if is_zero(r1) and is_zero(r2):
        if is_zero(a1) and is_zero(a2):
            return Jet(z, 0.0, 0.0)
        if isinstance(a1, float) and a1 == 1.0 and is_zero(a2):  # the input: z' = jz, z'' = −z
            return Jet(z, 1j * z, -z)
        z2 = -(a1 * a1) * z if is_zero(a2) else (1j * a2 - a1 * a1) * z
        return Jet(z, 1j * a1 * z, z2)
    z1 = (r1 + 1j * (r.value * a1)) * su if not is_zero(a1) else r1 * su
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
