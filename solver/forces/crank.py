"""Route 2 for the input crank (body c: pivot O on the ground, input effort Q about +z).

Equilibrium of the crank with its known wrench (F, M_O about O: the crank's wrench is kept
about its pivot, solver.forces.state), the ground's pin force R_O and the actuator's torque Q
(the opposite torque acts on the ground):
    ΣF:        F + R_O = 0                →  R_O = −F
    ΣM about O: M_O + Q = 0               →  Q = −M_O
Linear system: none (explicit). Singular positions: none of its own; Q inherits the dyads'
(the reactions they hand back grow without bound at their toggles).
Several inputs (five_bar): each crank closes its own balance, in the same reverse pass.
A crank in a model's convention (θ = θ₀ + σq) reports its effort in q: Q = σ·(−M_O). A coupled
crank (q = c₀ + c₁·p) is solved before the input p it follows (it comes later in the plan), and
by virtual work the input's effort gains c₁ times its effort: Q_p = σ_p·(−M_O,p) + Σ c₁·Q_q.
"""

from __future__ import annotations

from dataclasses import dataclass

from .state import ForcePass

__all__ = ["CrankForces"]


@dataclass(frozen=True)
class CrankForces:
    link: str
    center: str
    joint: str
    pin_center: int  # index of the pin (O, crank, ground)
    sign: float = 1.0  # σ: the joint's direction in the plane
    coupled: tuple[tuple[str, float], ...] = ()  # (joint q, ratio c₁) of the cranks following this one

    def refs(self) -> dict[str, str]:
        """The point the crank's wrench is kept about: its pivot O."""
        return {self.link: self.center}

    def solve(self, s: ForcePass) -> None:
        s.pins[self.pin_center] = s.force(self.link, negate=True)
        effort = s.moment(self.link, negate=True)
        if self.sign != 1.0:
            effort = -effort
        for joint, ratio in self.coupled:
            effort = effort + s.efforts[joint] * ratio
        s.efforts[self.joint] = effort
