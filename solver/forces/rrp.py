"""Route 2 for the RRP dyad (rod A–B, slider block at B on a fixed guide of unit direction e).

Unknowns (six, three equations per body): R_A (on the rod at A, from the owner of A), X (on the
block at B, from the rod; the rod gets −X), the guide's normal force N·n (n = j·e) and couple C
on the block (the ground gets the opposite). With p = B − A, the rod's known wrench (F_r, M_rA)
and the block's (F_k, M_kB), each kept about its reference point (solver.forces.state):
    block about B:     M_kB + C = 0                     →  C = −M_kB
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
from typing import Any

from .frames import along, divide
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

    def refs(self) -> dict[str, str]:
        """The rod's wrench is kept about A, the block's about its pin B."""
        return {self.rod: self.end, self.block: self.point}

    def solve(self, s: ForcePass) -> None:
        e = self.direction
        n = 1j * e
        a = self.end
        p = s.arm(self.point, a)
        f_k = s.force(self.block)
        minus_inv = divide(-1.0, along(e, p))  # real coefficients first: no complex-by-real division
        parts = []
        if self.block in s.forces:  # s₁ = −e·F_k
            parts.append(p * (along(e, f_k) * minus_inv))
        if self.rod in s.moments:  # s₂ = M_rA
            parts.append(-n * (s.moment(self.rod) * minus_inv))
        x: Any = parts[0] if parts else 0j
        if len(parts) == 2:
            x += parts[1]  # in place on the fresh product
        normal = along(n, f_k + x) * -n
        r_a = x - s.force(self.rod) if self.rod in s.forces else x
        pa, pb = self.pins
        s.pins[pa], s.pins[pb] = r_a, s.xp.negative(x)
        s.slides[self.slide] = (normal, s.moment(self.block, negate=True))
        s.add(self.owner, r_a, a, subtract=True)
