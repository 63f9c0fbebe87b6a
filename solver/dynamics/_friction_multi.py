"""Coulomb friction in forward dynamics, several inputs (docs/dynamics.md#friction-with-several-inputs).

Loop equation: none of its own — the groups' closed form gives the positions and the jets; the
kinetostatics (solver.forces.friction) gives every output affine in the inputs' accelerations ε
(a k-vector now) and in the friction magnitudes x:

    Q   = h + M·ε + Σⱼ xⱼ·dⱼ·uⱼ + F∘σ             (k efforts; Fᵢ the seals on input i's stroke)
    R_k = R⁰_k + A_k·ε + Σⱼ xⱼ·dⱼ·B_jk
    x_k = c_k·|R_k|                                (c = μ·r at a pin, μ at a slide)

h, R⁰, the other loads' efforts, each element's unit load (uⱼ ∈ ℝᵏ, B_jk) and its relative
velocity vⱼ and acceleration a⁰ⱼ: one compiled pass at (q, q̇, ε = 0) (:class:`StateLayer`); M's
column i, A's column i and Gⱼᵢ = ∂vⱼ/∂qᵢ (the relative acceleration at q̇ = 0, ε = eᵢ): one
compiled pass of the bodies' inertia alone at (q, 0, eᵢ) per input (:class:`InertiaLayer`).

Linear system. The inputs are **free** (F: moving, or slipping from rest) or **stuck** (S: q̇ᵢ =
εᵢ = 0, their efforts the unknowns that hold them). Q_F = Q_drive,F leaves ε_F free:

    ε_F = M_FF⁻¹·(Q_drive,F − h_F − F_F∘σ_F − Σⱼ xⱼ·dⱼ·uⱼ,F)
    x_k = c_k·|R̃⁰_k + Σⱼ xⱼ·dⱼ·B̃_jk|,  R̃⁰_k = R⁰_k + A_k,F·M_FF⁻¹·(Q_drive,F − h_F − F_F∘σ_F),
                                        B̃_jk = B_jk − A_k,F·M_FF⁻¹·uⱼ,F

— the one-input problem per right-hand side (solver.dynamics._friction.magnitudes), then ε_F and
the holding efforts Q_S = h_S + M_SF·ε_F + Σⱼ xⱼ·dⱼ·uⱼ,S + F_S∘σ_S. Derivatives: the jets'
(nothing is differentiated numerically).

Branch rule (the friction's direction). dⱼ = −sign vⱼ where |vⱼ| exceeds the rounding of the
terms it is a difference of (tolerances.RELATIVE_REST·Σᵢ wⱼᵢ·|q̇ᵢ|, wⱼᵢ the two links' rates
per unit q̇ᵢ at a pin, the block's and its guide point's at a slide: a zero rounded); where it is
zero, −sign Σᵢ Gⱼᵢ·sᵢ (s: the direction each input at rest starts in — a slip, or a side of a
stick test); where that is zero too, −sign of its relative acceleration under the frictionless
accelerations of the free inputs, a⁰ⱼ + Σᵢ Gⱼᵢ·ε̂ᵢ; else 0 (an element held at rest by the stuck
inputs: its static friction is part of their holding efforts). σᵢ = sign q̇ᵢ, else sᵢ. At a
segment's start each element at rest is checked (:meth:`MultiFrictionDynamics.consistent`):
where the solve gives it a relative acceleration of the friction's own sign, its direction is
reversed; where that holds either way it is **locked** — its moment λⱼ an unknown with the row
a⁰ⱼ + Gⱼ,F·ε_F = 0, i.e. [M_FF U_LF; G_LF 0]·[ε_F; λ_L] = [rest_F; −a⁰_L] − Σⱼ xⱼ·dⱼ·[uⱼ,F; 0],
still affine in x — while |λⱼ| ≤ cⱼ·|Rⱼ|. **Stick test** of input i at rest: its holding
interval [Q₋ᵢ, Q₊ᵢ] is its effort at εᵢ = 0 with the start sᵢ = −1 and +1, the other stuck inputs
held and the free ones under their drives; it sticks while Q_drive,i lies inside.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, NamedTuple

import numpy as np

from ..errors import DynamicsError
from ..tolerances import RELATIVE_REST
from ._friction import magnitudes

__all__ = ["InertiaLayer", "MultiFrictionDynamics", "MultiState", "StateLayer"]


def _sign(v: float) -> float:
    return 1.0 if v > 0.0 else -1.0 if v < 0.0 else 0.0


def _terms(friction: Any, e: Any, values: Any, xp: Any) -> tuple[Any, Any]:
    """The two terms element ``e``'s relative acceleration is the difference of (its rounding's
    scale): a pin's two links' angular accelerations (the jets' d2); a slide's block point's and
    guide point's accelerations (complex; 0 for a fixed guide). Operators only (traced)."""
    if e.kind == "pin":
        return friction._rate(e.body, values, xp)[1], friction._rate(e.other, values, xp)[1]
    ln = friction.links[e.body]
    return values[e.point].d2, (0j if ln.along is None else values[ln.along[0]].d2)


class _Layer:
    """What both layers below set alike: the friction's force model ``rubbing``, its targets,
    inputs and elements, and each element's carrier (its pin's or slide's place in the base
    layout)."""

    #: as a force layer's: solved here, not by the kinetostatics' friction
    friction = None

    def __init__(self, rubbing: Any) -> None:
        self.rubbing, self.targets, self.inputs = rubbing, rubbing.targets, rubbing.inputs
        index = rubbing.base_index
        self.elements = rubbing.friction.elements
        self.carriers = [index[("pin" if e.kind == "pin" else "slide"), e.index] for e in self.elements]


class StateLayer(_Layer):
    """The force layer of the compiled pass at (q, q̇, ε = 0) of a several-input scene with
    friction: h, the other loads' efforts, R⁰ at the carriers, each element's unit load (uⱼ, B_jk)
    and its relative velocity and acceleration (the jets carry the real motion: ω = 1, ε = 0)."""

    def __init__(self, rubbing: Any, other: Any) -> None:
        super().__init__(rubbing)
        self.other = other
        k, m = len(self.inputs), len(self.carriers)
        parts = [(f"h.{i}", False) for i in range(k)] + [(f"other.{i}", False) for i in range(k)]
        parts += [(f"R0.{c}", True) for c in range(m)]
        for j, e in enumerate(self.elements):
            parts += [*((f"u.{j}.{i}", False) for i in range(k)), *((f"B.{j}.{c}", True) for c in range(m)),
                      (f"v.{j}", False), (f"a.{j}", False), (f"a1.{j}", e.kind != "pin"),
                      (f"a2.{j}", e.kind != "pin")]
        self.layout = tuple(("friction", key, cplx) for key, cplx in parts)
        self.index = {(kind, key): i for i, (kind, key, _) in enumerate(self.layout)}

    def evaluate(self, values: Any, xp: Any, conditioning: Any, omega: Any, epsilon: Any) -> tuple:
        rub, other = self.rubbing, self.other
        k = len(self.inputs)
        base = rub.respond(values, xp, lambda s: rub._apply_loads(s, omega, epsilon))
        q_other = [0.0] * k if other is None else \
            other.respond(values, xp, lambda s: other._apply_loads(s, omega, epsilon))[:k]
        out = [*base[:k], *q_other, *(base[c] for c in self.carriers)]
        friction = rub.friction
        for e, (v, a, _, load) in zip(self.elements, friction.element_kinematics(values, xp)):
            unit = rub.respond(values, xp, load)
            out += [*unit[:k], *(unit[c] for c in self.carriers), v, a, *_terms(friction, e, values, xp)]
        return tuple(out)


class InertiaLayer(_Layer):
    """The force layer of the compiled pass at (q, 0, eᵢ): the bodies' inertia alone — M's and A's
    column i — and each element's relative acceleration there, Gⱼᵢ = ∂vⱼ/∂qᵢ."""

    def __init__(self, rubbing: Any, inertia: Any) -> None:
        super().__init__(rubbing)
        self.inertia = inertia
        k, m = len(self.inputs), len(self.carriers)
        parts = [(f"M.{i}", False) for i in range(k)] + [(f"A.{c}", True) for c in range(m)]
        parts += [(f"G.{j}", False) for j in range(m)]
        parts += [(f"G{n}.{j}", e.kind != "pin") for j, e in enumerate(self.elements) for n in (1, 2)]
        self.layout = tuple(("friction", key, cplx) for key, cplx in parts)
        self.index = {(kind, key): i for i, (kind, key, _) in enumerate(self.layout)}

    def evaluate(self, values: Any, xp: Any, conditioning: Any, omega: Any, epsilon: Any) -> tuple:
        inertia = self.inertia
        k = len(self.inputs)
        inert = inertia.respond(values, xp, lambda s: inertia._apply_loads(s, omega, epsilon))
        out = [*inert[:k], *(inert[c] for c in self.carriers)]
        friction = self.rubbing.friction
        out += [a for _, a, _, _ in friction.element_kinematics(values, xp)]
        for e in self.elements:
            out += _terms(friction, e, values, xp)
        return tuple(out)


@dataclass(frozen=True)
class _Passes:
    """Everything the friction's equations need at one state (module docstring)."""

    h: list[float]
    other: list[float]
    r0: list[complex]
    u: list[list[float]]  # u[j][i]
    b: list[list[complex]]  # b[j][k]
    v: list[float]
    a: list[float]
    mass: list[list[float]]  # M[i][l]
    inert: list[list[complex]]  # A[k][i]
    g: list[list[float]]  # G[j][i]
    #: the scales of the roundings: of vⱼ per unit q̇ᵢ (w[j][i]) and of a⁰ⱼ (the terms they are differences of)
    w: list[list[float]]
    a_scale: list[float]
    conditioning: float


@dataclass(frozen=True)
class MultiState:
    """The solved state: ε (k), the inputs' efforts (the drive's where free, the holding effort
    where stuck), the friction's dissipated power (W), the generalised forces of the loads other
    than gravity and springs (k), the groups' worst conditioning."""

    epsilon: list[float]
    efforts: list[float]
    loss: float
    other: list[float]
    conditioning: float
    #: per locked element: (λⱼ, cⱼ·|Rⱼ|), its friction moment and the most the friction gives
    holds: dict[int, tuple[float, float]] = field(default_factory=dict)


class Mode(NamedTuple):
    """What a segment holds: the friction's directions dⱼ (0 for a locked element), the seals'
    signs σᵢ, and the **locked** elements — at rest while the inputs move, their friction moment
    λⱼ the unknown that keeps their relative acceleration 0 (|λⱼ| ≤ cⱼ·|Rⱼ|)."""

    dirs: list[float]
    sigma: list[float]
    locked: frozenset[int] = frozenset()


class MultiFrictionDynamics:
    """The friction-coupled equation of motion of a several-input scene with ``friction:``.

    ``state``, ``inertia``: scenes whose force layers are a :class:`StateLayer` and an
    :class:`InertiaLayer`; ``rubbing``: the user scene's force model (its seals)."""

    def __init__(self, state: Any, inertia: Any, rubbing: Any) -> None:
        self.state_scene, self.inertia_scene = state, inertia
        self.name = state.name
        self.inputs: tuple[str, ...] = state.inputs
        self.k = len(self.inputs)
        self.elements = state.forces.elements
        self.m = len(self.elements)
        self.c_list = [float(e.coefficient) for e in self.elements]
        #: per input, the seal force (N) of the cylinders on its own stroke
        self.seal = [sum(s.force for s in rubbing.friction.spec.seals if s.joint == j) for j in self.inputs]
        self._memo: tuple[Any, Any] = (None, None)
        self._geometry_memo: tuple[Any, Any] = (None, None)

    @cached_property
    def _state_unit(self) -> Any:
        return self.state_scene.compiled()

    @cached_property
    def _inertia_unit(self) -> Any:
        return self.inertia_scene.compiled()

    def _geometry(self, q: tuple[float, ...]) -> tuple[list[list[float]], list[list[complex]], list[list[float]],
                                                       list[list[float]]]:
        """(M, A, G, the scale of G's rounding) at ``q``: k compiled passes of the inertia alone
        (kept for the last q)."""
        if self._geometry_memo[0] == q:
            return self._geometry_memo[1]  # type: ignore[no-any-return]
        unit = self._inertia_unit
        k, m = self.k, self.m
        zeros = (0.0,) * k
        cols = []
        for i in range(k):
            flat = unit.function(*q, *zeros, *(1.0 if j == i else 0.0 for j in range(k)))
            start = unit.size + len(unit.conditioning)
            cols.append(flat[start:start + k + 4 * m])
        mass = [[cols[l_][i] for l_ in range(k)] for i in range(k)]
        inert = [[cols[i][k + c] for i in range(k)] for c in range(m)]
        g = [[cols[i][k + m + j] for i in range(k)] for j in range(m)]
        w = [[abs(cols[i][k + 2 * m + 2 * j]) + abs(cols[i][k + 2 * m + 2 * j + 1]) for i in range(k)]
             for j in range(m)]
        out = (mass, inert, g, w)
        self._geometry_memo = (q, out)
        return out

    def passes(self, q: Sequence[float], qd: Sequence[float]) -> _Passes:
        """Every pass at (q, q̇): 1 + k compiled calls (the last state kept)."""
        key = (tuple(q), tuple(qd))
        if self._memo[0] == key:
            return self._memo[1]  # type: ignore[no-any-return]
        unit = self._state_unit
        k, m = self.k, self.m
        flat = unit.function(*key[0], *key[1], *(0.0,) * k)
        size = unit.size
        start = size + len(unit.conditioning)
        cond = min(flat[size:start]) if start > size else 1.0
        h = list(flat[start:start + k])
        other = [-x for x in flat[start + k:start + 2 * k]]
        i = start + 2 * k
        r0 = list(flat[i:i + m])
        i += m
        u, b, v, a, a_scale = [], [], [], [], []
        for _ in range(m):
            u.append(list(flat[i:i + k]))
            b.append(list(flat[i + k:i + k + m]))
            v.append(flat[i + k + m])
            a.append(flat[i + k + m + 1])
            a_scale.append(abs(flat[i + k + m + 2]) + abs(flat[i + k + m + 3]))
            i += k + m + 4
        mass, inert, g, w = self._geometry(key[0])
        out = _Passes(h, other, r0, u, b, v, a, mass, inert, g, w, a_scale, cond)
        self._memo = (key, out)
        return out

    def velocity(self, q: Sequence[float], qd: Sequence[float], j: int) -> float:
        """Element j's relative velocity at (q, q̇) (its reversal: where it passes through 0)."""
        return self.passes(q, qd).v[j]

    # -- the directions -------------------------------------------------------------------------
    def _tendency(self, p: _Passes, drive: Sequence[float], free: list[int], sigma: Sequence[float]) -> list[float]:
        """ε̂: the frictionless accelerations of the free inputs (0 for the stuck ones)."""
        eps = [0.0] * self.k
        if free:
            rest = [drive[i] - p.h[i] - self.seal[i] * sigma[i] for i in free]
            sol = np.linalg.solve(np.array([[p.mass[i][l_] for l_ in free] for i in free]), np.array(rest))
            for n, i in enumerate(free):
                eps[i] = float(sol[n])
        return eps

    def mode(self, q: Sequence[float], qd: Sequence[float], drive: Sequence[float], *,
             stuck: Iterable[int] = (), starts: Sequence[float] | None = None,
             override: dict[int, float] | None = None, keep: Sequence[float] | None = None,
             locked: Iterable[int] = ()) -> Mode:
        """The friction's directions and the seals' signs at (q, q̇) by the branch rule (module
        docstring); ``starts``: per input at rest the direction it starts in (0: none);
        ``override``: element → d (a restart at its reversal); ``keep``: a segment's directions,
        kept for the elements that move (so that a stick test along the segment is as smooth as
        its equation: their reversals end it); ``locked``: elements kept locked (a segment's, where
        the free inputs still move them)."""
        p = self.passes(q, qd)
        k = self.k
        s = list(starts) if starts is not None else [0.0] * k
        held = set(stuck)
        sigma = [0.0 if i in held and qd[i] == 0.0 else (_sign(qd[i]) or s[i]) for i in range(k)]
        free = [i for i in range(k) if i not in held]
        eps_hat: list[float] | None = None
        dirs = []
        keep_locked = frozenset(j for j in locked if sum(abs(p.g[j][i]) for i in free)
                                > RELATIVE_REST * sum(p.w[j][i] for i in range(k)))
        for j in range(self.m):
            if j in keep_locked:
                dirs.append(0.0)
                continue
            if override is not None and j in override:
                dirs.append(override[j])
                continue
            gj, wj = p.g[j], p.w[j]
            v = p.v[j]
            if abs(v) > RELATIVE_REST * sum(wj[i] * abs(qd[i]) for i in range(k)):
                dirs.append(keep[j] if keep is not None and keep[j] != 0.0 else -_sign(v))
                continue
            t = sum(gj[i] * s[i] for i in range(k))
            if abs(t) > RELATIVE_REST * sum(wj[i] * abs(s[i]) for i in range(k)):
                dirs.append(-_sign(t))
                continue
            if eps_hat is None:
                eps_hat = self._tendency(p, drive, free, sigma)
            acc = p.a[j] + sum(gj[i] * eps_hat[i] for i in range(k))
            scale = p.a_scale[j] + sum(wj[i] * abs(eps_hat[i]) for i in range(k))
            dirs.append(-_sign(acc) if abs(acc) > RELATIVE_REST * scale else 0.0)
        return Mode(dirs, sigma, keep_locked)

    # -- the solve ------------------------------------------------------------------------------
    def solve(self, q: Sequence[float], qd: Sequence[float], drive: Sequence[float], *,
              stuck: Iterable[int] = (), starts: Sequence[float] | None = None,
              mode: Mode | None = None, where: str = "") -> MultiState:
        """ε, the efforts and the dissipated power at (q, q̇) under the drive's efforts, with the
        inputs ``stuck`` held (εᵢ = 0: their efforts are the holding ones); ``mode``: the
        directions and signs held fixed (a segment's), else by the branch rule."""
        held = frozenset(stuck)
        if mode is None:
            mode = self.mode(q, qd, drive, stuck=held, starts=starts)
        p = self.passes(q, qd)
        return self._solve(p, qd, drive, held, mode, where or self._where(q))

    def _where(self, q: Sequence[float]) -> str:
        return ", ".join(f"{j} = {v:.6g}" for j, v in zip(self.inputs, q))

    def _solve(self, p: _Passes, qd: Sequence[float], drive: Sequence[float], held: frozenset[int], mode: Mode,
               where: str) -> MultiState:
        k, m = self.k, self.m
        dirs, sigma, locked = mode
        free = [i for i in range(k) if i not in held]
        lock = sorted(locked) if free else []
        seal = self.seal
        nf, nl = len(free), len(lock)
        if free:  # [M_FF U_LF; G_LF 0]·[ε_F; λ_L] = [rest_F; −a⁰_L] − Σⱼ xⱼ·dⱼ·[uⱼ,F; 0]
            kk = np.zeros((nf + nl, nf + nl))
            rhs = np.zeros((nf + nl, 1 + m))
            for n, i in enumerate(free):
                for n2, i2 in enumerate(free):
                    kk[n, n2] = p.mass[i][i2]
                for b, el in enumerate(lock):
                    kk[n, nf + b] = p.u[el][i]
                    kk[nf + b, n] = p.g[el][i]
                rhs[n, 0] = drive[i] - p.h[i] - seal[i] * sigma[i]
                for j in range(m):
                    rhs[n, 1 + j] = p.u[j][i]
            for b, el in enumerate(lock):
                rhs[nf + b, 0] = -p.a[el]
            try:
                sol = np.linalg.solve(kk, rhs).tolist()
            except np.linalg.LinAlgError:
                raise DynamicsError(f"at {where}: the locked elements' constraints are dependent (no motion of the "
                                    "free inputs keeps them all at rest)", scene=self.name) from None
            rt = [p.r0[c] + sum(p.inert[c][i] * sol[n][0] for n, i in enumerate(free))
                  + sum(p.b[el][c] * sol[nf + b][0] for b, el in enumerate(lock)) for c in range(m)]
            bt = [[p.b[j][c] - sum(p.inert[c][i] * sol[n][1 + j] for n, i in enumerate(free))
                   - sum(p.b[el][c] * sol[nf + b][1 + j] for b, el in enumerate(lock)) for c in range(m)]
                  for j in range(m)]
        else:
            sol, rt, bt = [], p.r0, p.b
        x = magnitudes(rt, bt, dirs, self.c_list, where=where, scene=self.name)
        xd = [x[j] * dirs[j] for j in range(m)]
        eps = [0.0] * k
        for n, i in enumerate(free):
            eps[i] = sol[n][0] - sum(sol[n][1 + j] * xd[j] for j in range(m))
        lam = [sol[nf + b][0] - sum(sol[nf + b][1 + j] * xd[j] for j in range(m)) for b in range(nl)]
        for b, el in enumerate(lock):  # (a locked element's moment where the others' act)
            xd[el] = lam[b]
        efforts = list(drive)
        for i in held:
            efforts[i] = (p.h[i] + sum(p.mass[i][l_] * eps[l_] for l_ in free)
                          + sum(xd[j] * p.u[j][i] for j in range(m)) + seal[i] * sigma[i])
        # the power of the friction against the motion, −Σ xⱼ·dⱼ·vⱼ + Σ Fᵢ·σᵢ·q̇ᵢ (= Σ x·|v| in its own mode)
        loss = -sum(xd[j] * p.v[j] for j in range(m)) + sum(seal[i] * sigma[i] * qd[i] for i in range(k))
        holds = {el: (lam[b], x[el]) for b, el in enumerate(lock)}
        return MultiState(eps, efforts, loss, p.other, p.conditioning, holds)

    def resting(self, q: Sequence[float], qd: Sequence[float]) -> list[int]:
        """The elements whose relative velocity is a rounded zero at (q, q̇) (the branch rule's)."""
        p = self.passes(q, qd)
        return [j for j in range(self.m)
                if abs(p.v[j]) <= RELATIVE_REST * sum(p.w[j][i] * abs(qd[i]) for i in range(self.k))]

    def consistent(self, q: Sequence[float], qd: Sequence[float], drive: Sequence[float], mode: Mode, *,
                   stuck: Iterable[int] = (), where: str = "") -> Mode:
        """``mode`` with each element at rest moving off against its friction: where the relative
        acceleration the solve gives has the friction's own sign (dⱼ·aⱼ > 0: the friction would
        drive the motion it opposes) its direction is reversed, once; where it is so either way
        the friction holds that element's relative motion while the inputs move: it is **locked**
        (its moment the unknown that keeps its relative acceleration 0). DynamicsError where no
        such assignment is found (a locked element's moment beyond its friction's)."""
        held = frozenset(stuck)
        dirs, sigma, locked = list(mode.dirs), list(mode.sigma), set(mode.locked)
        where = where or self._where(q)
        rest = [j for j in self.resting(q, qd) if dirs[j] != 0.0]
        flipped: set[int] = set()
        p = self.passes(q, qd)
        for _ in range(2 * self.m + 2):
            st = self.solve(q, qd, drive, stuck=held, mode=Mode(dirs, sigma, frozenset(locked)), where=where)
            acc = self.relative_accelerations(q, qd, st.epsilon)
            bad = [j for j in rest if j not in locked and acc[j] * dirs[j] > 0.0
                   and abs(acc[j]) > RELATIVE_REST * (p.a_scale[j] + sum(
                       p.w[j][i] * abs(st.epsilon[i]) for i in range(self.k)))]
            over = [j for j, (lam, most) in st.holds.items() if abs(lam) > most * (1.0 + RELATIVE_REST)]
            if not bad and not over:
                return Mode(dirs, sigma, frozenset(locked))
            if over:
                break
            for j in bad:
                if j in flipped:
                    locked.add(j)
                    dirs[j] = 0.0
                else:
                    dirs[j] = -dirs[j]
                    flipped.add(j)
        bad_el = self.elements[(over or bad)[0]]
        what = f"pin {bad_el.point}" if bad_el.kind == "pin" else f"the slide of {bad_el.body}"
        raise DynamicsError(f"at {where}: no direction of the friction at {what} (at rest while the inputs move) is "
                            "consistent with the motion it gives, nor a moment within its friction that holds it "
                            "(docs/dynamics.md#friction-with-several-inputs)", scene=self.name)

    def relative_accelerations(self, q: Sequence[float], qd: Sequence[float], eps: Sequence[float]) -> list[float]:
        """Each element's relative acceleration a⁰ⱼ + Σᵢ Gⱼᵢ·εᵢ at (q, q̇) under ``eps``."""
        p = self.passes(q, qd)
        return [p.a[j] + sum(p.g[j][i] * eps[i] for i in range(self.k)) for j in range(self.m)]

    # -- stick–slip -----------------------------------------------------------------------------
    def holding(self, q: Sequence[float], qd: Sequence[float], drive: Sequence[float], i: int, *,
                stuck: Iterable[int] = (), starts: Sequence[float] | None = None,
                keep: Sequence[float] | None = None, locked: Iterable[int] = ()) -> tuple[float, float]:
        """Input i's holding interval (Q₋, Q₊) at (q, q̇) — q̇ᵢ = 0 — with the inputs ``stuck``
        held and the others under their drives (``starts``: the direction of each free input at
        rest): its effort at εᵢ = 0 with the friction against a start toward −qᵢ and toward +qᵢ.
        An edge where that start self-locks is ∓inf (every effort beyond holds it). ``keep``: as
        :meth:`mode`'s, and ``locked``."""
        edges = []
        for side in (-1.0, 1.0):
            try:
                st = self.edge(q, qd, drive, i, side, stuck=stuck, starts=starts, keep=keep, locked=locked)
            except DynamicsError:  # that start self-locks
                edges.append(side * math.inf)
                continue
            edges.append(st.efforts[i])
        return edges[0], edges[1]

    def edge(self, q: Sequence[float], qd: Sequence[float], drive: Sequence[float], i: int, side: float, *,
             stuck: Iterable[int] = (), starts: Sequence[float] | None = None,
             keep: Sequence[float] | None = None, locked: Iterable[int] = ()) -> MultiState:
        """The solved state of one edge of :meth:`holding`: input i held (εᵢ = 0) with the
        friction against its start toward ``side`` (its effort there is the edge)."""
        held = frozenset(stuck) | {i}
        s = list(starts) if starts is not None else [0.0] * self.k
        s[i] = side
        mode = self.mode(q, qd, drive, stuck=held, starts=s, keep=keep, locked=locked)
        mode.sigma[i] = side
        return self.solve(q, qd, drive, stuck=held, mode=mode)

    def settle(self, q: Sequence[float], qd: Sequence[float], drive: Sequence[float], rest: Iterable[int], *,
               starts: Sequence[float] | None = None, locked: Iterable[int] = ()
               ) -> tuple[frozenset[int], list[float], dict[int, tuple[float, float]]]:
        """Which of the inputs at rest (``rest``: q̇ᵢ = 0) stick: each is tested with the others
        of ``rest`` held; those whose drive leaves their interval slip (toward +qᵢ beyond Q₊,
        toward −qᵢ below Q₋) and the rest are tested again with them slipping, until none
        changes. (stuck, starts, each tested input's last interval)."""
        held = set(rest)
        s = list(starts) if starts is not None else [0.0] * self.k
        for i in held:
            s[i] = 0.0
        tests: dict[int, tuple[float, float]] = {}
        for _ in range(self.k + 1):
            slipped = []
            for i in sorted(held):
                lo, hi = tests[i] = self.holding(q, qd, drive, i, stuck=held - {i}, starts=s, locked=locked)
                if not lo <= drive[i] <= hi:
                    slipped.append((i, 1.0 if drive[i] > hi else -1.0))
            if not slipped:
                break
            for i, side in slipped:
                held.discard(i)
                s[i] = side
        return frozenset(held), s, tests
