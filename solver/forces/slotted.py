"""Route 2 for the slotted link (seed 000's kulisa, RPR): link pivoted at A, block at the eyelet B.

The block is pinned at B to the body that carries B (the drum in seed 000) and slides along the
link. Unknowns (six): R_A (on the link at A, from the owner of A), R_B (on the block at B, from
the owner of B), the link's normal force N·n and couple C on the block (the link gets the
opposite), n = j·u, u = r/ρ the link's direction, r = B − A, ρ = |r|. With the link's known
wrench (F_l, M_lA) about A and the block's (F_k, M_kB) about B (solver.forces.state):
    block about B:   M_kB + C = 0                           →  C = −M_kB
    link about A:    M_lA + (B − A) × (−N·n) − C = 0,  r × n = ρ
                                                           →  N = (M_lA − C)/ρ,  N·n = j·r·(M_lA − C)/ρ²
    block, ΣF:       R_B = −F_k − N·n
    link, ΣF:        R_A = N·n − F_l
Linear system: explicit (the pair's force has no component along the slot: no friction).
Singular where ρ → 0 (the eyelet on the pivot): flagged by the group's conditioning ρ/ρ_max,
NaN there.
"""

from __future__ import annotations

from dataclasses import dataclass

from .._backend import abs2
from .frames import divide
from .state import ForcePass

__all__ = ["SlottedForces"]


@dataclass(frozen=True)
class SlottedForces:
    link: str
    block: str
    pivot: str  # A
    through: str  # B
    owners: tuple[str, str]  # the bodies at A and at B
    pins: tuple[int, int]  # (A, link, owner A), (B, block, owner B)
    slide: int

    def refs(self) -> dict[str, str]:
        """The link's wrench is kept about its pivot A, the block's about its eyelet B."""
        return {self.link: self.pivot, self.block: self.through}

    def solve(self, s: ForcePass) -> None:
        a, b = self.pivot, self.through
        r = s.arm(b, a)
        couple = s.moment(self.block, negate=True)
        normal = (1j * r) * divide(s.moment(self.link) - couple, abs2(r))
        minus_r_b = s.force(self.block) + normal  # −R_B
        r_a = normal - s.force(self.link) if self.link in s.forces else normal
        pa, pb = self.pins
        s.pins[pa], s.pins[pb] = r_a, s.xp.negative(minus_r_b)
        s.slides[self.slide] = (normal, couple)
        s.add(self.owners[0], r_a, a, subtract=True)
        s.add(self.owners[1], minus_r_b, b)
