"""Where a mechanism cannot be assembled: φ intervals per group.

A first version: the intervals are located on a fine grid of one turn and refined by bisection
on the closed-form scalar path to the last bit, so each end is exact to rounding.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .scene import Scene

__all__ = ["unassemblable_intervals"]

_GRID = 4096


def unassemblable_intervals(scene: Scene, group: str) -> list[tuple[float, float]]:
    """Open intervals of φ in [0, 2π) where ``group`` (or a group before it) fails."""
    probe = scene.with_outputs(points=scene.point_names, joints=())

    def ok(phi: float) -> bool:
        return probe.assemblable(phi)

    grid = np.linspace(0.0, 2 * math.pi, _GRID + 1)
    good = [ok(float(p)) for p in grid]
    intervals: list[tuple[float, float]] = []
    start: float | None = None if good[0] else 0.0
    for i in range(1, len(grid)):
        if good[i - 1] and not good[i]:
            start = _edge(ok, float(grid[i - 1]), float(grid[i]))
        elif not good[i - 1] and good[i]:
            intervals.append((start if start is not None else 0.0, _edge(ok, float(grid[i - 1]), float(grid[i]))))
            start = None
    if start is not None:
        intervals.append((start, 2 * math.pi))
    return intervals


def _edge(ok, lo: float, hi: float) -> float:  # type: ignore[no-untyped-def]
    """Bisect the boundary between ``lo`` and ``hi`` (ok differs at the ends) to rounding."""
    ok_lo = ok(lo)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if ok(mid) == ok_lo:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)
