"""What an engineer asks of a mechanism over one turn: Grashof class, transmission angle,
singular positions (toggles, change points) and the dead centres of its outputs.

Every angle here is found in closed form or by bisection on an exact quantity to the last bit,
never read off a sampled sweep:

* Grashof class of a four-bar (a crank and an RRR dyad against a fixed pivot): s + l against
  p + q (s shortest, l longest link, ground included); equality within
  :data:`~solver.tolerances.GRASHOF_EQUAL` is a change-point four-bar.
* Transmission angle μ of an RRR dyad, the angle at B between BA and BC:
  cos μ = (l₁² + l₂² − D²)/(2·l₁·l₂), D = |C − A|; its range over the turn comes from the
  extremes of D² (zeros of dD²/dφ, bisected) and the edges of unassemblable ranges (μ = 0 or π).
* Toggles (conditioning 0): the edges of unassemblable ranges (solver.assembly) and the change
  points, where the closure's discriminant has a double zero (solver.singular).
* Dead centres of an output joint: zeros of its velocity analog dq/dφ, bracketed on a grid of
  one turn and bisected to the last bit (e.g. a rocker's extreme positions).

A scene driven by an actuator is analysed over its stroke [s_min, s_max] (m) instead of a turn
(solver.singular.input_grid); the stroke's ends are limits, not singular positions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .assembly import crank_and_pivot, unassemblable_intervals
from .singular import bisect_roots, change_points, input_grid, probe, sign_changes, upstream_plan
from .tolerances import GRASHOF_EQUAL, STATIONARY

if TYPE_CHECKING:
    from .scene import Scene

__all__ = ["Grashof", "grashof", "transmission_range", "toggles", "dead_centres"]


@dataclass(frozen=True)
class Grashof:
    """A four-bar's Grashof class: ``kind`` and the sums it follows from (m)."""

    kind: str
    s_plus_l: float
    p_plus_q: float

    def __str__(self) -> str:
        rel = "=" if self.kind.startswith("change-point") else ("<" if self.s_plus_l < self.p_plus_q else ">")
        return f"{self.kind} (s + l = {self.s_plus_l:.6g} m {rel} p + q = {self.p_plus_q:.6g} m)"


def grashof(scene: Scene, group: Any) -> Grashof | None:
    """The Grashof class of the four-bar formed by ``group`` (an RRR dyad), or None."""
    found = crank_and_pivot(scene, group)
    if found is None:
        return None
    crank, o, c = found
    links = {"ground": abs(c - o), "crank": crank.length, "coupler": group.lengths[0], "rocker": group.lengths[1]}
    ordered = sorted(links.values())
    s_l, p_q = ordered[0] + ordered[3], ordered[1] + ordered[2]
    shortest = min(links, key=lambda k: links[k])
    if abs(s_l - p_q) <= GRASHOF_EQUAL * ordered[3]:
        kind = "change-point four-bar (Grashof-neutral: the dyad's assemblies meet twice a turn)"
    elif s_l < p_q:
        kind = {
            "crank": "Grashof crank-rocker",
            "ground": "Grashof double-crank (drag link)",
            "coupler": "Grashof double-rocker",
            "rocker": "Grashof rocker-crank",
        }[shortest]
    else:
        kind = "non-Grashof triple-rocker (no link turns fully; the crank cannot make a full turn)"
    return Grashof(kind, s_l, p_q)


def _dd(scene: Scene, group: Any, phi: np.ndarray, plan: Any) -> tuple[np.ndarray, np.ndarray]:
    ctx = probe(scene, phi, plan)
    ja, jc = ctx.values[group.ends[0]], ctx.values[group.ends[1]]
    d = np.broadcast_to(jc.value - ja.value, phi.shape)
    d1 = np.broadcast_to(jc.d1 - ja.d1, phi.shape)
    bad = np.broadcast_to(np.asarray(ctx.invalid, bool), phi.shape)
    dd = np.where(bad, np.nan, d.real**2 + d.imag**2)
    return dd, np.where(bad, np.nan, 2.0 * (d.real * d1.real + d.imag * d1.imag))


def transmission_range(scene: Scene, group: Any) -> tuple[float, float] | None:
    """(min, max) of the transmission angle μ ∈ [0, π] (rad) of an RRR dyad over the turn."""
    if getattr(group, "kind", "") != "rrr":
        return None
    plan = upstream_plan(scene, group.ends)
    grid, _ = input_grid(scene)
    _, slope = _dd(scene, group, grid, plan)
    idx = sign_changes(slope)
    extremes = bisect_roots(lambda p: _dd(scene, group, p, plan)[1], grid[idx], grid[idx + 1])
    dd, _ = _dd(scene, group, np.concatenate([grid, extremes]), plan)
    l1, l2 = group.lengths
    dd = np.clip(dd[np.isfinite(dd)], (l1 - l2) ** 2, (l1 + l2) ** 2)
    if dd.size == 0:
        return None
    cos_mu = np.clip((l1 * l1 + l2 * l2 - dd) / (2.0 * l1 * l2), -1.0, 1.0)
    mu = np.arccos(cos_mu)
    lo, hi = float(mu.min()), float(mu.max())
    for a, b in unassemblable_intervals(scene, group.name):
        # at a gap's edges the dyad is folded (μ = 0) or stretched (μ = π)
        edge = _dd(scene, group, np.array([a, b]), plan)[0]
        for v in edge[np.isfinite(edge)]:
            m = 0.0 if abs(v - (l1 - l2) ** 2) < abs(v - (l1 + l2) ** 2) else math.pi
            lo, hi = min(lo, m), max(hi, m)
    return lo, hi


def toggles(scene: Scene, group: Any) -> dict[str, tuple[float, ...]]:
    """φ of a group's singular positions over the turn: ``{"change points": …, "range edges": …}``."""
    out: dict[str, tuple[float, ...]] = {}
    if getattr(group, "kind", "") == "rrr":
        cps = change_points(scene, group)
        if cps:
            out["change points"] = cps
    grid, periodic = input_grid(scene, 1)
    if periodic:
        edges = sorted({round(x % (2 * math.pi), 15) for iv in unassemblable_intervals(scene, group.name) for x in iv})
    else:  # a stroke: the ends of its range are limits, not singular positions
        ends = (float(grid[0]), float(grid[-1]))
        edges = sorted({x for iv in unassemblable_intervals(scene, group.name) for x in iv if x not in ends})
    if edges:
        out["range edges"] = tuple(edges)
    return out


def dead_centres(scene: Scene, joint: str) -> tuple[float, ...]:
    """φ in [0, 2π) where output joint ``joint`` stops (dq/dφ = 0), over the assemblable turn."""
    one = scene.with_outputs(points=(), joints=(joint,))

    def dq(phi: np.ndarray) -> np.ndarray:
        k = one.solve(phi, mask=True)
        v = np.array(k.joint(joint).velocity, float)
        v[~np.asarray(k.valid, bool) | k.singular] = np.nan
        return v

    grid, periodic = input_grid(scene)
    values = dq(grid)
    top = np.nanmax(np.abs(values)) if np.isfinite(values).any() else 0.0
    if top <= STATIONARY:  # the joint does not move (a parallelogram's coupler): no dead centres
        return ()
    idx = sign_changes(values)
    roots = bisect_roots(dq, grid[idx], grid[idx + 1])
    if periodic:
        roots = np.mod(roots, 2.0 * math.pi)
        roots = np.where(np.abs(roots - 2.0 * math.pi) < 8 * np.spacing(2.0 * math.pi), 0.0, roots)
    return tuple(sorted({float(r) for r in roots}))
