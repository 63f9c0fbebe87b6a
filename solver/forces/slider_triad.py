"""Route 2 for the slider triad (solver.groups.slider_triad: the triad with one prismatic pair):
a slider block K at D on the fixed guide of unit direction e (normal n = j·e), the ternary link
T = D–E–F, binary links 2 (B–E) and 3 (C–F) from the known points B, C.

Unknowns (eight, three equations per body... reduced as the RRR triad's, solver.forces.triad):
the reactions R₂, R₃ on the binary links at B, C (from their owners), the force Y on T at D
from the block (the block gets −Y), the guide's normal force N·n and couple C on the block.
Each binary link's known wrench (Fᵢ, Mᵢ about its pin on T) gives, with pᵢ = (E − B, F − C),
    Rᵢ = λᵢ·pᵢ + μᵢ·j·pᵢ,  μᵢ = Mᵢ/|pᵢ|²,  and T gets Kᵢ + λᵢ·pᵢ there (Kᵢ = Fᵢ + μᵢ·j·pᵢ);
the block's wrench (F_K, M_K about D) and T's (F_T, M_T about D):
    block along e:   e·(F_K − Y) = 0                →  e·Y = e·F_K
    block about D:   M_K + C = 0                    →  C = −M_K
    T, ΣF:           Y + λ₂p₂ + λ₃p₃ = S = −F_T − K₂ − K₃
    T about D:       g·λ₂ + h·λ₃ = m = −M_T − (E − D) × K₂ − (F − D) × K₃
with g = (E − D) × p₂, h = (F − D) × p₃. Dotting ΣF with e leaves the 2×2 system
    (e·p₂)·λ₂ + (e·p₃)·λ₃ = e·S − e·F_K,    g·λ₂ + h·λ₃ = m,
whose determinant (e·p₂)·h − (e·p₃)·g is the kinematics' own (solver.groups.slider_triad):
λ₂, λ₃ by Cramer, then Y = S − λ₂p₂ − λ₃p₃ and the normal force N·n = (n·(Y − F_K))·n.
Pins: R(B, on 2) = R₂, R(C, on 3) = R₃; R(E, on 2) = −F₂ − R₂, R(F, on 3) = −F₃ − R₃ (from T);
R(D, on the block) = −Y (from T). Singular where the determinant is 0 (a dead point): flagged
by the group's conditioning, NaN there.

A guide on a moving link (the group's ``carrier`` P, Q): the same equations with that instant's
e = e₀·(Q − P)/|Q − P|; the carrier body gets the opposite of the guide's normal force (at D) and
couple.

The swinging block (the group's ``block_at`` A): the block K is pinned at A to A's owner and
slides along the line of T through D with the world direction e = e_t·(E − D)/|E − D|, n = j·e.
Unknowns λ₂, λ₃, the normal force N·n on K from T (T gets −N·n at A) and the couple C on K (T
gets −C); K's pin force R_A from A's owner. With K's wrench (F_K, M_K about A) and T's (F_T,
M_T about D), S and m as above, a = (A − D) × n:
    K about A:       M_K + C = 0                    →  C = −M_K
    T, ΣF:           λ₂p₂ + λ₃p₃ − N·n = S          →  along e: (e·p₂)·λ₂ + (e·p₃)·λ₃ = e·S,
                                                        along n: N = n·(λ₂p₂ + λ₃p₃ − S)
    T about D:       g·λ₂ + h·λ₃ − a·N = m + C      →  (g − a·(n·p₂))·λ₂ + (h − a·(n·p₃))·λ₃ = m + C − a·(n·S)
    K, ΣF:           R_A = −F_K − N·n.
The 2×2 by Cramer (its determinant vanishes with the kinematics' at a dead point).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .._backend import abs2, cross, dot
from .frames import along, divide
from .state import ForcePass

__all__ = ["SliderTriadForces"]


@dataclass(frozen=True)
class SliderTriadForces:
    links: tuple[str, str]  # the binary links B–E, C–F
    ternary: str  # D–E–F
    block: str  # the slider block at D
    ends: tuple[str, str]  # B, C
    points: tuple[str, str, str]  # D, E, F
    owners: tuple[str, str]  # the bodies at B and C
    direction: complex  # e (in the carrier's frame with ``carrier``, e_t in T's with ``block_at``)
    #: (B, 2, owner B), (C, 3, ·), (E, 2, T), (F, 3, T), and (D, block, T) — (A, block, owner A) for
    #: the swinging block
    pins: tuple[int, int, int, int, int]
    slide: int
    carrier: tuple[str, str] | None = None  # P, Q: the guide on the moving link through them
    carrier_body: str | None = None  # the body that carries the guide (gets the guide's reaction)
    block_at: str | None = None  # A: the swinging block's pin
    block_owner: str | None = None  # the body at A

    def refs(self) -> dict[str, str]:
        """Each binary link's wrench about its pin on T; T's about D, the block's about its pin
        (D on a guide, A for the swinging block)."""
        out = dict(zip(self.links, self.points[1:]))
        out[self.ternary] = self.points[0]
        out[self.block] = self.points[0] if self.block_at is None else self.block_at
        return out

    def _unit(self, s: ForcePass, tip: str, base: str) -> Any:
        r = s.arm(tip, base)
        return self.direction * r / s.xp.sqrt(abs2(r))

    def solve(self, s: ForcePass) -> None:
        if self.block_at is not None:
            self._solve_swinging(s)
            return
        e: Any = self.direction if self.carrier is None else self._unit(s, self.carrier[1], self.carrier[0])
        n = 1j * e
        d = self.points[0]
        p = [s.arm(y, x) for x, y in zip(self.ends, self.points[1:])]
        f = [s.force(link) for link in self.links]
        k = [fi + 1j * pi * divide(s.moment(link), abs2(pi)) for fi, pi, link in zip(f, p, self.links)]
        f_k = s.force(self.block)
        rhs_s = -(s.force(self.ternary) + k[0] + k[1])
        e_d, f_d = s.arm(self.points[1], d), s.arm(self.points[2], d)
        rhs_m = -s.moment(self.ternary) - cross(e_d, k[0]) - cross(f_d, k[1])
        g, h = cross(e_d, p[0]), cross(f_d, p[1])
        a2, a3 = (along(e, p[0]), along(e, p[1])) if self.carrier is None else (dot(e, p[0]), dot(e, p[1]))
        r1 = along(e, rhs_s) - along(e, f_k) if self.carrier is None else dot(e, rhs_s) - dot(e, f_k)
        inv = divide(1.0, a2 * h - a3 * g)
        lam2 = (r1 * h - a3 * rhs_m) * inv
        lam3 = (a2 * rhs_m - g * r1) * inv
        y = rhs_s - lam2 * p[0] - lam3 * p[1]
        for i, lam in enumerate((lam2, lam3)):
            r = lam * p[i] + (k[i] - f[i])  # λᵢ·pᵢ + μᵢ·j·pᵢ
            s.pins[self.pins[i]] = r
            s.pins[self.pins[2 + i]] = -(f[i] + r)
            s.add(self.owners[i], r, self.ends[i], subtract=True)
        s.pins[self.pins[4]] = -y
        normal = (along(n, y - f_k) if self.carrier is None else dot(n, y - f_k)) * n
        s.slides[self.slide] = (normal, s.moment(self.block, negate=True))
        if self.carrier_body is not None:  # the carrier gets −N·n at D and −C = M_K
            s.add(self.carrier_body, normal, d, subtract=True)
            s.couple(self.carrier_body, s.moment(self.block))

    def _solve_swinging(self, s: ForcePass) -> None:
        """The swinging block (module docstring)."""
        a_pt = self.block_at
        assert a_pt is not None and self.block_owner is not None
        d = self.points[0]
        e = self._unit(s, self.points[1], d)
        n = 1j * e
        p = [s.arm(y, x) for x, y in zip(self.ends, self.points[1:])]
        f = [s.force(link) for link in self.links]
        k = [fi + 1j * pi * divide(s.moment(link), abs2(pi)) for fi, pi, link in zip(f, p, self.links)]
        f_k = s.force(self.block)
        couple = s.moment(self.block, negate=True)  # C = −M_K
        rhs_s = -(s.force(self.ternary) + k[0] + k[1])
        e_d, f_d = s.arm(self.points[1], d), s.arm(self.points[2], d)
        rhs_m = -s.moment(self.ternary) - cross(e_d, k[0]) - cross(f_d, k[1])
        arm_n = cross(s.arm(a_pt, d), n)
        g = cross(e_d, p[0]) - arm_n * dot(n, p[0])
        h = cross(f_d, p[1]) - arm_n * dot(n, p[1])
        a2, a3 = dot(e, p[0]), dot(e, p[1])
        r1 = dot(e, rhs_s)
        r2 = rhs_m + couple - arm_n * dot(n, rhs_s)
        inv = divide(1.0, a2 * h - a3 * g)
        lam2 = (r1 * h - a3 * r2) * inv
        lam3 = (a2 * r2 - g * r1) * inv
        normal = dot(n, lam2 * p[0] + lam3 * p[1] - rhs_s) * n
        for i, lam in enumerate((lam2, lam3)):
            r = lam * p[i] + (k[i] - f[i])
            s.pins[self.pins[i]] = r
            s.pins[self.pins[2 + i]] = -(f[i] + r)
            s.add(self.owners[i], r, self.ends[i], subtract=True)
        r_a = -(f_k + normal)
        s.pins[self.pins[4]] = r_a
        s.slides[self.slide] = (normal, couple)
        s.add(self.block_owner, r_a, a_pt, subtract=True)
