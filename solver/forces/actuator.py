"""Route 2 for an actuator (solver.groups.actuator): the pushed link 2 (pivot O, eye C) and the
cylinder A–C, a massless two-force member whose force f along e = (C − A)/s is the input's
effort (N, extending positive: the cylinder pushes C by f·e and A by −f·e).

Unknowns: f and R_O (on the pushed link at O, from the owner of O). With p = C − A, q = C − O
and the pushed link's known wrench (F₂, M₂O) kept about O (solver.forces.state):
    link 2 about O:   M₂O + q × (f·p/s) = 0        →  f = M₂O·s / (p × q)
    link 2, ΣF:       F₂ + f·p/s + R_O = 0          →  R_O = −F₂ − f·p/s
    cylinder:         the pin at A pushes it by f·p/s, the pin at C by −f·p/s (no load of its own)
The determinant p × q is the kinematics' own (solver.groups.rrr.circle_point): singular where the
cylinder is aligned with the pushed link; the samples are flagged by the group's conditioning
|p × q|/(s·l) and the efforts and reactions are NaN there (solver.forces.model).
Check: the effort equals the virtual-power effort (solver.forces.virtual) and, for the same
mechanism driven by a crank about O, f = Q·dθ/ds (tests/forces/test_actuator_forces.py).
"""

from __future__ import annotations

from dataclasses import dataclass

from .frames import divide
from .state import ForcePass

__all__ = ["ActuatorForces"]


@dataclass(frozen=True)
class ActuatorForces:
    link: str  # the pushed link (O, C)
    cylinder: str  # the cylinder (A, C)
    base: str  # A
    pivot: str  # O
    point: str  # C
    joint: str  # the input joint (the stroke)
    owners: tuple[str, str]  # the bodies at A and at O
    pins: tuple[int, int, int]  # (O, link, owner O), (A, cylinder, owner A), (C, cylinder, link)

    def refs(self) -> dict[str, str]:
        """The pushed link's wrench is kept about its pivot O."""
        return {self.link: self.pivot}

    def solve(self, s: ForcePass) -> None:
        a, o, c = self.base, self.pivot, self.point
        p = s.arm(c, a)
        f2, m2 = s.force(self.link), s.moment(self.link)
        neg, det = s.cross(c, a, s.arm(c, o))  # p × q
        stroke = s.values[self.joint].value
        f = m2 * divide(-stroke if neg else stroke, det)  # the effort, N
        push = p * divide(f, stroke)  # f·e, on C (and on the cylinder at A)
        r_o = s.xp.negative(f2 + push)
        po, pa, pc = self.pins
        s.pins[po], s.pins[pa], s.pins[pc] = r_o, push, s.xp.negative(push)
        s.efforts[self.joint] = f
        s.add(self.owners[0], push, a, subtract=True)  # the cylinder pushes A's owner by −f·e
        s.add(self.owners[1], r_o, o, subtract=True)
