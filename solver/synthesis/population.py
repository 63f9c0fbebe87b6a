"""A population of designs evaluated as arrays: candidates × samples in one pass of the plan.

:meth:`Template.population` gives the plan of C designs (every free parameter a (C, 1) array);
here it is run on a (C, S) array of input angles with the numpy evaluator in mask mode, and the
task's figures are read off the jets:

* **feasibility**, over the required input range (``Goal.sweep``): the fraction of samples where
  a group cannot be assembled, the smallest conditioning of the dyads — |sin μ| of the
  transmission angle μ of an RRR dyad, |cos| of the rod's angle to the guide normal of an RRP
  one — and the ratio of the longest link to the shortest;
* **misses**, one per target: with timing the miss at the given input angle; without timing the
  distance from the target to the curve, found at the nearest sample and refined along the curve
  by its exact analogs (one Newton step on the squared distance with the second-order Taylor
  curve ``P + P'·Δφ + P''·Δφ²/2``), so that an exact design scores near zero on a coarse sweep.

:func:`objective` turns these into one figure per candidate for the global search: the targets'
RMS miss over the task's size for a feasible design, and above every feasible figure a penalty
that grows with how far a design is from feasible (never NaN). With weights, the force terms the
scene already computes are added to a feasible design's figure: the peak input effort and the
peak pin load over the sweep at a given speed, from the kinetostatics of each design's own
bodies (solver.forces, evaluated on the population's jets: the same arrays, one more pass), and
for a template with friction ``efficiency_weight · (1 − η_min)``: η_min the worst instantaneous
efficiency over the sweep (``k.efficiency``, solver.forces.friction; a self-locking sample
counts 0, and η_min is clipped to [0, 1]).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._backend import NUMPY
from ..groups import Context
from ..plan import Plan
from .template import Template

__all__ = ["Goal", "Evaluation", "evaluate", "group_of", "objective", "INFEASIBLE"]

#: Every infeasible design scores above this; a feasible one's figure is capped below it.
INFEASIBLE = 100.0


@dataclass(frozen=True)
class Goal:
    """A synthesis task in SI units (m, rad)."""

    kind: str  # "path", "function" or "motion"
    point: str | None
    joint: str | None
    targets: np.ndarray  # (K, 2) path (x, y); function (φ, q); motion (x, y, θ)
    at: np.ndarray | None  # (K,) given input angles (timing), or None: the phases are free
    sweep: np.ndarray  # (S,) input angles over the range the input must turn
    min_transmission: float  # rad
    max_ratio: float | None
    scale: float  # the targets' size (m), or 1 for function generation
    joint_wraps: bool  # the joint is an angle: differences wrapped to (−π, π]
    closures: tuple[str, ...]  # the points of every dyad (their conditioning is checked)
    full_turn: bool = True  # the input turns fully (sweep over [lo, lo + 2π)); else over [lo, hi]
    effort_weight: float = 0.0  # objective += weight · peak |input effort| (per N·m, or per N)
    pin_weight: float = 0.0  # objective += weight · peak |pin load| (per N)
    speed: float = 1.0  # ω (rad/s) of the force terms (ε = 0)
    efficiency_weight: float = 0.0  # objective += weight · (1 − worst efficiency over the sweep) (friction)

    @property
    def weighted(self) -> bool:
        """Whether the figure holds force terms (the designs' kinetostatics are evaluated)."""
        return self.effort_weight > 0.0 or self.pin_weight > 0.0 or self.efficiency_weight > 0.0

    @property
    def names(self) -> tuple[str, ...]:
        out = [n for n in (self.point, self.joint) if n is not None]
        return tuple(dict.fromkeys([*out, *self.closures]))


@dataclass
class Evaluation:
    """What one pass gives for C candidates."""

    misses: np.ndarray  # (C, K) in the task's units (m, or the joint's)
    phases: np.ndarray  # (C, K) the input angle at each target
    invalid: np.ndarray  # (C,) fraction of the sweep that cannot be assembled
    conditioning: np.ndarray  # (C,) smallest dyad conditioning over the sweep (1 without dyads)
    ratio: np.ndarray  # (C,) longest link over shortest
    effort: np.ndarray | None = None  # (C,) peak |input effort| over the sweep at ω = Goal.speed (N·m or N)
    pin_load: np.ndarray | None = None  # (C,) peak |pin reaction| over the sweep (N)
    efficiency: np.ndarray | None = None  # (C,) worst efficiency over the sweep, in [0, 1] (friction only)


def wrap(a: Any) -> Any:
    """Angles to (−π, π]."""
    return np.pi - np.mod(np.pi - a, 2.0 * np.pi)


def run(template: Template, x: np.ndarray, phi: np.ndarray, names: tuple[str, ...]) -> Context:
    """The plan of the designs ``x`` (C, n) solved at ``phi`` (C, S) in mask mode."""
    return solve(template, x, phi, names)[0]


def solve(template: Template, x: np.ndarray, phi: np.ndarray, names: tuple[str, ...], *,
          forces: bool = False) -> tuple[Context, Plan, Any]:
    """:func:`run`, and the plan and (with ``forces``) the designs' force layer."""
    plan, model = template.population(x, names, forces=forces)
    phi = np.ascontiguousarray(np.broadcast_to(phi, (x.shape[0], np.shape(phi)[-1])), dtype=float)
    with np.errstate(all="ignore"):
        return plan.run(Context(phi=phi, xp=NUMPY, mask=True)), plan, model


#: The group kinds whose rigid pairs count in the link ratio.
_LINKED = ("crank", "rrr", "rrp", "triad", "slider_triad")


def link_ratio(plan: Plan, c: int) -> np.ndarray:
    """Longest link over shortest: the cranks', dyads' and sliders' lengths and the distances
    between the fixed pivots they use."""
    lengths = [np.broadcast_to(length, (c, 1)) for g in plan.groups if g.kind in _LINKED
               for _, _, length in g.rigid_pairs()]
    pivots = [np.broadcast_to(v, (c, 1)) for v in plan.fixed.values() if np.iscomplexobj(v)]
    for i in range(len(pivots)):
        for j in range(i):
            lengths.append(np.abs(pivots[i] - pivots[j]))
    if not lengths:
        return np.ones(c)
    stack = np.abs(np.concatenate(lengths, axis=1))
    with np.errstate(all="ignore"):
        return np.nan_to_num(stack.max(axis=1) / np.maximum(stack.min(axis=1), 1e-300), nan=np.inf)


def _force_peaks(goal: Goal, ctx: Context, model: Any, s: int, invalid: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Peak |input effort|, peak |pin load| and (with friction) the worst efficiency over the
    valid sweep at ω = ``goal.speed``."""
    c = invalid.shape[0]
    with np.errstate(all="ignore"):
        out = model.evaluate(ctx.values, NUMPY, ctx.conditioning, goal.speed, 0.0)
    k = len(model.inputs)
    n_pins = len(model.spec.structure.pins)

    def peak(values: Any) -> np.ndarray:
        if not values:
            return np.zeros(c)
        a = np.stack([np.abs(np.broadcast_to(v, invalid.shape)) for v in values])[:, :, :s]
        a = np.where(invalid[None, :, :s], 0.0, np.nan_to_num(a, nan=np.inf))
        return a.max(axis=(0, 2))  # type: ignore[no-any-return]

    worst = None
    if model.friction is not None:
        from ..forces.friction import efficiency

        p, p0 = (np.broadcast_to(out[model.index[key, None]], invalid.shape)[:, :s] for key in ("power", "power0"))
        eta = np.nan_to_num(efficiency(p, p0), nan=0.0)  # NaN: self-locking (or singular): no efficiency
        eta = np.where(invalid[:, :s], np.inf, eta)
        worst = np.clip(eta.min(axis=1, initial=np.inf), 0.0, 1.0)
    return peak(out[:k]), peak(out[k : k + n_pins]), worst


def evaluate(template: Template, goal: Goal, x: np.ndarray) -> Evaluation:
    """One pass of the plan for the candidates ``x`` (C, n): sweep and targets together."""
    x = np.atleast_2d(np.asarray(x, float))
    c, s = x.shape[0], goal.sweep.size
    at = goal.at if goal.at is not None else np.empty(0)
    phi = np.concatenate([goal.sweep, at])
    ctx, plan, model = solve(template, x, phi, goal.names, forces=goal.weighted)
    invalid = np.broadcast_to(np.asarray(ctx.invalid, bool), (c, phi.size))
    frac = invalid[:, :s].mean(axis=1) if s else np.zeros(c)
    cond = np.ones(c)
    for g in goal.closures:
        k = ctx.conditioning.get(group_of(template, g))
        if k is not None:
            kk = np.where(invalid[:, :s], np.inf, np.broadcast_to(k, (c, phi.size))[:, :s])
            cond = np.minimum(cond, np.nan_to_num(kk, nan=0.0).min(axis=1, initial=np.inf))
    if goal.at is not None:
        misses = _timed(goal, ctx, s, invalid)
        phases = np.broadcast_to(goal.at, misses.shape).copy()
    else:
        misses, phases = _untimed(goal, ctx, s, invalid)
    ev = Evaluation(misses, phases, frac, cond, link_ratio(plan, c))
    if model is not None:
        ev.effort, ev.pin_load, ev.efficiency = _force_peaks(goal, ctx, model, s, invalid)
    return ev


def group_of(template: Template, point: str) -> str:
    """The name of the group that provides ``point``."""
    for g in template.template_scene.ordered:
        if point in g.provides():
            return g.name
    return point


def _jets(goal: Goal, ctx: Context, shape: tuple[int, int]) -> tuple[Any, ...]:
    def take(name: str | None) -> tuple[Any, Any, Any]:
        if name is None:
            return (None, None, None)
        jet = ctx.values[name]
        return tuple(np.broadcast_to(v, shape) for v in jet)  # type: ignore[return-value]

    return (*take(goal.point), *take(goal.joint))


def _timed(goal: Goal, ctx: Context, s: int, invalid: np.ndarray) -> np.ndarray:
    shape = invalid.shape
    p0, _, _, q0, _, _ = _jets(goal, ctx, shape)
    t = goal.targets
    if goal.kind == "function":
        d = q0[:, s:] - t[:, 1]
        miss = np.abs(wrap(d) if goal.joint_wraps else d)
    else:
        miss = np.abs(p0[:, s:] - (t[:, 0] + 1j * t[:, 1]))
        if goal.kind == "motion":
            miss = np.hypot(miss, goal.scale * wrap(q0[:, s:] - t[:, 2]))
    miss = np.where(invalid[:, s:], np.inf, miss)
    return np.nan_to_num(miss, nan=np.inf, posinf=np.inf)


def _untimed(goal: Goal, ctx: Context, s: int, invalid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from each target to the sampled curve, refined by the analogs (module docstring)."""
    shape = invalid.shape
    p0, p1, p2, q0, q1, q2 = _jets(goal, ctx, shape)
    p0, p1, p2 = p0[:, :s], p1[:, :s], p2[:, :s]
    motion = goal.kind == "motion"
    if motion:
        q0, q1, q2 = q0[:, :s], q1[:, :s], q2[:, :s]
    bad = invalid[:, :s]
    step = (goal.sweep[-1] - goal.sweep[0]) / max(s - 1, 1)
    rows = np.arange(shape[0])
    lw = goal.scale
    misses = np.empty((shape[0], len(goal.targets)))
    phases = np.empty_like(misses)
    for k, t in enumerate(goal.targets):
        z = t[0] + 1j * t[1]
        e = p0 - z
        d2 = e.real**2 + e.imag**2
        if motion:
            d2 = d2 + (lw * wrap(q0 - t[2])) ** 2
        d2 = np.where(bad, np.inf, np.nan_to_num(d2, nan=np.inf))
        i = np.argmin(d2, axis=1)
        e0, a1, a2 = e[rows, i], p1[rows, i], p2[rows, i]
        # Newton on f(Δ) = |e + a1Δ + a2Δ²/2|² (+ lw²·(dθ + θ'Δ + θ''Δ²/2)²) from Δ = 0, kept in a sample
        g = e0.real * a1.real + e0.imag * a1.imag
        h = a1.real**2 + a1.imag**2 + e0.real * a2.real + e0.imag * a2.imag
        if motion:
            dq, b1, b2 = wrap(q0[rows, i] - t[2]), q1[rows, i], q2[rows, i]
            g = g + lw * lw * dq * b1
            h = h + lw * lw * (b1 * b1 + dq * b2)
        with np.errstate(all="ignore"):
            delta = np.where(h > 0.0, -g / h, 0.0)
        delta = np.clip(np.nan_to_num(delta), -step, step)
        r = e0 + a1 * delta + 0.5 * a2 * delta * delta
        miss = np.abs(r)
        if motion:
            miss = np.hypot(miss, lw * (dq + b1 * delta + 0.5 * b2 * delta * delta))
        miss = np.where(np.isfinite(d2[rows, i]), miss, np.inf)
        misses[:, k] = np.nan_to_num(miss, nan=np.inf)
        phases[:, k] = goal.sweep[i] + delta
    return misses, phases


def objective(goal: Goal, ev: Evaluation) -> np.ndarray:
    """One figure per candidate (module docstring): feasible ones below ``INFEASIBLE``."""
    with np.errstate(all="ignore"):
        rms = np.sqrt(np.mean(np.minimum(ev.misses / goal.scale, 1e6) ** 2, axis=1))
    fit = np.minimum(np.nan_to_num(rms, nan=INFEASIBLE, posinf=INFEASIBLE), 0.999 * INFEASIBLE)
    deficit = np.maximum(math.sin(goal.min_transmission) - ev.conditioning, 0.0)
    excess = np.zeros_like(fit) if goal.max_ratio is None else np.maximum(ev.ratio / goal.max_ratio - 1.0, 0.0)
    excess = np.nan_to_num(excess, nan=1.0, posinf=1.0)
    infeasible = (ev.invalid > 0.0) | (deficit > 0.0) | (excess > 0.0)
    if ev.effort is not None:
        fit = fit + goal.effort_weight * np.nan_to_num(ev.effort, nan=INFEASIBLE, posinf=INFEASIBLE)
    if ev.pin_load is not None:
        fit = fit + goal.pin_weight * np.nan_to_num(ev.pin_load, nan=INFEASIBLE, posinf=INFEASIBLE)
    if ev.efficiency is not None:
        fit = fit + goal.efficiency_weight * (1.0 - ev.efficiency)
    fit = np.minimum(fit, 0.999 * INFEASIBLE)
    penalty = INFEASIBLE * (1.0 + ev.invalid + deficit + np.minimum(excess, 1.0)) + fit / INFEASIBLE
    return np.where(infeasible, penalty, fit)  # type: ignore[no-any-return]
