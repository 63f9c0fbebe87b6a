"""The velocity and acceleration analogs of any planar vector module (seed 004, eq. 1 differentiated).

Closure of a contour (seed 004, eq. 1, in complex form):  Σ_s σ_s·r_s·e^{jα_s} = 0.
Every parameter is a base plus a constant offset, so a term's length derivative is the
unknown's (r_s' = u', r_s'' = u'') when it is linked to an unknown length u, and its angle
derivative likewise for an unknown angle. Differentiating the closure once:
    Σ_s σ_s·(r_s' + j·r_s·α_s')·e^{jα_s} = 0,
    x₁·A₁ + x₂·A₂ = R₁,
where, for an unknown length k, A_k = Σ_{s: r_s ~ k} σ_s·e^{jα_s}, for an unknown angle k,
A_k = Σ_{s: α_s ~ k} j·z_s (z_s = σ_s·r_s·e^{jα_s}), and R₁ = −Σ (the terms' known parts):
    R₁ = −K' − Σ_{r_s known} σ_s·r_s'·e^{jα_s} − Σ_{α_s known} j·z_s·α_s'
(K = the sum of the terms that depend on no unknown). Twice:
    Σ_s σ_s·(r_s'' − r_s·α_s'² + j·(2·r_s'·α_s' + r_s·α_s''))·e^{jα_s} = 0,
    y₁·A₁ + y₂·A₂ = R₂,
    R₂ = −K'' − Σ_s [σ_s·r''_s,known·e^{jα_s} − z_s·α_s'² + j·(2·σ_s·r_s'·α_s'·e^{jα_s} + z_s·α''_s,known)],
with r_s', α_s' now all known. The matrix [A₁ A₂] (two real unknowns, one complex equation)
is the Jacobian of the closure in the two unknowns; Cramer's rule on the real 2×2 system:
    x₁ = (R × A₂)/(A₁ × A₂),   x₂ = (A₁ × R)/(A₁ × A₂)     (× = the planar cross product).
Conditioning: |A₁ × A₂| / (|A₁|·|A₂|) = |sin| of the angle between the Jacobian's columns,
1 when they are perpendicular, 0 at a singular position (a dead centre).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .._backend import Backend, abs2, cross
from ..jet import Jet
from .terms import is_zero

__all__ = ["Dep", "analogs"]

Num = Any


@dataclass
class Dep:
    """A term that depends on an unknown, with its position solved.

    ``len_of``/``ang_of``: the index (0, 1) of the unknown its length / angle follows, or None;
    ``r1, r2`` / ``a1, a2``: the known derivatives of a length / angle that follows no unknown.
    """

    sign: float
    r: Num
    u: Num
    len_of: int | None
    ang_of: int | None
    r1: Num = 0.0
    r2: Num = 0.0
    a1: Num = 0.0
    a2: Num = 0.0

    @property
    def z(self) -> Num:
        return self.sign * self.r * self.u


def _acc(total: Num, x: Num) -> Num:
    return x if is_zero(total) else total + x


def analogs(k: Jet, deps: list[Dep], xp: Backend) -> tuple[tuple[Num, Num], tuple[Num, Num], Num, Num]:
    """``((x₁, x₂), (y₁, y₂), det, conditioning)``: first and second analogs of the two unknowns."""
    cols: list[Num] = [0.0, 0.0]
    zs = [d.z for d in deps]
    for d, z in zip(deps, zs):
        if d.len_of is not None:
            cols[d.len_of] = _acc(cols[d.len_of], d.sign * d.u)
        if d.ang_of is not None:
            cols[d.ang_of] = _acc(cols[d.ang_of], 1j * z)
    a1, a2 = cols
    det = cross(a1, a2)
    r1: Num = 0.0 if is_zero(k.d1) else -k.d1
    for d, z in zip(deps, zs):
        if d.len_of is None and not is_zero(d.r1):
            r1 = r1 - d.sign * d.r1 * d.u
        if d.ang_of is None and not is_zero(d.a1):
            r1 = r1 - 1j * z * d.a1
    # an exact dead centre on the per-tick path: ±inf as numpy gives on the vectorised path (the
    # sample is flagged singular by its conditioning 0), not a ZeroDivisionError
    inv = 1.0 / det if det.__class__ is not float or det != 0.0 else math.copysign(math.inf, det)
    x = (cross(r1, a2) * inv, cross(a1, r1) * inv)
    r2: Num = 0.0 if is_zero(k.d2) else -k.d2
    for d, z in zip(deps, zs):
        rd1 = x[d.len_of] if d.len_of is not None else d.r1
        ad1 = x[d.ang_of] if d.ang_of is not None else d.a1
        rd2 = 0.0 if d.len_of is not None else d.r2
        ad2 = 0.0 if d.ang_of is not None else d.a2
        if not is_zero(rd2):
            r2 = r2 - d.sign * rd2 * d.u
        if not is_zero(ad1):
            r2 = r2 + z * (ad1 * ad1)
            if not is_zero(rd1):
                r2 = r2 - 2j * d.sign * (rd1 * ad1) * d.u
        if not is_zero(ad2):
            r2 = r2 - 1j * z * ad2
    y = (cross(r2, a2) * inv, cross(a1, r2) * inv)
    cond = abs(det) / xp.sqrt(abs2(a1) * abs2(a2))
    return x, y, det, cond
