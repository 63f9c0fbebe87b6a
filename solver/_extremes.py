"""Extremes of a sampled quantity, refined to the closed form where the scene can be evaluated.

A summary's "max |v| = … at φ = …" read off 1° samples is off by up to (Δφ/2)²·|f''|/2 (0.0999966
for an exact 0.1). Where the output can be evaluated at any φ (one input: the scene's closed form),
:func:`extreme` takes the best sample and narrows the bracket between its two neighbours by
:data:`ZOOM` points per pass, :data:`PASSES` times: the bracket ends 2°/32⁶ ≈ 3e-11 rad wide, so
the value at an interior extreme (where f' = 0) is exact to rounding and its φ to ~1e-11 rad. An
extreme at the edge of the samples' span is the value there, exact. Beside a gap (samples that
do not assemble) whose exact edge is known the bracket reaches the edge: a position's extreme
there is exact, and a rate that is not finite at the edge (a toggle) grows without bound. An
extreme beside a gap of unknown edge, a quantity that is not finite inside its bracket, or
samples that are not an ordered one-input sweep stay as sampled, and the summary says so.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

__all__ = ["EDGE_NUDGE", "Extreme", "extreme", "Evaluate", "Quantity", "PASSES", "ZOOM"]

#: The output at any φ (rad, (M,)): position, velocity, acceleration; NaN where not assemblable.
Evaluate = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]
#: The quantity whose extreme is sought, from (position, velocity, acceleration): (M,) values.
Quantity = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]

#: Points per pass of the zoom (the bracket shrinks by (ZOOM − 1)/2 = 32 per pass; a solve of 65
#: points costs hardly more than one of 17: the passes, not the points, are the cost).
ZOOM = 65
#: Passes of the zoom: 2° / 32⁶ ≈ 3e-11 rad — the value at an interior extreme (error ∝ width²)
#: far below rounding.
PASSES = 6


class Extreme(NamedTuple):
    """``value`` at ``sample`` (the index of the best one) or at ``phi`` (rad, refined); ``exact``: refined or
    at the end of the span (True), or read off the samples (False)."""

    value: float
    sample: int
    phi: float | None
    exact: bool


def extreme(
    values: np.ndarray,
    *,
    largest: bool,
    phi: np.ndarray | None = None,
    evaluate: Evaluate | None = None,
    quantity: Quantity | None = None,
    periodic: bool = False,
    gaps: np.ndarray | None = None,
    edges: np.ndarray | None = None,
) -> Extreme:
    """The largest (or smallest) of ``values`` (finite ones), refined when ``evaluate`` is given.

    ``phi``: the samples' input angles, increasing; ``periodic``: the last sample is followed by
    the first one turn later; ``gaps``: (N,) True after a sample whose successor was not
    assemblable (a hole in the samples); ``edges``: (N, 2) the exact φ where the hole before /
    after each sample begins (NaN where there is none). Beside a hole with a known edge the
    bracket reaches the edge: an extreme there is exact, and a rate that is not finite at the
    edge (a toggle at the end of an unassemblable range) is unbounded: ``value`` ±inf, ``phi`` the
    edge. Beside a hole without one the extreme is the sample's, not refined.
    """
    sign = 1.0 if largest else -1.0
    scored = np.where(np.isfinite(values), sign * values, -np.inf)
    i = int(np.argmax(scored))
    sampled = Extreme(float(values[i]), i, None, False)
    if evaluate is None or quantity is None or phi is None or np.ndim(phi) != 1 or len(phi) < 2:
        return sampled
    n = len(phi)
    if not bool(np.all(np.diff(phi) > 0)):
        return sampled
    hole = np.zeros(n, bool) if gaps is None else np.asarray(gaps, bool)
    edge = np.full((n, 2), np.nan) if edges is None else np.asarray(edges, float)
    left = right = None
    left_edge = right_edge = False
    if i > 0 and not hole[i - 1]:
        left = float(phi[i - 1])
    elif i == 0 and periodic and not hole[-1]:
        left = float(phi[-1]) - 2.0 * math.pi
    elif (i > 0 or periodic) and math.isfinite(edge[i, 0]):
        left, left_edge = _inside(evaluate, float(edge[i, 0]), toward=float(phi[i])), True
    if i < n - 1 and not hole[i]:
        right = float(phi[i + 1])
    elif i == n - 1 and periodic and not hole[-1]:
        right = float(phi[0]) + 2.0 * math.pi
    elif (i < n - 1 or periodic) and math.isfinite(edge[i, 1]):
        right, right_edge = _inside(evaluate, float(edge[i, 1]), toward=float(phi[i])), True
    open_end = (left is None and (i > 0 or periodic)) or (right is None and (i < n - 1 or periodic))
    if open_end:  # beside a gap whose edge is not known: the extreme may lie at the edge
        return sampled
    lo = float(phi[i]) if left is None else left
    hi = float(phi[i]) if right is None else right
    for at, is_edge in ((lo, left_edge), (hi, right_edge)):
        if is_edge and largest and not np.isfinite(quantity(*evaluate(np.array([at])))).all():
            return Extreme(math.inf, i, at, True)  # a rate growing without bound into the gap
    best_x, best_y = float(phi[i]), sign * float(values[i])
    for _ in range(PASSES):
        xs = np.linspace(lo, hi, ZOOM)
        ys = sign * np.asarray(quantity(*evaluate(xs)), float)
        if not np.isfinite(ys).all():
            return sampled
        j = int(np.argmax(ys))
        if ys[j] > best_y:  # (a plateau keeps the sample: no neighbour is "larger")
            best_x, best_y = float(xs[j]), float(ys[j])
        lo, hi = float(xs[max(j - 1, 0)]), float(xs[min(j + 1, ZOOM - 1)])
    if (left is not None and not left_edge and best_x == left) or (
        right is not None and not right_edge and best_x == right
    ):
        return sampled  # larger at a neighbour than at the best sample: not an extreme in between
    return Extreme(sign * best_y, i, best_x, True)


#: How far inside a gap's edge (rad) a position is sought when the edge itself does not assemble.
EDGE_NUDGE = 1e-12


def _inside(evaluate: Evaluate, edge: float, *, toward: float) -> float | None:
    """``edge``, or the nearest φ toward ``toward`` (within EDGE_NUDGE) where the scene assembles."""
    step = math.copysign(1.0, toward - edge) * max(abs(edge), 1.0) * float(np.finfo(float).eps)
    x = edge
    while abs(x - edge) <= EDGE_NUDGE:
        if np.isfinite(evaluate(np.array([x]))[0]).all():
            return x
        x += step
        step *= 4.0
    return None
