"""Singular positions: the analogs' limit there, and the change points of a continuous branch.

A group is *singular* at a sample where its conditioning (``Kinematics.conditioning``) is below
:data:`~solver.tolerances.SINGULAR`: the linear system for its analogs has (nearly) no unique
solution. Positions stay exact there — they come from the closed form, not from the system.

What the analogs are at a singular sample
    The two-sided limit of the exact analogs along the branch, where it exists: the analogs are
    evaluated exactly at φ₀ ± δ, ±2δ, ±4δ (δ = :data:`~solver.tolerances.LIMIT_STEP`), where the
    group is regular, and the symmetric means are Richardson-extrapolated to δ → 0 (truncation
    of order δ⁶, rounding of order EPS/δ²: about 1e-11 relative). This is the case at a change point
    passed on a continuous branch (a parallelogram at φ = 0 and π), and at a rocker-driven dyad
    that the input moves only tangentially.
    Where the left and right limits differ (a kink: the branch is kept through a change point
    without following it) or do not exist (the edge of an unassemblable range, where the analogs
    grow without bound), the analogs are NaN. Either way the sample is flagged:
    ``Kinematics.singular`` is True there, so no NaN is silent.

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
from typing import TYPE_CHECKING, Any

import numpy as np

from ._backend import NUMPY, dot
from .jet import Jet
from .tolerances import ASSEMBLY_SLACK, LIMIT_AGREEMENT, LIMIT_STEP, ROOT_ITERATIONS, SINGULAR

if TYPE_CHECKING:
    from .groups.base import Context, Group
    from .plan import Plan

__all__ = [
    "refine_singular",
    "change_points",
    "probe",
    "upstream_plan",
    "bisect_roots",
    "sign_changes",
    "turn_grid",
    "branch_sign",
    "GRID",
]

#: Samples of one turn used to bracket roots (then refined by bisection to rounding).
GRID = 4096

_refining: contextvars.ContextVar[bool] = contextvars.ContextVar("refining", default=False)
_CHANGE_POINTS: dict[Any, tuple[float, ...]] = {}


def turn_grid(n: int = GRID) -> np.ndarray:
    """``n + 1`` angles from 0 to 2π inclusive."""
    return np.linspace(0.0, 2.0 * math.pi, n + 1)


def upstream_plan(owner: Any, names: Sequence[str]) -> Plan:
    """The part of ``owner``'s plan that computes ``names``."""
    from .plan import build_plan

    return build_plan(owner.plan.groups, owner.plan.fixed, tuple(names))


def probe(owner: Any, phi: np.ndarray, plan: Plan | None = None) -> Context:
    """Run ``plan`` (default: the owner's) at the angles ``phi``, unassemblable samples flagged."""
    from .groups.base import Context

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


def refine_singular(ctx: Context, group: Group, names: Sequence[str]) -> None:
    """Replace the analogs of ``names`` at ``group``'s singular samples by their limit (or NaN).

    Called by a group at the end of its ``solve``; costs one comparison when nothing is singular.
    """
    cond = ctx.conditioning.get(group.name)
    if cond is None:
        return
    bad = np.asarray(cond < SINGULAR)
    if not bad.any():
        return
    scalar = not ctx.xp.vectorised
    phi = np.atleast_1d(np.asarray(ctx.phi, float))
    bad_idx = np.flatnonzero(np.broadcast_to(bad, phi.shape))
    phi0 = phi[bad_idx]
    n = phi.shape[0]
    limits: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    if ctx.owner is not None and not _refining.get():
        steps = LIMIT_STEP * np.array([1.0, 2.0, 4.0])
        grid = phi0[:, None] + np.concatenate([steps, -steps])[None, :]  # (m, 6)
        pctx = probe(ctx.owner, grid.ravel())
        ok = ~np.broadcast_to(np.asarray(pctx.invalid, bool), grid.ravel().shape).reshape(grid.shape)
        ok = ok.all(axis=1)
        for name in names:
            jet = pctx.values[name]
            limits[name] = tuple(  # type: ignore[assignment]
                _limit(np.asarray(np.broadcast_to(d, grid.ravel().shape + np.shape(d)[1:])), grid.shape, ok)
                for d in (jet.d1, jet.d2)
            )
    for name in names:
        jet = ctx.values[name]
        if scalar:
            d1, d2 = limits[name] if name in limits else (np.array([np.nan]), np.array([np.nan]))
            cast = complex if isinstance(jet.value, complex) else float
            ctx.values[name] = Jet(jet.value, cast(d1[0]), cast(d2[0]))
            continue
        tail = np.shape(jet.value)[1:]
        dtype = complex if np.iscomplexobj(np.asarray(jet.value)) else float
        new = []
        for k, d in enumerate((jet.d1, jet.d2)):
            arr = np.array(np.broadcast_to(np.asarray(d, dtype), (n, *tail)))
            arr[bad_idx] = limits[name][k] if name in limits else np.nan
            new.append(arr)
        ctx.values[name] = Jet(jet.value, new[0], new[1])


def _limit(d: np.ndarray, shape: tuple[int, int], ok: np.ndarray) -> np.ndarray:
    """Two-sided limit at δ → 0 from samples at +δ, +2δ, +4δ, −δ, −2δ, −4δ (NaN where none)."""
    d = d.reshape(shape + d.shape[1:])
    plus, minus = d[:, :3], d[:, 3:]
    sym = 0.5 * (plus + minus)
    r1 = (4.0 * sym[:, 0] - sym[:, 1]) / 3.0
    r2 = (4.0 * sym[:, 1] - sym[:, 2]) / 3.0
    two_sided = (16.0 * r1 - r2) / 15.0
    # one-sided quadratic extrapolation from the nodes 1, 2, 4 (Lagrange weights at 0)
    w = np.array([8.0 / 3.0, -2.0, 1.0 / 3.0]).reshape((1, 3) + (1,) * (d.ndim - 2))
    right, left = (plus * w).sum(axis=1), (minus * w).sum(axis=1)
    size = np.abs(d).max(axis=1)  # the analogs' magnitude near φ₀, per sample (and axis)
    if size.ndim > 1:
        size = size.max(axis=tuple(range(1, size.ndim)), keepdims=True)
    agree = np.abs(right - left) <= LIMIT_AGREEMENT * size
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
def branch_sign(phi: Any, points: Sequence[float]) -> Any:
    """(−1)^(number of change points in (0, φ mod 2π]): +1 on the arc just after φ = 0."""
    if not points:
        return 1.0
    c = np.asarray(points, float)
    at_zero = int(np.count_nonzero(c <= 0.0))
    u = np.mod(phi, 2.0 * math.pi)
    count = np.searchsorted(c, u, side="right") - at_zero
    sign = 1.0 - 2.0 * (count % 2)
    return float(sign) if np.ndim(sign) == 0 else sign


def change_points(owner: Any, group: Any) -> tuple[float, ...]:
    """The φ in [0, 2π) where the RRR dyad ``group`` of ``owner`` passes a change point."""
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

    grid = turn_grid()
    _, slope, valid = dd_and_slope(grid)
    slope = np.where(valid, slope, np.nan)
    idx = sign_changes(slope)
    roots = bisect_roots(lambda p: dd_and_slope(p)[1], grid[idx], grid[idx + 1])
    dd, _, ok = dd_and_slope(roots) if roots.size else (roots, roots, roots.astype(bool))
    tol = ASSEMBLY_SLACK * (l1 + l2) ** 2
    touch = ok & (
        (np.abs((l1 + l2) ** 2 - dd) <= tol) | (np.abs(dd - (l1 - l2) ** 2) <= tol)
    )
    found = np.mod(roots[touch], 2.0 * math.pi)
    found = np.where(np.abs(found - 2.0 * math.pi) < 4 * np.spacing(2.0 * math.pi), 0.0, found)
    result = tuple(sorted(set(float(x) for x in found)))
    _CHANGE_POINTS[key] = result
    return result
