"""The equation of motion in the input coordinates, from the kinetostatics (docs/dynamics.md).

The effort Q that produces a prescribed motion (q, q̇, q̈) is affine in q̈, since Newton–Euler is
linear in the accelerations and every body's acceleration is affine in q̈:

    Q(q, q̇, q̈) = M(q)·q̈ + h(q, q̇),     M = ∂Q/∂q̈,   h = Q(q, q̇, 0)

One input: M is the reduced moment of inertia J(φ) = Σ m|G_φ|² + I·θ_φ², h = ½J'(φ)ω² − Q_loads.
Nothing is differentiated numerically; each quantity is one force pass (solver.forces) of a
scene that differs from the user's only in what loads it:

* h: the scene itself at (q, q̇, q̈ = 0);
* M, column i: the scene with its bodies alone (no gravity, no loads) at (q, 0, e_i) — the
  inertial loads of a unit acceleration of input i, with no velocity term and no cancellation;
* a load's generalised force: −(the effort) of the scene with massless bodies and that load alone.

Per instant each pass is the scene's compiled instant (solver._codegen) with no outputs but the
efforts; over many states it is the numpy backend, one plan run shared by every pass of a state.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from functools import cached_property
from typing import Any

import numpy as np

from .._arguments import Arguments
from .._backend import NUMPY
from ..errors import DynamicsArgumentError, DynamicsError
from ..forces.frames import body_motion
from ..forces.spec import Body, Damper, ForceSpec, Spring
from ..groups import Context
from ..jet import Jet
from ..scene import CHUNK, Scene
from ._friction import FrictionDynamics, FrictionLayer
from ._friction_multi import InertiaLayer, MultiFrictionDynamics, StateLayer

__all__ = ["ReducedModel", "reduced_model"]


def _variant(scene: Scene, spec: ForceSpec) -> Scene:
    """The scene with another force layer and no outputs but its efforts."""
    return Scene(replace(scene._data, forces=spec), points=(), joints=())


def _massless(bodies: Sequence[Body]) -> tuple[Body, ...]:
    return tuple(replace(b, mass=0.0, inertia=0.0) for b in bodies)


class _Stacked:
    """One input: the force layer of the one-pass (M, h) instant — the full scene's efforts at
    (ω, ε = 0), the bodies' alone at (0, 1) and the other loads' at (ω, 0), all on the same jets,
    so that the compiled instant runs the kinematics once for the three (``evaluate`` is what
    the tracer records; the scalar path takes it too where a guard trips)."""

    #: as a force layer's: a scene with friction has no reduced model (ReducedModel refuses it)
    friction = None

    def __init__(self, full: Any, inertia: Any, other: Any) -> None:
        self.full, self.inertia, self.other = full, inertia, other
        self.targets = full.targets
        self.inputs = full.inputs
        parts = ("h", "M") if other is None else ("h", "M", "other")
        #: what ``evaluate`` returns, in the force layer's (kind, key, complex?) form
        self.layout = tuple(("effort", part, False) for part in parts)
        self.index = {(kind, key): i for i, (kind, key, _) in enumerate(self.layout)}

    def evaluate(self, values: Any, xp: Any, conditioning: Any, omega: Any, epsilon: Any) -> tuple:
        out = [self.full.evaluate(values, xp, conditioning, omega, 0.0)[0],
               self.inertia.evaluate(values, xp, conditioning, 0.0, 1.0)[0]]
        if self.other is not None:
            out.append(self.other.evaluate(values, xp, conditioning, omega, 0.0)[0])
        return tuple(out)


class ReducedModel:
    """M(q), h(q, q̇) and the loads' generalised forces of one scene, per instant and vectorised.

    ``k`` inputs; per instant ``q``, ``qd`` are k-tuples of floats (one input: 1-tuples), the
    results plain floats and lists; vectorised they are (N, k) arrays and M is (N, k, k).
    """

    def __init__(self, scene: Scene) -> None:
        model = scene.forces
        if model is None:
            raise DynamicsError("names no bodies, gravity or loads: nothing gives it inertia (docs/dynamics.md)",
                                scene=scene.name)
        #: the scene's Coulomb friction (solver.dynamics._friction), None without any; M, h and
        #: the loads' forces below are the frictionless mechanism's (friction is solved per state)
        self.friction: FrictionDynamics | MultiFrictionDynamics | None = None
        spec = model.spec
        if all(b.inert for b in spec.bodies):
            raise DynamicsError("every link is massless (no mass, inertia or flywheel): the reduced inertia is "
                                "zero, so the motion under given efforts is not defined", scene=scene.name)
        self.scene = scene
        self.spec = spec
        rubs = spec
        spec = replace(spec, friction=None)
        self.inputs: tuple[str, ...] = scene.inputs
        self.k = len(self.inputs)
        self.full = _variant(scene, spec)
        self.inertia = _variant(scene, replace(spec, gravity=0j, loads=()))
        other = tuple(ld for ld in spec.loads if not isinstance(ld, Spring))
        #: the loads whose work is counted apart in the energy balance (all but gravity and springs)
        self.other: Scene | None = (
            _variant(scene, replace(spec, bodies=_massless(spec.bodies), gravity=0j, loads=other)) if other else None
        )
        self.motors = dict(spec.motors)
        other_forces = None if self.other is None else self.other.forces
        if model.friction is not None and self.k == 1:  # one compiled pass of every response the friction needs
            rubbing = _variant(scene, rubs)
            rubbing.forces = FrictionLayer(rubbing.forces, self.inertia.forces, other_forces)  # type: ignore[assignment]
            self.friction = FrictionDynamics(rubbing, model)
        elif model.friction is not None:  # one pass at (q, q̇, 0) and one of the inertia per input
            state, inert = _variant(scene, rubs), _variant(scene, rubs)
            state.forces = StateLayer(state.forces, other_forces)  # type: ignore[assignment]
            inert.forces = InertiaLayer(inert.forces, self.inertia.forces)  # type: ignore[assignment]
            self.friction = MultiFrictionDynamics(state, inert, model)
        #: one input: the scene whose compiled instant gives (h, M, Q_other) in one pass
        self.stacked: Scene | None = None
        if self.k == 1:
            self.stacked = _variant(scene, spec)
            self.stacked.forces = _Stacked(  # type: ignore[assignment]
                self.full.forces, self.inertia.forces, None if self.other is None else self.other.forces)

    # -- per instant -----------------------------------------------------------------------------
    @cached_property
    def _units(self) -> tuple[Any, Any, Any]:
        return (self.full.compiled(), self.inertia.compiled(), None if self.other is None else self.other.compiled())

    def _efforts(self, unit: Any, args: tuple[float, ...]) -> tuple[list[float], float]:
        flat = unit.function(*args)
        start = unit.size + len(unit.conditioning)
        cond = flat[unit.size:start]
        return list(flat[start:start + self.k]), min(cond) if cond else 1.0

    @cached_property
    def _stacked_unit(self) -> Any:
        assert self.stacked is not None
        return self.stacked.compiled()

    def state(
        self, q: Sequence[float], qd: Sequence[float], *, other: bool = True
    ) -> tuple[Any, list[float], list[float], float]:
        """(M, h, Q_other, conditioning) at one state (Q_other: the generalised forces of the loads
        other than gravity and springs; zeros when there are none, or with ``other=False``). One
        input: one compiled pass. (The unit is kept, not its ``function``: a unit compiles on its
        first call and then replaces its ``function``.)"""
        if self.k != 1:
            m, h, cond = self.instant(q, qd)
            return m, h, self.other_forces(q, qd) if other else [0.0] * self.k, cond
        unit = self._stacked_unit
        flat = unit.function(q[0], qd[0], 0.0)
        start = unit.size + len(unit.conditioning)
        cond = min(flat[unit.size:start]) if start > unit.size else 1.0
        return flat[start + 1], [flat[start]], [-flat[start + 2]] if self.other is not None else [0.0], cond

    def instant(self, q: Sequence[float], qd: Sequence[float]) -> tuple[Any, list[float], float]:
        """(M, h, conditioning) at one state: M a float (one input) or a k×k list of rows, h a list
        of k floats, the worst conditioning of the groups (below tolerances.SINGULAR: singular)."""
        k = self.k
        if k == 1:
            m, h, _, cond = self.state(q, qd)
            return m, h, cond
        full, inertia, _ = self._units
        zeros = (0.0,) * k
        h, cond = self._efforts(full, (*q, *qd, *zeros))
        cols = []
        for i in range(k):
            unit = tuple(1.0 if j == i else 0.0 for j in range(k))
            cols.append(self._efforts(inertia, (*q, *zeros, *unit))[0])
        return [[cols[j][i] for j in range(k)] for i in range(k)], h, cond

    def other_forces(self, q: Sequence[float], qd: Sequence[float]) -> list[float]:
        """The generalised forces of the loads other than gravity and springs (dampers, forces,
        torques, tables) at one state; zeros when the scene has none."""
        unit = self._units[2]
        if unit is None:
            return [0.0] * self.k
        efforts, _ = self._efforts(unit, (*q, *qd, *(0.0,) * self.k))
        return [-x for x in efforts]

    # -- vectorised ------------------------------------------------------------------------------
    def _jets(self, q: np.ndarray, rates: np.ndarray | None, accels: np.ndarray | None) -> tuple[dict, dict]:
        """One plan run of the full scene's plan (which reads every point any pass needs): the
        analogs (one input) or the jets seeded with (q, rates, accels) (several)."""
        scene = self.full
        seeds = None
        if self.k > 1:
            n = q.shape[0]
            r = np.zeros((n, self.k)) if rates is None else rates
            a = np.zeros((n, self.k)) if accels is None else accels
            seeds = {j: Jet(np.ascontiguousarray(q[:, i]), r[:, i].copy(), a[:, i].copy())
                     for i, j in enumerate(self.inputs)}
        ctx = Context(phi=q[:, 0] if self.k == 1 else q, xp=NUMPY, mask=True, owner=scene, seeds=seeds,
                      scene=scene.name)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            scene.plan.run(ctx)
        if np.any(ctx.invalid):
            bad = np.flatnonzero(np.broadcast_to(ctx.invalid, q.shape[:1]))
            raise DynamicsError(f"cannot be assembled at {len(bad)} of the states (first: "
                                f"{', '.join(f'{v:.6g}' for v in q[bad[0]])})", scene=self.scene.name)
        return ctx.values, ctx.conditioning

    def _pass(self, scene: Scene, values: dict, cond: dict, w: Any, e: Any) -> np.ndarray:
        model = scene.forces
        assert model is not None
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            out = model.evaluate(values, NUMPY, cond, w, e)
        return np.stack([np.broadcast_to(np.asarray(x, float), np.shape(values[self.inputs[0]].value))
                         for x in out[:self.k]], axis=-1)

    def _states(self, q: Any, qd: Any) -> tuple[np.ndarray, np.ndarray]:
        args = Arguments("reduced model", scene=self.scene.name, error=DynamicsArgumentError)
        q = args.numbers("q", q)
        qd = args.numbers("qd", 0.0 if qd is None else qd)
        q = q.reshape(-1, self.k) if self.k > 1 or q.ndim != 1 else q[:, None]
        qd = np.broadcast_to(qd.reshape(-1, self.k) if qd.ndim else qd, q.shape)
        return q, np.ascontiguousarray(qd)

    def mass(self, q: Any) -> np.ndarray:
        """M(q): (N,) for one input (J(φ), kg·m²), (N, k, k) for several."""
        q, _ = self._states(q, None)
        if self.k == 1:
            values, cond = self._jets(q, None, None)
            return self._pass(self.inertia, values, cond, 0.0, 1.0)[:, 0]
        cols = []
        for i in range(self.k):
            unit = np.zeros_like(q)
            unit[:, i] = 1.0
            values, cond = self._jets(q, None, unit)
            cols.append(self._pass(self.inertia, values, cond, 1.0, 0.0))
        return np.stack(cols, axis=-1)

    def mass_bias(self, q: Any, qd: Any) -> tuple[np.ndarray, np.ndarray]:
        """M(q) and h(q, q̇) together: one plan run for one input ((N,), (N,)); with k inputs
        k + 1 runs ((N, k, k), (N, k))."""
        q, qd = self._states(q, qd)
        n, k = q.shape
        m, h = (np.empty(n), np.empty(n)) if k == 1 else (np.empty((n, k, k)), np.empty((n, k)))
        for lo in range(0, n, CHUNK):  # in blocks, as Scene.solve, so that the temporaries stay in cache
            rows = slice(lo, min(lo + CHUNK, n))
            if k != 1:
                m[rows], h[rows] = self.mass(q[rows]), self.bias(q[rows], qd[rows])
                continue
            values, cond = self._jets(q[rows], None, None)
            m[rows] = self._pass(self.inertia, values, cond, 0.0, 1.0)[:, 0]
            h[rows] = self._pass(self.full, values, cond, qd[rows, 0], 0.0)[:, 0]
        return m, h

    def bias(self, q: Any, qd: Any) -> np.ndarray:
        """h(q, q̇): (N,) for one input, (N, k) for several (N·m per input)."""
        q, qd = self._states(q, qd)
        if self.k == 1:
            values, cond = self._jets(q, None, None)
            return self._pass(self.full, values, cond, qd[:, 0], 0.0)[:, 0]
        values, cond = self._jets(q, qd, None)
        return self._pass(self.full, values, cond, 1.0, 0.0)

    @cached_property
    def _load_variants(self) -> tuple[tuple[str, Scene, bool], ...]:
        """(name, scene, moving?) per generalised force: gravity on the bodies alone, then each
        load alone on massless bodies (built once: each is a Scene with its own plan)."""
        spec = replace(self.spec, friction=None)  # (each load's own force: friction is not one of them)
        out: list[tuple[str, Scene, bool]] = []
        if spec.gravity != 0:
            out.append(("gravity", _variant(self.scene, replace(spec, loads=())), False))
        bare = _massless(spec.bodies)
        for i, ld in enumerate(spec.loads):
            name = f"damping.{ld.joint}" if isinstance(ld, Damper) else f"loads[{i}]"
            out.append((name, _variant(self.scene, replace(spec, bodies=bare, gravity=0j, loads=(ld,))), True))
        return tuple(out)

    def generalized_forces(self, q: Any, qd: Any) -> dict[str, np.ndarray]:
        """Each load's generalised force (N·m per input; (N,) or (N, k)): ``gravity`` and
        ``loads[i]`` by their place in the scene (dampers follow the listed loads as
        ``damping.JOINT``), and ``velocity`` the velocity terms −(h + Σ the others)."""
        q, qd = self._states(q, qd)
        values, cond = self._jets(q, qd if self.k > 1 else None, None)
        w = qd[:, 0] if self.k == 1 else 1.0
        out = {name: -self._pass(scene, values, cond, w if moving else 0.0, 0.0)
               for name, scene, moving in self._load_variants}
        h = self._pass(self.full, values, cond, w, 0.0)
        out["velocity"] = -h - sum(out.values(), np.zeros_like(h))
        return {name: v[:, 0] if self.k == 1 else v for name, v in out.items()}

    def potential(self, q: Any) -> dict[str, np.ndarray]:
        """Potential energy (J) at each state: of gravity (−Σ m·g·G) and of the springs (Σ ½k(ℓ − ℓ₀)²)."""
        q, _ = self._states(q, None)
        values, _ = self._jets(q, None, None)
        g = self.spec.gravity
        grav = np.zeros(q.shape[0])
        for b in self.spec.bodies:
            if b.mass:
                center = body_motion(b, values, NUMPY).center.value
                grav = grav - b.mass * (np.real(center) * g.real + np.imag(center) * g.imag)
        springs = np.zeros(q.shape[0])
        for ld in self.spec.loads:
            if isinstance(ld, Spring):
                p, r = values[ld.ends[0][1]].value, values[ld.ends[1][1]].value
                length = np.abs(np.asarray(r - p))
                springs = springs + 0.5 * ld.stiffness * (length - ld.free_length) ** 2
        return {"gravity": grav, "springs": springs}

    def kinetic(self, q: Any, qd: Any) -> np.ndarray:
        """Kinetic energy ½·q̇ᵀ·M·q̇ (J) at each state."""
        q, qd = self._states(q, qd)
        m = self.mass(q)
        if self.k == 1:
            return 0.5 * m * qd[:, 0] ** 2
        return 0.5 * np.einsum("ni,nij,nj->n", qd, m, qd)


def reduced_model(scene: Scene) -> ReducedModel:
    """The scene's :class:`ReducedModel`, built once per scene (kept on it)."""
    cache = scene.__dict__.get("_reduced")
    if cache is None:
        cache = scene.__dict__["_reduced"] = ReducedModel(scene)
    return cache  # type: ignore[no-any-return]

