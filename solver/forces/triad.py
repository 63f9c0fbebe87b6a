"""Route 2 for the triad (class-3 Assur group, solver.groups.triad): binary links i = 1, 2, 3
(A–D, B–E, C–F: outer pin Xᵢ ∈ {A, B, C} on an earlier body, inner pin Yᵢ ∈ {D, E, F} on the
ternary link T = D–E–F).

Unknowns: the reactions Rᵢ on link i at Xᵢ (from the owner of Xᵢ), six scalars; the inner pins
follow. Each binary link's known wrench (Fᵢ, Mᵢ about Yᵢ) and the ternary link's (F_T, M_T about
D) are kept about those points (solver.forces.state). With pᵢ = Yᵢ − Xᵢ:
    link i about Yᵢ:   Mᵢ + (Xᵢ − Yᵢ) × Rᵢ = 0   →  pᵢ × Rᵢ = Mᵢ
so Rᵢ = λᵢ·pᵢ + μᵢ·j·pᵢ with μᵢ = Mᵢ/|pᵢ|² (p × jp = |p|²) and λᵢ (the force along the link)
unknown. The ternary link gets Fᵢ + Rᵢ = Kᵢ + λᵢ·pᵢ at Yᵢ (Kᵢ = Fᵢ + μᵢ·j·pᵢ, known):
    T, ΣF:         λ₁p₁ + λ₂p₂ + λ₃p₃ = S = −F_T − ΣKᵢ
    T about D:     g·λ₂ + h·λ₃ = m = −M_T − (E − D) × K₂ − (F − D) × K₃
with g = (E − D) × p₂ and h = (F − D) × p₃ — the kinematics' own g and h (solver.groups.triad).
The 6×6 statics thus reduce to this 3×3 system. Crossing the first row with p₁ leaves
    (p₁ × p₂)·λ₂ + (p₁ × p₃)·λ₃ = p₁ × S,   g·λ₂ + h·λ₃ = m,
whose determinant h·(p₁ × p₂) − g·(p₁ × p₃) is the triad's kinematic determinant p × m (the
Jacobian of the loop): λ₂, λ₃ by Cramer, then λ₁ = p₁·(S − λ₂p₂ − λ₃p₃)/|p₁|².
Pins: R(Xᵢ, on=i) = Rᵢ; R(Yᵢ, on=i) = −Fᵢ − Rᵢ (from the ternary link; T gets the opposite).
Singular where the determinant is 0 (the three binary links' lines and the ternary link's
instant centre meet: a dead point, two modes merging): the reactions grow without bound there,
flagged by the group's conditioning (k.singular) and NaN, as the dyads'.
"""

from __future__ import annotations

from dataclasses import dataclass

from .._backend import abs2, cross, dot
from .frames import divide
from .state import ForcePass

__all__ = ["TriadForces"]


@dataclass(frozen=True)
class TriadForces:
    links: tuple[str, str, str]  # the binary links A–D, B–E, C–F
    ternary: str  # the ternary link D–E–F
    ends: tuple[str, str, str]  # A, B, C
    points: tuple[str, str, str]  # D, E, F
    owners: tuple[str, str, str]  # the bodies at A, B and C
    pins: tuple[int, int, int, int, int, int]  # (A, 1, owner A), (B, 2, ·), (C, 3, ·), (D, 1, T), (E, 2, T), (F, 3, T)

    def refs(self) -> dict[str, str]:
        """Each binary link's wrench is kept about its pin on the ternary link, the ternary's about D."""
        out = dict(zip(self.links, self.points))
        out[self.ternary] = self.points[0]
        return out

    def solve(self, s: ForcePass) -> None:
        d = self.points[0]
        p = [s.arm(y, x) for x, y in zip(self.ends, self.points)]
        f = [s.force(link) for link in self.links]
        k = [fi + 1j * pi * divide(s.moment(link), abs2(pi)) for fi, pi, link in zip(f, p, self.links)]
        total = s.force(self.ternary) + k[0] + k[1] + k[2]
        rhs_s = -total
        e_d, f_d = s.arm(self.points[1], d), s.arm(self.points[2], d)
        rhs_m = -s.moment(self.ternary) - cross(e_d, k[1]) - cross(f_d, k[2])
        g, h = cross(e_d, p[1]), cross(f_d, p[2])
        c12, c13, c1s = cross(p[0], p[1]), cross(p[0], p[2]), cross(p[0], rhs_s)
        inv = divide(1.0, h * c12 - g * c13)
        lam2 = (h * c1s - c13 * rhs_m) * inv
        lam3 = (c12 * rhs_m - g * c1s) * inv
        lam1 = dot(p[0], rhs_s - lam2 * p[1] - lam3 * p[2]) * divide(1.0, abs2(p[0]))
        for i, lam in enumerate((lam1, lam2, lam3)):
            r = lam * p[i] + (k[i] - f[i])  # λᵢ·pᵢ + μᵢ·j·pᵢ
            s.pins[self.pins[i]] = r
            s.pins[self.pins[3 + i]] = -(f[i] + r)
            s.add(self.owners[i], r, self.ends[i], subtract=True)
