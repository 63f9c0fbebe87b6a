"""One run of :func:`solver.dynamics.simulate` on the own step loop (solver.dynamics._stepping):
samples, events located on the steps' interpolants, the run's dense output.

What scipy's ``solve_ivp`` did for ``simulate`` before (its events, ``t_eval``, dense output),
with the integrator's steps placed on the tables' kinks and without numpy's per-call overhead on
a state of four numbers. The toggle event reads the conditioning the last evaluation left
(the step's end), not another pass.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import AssemblyError
from ..tolerances import DYNAMICS_TOGGLE
from ._breaks import breaks_of
from ._rk import Dense
from ._stepping import Integrator, StepFailure, _root

__all__ = ["Outcome", "Solution", "run"]


class Solution:
    """The run's dense output: y(t) (n,) for a time, (n, N) for N times, from the interpolant of
    the step that holds each time (or of the piece: a friction run's segments and held states)."""

    def __init__(self, steps: Sequence[Dense]) -> None:
        self.steps = list(steps)
        self.starts = [d.t_old for d in self.steps]
        self.t_min = self.starts[0] if self.steps else 0.0
        self.t_max = self.steps[-1].t if self.steps else 0.0

    def _one(self, t: float) -> list[float]:
        i = max(0, min(bisect.bisect_right(self.starts, t) - 1, len(self.steps) - 1))
        return self.steps[i](t)

    def __call__(self, t: Any) -> np.ndarray:
        arr = np.asarray(t, float)
        if arr.ndim == 0:
            return np.array(self._one(float(arr)))
        return np.array([self._one(float(v)) for v in arr.ravel()]).T.reshape(-1, *arr.shape)


@dataclass
class Outcome:
    """What :func:`run` gives :func:`solver.dynamics.simulate`: the samples ``t`` (N,), ``y``
    (n, N); ``status`` 0 (t_end), 1 (an event: ``hit`` its index, the last sample at it), −1 (a
    step could not be made: ``fault`` (group, reason, q) — q the state's coordinates); the
    evaluations; the dense output."""

    t: np.ndarray
    y: np.ndarray
    status: int
    hit: int | None
    fault: tuple[str, str, list[float]] | None
    nfev: int
    sol: Solution
    #: per sample, y' there where the integrator had it (a step's end: its last evaluation), else None
    rates: list[list[float] | None] | None = None


def run(
    eq: Any, t_end: float, y0: Sequence[float], *, method: str, rtol: float, atol: float, step: float | None,
    max_step: float, events: Sequence[tuple[Callable[[float, Any], float], int]], t_eval: np.ndarray | None,
) -> Outcome:
    """Integrate ``eq`` (solver.dynamics.integrate.Equation) from y0 at t = 0 to ``t_end``.
    ``events``: (g(t, y), direction) each, terminal; the first is the toggle (g: the conditioning
    − DYNAMICS_TOGGLE, read at step ends from the last evaluation)."""
    k = eq.k
    integ = Integrator(eq.rates, 0.0, y0, k=k, method=method, rtol=rtol, atol=atol, step=step, max_step=max_step,
                       breaks=breaks_of(eq.model))

    def value(i: int, t: float, y: list[float], *, end: bool = False) -> float:
        g, _ = events[i]
        if i == 0:
            if end:
                return eq.last_conditioning - DYNAMICS_TOGGLE
            try:
                return eq.model.instant(y[:k], y[k:2 * k])[2] - DYNAMICS_TOGGLE
            except AssemblyError:
                return -DYNAMICS_TOGGLE
        return float(g(t, y if plain[i] else np.asarray(y)))

    plain = [bool(getattr(g, "plain", False)) for g, _ in events]
    g_old = [value(i, 0.0, integ.y, end=True) for i in range(len(events))]
    ts: list[float] = []
    ys: list[list[float]] = []
    rs: list[list[float] | None] = []
    sample = 0
    if t_eval is None:
        ts.append(0.0)
        ys.append(list(integ.y))
        rs.append(integ.fy)
    steps: list[Dense] = []
    status, hit, fault = 0, None, None
    while integ.t < t_end:
        t_old = integ.t
        try:
            dense = integ.step(t_end)
        except StepFailure as failure:
            status, fault = -1, (failure.group, failure.reason, list(failure.y[:k]))
            break
        steps.append(dense)
        t_new, y_new = integ.t, integ.y
        g_new = [value(i, t_new, y_new, end=True) for i in range(len(events))]
        first: tuple[float, int] | None = None
        for i, (_, direction) in enumerate(events):
            a, b = g_old[i], g_new[i]
            up, down = a < 0.0 <= b, a > 0.0 >= b
            if (up and direction >= 0) or (down and direction <= 0):
                tau = _root(lambda s, i=i, t0=t_old, d=dense: value(i, t0 + s, d(t0 + s)), t_new - t_old)
                if first is None or tau < first[0]:
                    first = (tau, i)
        t_stop = t_new if first is None else t_old + first[0]
        if t_eval is None:
            if first is None:
                ts.append(t_new)
                ys.append(list(y_new))
                rs.append(integ.fy)
        else:
            while sample < t_eval.size and t_eval[sample] <= t_stop:
                ts.append(float(t_eval[sample]))
                on_end = t_eval[sample] == t_new
                ys.append(list(y_new) if on_end else dense(float(t_eval[sample])))
                rs.append(integ.fy if on_end else None)
                sample += 1
        if first is not None:
            status, hit = 1, first[1]
            if not ts or ts[-1] < t_stop:
                ts.append(t_stop)
                ys.append(dense(t_stop))
                rs.append(None)
            dense.t = t_stop
            break
        g_old = g_new
    if status == -1 and integ.t > (ts[-1] if ts else -math.inf):
        ts.append(integ.t)  # the last step made, past the last requested sample
        ys.append(list(integ.y))
        rs.append(integ.fy)
    y_arr = np.array(ys, float).T if ys else np.empty((len(y0), 0))
    return Outcome(np.array(ts, float), y_arr, status, hit, fault, integ.nfev, Solution(steps), rs)
