"""Extremes of a sampled quantity, refined to the closed form where the scene can be evaluated.

A summary's "max |v| = … at φ = …" read off 1° samples is off by up to (Δφ/2)²·|f''|/2 (0.0999966
for an exact 0.1). Where the output can be evaluated at any φ (one input: the scene's closed form),
:func:`extreme` takes the best sample and narrows the bracket between its two neighbours by
:data:`ZOOM` points per pass, :data:`PASSES` times: the bracket ends 2°/16⁸ ≈ 8e-12 rad wide, so
the value at an interior extreme (where f' = 0) is exact to rounding and its φ to ~1e-11 rad. An
extreme at the edge of the samples' span is the value there, exact. An extreme next to a sample
that is not assemblable (the rate growing without bound into a gap), a quantity that is not
finite in its bracket, or samples that are not an ordered one-input sweep stay as sampled, and the
summary says so.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

__all__ = ["Extreme", "extreme", "Evaluate", "Quantity", "PASSES", "ZOOM"]

#: The output at any φ (rad, (M,)): position, velocity, acceleration; NaN where not assemblable.
Evaluate = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]
#: The quantity whose extreme is sought, from (position, velocity, acceleration): (M,) values.
Quantity = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]

#: Points per pass of the zoom (the bracket shrinks by (ZOOM − 1)/2 per pass).
ZOOM = 17
#: Passes of the zoom: 2° / 8^12 — far below rounding for the value at an interior extreme.
PASSES = 12


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
) -> Extreme:
    """The largest (or smallest) of ``values`` (finite ones), refined when ``evaluate`` is given.

    ``phi``: the samples' input angles, increasing; ``periodic``: the last sample is followed by
    the first one turn later; ``gaps``: (N,) True after a sample whose successor was not
    assemblable (a hole in the samples: the extreme there is the sample's, not refined).
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
    left = right = None
    if i > 0 and not hole[i - 1]:
        left = float(phi[i - 1])
    elif i == 0 and periodic and not hole[-1]:
        left = float(phi[-1]) - 2.0 * math.pi
    if i < n - 1 and not hole[i]:
        right = float(phi[i + 1])
    elif i == n - 1 and periodic and not hole[-1]:
        right = float(phi[0]) + 2.0 * math.pi
    open_end = (left is None and (i > 0 or periodic)) or (right is None and (i < n - 1 or periodic))
    if open_end:  # beside a gap: the supremum lies at the gap's edge, not at a sample
        return sampled
    lo = float(phi[i]) if left is None else left
    hi = float(phi[i]) if right is None else right
    best_x, best_y = float(phi[i]), sign * float(values[i])
    for _ in range(PASSES):
        xs = np.linspace(lo, hi, ZOOM)
        ys = sign * np.asarray(quantity(*evaluate(xs)), float)
        if not np.isfinite(ys).all():
            return sampled
        j = int(np.argmax(ys))
        if ys[j] >= best_y:
            best_x, best_y = float(xs[j]), float(ys[j])
        lo, hi = float(xs[max(j - 1, 0)]), float(xs[min(j + 1, ZOOM - 1)])
    if (left is not None and best_x == left) or (right is not None and best_x == right):
        return sampled  # larger at a neighbour than at the best sample: not an extreme in between
    return Extreme(sign * best_y, i, best_x, True)
