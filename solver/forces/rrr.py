"""Route 2 for the RRR dyad (seed 003's group; links 1 = A–B, 2 = C–B, middle pin B).

Unknowns: R_A (on link 1 at A, from the owner of A), R_C (on link 2 at C), R_B (on link 1 at
B, from link 2; link 2 gets −R_B). With p = B − A, q = B − C, each link's known wrench (F₁, M₁)
and (F₂, M₂), M_iB = M_i − B × F_i its moment about B:
    link 1 about B:   M₁B + (A − B) × R_A = 0     →  p × R_A = M₁B
    link 2 about B:   M₂B + (C − B) × R_C = 0     →  q × R_C = M₂B
    the pair, ΣF:     F₁ + F₂ + R_A + R_C = 0
Eliminating R_C = −(F₁ + F₂) − R_A:
    p × R_A = s₁ = M₁B,   q × R_A = s₂ = −M₂B − q × (F₁ + F₂),
a 2×2 linear system with determinant p × q (the kinematics' own, solver.groups.rrr):
    R_A = (s₁·q − s₂·p) / (p × q),   R_C = −(F₁ + F₂) − R_A,   R_B = −F₁ − R_A.
Singular where p × q = 0 (the links collinear, a toggle): the reactions grow without bound;
the samples are flagged by the group's conditioning |p × q|/(l₁l₂) (k.singular), and NaN there.
"""

from __future__ import annotations

from dataclasses import dataclass

from .frames import divide, moment_of
from .state import ForcePass

__all__ = ["RRRForces"]


@dataclass(frozen=True)
class RRRForces:
    links: tuple[str, str]  # link 1 (A–B), link 2 (C–B)
    ends: tuple[str, str]  # A, C
    point: str  # B
    owners: tuple[str, str]  # the bodies at A and at C
    pins: tuple[int, int, int]  # (A, 1, owner A), (C, 2, owner C), (B, 1, 2)

    def solve(self, s: ForcePass) -> None:
        a, c, b = s.point(self.ends[0]), s.point(self.ends[1]), s.point(self.point)
        p, q = b - a, b - c
        f1, m1 = s.about(self.links[0], b)
        f2, m2 = s.about(self.links[1], b)
        total = f1 + f2
        s2 = -m2 - moment_of(q, total)
        inv = divide(1.0, moment_of(p, q))  # real coefficients first: no complex-by-real division
        r_a = q * (m1 * inv)
        r_a -= p * (s2 * inv)
        r_c = -total - r_a
        pa, pc, pb = self.pins
        s.pins[pa], s.pins[pc], s.pins[pb] = r_a, r_c, -f1 - r_a
        s.add(self.owners[0], a, -r_a)
        s.add(self.owners[1], c, -r_c)
