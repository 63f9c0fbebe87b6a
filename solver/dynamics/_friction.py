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

solved by the kinetostatics' own one-sample Newton (solver.forces.friction.solve_one; its vectorised
solve_magnitudes where that gives up) on
the responses of the free input. Derivatives: the analogs dv/dφ, d²v/dφ² of each element's
relative velocity (FrictionModel.element_kinematics); nothing is differentiated numerically.

Branch rule (the friction's direction). Where an element's relative velocity v = v′·q̇ ≠ 0,
d = −sign v. Where it is 0 the sign of its relative acceleration v″·q̇² + v′·ε decides: at a
crossing of v′ = 0 with q̇ ≠ 0 that is sign v″ (the run restarts there, solver.dynamics.
_friction_run, and holds the directions so found until the next switch: FrictionDynamics.mode);
at rest (q̇ = 0) it is sign(v′·s), s the direction the input slips in. **Stick–slip**: at rest
the holding efforts are the interval [Q₋, Q₊] (each edge the kinetostatic effort at ε = 0 with
the friction against a start toward −q and +q, as solver.forces.friction.breakaway); the input
sticks while Q_drive stays inside it and slips toward +q where Q_drive > Q₊, toward −q where
Q_drive < Q₋.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..errors import DynamicsError
from ..forces._friction_solve import solve_flat
from ..forces.friction import solve_magnitudes, solve_one

__all__ = ["FrictionDynamics", "FrictionLayer", "FrictionState", "magnitudes"]


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


def magnitudes(r0: list[complex], b: list[list[complex]], dirs: list[float], c: list[float], *, where: str,
               scene: str) -> list[float]:
    """x = c·|R⁰ + Σⱼ xⱼ·dⱼ·B_j| at one state: the kinetostatics' one-sample sweeps
    (solver.forces.friction.solve_one: straight-line code on plain numbers), handed to its
    vectorised solve (Newton) where they do not settle; DynamicsError naming ``where`` where the
    equations have no solution (the friction locks the motion)."""
    x = solve_one(r0, b, dirs, c)
    if x is not None:
        return x
    m = len(r0)
    base = [np.array([r0[k]], complex) for k in range(m)]
    responses = [[np.array([b[j][k]], complex) for k in range(m)] for j in range(m)]
    xs, locked = solve_magnitudes(base, responses, [np.array([d]) for d in dirs], list(range(m)),
                                  np.asarray(c, float), 1)
    if locked[0]:
        raise DynamicsError(f"the friction equations have no solution at {where}: the friction locks the "
                            "mechanism against its own motion (no acceleration satisfies them)", scene=scene)
    return [float(v) for v in xs[0]]


class FrictionLayer:
    """The force layer of the compiled instant of a scene with friction, in forward dynamics:
    every pass the friction's equations need, on the jets of one plan run — the frictionless
    effort and carriers at (q̇, ε = 0) (h, R⁰), the bodies' inertia alone at (0, 1) (M, A), the
    other loads' effort, each element's unit load (uⱼ, B_jk) and its analogs (v′ⱼ, v″ⱼ). It names
    no friction of its own, so it is compiled (solver._codegen); the scalar path evaluates the same
    source where a guard trips."""

    #: as a force layer's: solved here, not by the kinetostatics' friction
    friction = None

    def __init__(self, rubbing: Any, inertia: Any, other: Any) -> None:
        self.rubbing, self.inertia, self.other = rubbing, inertia, other
        self.targets = rubbing.targets
        self.inputs = rubbing.inputs
        index = rubbing.base_index
        self.elements = rubbing.friction.elements
        self.carriers = [index[("pin" if e.kind == "pin" else "slide"), e.index] for e in self.elements]
        m = len(self.carriers)
        parts = [("h", False), ("M", False), ("other", False)]
        parts += [(f"R0.{k}", True) for k in range(m)] + [(f"A.{k}", True) for k in range(m)]
        for j in range(m):
            parts += [(f"u.{j}", False), *((f"B.{j}.{k}", True) for k in range(m)), (f"v1.{j}", False),
                      (f"v2.{j}", False)]
        self.layout = tuple(("friction", key, cplx) for key, cplx in parts)
        self.index = {(kind, key): i for i, (kind, key, _) in enumerate(self.layout)}

    def evaluate(self, values: Any, xp: Any, conditioning: Any, omega: Any, epsilon: Any) -> tuple:
        rub, inertia, other = self.rubbing, self.inertia, self.other
        base = rub.respond(values, xp, lambda s: rub._apply_loads(s, omega, 0.0))
        inert = inertia.respond(values, xp, lambda s: inertia._apply_loads(s, 0.0, 1.0))
        q_other = 0.0 if other is None else other.respond(values, xp, lambda s: other._apply_loads(s, omega, 0.0))[0]
        out = [base[0], inert[0], q_other, *(base[k] for k in self.carriers), *(inert[k] for k in self.carriers)]
        for v1, v2, _, load in rub.friction.element_kinematics(values, xp):
            unit = rub.respond(values, xp, load)
            out += [unit[0], *(unit[k] for k in self.carriers), v1, v2]
        return tuple(out)


class FrictionDynamics:
    """The friction-coupled equation of motion of a one-input scene with ``friction:``.

    ``scene``: a scene whose force layer is a :class:`FrictionLayer` (its plan reads every point
    the elements need); its compiled instant gives every pass at a state in one call."""

    def __init__(self, scene: Any, rubbing: Any) -> None:
        layer: FrictionLayer = scene.forces
        self.scene, self.layer = scene, layer
        self.name = scene.name
        self.input = scene.inputs[0]
        self.elements = layer.elements
        self.c = np.array([e.coefficient for e in self.elements], float)
        self.c_list = [float(v) for v in self.c]
        #: the seal force (N) of a cylinder on the input's own stroke (a seal elsewhere moves no effort)
        self.seal = sum(s.force for s in rubbing.friction.spec.seals if s.joint == self.input)
        self._memo: tuple[Any, Any, Any] = (None, None, None)
        self._last: tuple[Any, Any, Any] = (None, None, None)

    @cached_property
    def _unit(self) -> Any:
        return self.scene.compiled()

    @cached_property
    def _layout(self) -> tuple[int, int, list[int], list[int], Any]:
        """(where the conditioning starts, where the layer's outputs start, the index of each uⱼ and
        of each v′ⱼ in the compiled instant's flat output, the magnitudes' one-sample Newton reading
        that output in place: solver.forces._friction_solve.solve_flat)."""
        unit = self._unit
        size = unit.size
        start = size + len(unit.conditioning)
        m = len(self.elements)
        iu = [start + 3 + 2 * m + j * (m + 3) for j in range(m)]
        iv = [i + 1 + m for i in iu]
        fast = solve_flat(m, (start + 3, start + 3 + m, iu, [i + 1 for i in iu], iv))
        return size, start, iu, iv, fast

    def _flat(self, q: float, w: float) -> Any:
        """The compiled instant's flat output at (q, q̇, ε = 0) (the last one kept)."""
        last = self._last
        if last[0] == q and last[1] == w:
            return last[2]
        flat = self._unit.function(q, w, 0.0)  # (``function`` is replaced on the first call: read it each time)
        self._last = (q, w, flat)
        return flat

    def _passes(self, q: float, w: float) -> tuple[Any, ...]:
        """(h, M, Q_other, R⁰, A, u, B, analogs, conditioning) at (q, q̇) as lists: one compiled call
        (the last one kept)."""
        memo = self._memo
        if memo[0] == q and memo[1] == w:
            return memo[2]  # type: ignore[no-any-return]
        size, start = self._layout[:2]
        flat = self._flat(q, w)
        cond = min(flat[size:start]) if start > size else 1.0
        m = len(self.elements)
        h, mass, other = flat[start], flat[start + 1], -flat[start + 2]
        i = start + 3
        r0 = list(flat[i:i + m])
        a = list(flat[i + m:i + 2 * m])
        i += 2 * m
        u, b, rates = [], [], []
        for _ in range(m):
            u.append(flat[i])
            b.append(list(flat[i + 1:i + 1 + m]))
            rates.append((flat[i + 1 + m], flat[i + 2 + m]))
            i += m + 3
        out = (h, mass, other, r0, a, u, b, rates, cond)
        self._memo = (q, w, out)
        return out

    def analogs(self, q: float) -> list[tuple[float, float]]:
        """Each element's (v′, v″): the analogs of its relative velocity at ``q`` (v′'s zeros: where
        it reverses while the input moves). They depend on q alone: those of the last pass at this
        q whatever its q̇ (a step's events read the state its last stage was evaluated at)."""
        last = self._last
        if last[0] == q:
            flat = last[2]
            return [(flat[i], flat[i + 1]) for i in self._layout[3]]
        return list(self._passes(q, 0.0)[7])

    def _directions(self, rates: list[tuple[float, float]], w: float, slip: float,
                    override: dict[int, float] | None) -> list[float]:
        out = []
        for j, (v1, v2) in enumerate(rates):
            if override is not None and j in override:  # at its reversal (v′ is 0 there, to rounding)
                out.append(override[j])
                continue
            d = -_sign(v1 * w)
            if d == 0.0:
                if w != 0.0:
                    d = -_sign(v2)  # a crossing of v′ = 0: the relative acceleration is v″·q̇²
                else:
                    d = -_sign(v1 * slip)  # at rest: the relative acceleration is v′·ε, sign ε = s
            out.append(d)
        return out

    def _magnitudes(self, r0: list[complex], b: list[list[complex]], dirs: list[float], where: str) -> list[float]:
        """x = c·|R⁰ + Σⱼ xⱼ·dⱼ·B_j| at one state (:func:`magnitudes`)."""
        return magnitudes(r0, b, dirs, self.c_list, where=where, scene=self.name)

    def mode(self, q: float, w: float, *, slip: float = 0.0,
             override: dict[int, float] | None = None) -> tuple[list[float], float]:
        """The friction's directions at (q, q̇) by the branch rule (module docstring), and the
        sign of the input's motion (a seal's): what a segment of the run holds fixed."""
        return self._directions(self._passes(q, w)[7], w, slip, override), _sign(w) or slip

    def solve(self, q: float, w: float, drive: float, *, slip: float = 0.0,
              override: dict[int, float] | None = None,
              mode: tuple[list[float], float] | None = None) -> FrictionState:
        """ε and the dissipated power at (q, q̇) under the input's effort ``drive``; ``slip``: the
        direction the input starts in where q̇ = 0; ``override``: element → d where its relative
        velocity is zero (a restart at its reversal); ``mode``: the directions and the motion's
        sign held fixed (a segment's: the equation stays smooth past a switch, which the
        segment's events then locate), else they follow (q, q̇)."""
        return FrictionState(*self.solve_rates(q, w, drive, slip=slip, override=override, mode=mode))

    def solve_rates(self, q: float, w: float, drive: float, *, slip: float = 0.0,
                    override: dict[int, float] | None = None,
                    mode: tuple[list[float], float] | None = None) -> tuple[float, float, float, float]:
        """:meth:`solve` as the tuple (ε, loss, other, conditioning) (the run's right-hand side)."""
        size, start, iu, iv, fast = self._layout
        flat = self._flat(q, w)
        dirs, s = mode if mode is not None else self.mode(q, w, slip=slip, override=override)
        mass = flat[start + 1]
        rest = (drive - flat[start] - self.seal * s) / mass
        # the reduced system R̃⁰ = R⁰ + A·rest, B̃_jk = B_jk − A_k·uⱼ/M, formed by the generated
        # Newton itself from the compiled output in place
        # and the sums Σ x·d·u, Σ x·d·v′
        solved = fast(flat, dirs, self.c_list, rest, mass)
        if solved is not None:
            _, su, sv = solved
        else:
            _, _, _, r0, a, u, b, _, _ = self._passes(q, w)
            m = len(dirs)
            rt = [r0[k] + a[k] * rest for k in range(m)]
            bt = [[b[j][k] - a[k] * (u[j] / mass) for k in range(m)] for j in range(m)]
            x = self._magnitudes(rt, bt, dirs, f"{self.input} = {q:.6g}")
            su = sum([xj * dj * flat[i] for xj, dj, i in zip(x, dirs, iu)])
            sv = sum([xj * dj * flat[i] for xj, dj, i in zip(x, dirs, iv)])
        eps = rest - su / mass
        # the power of the friction against the motion, −Σ x·d·v′·q̇ (= Σ x·|v′·q̇| in its own mode)
        loss = -sv * w + self.seal * s * w
        return eps, loss, -flat[start + 2], (min(flat[size:start]) if start > size else 1.0)

    def holding(self, q: float) -> tuple[float, float]:
        """The breakaway interval (Q₋, Q₊) at rest at ``q``: the efforts of the input that hold the
        mechanism (the kinetostatic effort at q̇ = ε = 0 with the friction against a start toward −q
        and toward +q)."""
        h, _, _, r0, _, u, b, rates, _ = self._passes(q, 0.0)
        edges = []
        for s in (-1.0, 1.0):
            dirs = self._directions(rates, 0.0, s, None)
            try:
                x = self._magnitudes(r0, b, dirs, "rest")
            except DynamicsError:  # that start self-locks: every effort beyond holds it
                edges.append(s * math.inf)
                continue
            edges.append(h + sum(x[j] * dirs[j] * u[j] for j in range(len(dirs))) + self.seal * s)
        return edges[0], edges[1]
