"""Singular positions: the analogs' limit there, and the change points of a continuous branch.

A group is *singular* at a sample where its conditioning (``Kinematics.conditioning``) is below
:data:`~solver.tolerances.SINGULAR`: the linear system for its analogs has (nearly) no unique
solution. Positions stay exact there — they come from the closed form, not from the system.

What the analogs are at a singular sample
    The two-sided limit of the exact analogs along the branch, where it exists: the analogs are
    evaluated exactly at φ₀ ± h, ±2h, ±4h, ±8h (h = δ, 2δ or 4δ, δ = :data:`~solver.tolerances.LIMIT_STEP`,
    the smallest whose nodes are conditioned at least :data:`~solver.tolerances.LIMIT_NODE`), and
    the symmetric means are Richardson-extrapolated to h → 0 (truncation of order h⁸; about
    1e-10 relative, measured). This is the case at a change point
    passed on a continuous branch (a parallelogram at φ = 0 and π), and at a rocker-driven dyad
    that the input moves only tangentially.
    Where the left and right limits differ (a kink: the branch is kept through a change point
    without following it) or do not exist (the edge of an unassemblable range, where the analogs
    grow without bound), the analogs are NaN. Either way the sample is flagged:
    ``Kinematics.singular`` is True there, so no NaN is silent.

Near a singular position
    The linear system's rounding error grows as EPS/c in the velocity and EPS/c² in the
    acceleration analogs (c the conditioning). Below :data:`~solver.tolerances.REFINE_BELOW`
    the analogs are therefore taken from the same limit construction where it exists (on a
    continuous branch the nodes φ₀ ± kδ lie well away from the singular point), and left as the
    system gives them where it does not (beside the edge of an unassemblable range, where they
    are large but finite, or beside a kink).

Change points
    An RRR dyad with ``through_change_points: continuous`` changes its assembly mode M where
    both assemblies meet: h² (the closure's discriminant) has a double zero, i.e. |C − A| has an
    extreme equal to l₁ + l₂ or |l₁ − l₂|. Those φ are found once per scene (zeros of
    d|C − A|²/dφ bracketed on a grid of one turn, bisected to the last bit) and M(φ) is then a
    function of φ alone: M on the arc just after φ = 0 (counter-clockwise), flipped at each change
    point. The result does not depend on the sweep's direction, start or length.
"""

from __future__ import annotations

import contextvars
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ._backend import NUMPY, dot
from .groups.base import Context, Group
from .groups.rrr import branch_sign
from .jet import Jet
from .plan import Plan, build_plan
from .tolerances import (
    ASSEMBLY_SLACK,
    LIMIT_AGREEMENT,
    LIMIT_NODE,
    LIMIT_STEP,
    REFINE_BELOW,
    ROOT_ITERATIONS,
    SINGULAR,
)

__all__ = [
    "refine_singular",
    "change_points",
    "probe",
    "upstream_plan",
    "bisect_roots",
    "sign_changes",
    "turn_grid",
    "input_grid",
    "branch_sign",
    "GRID",
]

#: Samples of one turn used to bracket roots (then refined by bisection to rounding).
GRID = 4096

#: Nodes per side of the limit's extrapolation, and the steps tried (δ, 2δ, 4δ).
_NODES = 4
_LEVELS = 3
_refining: contextvars.ContextVar[bool] = contextvars.ContextVar("refining", default=False)
_CHANGE_POINTS: dict[Any, tuple[float, ...]] = {}


def turn_grid(n: int = GRID) -> np.ndarray:
    """``n + 1`` angles from 0 to 2π inclusive."""
    return np.linspace(0.0, 2.0 * math.pi, n + 1)


def input_grid(owner: Any, n: int = GRID) -> tuple[np.ndarray, bool]:
    """The grid a single-input analysis brackets roots on, and whether it is periodic: one turn
    (:func:`turn_grid`) for a crank, the stroke [s_min, s_max] (m) for an actuator."""
    ranges = getattr(owner, "input_ranges", (None,))
    span = ranges[0] if ranges else None
    if span is None:
        return turn_grid(n), True
    return np.linspace(span[0], span[1], n + 1), False


def upstream_plan(owner: Any, names: Sequence[str]) -> Plan:
    """The part of ``owner``'s plan that computes ``names``."""
    return build_plan(owner.plan.groups, owner.plan.fixed, tuple(names))


def probe(owner: Any, phi: np.ndarray, plan: Plan | None = None) -> Context:
    """Run ``plan`` (default: the owner's) at the angles ``phi``, unassemblable samples flagged."""
    ctx = Context(phi=np.asarray(phi, float), xp=NUMPY, mask=True, owner=owner)
    token = _refining.set(True)
    try:
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            (owner.plan if plan is None else plan).run(ctx)
    finally:
        _refining.reset(token)
    return ctx


def _broadcast(x: Any, n: int, dtype: type) -> np.ndarray:
    return np.array(np.broadcast_to(np.asarray(x, dtype), (n,)))


def refine_singular(ctx: Context, group: Group, names: Sequence[str] | None = None) -> None:
    """Replace the analogs of ``names`` (default: ``group.singular_names()``) at ``group``'s
    singular samples by their limit (or NaN).

    Called by whoever runs the plan, after the group's ``solve`` (``Plan.run`` calls the owning
    scene's ``refine_group``); costs one comparison when nothing is singular.
    """
    if names is None:
        names = group.singular_names()
    cond = ctx.conditioning.get(group.name)
    if cond is None:
        return
    if isinstance(cond, float):  # the per-tick scalar path: one comparison, no numpy
        if not cond < REFINE_BELOW:
            return
        bad = np.asarray(True)
    else:
        bad = np.asarray(cond < REFINE_BELOW)
        if not bad.any():
            return
    if ctx.seeds is not None:  # several inputs: no limit along one branch (docs/inputs.md)
        _singular_nan(ctx, cond, names)
        return
    scalar = not ctx.xp.vectorised
    phi = np.atleast_1d(np.asarray(ctx.phi, float))
    bad_idx = np.flatnonzero(np.broadcast_to(bad, phi.shape))
    phi0 = phi[bad_idx]
    # singular samples get the limit or NaN; merely ill-conditioned ones the limit where it exists
    strict = np.broadcast_to(np.asarray(cond < SINGULAR), phi.shape)[bad_idx]
    n = phi.shape[0]
    limits: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    if ctx.owner is not None and not _refining.get():
        # nodes φ₀ ± δ·2^i, i = 0..5; level k uses the nodes 2^k·{1, 2, 4, 8}·δ, the first level
        # whose nodes are all assemblable and conditioned at least LIMIT_NODE wins
        mult = 2.0 ** np.arange(_NODES + _LEVELS - 1)
        half = len(mult)
        grid = phi0[:, None] + LIMIT_STEP * np.concatenate([mult, -mult])[None, :]
        flat = grid.ravel()
        pctx = probe(ctx.owner, flat)
        ok = ~np.broadcast_to(np.asarray(pctx.invalid, bool), flat.shape)
        node_cond = np.broadcast_to(np.asarray(pctx.conditioning.get(group.name, 1.0), float), flat.shape)
        ok = (ok & (node_cond >= LIMIT_NODE)).reshape(grid.shape)
        for name in names:
            jet = pctx.values[name]
            pair: list[np.ndarray] = []
            for raw in (jet.d1, jet.d2):
                tail = np.shape(raw)[1:]
                d = np.asarray(np.broadcast_to(raw, flat.shape + tail)).reshape(grid.shape + tail)
                best = np.full((len(phi0), *tail), np.nan)
                for k in range(_LEVELS):
                    cols = [k + i for i in range(_NODES)] + [half + k + i for i in range(_NODES)]
                    level = _limit(d[:, cols], np.asarray(ok[:, cols].all(axis=1)), 2.0**k)
                    best = np.where(np.isnan(best), level, best)
                pair.append(best)
            limits[name] = (pair[0], pair[1])
    for name in names:
        jet = ctx.values[name]
        tail = np.shape(jet.value)[1:]
        dtype = complex if np.iscomplexobj(np.asarray(jet.value)) else float
        new: list[Any] = []
        for k, d in enumerate((jet.d1, jet.d2)):
            arr = np.array(np.broadcast_to(np.asarray(d, dtype), (n, *tail)))
            limit = limits[name][k] if name in limits else np.full((len(bad_idx), *tail), np.nan, dtype)
            found = np.isfinite(limit).reshape(len(bad_idx), -1).all(axis=1)
            take = (found | strict).reshape((-1,) + (1,) * len(tail))
            arr[bad_idx] = np.where(take, limit, arr[bad_idx])
            new.append(arr)
        if scalar:
            cast = complex if isinstance(jet.value, complex) else float
            new = [cast(x[0]) for x in new]
        ctx.values[name] = Jet(jet.value, new[0], new[1])


def _singular_nan(ctx: Context, cond: Any, names: Sequence[str]) -> None:
    """Several inputs: the derivatives are NaN at the singular samples (conditioning below
    SINGULAR, flagged in ``Kinematics.singular``) and as the system gives them elsewhere.

    With one input the analogs at a singular sample are a limit along the one-dimensional branch;
    with k inputs the Jacobian itself is unbounded there (a five-bar with its distal links
    aligned), so no such limit defines it."""
    if isinstance(cond, float):
        if not cond < SINGULAR:
            return
        for name in names:
            jet = ctx.values[name]
            nan: Any = complex(math.nan, math.nan) if isinstance(jet.value, complex) else math.nan
            ctx.values[name] = Jet(jet.value, nan, nan)
        return
    strict = np.asarray(cond < SINGULAR)
    if not strict.any():
        return
    for name in names:
        jet = ctx.values[name]
        n = np.shape(jet.value)[0]
        dtype = complex if np.iscomplexobj(np.asarray(jet.value)) else float
        new = []
        for d in (jet.d1, jet.d2):
            arr = np.array(np.broadcast_to(np.asarray(d, dtype), np.shape(jet.value)))
            arr[np.broadcast_to(strict, (n,))] = complex(math.nan, math.nan) if dtype is complex else math.nan
            new.append(arr)
        ctx.values[name] = Jet(jet.value, new[0], new[1])


def _limit(d: np.ndarray, ok: np.ndarray, level: float) -> np.ndarray:
    """Two-sided limit at 0 from samples at ±h, ±2h, ±4h, ±8h (h = level·δ): NaN where none.

    The left and right one-sided (quadratic) extrapolations must agree to LIMIT_AGREEMENT·level³
    of the analogs' size: they differ by O(1) at a kink and by O(h³) on an analytic branch.
    """
    plus, minus = d[:, :_NODES], d[:, _NODES:]
    # Richardson on the symmetric means (even in h): eliminate h², h⁴, h⁶ with the steps 1, 2, 4, 8
    table = [0.5 * (plus[:, i] + minus[:, i]) for i in range(_NODES)]
    for j in range(1, _NODES):
        f = 4.0**j
        table = [(f * table[i] - table[i + 1]) / (f - 1.0) for i in range(len(table) - 1)]
    two_sided = table[0]
    # one-sided quadratic extrapolation from the nodes 1, 2, 4 (Lagrange weights at 0)
    w = np.array([8.0 / 3.0, -2.0, 1.0 / 3.0]).reshape((1, 3) + (1,) * (d.ndim - 2))
    right, left = (plus[:, :3] * w).sum(axis=1), (minus[:, :3] * w).sum(axis=1)
    size = np.abs(d).max(axis=1)  # the analogs' magnitude near φ₀, per sample (and axis)
    if size.ndim > 1:
        size = size.max(axis=tuple(range(1, size.ndim)), keepdims=True)
    agree = np.abs(right - left) <= LIMIT_AGREEMENT * level**3 * size
    if agree.ndim > 1:
        agree = agree.all(axis=tuple(range(1, agree.ndim)))
    good = ok & agree & np.isfinite(two_sided).reshape(two_sided.shape[0], -1).all(axis=1)
    good = good.reshape((-1,) + (1,) * (two_sided.ndim - 1))
    return np.where(good, two_sided, np.nan)


# -- roots on one turn -------------------------------------------------------------------------
def sign_changes(values: np.ndarray) -> np.ndarray:
    """Indices i with a root of the sampled function in [x_i, x_{i+1}) (exact zeros included)."""
    v = np.asarray(values, float)
    fin = np.isfinite(v[:-1]) & np.isfinite(v[1:])
    return np.flatnonzero(fin & ((v[:-1] == 0.0) | (np.sign(v[:-1]) * np.sign(v[1:]) < 0.0)))


def bisect_roots(f: Callable[[np.ndarray], np.ndarray], lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Roots of ``f`` (vectorised) bracketed by [lo, hi] each, bisected to the last bit."""
    lo, hi = np.array(lo, float), np.array(hi, float)
    if lo.size == 0:
        return lo
    flo = np.sign(f(lo))
    exact = flo == 0.0
    for _ in range(ROOT_ITERATIONS):
        mid = 0.5 * (lo + hi)
        if np.all((mid == lo) | (mid == hi) | exact):
            break
        fm = np.sign(f(mid))
        same = (fm == flo) & ~exact
        lo = np.where(same, mid, lo)
        hi = np.where(same | exact, hi, mid)
    return np.where(exact, lo, 0.5 * (lo + hi))


# -- change points ------------------------------------------------------------------------------
def change_points(owner: Any, group: Any) -> tuple[float, ...]:
    """The φ in [0, 2π) where the RRR dyad ``group`` of ``owner`` passes a change point (the
    strokes in [s_min, s_max] for a scene driven by an actuator)."""
    plan = upstream_plan(owner, group.ends)
    key = (group, plan.groups, tuple(sorted((k, complex(v)) for k, v in plan.fixed.items())))
    if key in _CHANGE_POINTS:
        return _CHANGE_POINTS[key]
    l1, l2 = group.lengths
    ends = group.ends

    def dd_and_slope(phi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        ctx = probe(owner, phi, plan)
        ja, jc = ctx.values[ends[0]], ctx.values[ends[1]]
        d = _broadcast(jc.value - ja.value, len(phi), complex)
        d1 = _broadcast(jc.d1 - ja.d1, len(phi), complex)
        valid = ~_broadcast(ctx.invalid, len(phi), bool)
        dd = d.real * d.real + d.imag * d.imag
        return dd, 2.0 * dot(d, d1), valid

    grid, periodic = input_grid(owner)
    _, slope, valid = dd_and_slope(grid)
    slope = np.where(valid, slope, np.nan)
    idx = sign_changes(slope)
    roots = bisect_roots(lambda p: dd_and_slope(p)[1], grid[idx], grid[idx + 1])
    dd, _, ok = dd_and_slope(roots) if roots.size else (roots, roots, roots.astype(bool))
    tol = ASSEMBLY_SLACK * (l1 + l2) ** 2
    touch = ok & (
        (np.abs((l1 + l2) ** 2 - dd) <= tol) | (np.abs(dd - (l1 - l2) ** 2) <= tol)
    )
    found = roots[touch]
    if periodic:
        found = np.mod(found, 2.0 * math.pi)
        found = np.where(np.abs(found - 2.0 * math.pi) < 4 * np.spacing(2.0 * math.pi), 0.0, found)
    result = tuple(sorted(set(float(x) for x in found)))
    _CHANGE_POINTS[key] = result
    return result
