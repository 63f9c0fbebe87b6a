"""Modules Пл3 and Пл3s (seed 004, Tables 1–2): unknown length ρ of one vector, angle θ of another.

Loop equation (seed 004, eq. 1 in complex form), after links are followed:
    ρ·D + e^{jθ}·P + K = 0,
    D = σ·e^{jα} of the ρ-vector's term (a unit vector: its angle is known),
    P = Σ σ_s·r_s·e^{jΔ_s} over the θ-vector and, for Пл3s, the vectors whose angle is linked to
        it (α_s = θ + Δ_s; the paper's summed vector in the local frame, Пл3s steps 4–5),
    K = the sum of the other terms (plus σ·Δr·e^{jα} if the ρ-term is a link r = ρ + Δr).
Position: with t = D·K and n = D × K,  |ρ·D + K| = |P|  gives
    ρ = −t + M·√(|P|² − n²),   e^{jθ} = −(ρ·D + K)/P.  Two solutions (Table 1: 2).
Derivatives, linear system: see :mod:`solver.vectors.analogs` (A_ρ = D, A_θ = j·e^{jθ}·P).
Branch rule
    M = +1 takes the larger root ρ, i.e. the rotating part e^{jθ}·P points against D:
    −(e^{jθ}·P)·D ≥ 0. For the slider-crank written OA + AB − s·e = 0 this is (B − A)·e ≥ 0,
    the RRP group's M (seed 003's reasoning, docs/architecture.md).
    Seed 004 counts 4 solutions for Пл3s (its algorithm chains two Пл3 solves); with links
    α_s = θ + Δ_s the summed vector P is known before the solve, the closure is the one above
    and has at most these two.
Assembly fails where |n| > |P| (the rotating part cannot reach the slide).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from .._backend import Backend, abs2, cross, dot
from ..tolerances import ASSEMBLY_SLACK

__all__ = ["position"]

Num = Any


def position(
    d: complex | Num, p: Num, k: Num, mode: int, xp: Backend, require: Callable[[Num, str], None]
) -> tuple[Num, Num]:
    """``(ρ, e^{jθ})`` of ``ρ·D + e^{jθ}·P + K = 0`` with |D| = 1."""
    t = dot(d, k)
    n = cross(d, k)
    pp = abs2(p)
    disc = pp - n * n
    require(disc >= -ASSEMBLY_SLACK * pp, "cannot be assembled")
    rho = -t + mode * xp.sqrt(disc * (disc > 0.0))
    return rho, (rho * d + k) * (-1.0 / p) if isinstance(p, complex) else -(rho * d + k) / p
