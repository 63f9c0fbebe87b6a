"""A population of triads (solver.synthesis): C designs at once, each its own sweep.

solver.synthesis evaluates C candidate designs in one pass of the plan: the input angles are a
(C, S) array and every free parameter a (C, 1) array (solver.synthesis.template). A dyad's closed
form broadcasts over that leading axis; a triad's mode does not — it is a root *followed* along
the samples from θ₀ (the branch rule of solver.groups.triad), so it is decided per design. Row c
is solved by the triad of design c's own values (scalars) exactly as a loaded scene solves a
sweep of those S samples — the same roots (eigenvalues and the anchors' shortcut), the same
branch rule, the same refusals — so a design scores as its own scene solves it (the test
compares them to the bit). A row whose values give no ternary link (sides that make no triangle,
three shape points on one line: NaN shape from ``Triad.from_entry``) or no real root at a sample
is invalid there (the population runs in mask mode): rejected, never a silent NaN.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from ..jet import Jet
from . import _triad_tick as _tick
from .base import Context

__all__ = ["solve_population"]


def solve_population(group: Any, ctx: Context) -> None:
    """Solve the triad ``group`` (parameters (C, 1) arrays or constants) at ``ctx.phi`` (C, S),
    one design per row (module docstring)."""
    phi = np.asarray(ctx.phi, float)
    n_rows, n_samples = phi.shape
    (a, b, c), (u, v) = group.lengths, group.shape

    def row(x: Any, i: int) -> Any:
        x = np.asarray(x)
        return np.broadcast_to(x, (n_rows, x.shape[1]))[i] if x.ndim == 2 else x

    def first(x: Any, i: int) -> Any:  # design i's value of a (C, 1) parameter (or the constant)
        return np.asarray(row(x, i)).reshape(-1)[0]

    def sample(x: Any, i: int) -> np.ndarray:
        return np.array(np.broadcast_to(row(x, i), (n_samples,)))

    names = (*group.points, *(() if group.joint is None else (group.joint,)))
    out = {k: [np.full((n_rows, n_samples), np.nan, complex) for _ in range(3)] for k in group.points}
    if group.joint is not None:
        out[group.joint] = [np.full((n_rows, n_samples), np.nan) for _ in range(3)]
    cond = np.full((n_rows, n_samples), np.nan)
    ok = np.zeros((n_rows, n_samples), bool)
    for i in range(n_rows):
        lengths = (float(first(a, i)), float(first(b, i)), float(first(c, i)))
        shape = (complex(first(u, i)), complex(first(v, i)))
        if not all(math.isfinite(x) for x in (*lengths, shape[0].real, shape[1].real, shape[1].imag)):
            continue  # no ternary link: the whole row is invalid
        one = replace(group, lengths=lengths, shape=shape, _last={}, _end_state={})
        sub = Context(phi=np.array(phi[i]), xp=ctx.xp, mask=True, scene=ctx.scene)
        for n in group.ends:
            jet = ctx.values[n]
            sub.values[n] = Jet(sample(jet.value, i), sample(jet.d1, i), sample(jet.d2, i))
        with np.errstate(all="ignore"):
            one.solve(sub)
        good = ~np.broadcast_to(np.asarray(sub.invalid, bool), (n_samples,))
        ok[i] = good
        for k in names:
            for m in range(3):
                out[k][m][i] = np.where(good, sub.values[k][m], np.nan)
        cond[i] = np.where(good, sub.conditioning[group.name], np.nan)
    ctx.require(group, ok, reason=_tick.NO_ROOT)
    for k in names:
        ctx.values[k] = Jet(*out[k])
    ctx.conditioning[group.name] = cond
