"""Coulomb friction in pins, slides and cylinder seals, solved exactly on route 2 (docs/forces.md#friction).

Equations. A pin P joining bodies i and j (link names), reaction R (of j on i), friction circle
c = μ·r: a couple x·d on i and −x·d on j, x = c·|R|, d = −sign(ωᵢ − ωⱼ). A slide (block on its
guide), normal force N, coefficient μ: a force x·d·e on the block at its pin (−x·d·e on a
slotted guide), x = μ·|N|, e the guide's unit direction, d = −sign(v_rel). A seal of force F:
the effort of its stroke grows by F·sign(ṡ) (the cylinder's push on the linkage is unchanged).

Linear system. Route 2 is linear in the loads, so every output is affine in the friction
magnitudes x: out = out₀ + Σⱼ xⱼ·dⱼ·Uⱼ, where out₀ is the frictionless solve and Uⱼ the solve
with only a unit load of friction element j (one more pass of the groups per element). The
magnitudes solve x = c·|R₀ + B·x| per sample, vectorised (a sweep's (n,) samples, or a synthesis
population's (C, S) block solved as C·S samples and reshaped): Newton read as the reactions'
directions held — (I − diag(c)·G)·x = c·Re(ū·R₀), G_kj = dⱼ·Re(ū_k·B_jk), u_k = R_k/|R_k| —
on whole columns from the frictionless directions, two or three steps to round-off, checked by
a fixed-point sweep to |Δx| ≤ CONVERGED·|x|; the samples left go to a pivoted Newton per sample
(an m × m system each), which also stops at the rounding floor (steps that no longer halve:
near self-locking 1/(1 − gain) amplifies the rounding): solver.forces._friction_solve. One
sample (an instant) is solved on Python numbers by :func:`solve_one` (the same Newton in
generated straight-line code), the columns' solve where it gives up.

No solution. Where Newton does not converge in NEWTON_STEPS the equations have no solution with
the friction against the motion: the mechanism **self-locks** there (no finite effort drives
it); every value of such a sample is NaN and ``locked`` True there (``k.locked``, and
``locking_message`` names the φ intervals in one line).

Direction rule where a relative velocity is zero (its analog within tolerances.RELATIVE_REST of
the rates it is a difference of: a zero rounded): the sign of the relative acceleration; where
that is zero too (at rest), the load's tendency — the motion the loads would start if the
input let go, i.e. the input moving by −sign(Q₀) (Q₀ the frictionless effort of the first
input): the friction then opposes it and the effort is the smallest that holds. The breakaway
interval (the efforts that hold the mechanism at rest) is :func:`breakaway`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Protocol

import numpy as np

from .._backend import Backend
from ..errors import SolverError
from ..tolerances import RELATIVE_REST
from ._friction_solve import CONVERGED, NEWTON_STEPS, solve_one
from ._friction_solve import solve as _solve_columns
from .friction_spec import FrictionSpec
from .state import ForcePass
from .structure import GROUND, Structure

__all__ = ["FrictionModel", "breakaway", "solve_magnitudes", "solve_one", "cycle_efficiency", "efficiency",
           "locked_intervals", "locking_message",
           "NEWTON_STEPS", "CONVERGED", "TENDENCY"]


class _Responses(Protocol):
    """What :meth:`FrictionModel.apply` asks of its force model (solver.forces.model.ForceModel,
    which holds the friction model: named by this protocol, not imported)."""

    @property
    def base_index(self) -> dict[tuple[str, Any], int]: ...

    def respond(self, values: Any, xp: Backend, load: Callable[[ForcePass], None]) -> list[Any]: ...


#: Fixed-point sweeps a plain Gauss–Seidel loop on one sample may take before it hands the sample to
#: :func:`solve_magnitudes` (the former one-sample solve's bound; :func:`solve_one` is bounded by
#: its own ONE_SAMPLE_STEPS Newton steps).
FIXED_STEPS = 24
#: The angular acceleration that only gives the friction its direction in :func:`breakaway`
#: (its inertial loads, ~1e-200, vanish beside any load to round-off).
TENDENCY = 1e-200


@dataclass(frozen=True)
class _Element:
    kind: str  # "pin" | "slide"
    index: int  # the pin's or the slide's index in the structure
    coefficient: float  # μ·r (pin), μ (slide)
    body: str  # pin: body i; slide: the block
    other: str  # pin: body j; slide: the guide (ground or a slotted link)
    point: str  # the pin's point / the block's pin


class FrictionModel:
    """The friction elements of a scene and how they act on its route-2 pass."""

    def __init__(self, spec: FrictionSpec, structure: Structure, inputs: tuple[str, ...]) -> None:
        self.spec = spec
        self.inputs = inputs
        self.structure = structure
        pins, slides = structure.pins, structure.slides
        els = [_Element("pin", f.index, f.circle, pins[f.index].body, pins[f.index].other, pins[f.index].point)
               for f in spec.pins]
        els += [_Element("slide", f.index, f.mu, slides[f.index].body, slides[f.index].guide, slides[f.index].point)
                for f in spec.slides]
        self.elements: tuple[_Element, ...] = tuple(els)
        self.links = {ln.name: ln for ln in structure.links}

    @cached_property
    def layout(self) -> tuple[tuple[str, Any, bool], ...]:
        """The values friction adds to the force layer's flat tuple."""
        return (
            *(("effort0", j, False) for j in self.inputs),
            *(("loss", (e.kind, e.index), False) for e in self.elements),
            *(("loss", ("seal", s.joint), False) for s in self.spec.seals),
            ("power", None, False),
            ("power0", None, False),
            ("locked", None, False),
        )

    @cached_property
    def targets(self) -> tuple[str, ...]:
        """The points whose jets give the links' rates and the slides' directions."""
        names: list[str] = []
        for e in self.elements:
            for link in (e.body, e.other):
                names += self._frame(link)
            names.append(e.point)
        return tuple(dict.fromkeys(names))

    def _frame(self, link: str) -> tuple[str, ...]:
        if link == GROUND:
            return ()
        ln = self.links[link]
        if ln.block:
            return ln.along or ()
        return ln.points[:2]

    # -- kinematics of the elements -------------------------------------------------------------
    def _rate(self, link: str, values: Any, xp: Backend) -> tuple[Any, Any]:
        """(dθ/dφ, d²θ/dφ²) of ``link`` (0 for the ground and a block on a fixed guide). Operators
        only (one source for numpy, the scalar path and the tracer of the compiled instant)."""
        frame = self._frame(link)
        if not frame:
            return 0.0, 0.0
        p, q = values[frame[0]], values[frame[1]]
        r, r1, r2 = _lift(q.value - p.value, xp), _lift(q.d1 - p.d1, xp), _lift(q.d2 - p.d2, xp)
        rr = r.real * r.real + r.imag * r.imag
        rc = r.conjugate()
        c1 = rc * r1
        return c1.imag / rr, (rc * r2).imag / rr - 2.0 * c1.real * c1.imag / (rr * rr)

    def _slide(self, e: _Element, values: Any, xp: Backend) -> tuple[Any, Any, Any]:
        """The block's unit direction along its guide, and (dv/dφ, d²v/dφ²) of its sliding."""
        ln = self.links[e.body]
        b = values[e.point]
        if ln.along is None:  # a fixed guide
            u = complex(ln.guide if ln.guide is not None else 1.0)
            uc = u.conjugate()
            return u, (uc * _lift(b.d1, xp)).real, (uc * _lift(b.d2, xp)).real
        a = values[ln.along[0]]
        r, r1, r2 = _lift(b.value - a.value, xp), _lift(b.d1 - a.d1, xp), _lift(b.d2 - a.d2, xp)
        rho = xp.sqrt(r.real * r.real + r.imag * r.imag)
        rc = r.conjugate()
        c1 = (rc * r1).real
        v1 = c1 / rho
        v2 = (rc * r2).real / rho + (r1.real * r1.real + r1.imag * r1.imag) / rho - c1 * c1 / (rho * rho * rho)
        return r / rho, v1, v2

    def element_kinematics(self, values: Any, xp: Backend, *, scales: list[Any] | None = None
                           ) -> list[tuple[Any, Any, Any, Callable[[ForcePass], None]]]:
        """Per element (in :attr:`elements` order): the analogs (dv/dφ, d²v/dφ²) of its relative
        velocity (pin: ωᵢ − ωⱼ; slide: the block along its guide: arrays on numpy, numbers on the
        scalar path and tracers when compiled); the slide's unit
        direction (None for a pin); and its unit load on a route-2 pass (a unit couple on i and
        its opposite on j; a unit push along the guide on the block at its pin). ``scales`` (numpy
        path only): a list given is filled, per element, with the scale of dv/dφ's rounding (a pin:
        |dθᵢ/dφ| + |dθⱼ/dφ|; a slide: the block's and its guide point's |dB/dφ|)."""
        rates: dict[str, tuple[Any, Any]] = {}
        out: list[tuple[Any, Any, Any, Callable[[ForcePass], None]]] = []
        for e in self.elements:
            if e.kind == "pin":
                for link in (e.body, e.other):
                    if link not in rates:
                        rates[link] = self._rate(link, values, xp)
                (a1, a2), (b1, b2) = rates[e.body], rates[e.other]
                out.append((a1 - b1, a2 - b2, None, _couples(e.body, e.other)))
                if scales is not None:
                    scales.append(np.abs(_arr(a1)) + np.abs(_arr(b1)))
            else:
                unit, v1, v2 = self._slide(e, values, xp)
                out.append((v1, v2, unit, _pushes(e.body, e.other, e.point, unit)))
                if scales is not None:
                    ln = self.links[e.body]
                    guide = 0.0 if ln.along is None else np.abs(_arr(values[ln.along[0]].d1))
                    scales.append(np.abs(_arr(values[e.point].d1)) + guide)
        return out

    # -- the solve --------------------------------------------------------------------------------
    def apply(self, model: _Responses, values: Any, xp: Backend, omega: Any, epsilon: Any,
              out: list[Any]) -> list[Any]:
        """``out`` (the frictionless flat tuple, in ``model``'s base layout) with friction, then the
        values of :attr:`layout`."""
        index = model.base_index
        # the samples' shape: (n,) for a sweep, (C, S) for a synthesis population (solved flat,
        # reshaped at the end); n its size
        shape = _shape(out, omega, epsilon)
        n = math.prod(shape)

        def flat(v: Any) -> np.ndarray:
            a = np.asarray(v)
            if a.shape == shape:
                return a if len(shape) == 1 else a.reshape(-1)
            if a.size == 1 and n == 1:  # one instant: a float
                return a.reshape(1)
            return np.broadcast_to(a, shape).reshape(-1)

        w, eps = flat(omega).astype(float), flat(epsilon).astype(float)
        base = [flat(v) for v in out]
        q0 = base[index["effort", self.inputs[0]]]
        tendency = -np.sign(q0)
        dirs, speeds, responses, carriers, units = [], [], [], [], []
        scales: list[Any] = []
        kinematics = self.element_kinematics(values, xp, scales=scales)
        for e, (v1, v2, unit, load), scale in zip(self.elements, kinematics, scales):
            v1, v2, scale = flat(v1), flat(v2), flat(scale)
            if unit is not None:
                unit = unit if np.ndim(unit) == 0 else flat(unit)
            carriers.append(index[("pin" if e.kind == "pin" else "slide"), e.index])
            velocity = v1 * w
            d = np.sign(velocity)
            d[np.abs(v1) <= RELATIVE_REST * scale] = 0.0  # a zero rounded (tolerances.RELATIVE_REST)
            if not d.all():  # (the rule's later cases only where the velocity is zero)
                z = np.flatnonzero(d == 0.0)
                wz, vz = w[z], v1[z]
                d[z] = -_direction(np.zeros(z.size), v2[z] * wz * wz + vz * eps[z], vz * tendency[z])
            np.negative(d, out=d)
            dirs.append(d)
            speeds.append(np.abs(velocity))
            units.append(unit)
            responses.append([flat(v) for v in model.respond(values, xp, load)])
        x, locked = _magnitudes(base, responses, dirs, carriers, np.array([e.coefficient for e in self.elements]), n)
        # out = out₀ + Σⱼ xⱼ·dⱼ·Uⱼ, summed in place (each output copied once, one scratch per kind)
        final = list(base)
        fresh = [False] * len(final)
        scratch: dict[str, np.ndarray] = {}
        for j in range(len(self.elements)):
            xd = x[:, j] * dirs[j]
            for o, r in enumerate(responses[j]):
                if _zero(r):
                    continue
                kind = np.result_type(final[o], r, xd)
                if not fresh[o]:
                    final[o], fresh[o] = np.array(np.broadcast_to(final[o], (n,)), dtype=kind), True
                elif final[o].dtype != kind:
                    final[o] = final[o].astype(kind)
                tmp = scratch.get(kind.char)
                if tmp is None:
                    tmp = scratch[kind.char] = np.empty(n, kind)
                final[o] += np.multiply(xd, r, out=tmp)
            if units[j] is not None:
                k = index["slide", self.elements[j].index]
                final[k] = final[k] + xd * units[j]
        losses = [x[:, j] * speeds[j] for j in range(len(self.elements))]
        for seal in self.spec.seals:
            jet = values[seal.joint]
            d1, d2 = flat(_arr(jet.d1)), flat(_arr(jet.d2))
            k = index["effort", seal.joint]
            q = base[k]
            d = _direction(d1 * w, d2 * w * w + d1 * eps, d1 * -np.sign(q))
            final[k] = final[k] - seal.force * d
            losses.append(seal.force * np.abs(d1 * w))
        rate = [flat(_arr(values[j].d1)) * w for j in self.inputs]
        power = sum(final[index["effort", j]] * r for j, r in zip(self.inputs, rate))
        power0 = sum(base[index["effort", j]] * r for j, r in zip(self.inputs, rate))
        extra = [base[index["effort", j]] for j in self.inputs] + losses + [power, power0, locked.astype(float)]
        result: list[Any] = final + extra
        if locked.any():
            result = [np.where(locked, _nan_like(v), v) for v in result[:-1]] + [result[-1]]
        if xp.vectorised:
            return result if len(shape) == 1 else [v.reshape(shape) for v in result]
        return [complex(v[0]) if np.iscomplexobj(v) else float(v[0]) for v in result]


def _magnitudes(base: list[np.ndarray], responses: list[list[np.ndarray]], dirs: list[np.ndarray],
                carriers: list[int], c: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The magnitudes' solve (solver.forces._friction_solve): one sample (an instant) on Python
    numbers by :func:`solve_one`, else — or where it does not settle — on whole columns."""
    if n == 1:
        x = solve_one([complex(base[k][0]) for k in carriers],
                      [[complex(r[k][0]) for k in carriers] for r in responses],
                      [float(d[0]) for d in dirs], [float(v) for v in c])
        if x is not None:
            return np.array([x]), np.zeros(1, bool)
    return _solve_columns(base, responses, dirs, carriers, c, n)


def _lift(x: Any, xp: Backend) -> Any:
    """``x`` as an array on the numpy path (a Python number stays one on the others)."""
    return np.atleast_1d(np.asarray(x)) if xp.vectorised else x


def _arr(x: Any) -> np.ndarray:
    return np.atleast_1d(np.asarray(x))


def _zero(a: np.ndarray) -> bool:
    """A response that is one broadcast zero (a load this output does not feel)."""
    return a.strides == (0,) and a.size > 0 and a[0] == 0


def _shape(out: Sequence[Any], omega: Any, epsilon: Any) -> tuple[int, ...]:
    """The samples' shape: every value's broadcast together (at least (1,))."""
    shape = np.broadcast_shapes(*(np.shape(v) for v in out), np.shape(omega), np.shape(epsilon))
    return shape if shape else (1,)


def _nan_like(v: np.ndarray) -> Any:
    return complex(math.nan, math.nan) if np.iscomplexobj(v) else math.nan


def _direction(velocity: np.ndarray, acceleration: np.ndarray, tendency: np.ndarray) -> np.ndarray:
    """d = −sign of the relative velocity; where it is 0 of the relative acceleration; where
    that is 0 too of the load's tendency (0 where nothing tends to move)."""
    s = np.sign(velocity)
    s = np.where(s == 0.0, np.sign(acceleration), s)
    s = np.where(s == 0.0, np.sign(tendency), s)
    return np.asarray(-s, float)


def _couples(body: str, other: str) -> Callable[[ForcePass], None]:
    def load(s: ForcePass) -> None:
        s.couple(body, 1.0)
        if other != GROUND:
            s.couple(other, -1.0)
    return load


def _pushes(block: str, guide: str, point: str, unit: Any) -> Callable[[ForcePass], None]:
    def load(s: ForcePass) -> None:
        s.add(block, unit, point)
        if guide != GROUND:
            s.add(guide, unit, point, subtract=True)
    return load


#: x = c·|R₀ + B·x| per sample (the solve :meth:`FrictionModel.apply` uses; forward dynamics
#: calls it on the reduced system of a free input, solver.dynamics._friction)
solve_magnitudes = _solve_columns


# -- read-outs -----------------------------------------------------------------------------------
def locked_intervals(phi: np.ndarray, locked: np.ndarray) -> list[tuple[float, float]]:
    """The runs of consecutive self-locking samples, as (first φ, last φ)."""
    phi, locked = np.ravel(phi), np.ravel(locked).astype(bool)
    out: list[tuple[float, float]] = []
    i = 0
    while i < locked.size:
        if locked[i]:
            j = i
            while j + 1 < locked.size and locked[j + 1]:
                j += 1
            out.append((float(phi[i]), float(phi[j])))
            i = j + 1
        else:
            i += 1
    return out


def locking_message(phi: Any, locked: Any, *, unit: str = "rad") -> str:
    """One line naming where the input cannot drive the mechanism; "" where it can everywhere."""
    spans = locked_intervals(np.asarray(phi, float), np.asarray(locked))
    if not spans:
        return ""
    text = ", ".join(f"{a:.6g}" if a == b else f"[{a:.6g}, {b:.6g}]" for a, b in spans)
    count = int(np.count_nonzero(locked))
    return (f"self-locking at φ = {text} {unit} ({count} sample{'s' if count > 1 else ''}): the friction "
            "equations have no solution there — no finite effort drives the mechanism")


def breakaway(scene: Any, phi: Any, joint: str | None = None) -> tuple[Any, Any]:
    """The interval (low, high) of efforts of ``joint`` that hold the mechanism at rest at ``phi``:
    ``high`` starts it moving toward +φ, ``low`` toward −φ (each solved with the friction
    against that motion, at ω = 0 and an ε of ±TENDENCY that only gives the direction). An
    edge where that motion self-locks is ±inf (every effort beyond holds it)."""
    joint = joint or scene.inputs[0]
    if len(scene.inputs) != 1:
        raise SolverError(f"breakaway efforts are given for one input; '{scene.name}' has {list(scene.inputs)}")
    edges = []
    for sign in (-1.0, 1.0):
        k = scene.solve(phi, omega=0.0, epsilon=sign * TENDENCY, mask=False)
        q = np.asarray(k.effort(joint), float)
        q = np.where(np.asarray(k.locked), sign * math.inf, q)
        edges.append(float(q) if q.ndim == 0 else q)
    return edges[0], edges[1]


def efficiency(power: Any, ideal: Any) -> Any:
    """The instantaneous efficiency from the input power P = Σ Q·q̇ and the ideal P₀ = Σ Q₀·q̇
    (arrays or floats): P₀/P where the ideal mechanism takes power from its inputs (P₀ > 0);
    P/P₀ where it gives power to them (P₀ < 0: back-driven; negative where friction still needs
    the input to push); where P₀ = 0, 1 if P = 0 (at rest) else 0; NaN where either is NaN. The
    one formula of ``k.efficiency`` and of the recorded runs' efficiency plot."""
    with np.errstate(divide="ignore", invalid="ignore"):
        p, p0 = np.asarray(power, float), np.asarray(ideal, float)
        eta = np.where(p0 > 0.0, p0 / np.where(p0 > 0.0, p, 1.0),
                       np.where(p0 < 0.0, p / np.where(p0 < 0.0, p0, 1.0), np.where(p == 0.0, 1.0, 0.0)))
        return np.where(np.isnan(p) | np.isnan(p0), np.nan, eta)


def cycle_efficiency(k: Any) -> float:
    """Σ over a sweep of the useful work over the work put in: 1 − W_loss / W_in, W_in the work
    the inputs deliver (their positive power) — each integrated over time by the trapezoid
    rule, dt = |dφ/ω| (the samples in order along the sweep)."""
    phi = np.asarray(k.phi, float)
    w = np.broadcast_to(np.asarray(k.omega, float), phi.shape)
    power = np.asarray(k.input_power, float)
    loss = np.asarray(k.friction_power, float)
    if phi.ndim != 1 or phi.size < 2 or not np.all(w != 0.0):
        raise SolverError("a cycle's efficiency needs a sweep (≥ 2 samples, one input) with ω ≠ 0")
    dt = np.abs(np.diff(phi) / (0.5 * (w[1:] + w[:-1])))
    def work(p: np.ndarray) -> float:
        return float(np.sum(0.5 * (p[1:] + p[:-1]) * dt))
    w_in = work(np.maximum(power, 0.0))
    return 1.0 - work(loss) / w_in if w_in > 0.0 else 0.0
