"""Modules Пл1 and Пл1s (seed 004, Tables 1–2): unknown length ρ and angle θ of one vector.

Loop equation (seed 004, eq. 1 in complex form), after links are followed:
    e^{jθ}·(ρ·c + Q) + K = 0,
    c = σ·e^{jΔ} of the unknown vector's term (σ = ±1 its sign in the contour, Δ its angle offset),
    Q = Σ σ_s·r_s·e^{jΔ_s} over the vectors whose angle is linked to θ (α_s = θ + Δ_s, known
        lengths): the paper's "summed vector in the local frame of vector 1" (Пл1s, steps 4–5);
        Q = 0 for the elementary Пл1,
    K = the sum of the terms that depend on neither unknown.
Position
    Пл1 (Q = 0): ρ·e^{jθ} = −K/c, one solution: ρ = |K| ≥ 0, e^{jθ} = −K/(c·ρ).
    Пл1s: with w = c̄·Q, |ρ + w| = |K|, so ρ = −Re w + M·√(|K|² − (Im w)²) and
    e^{jθ} = −c̄·K/(ρ + w): two solutions (Table 2: 2).
Derivatives, linear system: see :mod:`solver.vectors.analogs` (columns A_ρ = c·e^{jθ},
    A_θ = j·Σ z_s over the rotating terms; det = 0 where ρ + w = 0 or at the double root).
Branch rule (Пл1s)
    M = +1 takes the larger root ρ (ρ + Re w ≥ 0), M = −1 the smaller. For the elementary Пл1
    there is no choice: (ρ, θ) and (−ρ, θ + π) are the same vector, and ρ ≥ 0 is reported.
Assembly fails where |Im w| > |K| (Пл1s) or K = 0 (Пл1: the direction is undefined).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from .._backend import Backend, abs2
from ..tolerances import ASSEMBLY_SLACK

__all__ = ["position"]

Num = Any


def position(
    c: complex, q: Num | None, k: Num, mode: int, xp: Backend, require: Callable[[Num, str], None]
) -> tuple[Num, Num]:
    """``(ρ, e^{jθ})`` of the closure ``e^{jθ}·(ρ·c + Q) + K = 0``; ``q is None`` for Пл1."""
    kk = abs2(k)
    if q is None:
        require(kk > 0.0, "has a zero closing vector: the unknown vector's direction is undefined")
        rho = xp.sqrt(kk)
        return rho, k * (-1.0 / c) / rho
    w = c.conjugate() * q
    wr, wi = w.real, w.imag
    disc = kk - wi * wi
    require(disc >= -ASSEMBLY_SLACK * kk, "cannot be assembled")
    rho = -wr + mode * xp.sqrt(disc * (disc > 0.0))
    s = rho + w
    require(abs2(s) > 0.0, "has a zero summed vector")
    return rho, -c.conjugate() * k / s
