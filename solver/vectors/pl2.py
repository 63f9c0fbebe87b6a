"""Modules Пл2 and Пл2s (seed 004, Tables 1–2): unknown lengths ρ₁, ρ₂ of vectors with known angles.

Loop equation (seed 004, eq. 1 in complex form), after links are followed:
    ρ₁·D₁ + ρ₂·D₂ + K = 0,
    D_k = Σ σ_s·e^{jα_s} over the terms whose length is ρ_k (+ Δr_s; the owner and, for Пл2s,
        the vectors linked to it: r_s = ρ_k + Δr_s, seed 004 Fig. 6),
    K = the sum of the other terms plus Σ σ_s·Δr_s·e^{jα_s}.
Position (linear): ρ₁ = (−K × D₂)/(D₁ × D₂), ρ₂ = (D₁ × −K)/(D₁ × D₂). One solution.
    Seed 004 resolves Пл2s's length-on-length link only in its "inertial" model (from the previous
    position) and counts 2 solutions; substituting the link keeps the closure linear, so it has
    exactly one solution and is solved here exactly, in the same step (a documented departure).
Derivatives, linear system: see :mod:`solver.vectors.analogs` (columns A_k = D_k).
Branch rule: none (one solution).
Assembly fails where D₁ × D₂ = 0 (the two slides are parallel).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from .._backend import abs2, cross
from ..tolerances import SINGULAR

__all__ = ["position"]

Num = Any


def position(d1: Num, d2: Num, k: Num, require: Callable[[Num, str], None]) -> tuple[Num, Num]:
    """``(ρ₁, ρ₂)`` of ``ρ₁·D₁ + ρ₂·D₂ + K = 0``."""
    det = cross(d1, d2)
    require(abs(det) > SINGULAR * abs2(d1) ** 0.5 * abs2(d2) ** 0.5, "has its two slides parallel")
    if det.__class__ is float and det == 0.0:  # the scalar path in mask mode: flagged above, no division
        return math.nan, math.nan
    return cross(k, d2) / -det, cross(d1, k) / -det
