"""One load cycle of a one-input machine in its angle: the map ω₀ ↦ ω(φ₀ + Φ) (solver.dynamics.machine).

With the input angle φ as the independent variable the state is one number, the square of the
rate u = ω²:

    du/dφ = 2·(Q_drive(φ, ω) − h(φ, ω)) / (J(φ) + J_F),      dt/dφ = 1/ω,      ω = √u

(J ε = Q_drive − h with ε = ω·dω/dφ = ½·du/dφ). u passes smoothly through 0 where the machine
stalls (ω would not: dω/dφ = ε/ω is unbounded there), so a stall is u reaching 0 within the cycle,
an ordinary sign test. J_F is an extra flywheel on the input: it adds to J and nothing to h.

The load is piecewise smooth in φ: a table of the input's angle has a kink at each entry (the
engine's gas force: 145 in 720°). The cycle is integrated **breakpoint to breakpoint**, one
scipy DOP853 from kink to kink (the step carried over), so no step straddles a kink and the
error is the tolerance's, not a kink's (integrated across them, the same equation in φ came out
1000 times less accurate). Being one-dimensional, the flow keeps order: a larger ω₀ gives a
larger ω all along the cycle, so the miss ω(φ₀ + Φ) − ω₀ is bracketed by sign (a stall counts as
"too slow") and the periodic ω₀ found by Brent's method within the bracket (machine.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import DOP853

from ..errors import AssemblyError
from ..forces.spec import TableForce

__all__ = ["Cycle", "CycleMap", "breakpoints"]


def breakpoints(model: Any, phi0: float, cycle: float) -> np.ndarray:
    """φ₀, the kinks of the loads in (φ₀, φ₀ + cycle) — the entries of every table of the input's
    angle, repeated over its period — and φ₀ + cycle, increasing."""
    joint = model.full.inputs[0]
    out = [phi0, phi0 + cycle]
    for load in model.spec.loads:
        if not isinstance(load, TableForce) or load.joint != joint:
            continue
        at = np.asarray(load.at, dtype=float)
        period = load.period
        if period:
            first = math.floor((phi0 - at[-1]) / period)
            last = math.ceil((phi0 + cycle - at[0]) / period)
            at = np.concatenate([at + n * period for n in range(first, last + 1)])
        out.extend(float(a) for a in at if phi0 < a < phi0 + cycle)
    knots = np.unique(np.asarray(out))
    # a kink within round-off of another is the same kink: no segment shorter than that
    keep = np.concatenate([[True], np.diff(knots) > 1e-12 * max(1.0, abs(phi0) + cycle)])
    knots = knots[keep]
    knots[-1] = phi0 + cycle
    return knots


@dataclass
class Cycle:
    """One cycle from (φ₀, ω₀): ω at its end, its duration (s) and, when kept, the steps' dense
    interpolants of (u, t) in φ (``(φ_start, φ_end, interpolant)``)."""

    omega_end: float
    period: float
    steps: list[tuple[float, float, Any]]

    def at(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(ω, t) at the angles ``phi`` (increasing, within the cycle)."""
        phi = np.asarray(phi, dtype=float)
        w, t = np.empty(phi.shape), np.empty(phi.shape)
        starts = np.array([s[0] for s in self.steps])
        index = np.clip(np.searchsorted(starts, phi, side="right") - 1, 0, len(self.steps) - 1)
        for i in np.unique(index):
            mask = index == i
            y = self.steps[i][2](phi[mask])
            w[mask], t[mask] = np.sqrt(np.maximum(y[0], 0.0)), y[1]
        return w, t

    def extreme(self, pick: Callable[[np.ndarray], int], samples: int = 8) -> float:
        """ω's extreme (``np.argmin`` or ``np.argmax``) over the cycle: each step's interpolant at
        ``samples`` points, then the best step refined on 201 points of its neighbourhood."""
        grid = np.concatenate([np.linspace(a, b, samples) for a, b, _ in self.steps])
        w, _ = self.at(grid)
        i = int(pick(w))
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        fine = np.linspace(lo, hi, 201)
        wf, _ = self.at(fine)
        return float(wf[int(pick(wf))])


class CycleMap:
    """ω₀ ↦ the cycle from (φ₀, ω₀) of a one-input ``model`` under ``drive`` with an extra
    flywheel ``flywheel`` (see the module docstring); ``run`` returns None where it stalls."""

    def __init__(self, model: Any, drive: Any, *, phi0: float, cycle: float, flywheel: float = 0.0,
                 rtol: float = 1e-10, atol: float = 1e-10) -> None:
        self.model, self.drive, self.flywheel = model, drive, float(flywheel)
        self.knots = breakpoints(model, phi0, cycle)
        self.rtol, self.atol = rtol, atol
        self.runs = 0

    def _rhs(self, phi: float, y: np.ndarray) -> np.ndarray:
        u = float(y[0])
        if not u > 0.0:
            return np.array([math.nan, math.nan])
        w = math.sqrt(u)
        try:
            m, h, _, _ = self.model.state((phi,), (w,), other=False)
        except AssemblyError:
            return np.array([math.nan, math.nan])
        q = self.drive(0.0, (phi,), (w,))[0]
        return np.array([2.0 * (q - h[0]) / (m + self.flywheel), 1.0 / w])

    def run(self, omega0: float, *, keep: bool = False) -> Cycle | None:
        """The cycle from ω₀ > 0, or None where u reaches 0 (a stall) or the integrator fails."""
        self.runs += 1
        if not omega0 > 0.0:
            return None
        y = np.array([omega0 * omega0, 0.0])
        # tolerances on u = ω² and t: relative as given; absolute scaled to their sizes
        atol = np.array([self.atol * omega0 * omega0, self.atol / omega0])
        steps: list[tuple[float, float, Any]] = []
        first: float | None = None
        knots = self.knots
        for a, b in zip(knots[:-1], knots[1:]):
            solver = DOP853(self._rhs, float(a), y, float(b), rtol=self.rtol, atol=atol,
                            first_step=None if first is None else min(first, float(b - a)))
            while solver.status == "running":
                solver.step()
                if solver.status == "failed" or not solver.y[0] > 0.0:
                    return None
                if keep:
                    steps.append((float(solver.t_old), float(solver.t), solver.dense_output()))
            proposed = getattr(solver, "h_abs", None)  # the next step it would take (the last one was cut)
            if proposed is not None and proposed > 0:
                first = float(proposed)
            y = solver.y
        return Cycle(omega_end=math.sqrt(float(y[0])), period=float(y[1]), steps=steps)
