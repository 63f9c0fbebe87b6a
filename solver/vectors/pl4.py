"""Modules Пл4 and Пл4s (seed 004, Tables 1–2): unknown angles θ₁, θ₂ of two vectors.

Loop equation (seed 004, eq. 1 in complex form), after links are followed:
    e^{jθ₁}·P₁ + e^{jθ₂}·P₂ + K = 0,
    P_k = Σ σ_s·r_s·e^{jΔ_s} over the vector of θ_k and, for Пл4s, the vectors whose angle is
        linked to it (α_s = θ_k + Δ_s: Пл4s steps 4–5, the summed vectors Σ1, Σ2),
    K = the sum of the terms that depend on neither unknown.
Position: v₁ = e^{jθ₁}·P₁ and v₂ = e^{jθ₂}·P₂ close the triangle v₁ + v₂ = W = −K with
    |v₁| = |P₁|, |v₂| = |P₂| (the law of cosines, as the RRR dyad of seed 003):
    a = (|P₁|² − |P₂|² + |W|²)/(2·|W|²),  h² = |P₁|²/|W|² − a²,
    v₁ = W·(a − j·M·h),  v₂ = W − v₁,  e^{jθ_k} = v_k/P_k.  Two solutions (Table 1: 2).
Derivatives, linear system: see :mod:`solver.vectors.analogs` (A_k = j·v_k, det = v₁ × v₂).
Branch rule (seed 003)
    M = +1 when the triangle traversed by v₁ then v₂ (in the contour's order) is
    counter-clockwise, v₁ × v₂ > 0; M = −1 clockwise. For the four-bar written
    OA + AB − CB − OC = 0 this is the RRR dyad's M (A → B → C counter-clockwise).
    Seed 004 counts 4 solutions for Пл4s (Пл1 reductions chained with Пл4); with links
    α_s = θ_k + Δ_s the summed vectors P_k are known before the solve and the closure above has
    at most these two.
Assembly fails where h² < 0 (|P₁| + |P₂| < |K| or ||P₁| − |P₂|| > |K|) or K = 0.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from .._backend import Backend, abs2
from ..tolerances import ASSEMBLY_SLACK

__all__ = ["position"]

Num = Any


def _div(v: Num, p: Num) -> Num:
    return v * (1.0 / p) if isinstance(p, complex) else v / p


def position(
    p1: Num, p2: Num, k: Num, mode: int, xp: Backend, require: Callable[[Num, str], None]
) -> tuple[Num, Num, Num, Num]:
    """``(e^{jθ₁}, e^{jθ₂}, v₁, v₂)`` of ``e^{jθ₁}·P₁ + e^{jθ₂}·P₂ + K = 0``."""
    w = -k
    dd = abs2(w)
    require(dd > 0.0, "has a zero closing vector")
    l1, l2 = abs2(p1), abs2(p2)
    a = (l1 - l2 + dd) / (2.0 * dd)
    h2 = l1 / dd - a * a
    require(h2 >= -ASSEMBLY_SLACK * (l1 + l2) / dd, "cannot be assembled")
    h = xp.sqrt(h2 * (h2 > 0.0))
    v1 = w * (a - 1j * mode * h)
    v2 = w - v1
    return _div(v1, p1), _div(v2, p2), v1, v2
