"""Route 2 for the slotted link (seed 000's kulisa, RPR): link pivoted at A, block at the eyelet B.

The block is pinned at B to the body that carries B (the drum in seed 000) and slides along the
link. Unknowns (six): R_A (on the link at A, from the owner of A), R_B (on the block at B, from
the owner of B), the link's normal force N·n and couple C on the block (the link gets the
opposite), n = j·u, u = r/ρ the link's direction, r = B − A, ρ = |r|. With the link's known
wrench (F_l, M_l) and the block's (F_k, M_k):
    block about B:   M_k − B × F_k + C = 0                  →  C = −(M_k − B × F_k)
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

    def solve(self, s: ForcePass) -> None:
        a, b = s.point(self.pivot), s.point(self.through)
        r = b - a
        f_l, m_la = s.about(self.link, a)
        f_k, m_kb = s.about(self.block, b)
        couple = -m_kb
        normal = (1j * r) * divide(m_la - couple, abs2(r))
        r_b = -f_k - normal
        r_a = normal - f_l
        pa, pb = self.pins
        s.pins[pa], s.pins[pb] = r_a, r_b
        s.slides[self.slide] = (normal, couple)
        s.add(self.owners[0], a, -r_a)
        s.add(self.owners[1], b, -r_b)
