"""Where a mechanism cannot be assembled: exact φ intervals per group.

Closed form where the geometry allows, root-finding on the closed-form residual otherwise; never
by sampling which angles fail.

* RRR dyad driven by a crank about O against a fixed pivot C (a four-bar): with v = C − O,
  g = |v|, θ = arg v and r the crank, D² = |C − A(φ)|² = g² + r² − 2gr·cos(φ − θ), and the
  dyad closes iff (l₁ − l₂)² ≤ D² ≤ (l₁ + l₂)², i.e.
  ``(g² + r² − (l₁+l₂)²)/(2gr) ≤ cos(φ − θ) ≤ (g² + r² − (l₁−l₂)²)/(2gr)``: each violated
  bound is one interval, its ends ``θ ± arccos(bound)``.
* Any other RRR or RRP group: its residual R(φ) (≥ 0 where it closes; the group's
  ``assembly_residual``, with an exact dR/dφ) is evaluated on a grid of one turn together with
  every extreme of R (zeros of dR/dφ, bisected to the last bit), so a dip narrower than the grid
  is still seen; each sign change of R is then bisected to the last bit.

* An actuator between fixed points (solver.groups.actuator): closed form, |s − l| ≤ D ≤ s + l.

An interval is ``(lo, hi)`` with ``0 ≤ lo < 2π`` and ``lo < hi < lo + 2π``: one that contains
φ = 0 has ``hi > 2π`` (e.g. ``(5.8, 6.9)``). Only the group's own failures are reported, at the
angles where the groups before it can be assembled. A scene driven by an actuator has strokes
(m) instead: the grid spans its stroke [s_min, s_max], which bounds every interval (no wrap).
"""

from __future__ import annotations

import math
from typing import Any, TypeAlias

import numpy as np

from .groups.actuator import stroke_intervals
from .singular import bisect_roots, input_grid, probe, sign_changes, upstream_plan
from .tolerances import ASSEMBLY_SLACK

#: a :class:`solver.scene.Scene`; not imported, since the scene sits above this module (it
#: calls this one): dependencies point one way, annotations included.
Scene: TypeAlias = Any

__all__ = ["unassemblable_intervals", "gaps", "crank_and_pivot"]

TWO_PI = 2.0 * math.pi
_CACHE: dict[Any, list[tuple[float, float]]] = {}


def unassemblable_intervals(scene: Scene, group: str) -> list[tuple[float, float]]:
    """Open intervals of φ (one turn) where ``group`` cannot be assembled."""
    g = _group(scene, group)
    if getattr(g, "kind", "") == "actuator":
        fixed = scene.plan.fixed
        if g.base in fixed and g.pivot in fixed:
            return stroke_intervals(g, complex(fixed[g.base]), complex(fixed[g.pivot]))
        return []
    if g is None or not hasattr(g, "assembly_residual"):
        return []
    key = (g, scene.plan.groups, tuple(sorted((k, str(v)) for k, v in scene.plan.fixed.items())))
    if key not in _CACHE:
        closed = _four_bar_intervals(scene, g)
        _CACHE[key] = closed if closed is not None else _residual_intervals(scene, g)
    return list(_CACHE[key])


def gaps(scene: Scene) -> dict[str, list[tuple[float, float]]]:
    """Every group of the scene's plan that has unassemblable intervals, with them."""
    out = {}
    for g in scene.plan.groups:
        iv = unassemblable_intervals(scene, g.name)
        if iv:
            out[g.name] = iv
    return out


def _group(scene: Scene, name: str) -> Any:
    return next((g for g in scene.plan.groups if g.name == name), None)


def crank_and_pivot(scene: Scene, group: Any) -> tuple[Any, complex, complex] | None:
    """For an RRR dyad between a crank's point and a fixed pivot: (crank, O, C); else None."""
    if getattr(group, "kind", "") != "rrr":
        return None
    fixed = scene.plan.fixed
    for a, c in (group.ends, group.ends[::-1]):
        crank: Any = next((g for g in scene.plan.groups if g.kind == "crank" and getattr(g, "point", None) == a), None)
        if crank is not None and crank.drives and crank.plain and c in fixed and crank.center in fixed:
            return crank, complex(fixed[crank.center]), complex(fixed[c])
    return None


def _four_bar_intervals(scene: Scene, group: Any) -> list[tuple[float, float]] | None:
    found = crank_and_pivot(scene, group)
    if found is None:
        return None
    crank, o, c = found
    v = c - o
    g, r, theta = abs(v), crank.length, math.atan2(v.imag, v.real)
    if g == 0.0:
        return None  # D = r for every φ: assemblable everywhere or nowhere; the residual decides
    l1, l2 = group.lengths
    base = g * g + r * r
    out: list[tuple[float, float]] = []
    hi_bound = (base - (l1 - l2) ** 2) / (2.0 * g * r)  # cos(φ − θ) ≤ this
    lo_bound = (base - (l1 + l2) ** 2) / (2.0 * g * r)  # cos(φ − θ) ≥ this
    if hi_bound < -1.0 or lo_bound > 1.0:
        return [(0.0, TWO_PI)]  # D never reaches the band: the dyad closes nowhere
    # a residual within its rounding is a touch (a change point), not a gap: judged where D is
    # smallest (φ = θ) and largest (φ = θ + π) exactly as the solve judges it (rrr.closure_slack)
    from .groups.rrr import closure_slack

    near, far = (g - r) ** 2, (g + r) ** 2
    size_near, size_far = abs(o + r * v / g) + abs(c), abs(o - r * v / g) + abs(c)
    folded = (l1 - l2) ** 2 > near and ((l1 + l2) ** 2 - near) * (near - (l1 - l2) ** 2) < -closure_slack(
        (l1, l2), near, size_near)
    if folded:  # D² = (g − r)² + 4gr·sin²(x/2) < (l₁ − l₂)²: |x| < 2·asin(…), exact for a tiny gap
        dl, dg = abs(l1 - l2), abs(g - r)
        half = 2.0 * math.asin(min(1.0, math.sqrt((dl - dg) * (dl + dg) / (4.0 * g * r))))
        out.append(_interval(theta - half, theta + half))
    stretched = far > (l1 + l2) ** 2 and ((l1 + l2) ** 2 - far) * (far - (l1 - l2) ** 2) < -closure_slack(
        (l1, l2), far, size_far)
    if lo_bound > -1.0 and stretched:
        half = math.acos(lo_bound)
        out.append(_interval(theta + half, theta + TWO_PI - half))
    return sorted(out)


def _interval(lo: float, hi: float) -> tuple[float, float]:
    shift = math.floor(lo / TWO_PI) * TWO_PI
    return lo - shift, hi - shift


def _residual_intervals(scene: Scene, group: Any) -> list[tuple[float, float]]:
    plan = upstream_plan(scene, group.requires())
    scale: list[float] = [1.0]

    def residual(phi: np.ndarray, *, slope: bool = False) -> np.ndarray:
        ctx = probe(scene, phi, plan)
        r, r1, s = group.assembly_residual(ctx.values)
        scale[0] = s
        out = np.array(np.broadcast_to(r1 if slope else r, phi.shape), float)
        out[np.broadcast_to(np.asarray(ctx.invalid, bool), phi.shape)] = np.nan
        return out

    grid, periodic = input_grid(scene)
    slope = residual(grid, slope=True)
    idx = sign_changes(slope)
    extremes = bisect_roots(lambda p: residual(p, slope=True), grid[idx], grid[idx + 1])
    phi = np.unique(np.concatenate([grid, extremes]))
    value = residual(phi)
    bad = value < -ASSEMBLY_SLACK * scale[0]
    if not bad.any():
        return []
    if bad.all():
        return [(float(grid[0]), float(grid[-1]))]
    # ends: between consecutive candidates where the verdict changes, bisect R's sign
    change = np.flatnonzero(bad[:-1] != bad[1:])
    ends = bisect_roots(residual, phi[change], phi[change + 1])
    where = change.tolist()  # Python ints, to index with
    starts = [float(e) for e, i in zip(ends, where) if bad[i + 1]]
    stops = [float(e) for e, i in zip(ends, where) if bad[i]]
    if not periodic:  # a stroke: an interval at either end of the stroke ends there
        starts = ([float(grid[0])] if bad[0] else []) + starts
        stops = stops + ([float(grid[-1])] if bad[-1] else [])
        out = list(zip(starts, stops))
    elif bad[0]:  # wraps through φ = 0 (grid[0] = 0 and grid[-1] = 2π are the same position)
        out = list(zip(starts[:-1], stops[1:]))
        out.append((starts[-1], stops[0] + TWO_PI))
    else:
        out = list(zip(starts, stops))
    return sorted(out)
