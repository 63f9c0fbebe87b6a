"""Coulomb friction in forward dynamics, one input (docs/dynamics.md#friction).

Loop equation: none of its own — the groups' closed form gives the positions and the analogs; the
kinetostatics (solver.forces.friction) gives every output affine in the input's acceleration ε
and in the friction magnitudes x:

    Q   = h + M·ε + Σⱼ xⱼ·dⱼ·uⱼ + F·sgn(q̇)        (the effort: route 2, friction included)
    R_k = R⁰_k + ε·A_k + Σⱼ xⱼ·dⱼ·B_jk           (the reaction carrying element k's friction)
    x_k = c_k·|R_k|                               (c = μ·r at a pin, μ at a slide)

with h, R⁰ the frictionless pass at (q, q̇, ε = 0), M, A the pass of the bodies' inertia alone at
(q, 0, 1), uⱼ, B_jk the pass of element j's unit load (a unit couple, a unit push along a guide),
dⱼ = −sign of element j's relative velocity and F a cylinder seal's force on a stroke input.

Linear system. Forward dynamics fixes the effort, Q = Q_drive, and leaves ε free: eliminating
ε = (Q_drive − h − F·sgn − Σ xⱼdⱼuⱼ)/M gives the same problem as the kinetostatics,

    x_k = c_k·|R̃⁰_k + Σⱼ xⱼ·dⱼ·B̃_jk|,   R̃⁰_k = R⁰_k + A_k·(Q_drive − h − F·sgn)/M,
                                         B̃_jk = B_jk − A_k·uⱼ/M,

solved by the kinetostatics' own fixed point/Newton (solver.forces.friction.solve_magnitudes) on
the responses of the free input. Derivatives: the analogs dv/dφ, d²v/dφ² of each element's
relative velocity (FrictionModel.element_kinematics); nothing is differentiated numerically.

Branch rule (the friction's direction). Where an element's relative velocity v = v′·q̇ ≠ 0,
d = −sign v. Where it is 0 the sign of its relative acceleration v″·q̇² + v′·ε decides: at a
crossing of v′ = 0 with q̇ ≠ 0 that is sign v″ (the run restarts there, solver.dynamics.
_friction_run, with that sign for the step's first stage); at rest (q̇ = 0) it is sign(v′·s), s
the direction the input slips in. **Stick–slip**: at rest the holding efforts are the interval
[Q₋, Q₊] (each edge the kinetostatic effort at ε = 0 with the friction against a start toward −q
and +q, as solver.forces.friction.breakaway); the input sticks while Q_drive stays inside it and
slips toward +q where Q_drive > Q₊, toward −q where Q_drive < Q₋.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._backend import SCALAR
from ..errors import DynamicsError
from ..forces.friction import solve_magnitudes
from ..groups import Context

__all__ = ["FrictionDynamics", "FrictionState"]


@dataclass(frozen=True)
class FrictionState:
    """The solved state: ε (the input's acceleration), the friction's dissipated power (W), the
    generalised force of the loads other than gravity and springs, the groups' worst conditioning."""

    epsilon: float
    loss: float
    other: float
    conditioning: float


def _sign(v: float) -> float:
    return 1.0 if v > 0.0 else -1.0 if v < 0.0 else 0.0


class FrictionDynamics:
    """The friction-coupled equation of motion of a one-input scene with ``friction:``.

    ``scene``: the scene's force layer with its friction (its plan reads every point the elements
    need); ``inertia``, ``other``: the reduced model's frictionless variants (the bodies alone;
    the loads other than gravity and springs on massless bodies, or None)."""

    def __init__(self, scene: Any, inertia: Any, other: Any) -> None:
        forces = scene.forces
        self.scene, self.forces, self.friction = scene, forces, forces.friction
        self.inertia = inertia.forces
        self.other = None if other is None else other.forces
        self.name = scene.name
        self.input = scene.inputs[0]
        index = forces.base_index
        self.elements = self.friction.elements
        self.carriers = [index[("pin" if e.kind == "pin" else "slide"), e.index] for e in self.elements]
        self.c = np.array([e.coefficient for e in self.elements], float)
        #: the seal force (N) of a cylinder on the input's own stroke (a seal elsewhere moves no effort)
        self.seal = sum(s.force for s in self.friction.spec.seals if s.joint == self.input)
        self._memo: tuple[float, Any] | None = None  # (q, the passes at q)

    # -- one state -------------------------------------------------------------------------------
    def _kinematics(self, q: float) -> Any:
        """The plan run at ``q`` and the passes that do not depend on q̇: the inertia's, each
        element's unit load's, the elements' analogs, the conditioning (kept for the last q)."""
        memo = self._memo
        if memo is not None and memo[0] == q:
            return memo[1]
        ctx = Context(phi=q, xp=SCALAR, mask=False, scene=self.name, owner=self.scene)
        self.scene.plan.run(ctx)
        values = ctx.values
        cond = min(ctx.conditioning.values()) if ctx.conditioning else 1.0
        inertia = self.inertia
        inert = inertia.respond(values, SCALAR, lambda s: inertia._apply_loads(s, 0.0, 1.0))
        kin = self.friction.element_kinematics(values, SCALAR)
        units = [self.forces.respond(values, SCALAR, load) for _, _, _, load in kin]
        rates = [(float(np.ravel(v1)[0]), float(np.ravel(v2)[0])) for v1, v2, _, _ in kin]
        out = (values, inert, units, rates, cond)
        self._memo = (q, out)
        return out

    def _passes(self, q: float, w: float) -> Any:
        """:meth:`_kinematics` and the frictionless pass at (q, q̇, ε = 0), with the other loads'
        generalised force."""
        values, inert, units, rates, cond = self._kinematics(q)
        forces = self.forces
        base = forces.respond(values, SCALAR, lambda s: forces._apply_loads(s, w, 0.0))
        other = 0.0
        if self.other is not None:
            o = self.other
            other = -float(o.respond(values, SCALAR, lambda s: o._apply_loads(s, w, 0.0))[0])
        return base, inert, units, rates, other, cond

    def rates(self, q: float) -> list[float]:
        """Each element's relative-velocity analog dv/dφ at ``q`` (its zeros: where it reverses)."""
        return [v1 for v1, _ in self._kinematics(q)[3]]

    def _directions(self, rates: list[tuple[float, float]], w: float, slip: float,
                    override: dict[int, float] | None) -> list[float]:
        out = []
        for j, (v1, v2) in enumerate(rates):
            d = -_sign(v1 * w)
            if d == 0.0:
                if override is not None and j in override:
                    d = override[j]
                elif w != 0.0:
                    d = -_sign(v2)  # a crossing of v′ = 0: the relative acceleration is v″·q̇²
                else:
                    d = -_sign(v1 * slip)  # at rest: the relative acceleration is v′·ε, sign ε = s
            out.append(d)
        return out

    def _magnitudes(self, r0: list[complex], b: list[list[complex]], dirs: list[float], where: str) -> np.ndarray:
        m = len(self.carriers)
        base = [np.array([r0[k]], complex) for k in range(m)]
        responses = [[np.array([b[j][k]], complex) for k in range(m)] for j in range(m)]
        x, locked = solve_magnitudes(base, responses, [np.array([d]) for d in dirs], list(range(m)), self.c, 1)
        if locked[0]:
            raise DynamicsError(f"the friction equations have no solution at {where}: the friction locks the "
                                "mechanism against its own motion (no acceleration satisfies them)", scene=self.name)
        return x[0]

    def solve(self, q: float, w: float, drive: float, *, slip: float = 0.0,
              override: dict[int, float] | None = None) -> FrictionState:
        """ε and the dissipated power at (q, q̇) under the input's effort ``drive``; ``slip``: the
        direction the input starts in where q̇ = 0; ``override``: element → d where its relative
        velocity is zero (a restart at its reversal)."""
        base, inert, units, rates, other, cond = self._passes(q, w)
        mass, h = float(inert[0]), float(base[0])
        s = _sign(w) or slip
        rest = (drive - h - self.seal * s) / mass
        dirs = self._directions(rates, w, slip, override)
        r0 = [complex(base[k]) + complex(inert[k]) * rest for k in self.carriers]
        b = [[complex(units[j][k]) - complex(inert[k]) * float(units[j][0]) / mass for k in self.carriers]
             for j in range(len(self.carriers))]
        x = self._magnitudes(r0, b, dirs, f"{self.input} = {q:.6g}")
        eps = rest - sum(x[j] * dirs[j] * float(units[j][0]) for j in range(len(dirs))) / mass
        loss = sum(x[j] * abs(rates[j][0] * w) for j in range(len(dirs))) + self.seal * abs(w)
        return FrictionState(eps, float(loss), other, cond)

    def holding(self, q: float) -> tuple[float, float]:
        """The breakaway interval (Q₋, Q₊) at rest at ``q``: the efforts of the input that hold the
        mechanism (the kinetostatic effort at q̇ = ε = 0 with the friction against a start toward −q
        and toward +q)."""
        base, _, units, rates, _, _ = self._passes(q, 0.0)
        h = float(base[0])
        edges = []
        for s in (-1.0, 1.0):
            dirs = self._directions(rates, 0.0, s, None)
            r0 = [complex(base[k]) for k in self.carriers]
            b = [[complex(units[j][k]) for k in self.carriers] for j in range(len(self.carriers))]
            try:
                x = self._magnitudes(r0, b, dirs, "rest")
            except DynamicsError:  # that start self-locks: every effort beyond holds it
                edges.append(s * math.inf)
                continue
            edges.append(h + sum(x[j] * dirs[j] * float(units[j][0]) for j in range(len(dirs))) + self.seal * s)
        return edges[0], edges[1]
