"""Route 2 for the RRP dyad (rod A–B, slider block at B on a fixed guide of unit direction e).

Unknowns (six, three equations per body): R_A (on the rod at A, from the owner of A), X (on the
block at B, from the rod; the rod gets −X), the guide's normal force N·n (n = j·e) and couple C
on the block (the ground gets the opposite). With p = B − A, the rod's known wrench (F_r, M_r)
and the block's (F_k, M_k):
    block about B:     M_k − B × F_k + C = 0            →  C = −(M_k − B × F_k)
    block along e:     e·(F_k + X) = 0                  →  X·e = s₁ = −e·F_k
    rod about A:       M_rA + (B − A) × (−X) = 0        →  X·(j·p) = s₂ = M_rA   (p × X = X·jp)
    block across e:    N = −n·(F_k + X)
    rod, ΣF:           R_A = X − F_r
The 2×2 system in X has determinant e × (j·p) = e·p, the kinematics' own (solver.groups.rrp):
    X = (s₁·p + j·s₂·e) / (e·p).
Singular where e·p = 0 (the rod perpendicular to the guide): flagged by the conditioning
|e·p|/l, NaN there. The pair's whole reaction is (N·n, C): its line of action lies at the
offset C/N from B along e.
"""

from __future__ import annotations

from dataclasses import dataclass

from .._backend import dot
from .frames import divide
from .state import ForcePass

__all__ = ["RRPForces"]


@dataclass(frozen=True)
class RRPForces:
    rod: str
    block: str
    end: str  # A
    point: str  # B
    owner: str  # the body at A
    direction: complex  # e
    pins: tuple[int, int]  # (A, rod, owner A), (B, rod, block)
    slide: int

    def solve(self, s: ForcePass) -> None:
        e = self.direction
        a, b = s.point(self.end), s.point(self.point)
        p = b - a
        f_r, m_ra = s.about(self.rod, a)
        f_k, m_kb = s.about(self.block, b)
        inv = divide(1.0, dot(e, p))  # real coefficients first: no complex-by-real division
        x = p * (dot(e, f_k) * -inv)
        x += (1j * e) * (m_ra * inv)
        n = 1j * e
        normal = n * -dot(n, f_k + x)
        r_a = x - f_r
        pa, pb = self.pins
        s.pins[pa], s.pins[pb] = r_a, -x
        s.slides[self.slide] = (normal, -m_kb)
        s.add(self.owner, a, -r_a)
