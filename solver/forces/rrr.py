"""Route 2 for the RRR dyad (seed 003's group; links 1 = A–B, 2 = C–B, middle pin B).

Unknowns: R_A (on link 1 at A, from the owner of A), R_C (on link 2 at C), R_B (on link 1 at
B, from link 2; link 2 gets −R_B). With p = B − A, q = B − C, and each link's known wrench
(F₁, M₁B) and (F₂, M₂B) kept about B (solver.forces.state):
    link 1 about B:   M₁B + (A − B) × R_A = 0     →  p × R_A = M₁B
    link 2 about B:   M₂B + (C − B) × R_C = 0     →  q × R_C = M₂B
    the pair, ΣF:     F₁ + F₂ + R_A + R_C = 0
Eliminating R_C = −(F₁ + F₂) − R_A:
    p × R_A = s₁ = M₁B,   q × R_A = s₂ = −M₂B − q × (F₁ + F₂),
a 2×2 linear system with determinant p × q (the kinematics' own, solver.groups.rrr):
    R_A = (s₁·q − s₂·p) / (p × q),   R_C = −(F₁ + F₂ + R_A),   R_B = −F₁ − R_A = R_C + F₂.
Singular where p × q = 0 (the links collinear, a toggle): the reactions grow without bound;
the samples are flagged by the group's conditioning |p × q|/(l₁l₂) (k.singular), and NaN there.
"""

from __future__ import annotations

from dataclasses import dataclass

from .frames import divide
from .state import ForcePass

__all__ = ["RRRForces"]


@dataclass(frozen=True)
class RRRForces:
    links: tuple[str, str]  # link 1 (A–B), link 2 (C–B)
    ends: tuple[str, str]  # A, C
    point: str  # B
    owners: tuple[str, str]  # the bodies at A and at C
    pins: tuple[int, int, int]  # (A, 1, owner A), (C, 2, owner C), (B, 1, 2)

    def refs(self) -> dict[str, str]:
        """Both links' wrenches are kept about the middle pin B."""
        return {self.links[0]: self.point, self.links[1]: self.point}

    def solve(self, s: ForcePass) -> None:
        (a, c), b = self.ends, self.point
        p, q = s.arm(b, a), s.arm(b, c)
        f1, m1 = s.force(self.links[0]), s.moment(self.links[0])
        f2, m2 = s.force(self.links[1]), s.moment(self.links[1])
        total = f1 + f2
        neg, qt = s.cross(b, c, total)  # q × (F₁ + F₂), as a term
        minus_s2 = m2 - qt if neg else m2 + qt  # −s₂
        neg, det = s.cross(b, a, q)  # p × q
        inv = divide(-1.0 if neg else 1.0, det)  # real coefficients first: no complex-by-real division
        r_a = q * (m1 * inv)
        r_a += p * (minus_s2 * inv)  # in place on the fresh product
        total += r_a  # in place on the fresh sum: F₁ + F₂ + R_A
        r_c = s.xp.negative(total)
        pa, pc, pb = self.pins
        s.pins[pa], s.pins[pc] = r_a, r_c
        s.pins[pb] = r_c + f2 if self.links[1] in s.forces else r_c  # −F₁ − R_A
        s.add(self.owners[0], r_a, a, subtract=True)
        s.add(self.owners[1], total, c)  # −R_C
