"""The spherical crank-slider of seed 001 (Kosiyuk & Kravchuk), in closed form.

A shaft turns by φ about the x axis' perpendicular (the paper's z₁ axis); its crank carries a
ring whose groove plane makes the angle α with the shaft axis; the ring drives a cage that
oscillates by ψ about the x axis (the half-shafts). All axes meet at the centre O; the rod
centre K lies on the sphere of radius R in the plane x = 0.

Loop equation (corrected, see the errata in shared/seeds/README.md)
    tan ψ = sin φ / tan α, i.e. ψ = atan2(sin φ, tan α), ψ ∈ (−(90° − α), 90° − α);
    K = O + R·(0, sin ψ, cos ψ) — the paper's eq. (5) with the denominator
    √(sin²φ + sin²α·cos²φ) in place of the misprinted √(sin²φ + cos²φ + sin²α).
Derivatives (exact), with T = tan α and S = T² + sin²φ:
    ψ'  = T·cos φ / S                                   (paper eq. 14)
    ψ'' = −T·sin φ·(S + 2cos²φ) / S²                    (the paper's eq. 12/15 put cos φ here)
    K'  = R·ψ'·(0, cos ψ, −sin ψ),  K'' = R·ψ''·(0, cos ψ, −sin ψ) − R·ψ'²·(0, sin ψ, cos ψ).
Linear system
    none: explicit.
Branch rule
    the rod nearer the viewer (the paper's "+" sign in eq. 5): K_z > 0.
Conditioning
    1 everywhere for 0 < α < 90° (α = 0 and α = 90° are rejected when the scene loads).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._fields import Entry, Units
from ..jet import Jet
from .base import Context, Group

__all__ = ["SphericalCrankSlider"]


@dataclass(frozen=True)
class SphericalCrankSlider(Group):
    kind = "spherical_crank_slider"
    drives = True
    spatial = True
    center: str
    point: str
    shaft: str  # the input joint, φ
    cage: str  # the output joint, ψ
    alpha: float  # rad
    radius: float

    def requires(self) -> tuple[str, ...]:
        return (self.center,)

    def provides(self) -> tuple[str, ...]:
        return (self.point, self.shaft, self.cage)

    def joints(self) -> tuple[str, ...]:
        return (self.shaft, self.cage)

    def input_joint(self) -> str:
        return self.shaft

    def links(self) -> tuple[tuple[str, ...], ...]:
        return ((self.center, self.point),)

    def solve(self, ctx: Context) -> None:
        xp, phi = ctx.xp, ctx.phi
        t = xp.tan(self.alpha)
        s, c = xp.sin(phi), xp.cos(phi)
        big_s = t * t + s * s
        psi = xp.atan2(s, t)
        psi1 = t * c / big_s
        psi2 = -t * s * (big_s + 2.0 * c * c) / (big_s * big_s)
        ctx.values[self.shaft] = Jet(phi, 1.0, 0.0)
        ctx.values[self.cage] = Jet(psi, psi1, psi2)
        sp, cp = xp.sin(psi), xp.cos(psi)
        r = self.radius
        o = ctx.values[self.center].value
        if not xp.vectorised:  # one φ: plain floats, no numpy per tick
            ox, oy, oz = (float(v) for v in o)
            ry, rz, t1, t2 = r * sp, r * cp, r * psi1, r * (psi1 * psi1)
            ctx.values[self.point] = Jet(
                (ox, oy + ry, oz + rz),
                (0.0, t1 * cp, -t1 * sp),
                (0.0, r * psi2 * cp - t2 * sp, -r * psi2 * sp - t2 * cp),
            )
            ctx.conditioning[self.name] = 1.0
            return
        zero = 0.0 * psi
        radial = np.stack([zero, sp, cp], axis=-1)  # (…, 3)
        tangent = np.stack([zero, cp, -sp], axis=-1)
        p1 = np.expand_dims(psi1, -1)
        p2 = np.expand_dims(psi2, -1)
        ctx.values[self.point] = Jet(o + r * radial, r * p1 * tangent, r * (p2 * tangent - p1 * p1 * radial))
        ctx.conditioning[self.name] = 1.0 + zero

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> SphericalCrankSlider:
        """``{type: spherical_crank_slider, name, center, point, shaft, cage, alpha, radius}``."""
        alpha = e.angle("alpha", units)
        if not 0.0 < alpha < math.pi / 2:
            raise e.error(
                f"alpha must lie strictly between 0° and 90°, got {math.degrees(alpha):g}°: at 0° the "
                "groove plane holds the shaft axis and the cage cannot be driven (tan α = 0), at 90° "
                "the ring is square to the shaft and the cage does not move",
                "alpha",
            )
        return cls(
            name=e.name("name"),
            center=e.name("center"),
            point=e.name("point"),
            shaft=e.name("shaft"),
            cage=e.name("cage"),
            alpha=alpha,
            radius=e.length("radius", units),
        )
