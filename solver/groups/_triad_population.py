"""A population of triads (solver.synthesis): C designs at once, each following its own mode.
The RRR triad (solver.groups.triad) and the slider triad (solver.groups.slider_triad) share
:func:`own_sweeps`; the batched short rows below are the RRR triad's.

solver.synthesis evaluates C candidate designs in one pass of the plan: the input angles are a
(C, S) array and every free parameter a (C, 1) array (solver.synthesis.template). A dyad's closed
form broadcasts over that leading axis; a triad's mode does not — it is a root *followed* along
the samples from θ₀ (the branch rule of solver.groups.triad) — so the branch rule runs per
design, on that design's own roots, with the triad of design c's values (scalars):

* **long rows** (the search's sweep, S ≥ ``LONG``; the slider triad's every row): row c is
  solved exactly as design c's loaded scene solves a sweep of those samples (the same lines: the
  anchors' shortcut where it holds, else every sample's roots), one design at a time;
* **short rows** (the polish's K phases, which a scene solves on its full path too): every real
  root of every sample of every design is one batched eigenvalue problem and Newton polish
  (:func:`~solver.groups.triad.triad_roots`, the parameters shaped (C, 1, 1)), then the branch
  rule per design (``Triad._pick_sweep``) and the analogs batched again.

Either way a design scores as its own scene solves it — the same root at each sample, the same
refusals (no real root; a mode jump at a branch point) — to the bit (the test compares 16 random
designs of three templates on a sweep and on scattered phases). A row whose values give no
ternary link (sides that make no triangle, three shape points on one line: a NaN shape from
``Triad.from_entry``) has no root: it is invalid at every sample (the population runs in mask
mode) — rejected, never a silent NaN.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from ..jet import Jet
from . import _triad_tick as _tick
from .base import Context

__all__ = ["solve_population", "own_sweeps"]


#: Rows of at least this many samples are solved one design at a time as its own scene's sweep
#: (the anchors' shortcut: a few eigenvalue problems per row); shorter rows (the polish's phases)
#: have their roots batched over every design at once.
LONG: int = 32


def _design(group: Any, i: int, rows: int) -> Any:
    """The group of design ``i``'s values (scalars: its lengths, shape and, for the slider triad,
    its guide's origin and direction and its drawn slide), its follow state fresh; None where a value is not finite
    (no ternary link: the whole row is invalid)."""
    changes: dict[str, Any] = {}
    for key in _PARAMETERS:
        if getattr(group, key, None) is None:
            continue
        value = getattr(group, key)
        items = value if isinstance(value, tuple) else (value,)
        kind = complex if key in _COMPLEX else float
        got = tuple(kind(_column(x, rows)[i, 0]) for x in items)
        if key in _OPTIONAL and not np.isfinite(got[0]):
            changes[key] = None
            continue
        if not np.isfinite(np.array(got, complex)).all():
            return None
        changes[key] = got if isinstance(value, tuple) else got[0]
    fresh: dict[str, dict[str, Any]] = {k: {} for k in ("_last", "_end_state") if hasattr(group, k)}
    return replace(group, **changes, **fresh)


#: The parameters a template may make (C, 1) arrays, by field of the triads' groups, and which are complex.
_PARAMETERS: tuple[str, ...] = ("lengths", "shape", "origin", "direction", "slide0")
_COMPLEX: tuple[str, ...] = ("shape", "origin", "direction")
#: ... and which are optional (NaN: none; the slider triad's drawn slide, where its angle is not the drawn one).
_OPTIONAL: tuple[str, ...] = ("slide0",)


def own_sweeps(group: Any, ctx: Context, phi: np.ndarray, *, reason: str = _tick.NO_ROOT) -> None:
    """Row c solved by the group of design c's values exactly as its loaded scene solves a sweep of
    those samples (the same lines: the shortcut where it holds, else every sample's roots). Shared
    by the triads (solver.groups.triad's long rows, solver.groups.slider_triad's every row)."""
    n_rows, n_samples = phi.shape
    joints = group.joints()
    out = {k: [np.full((n_rows, n_samples), np.nan, complex) for _ in range(3)] for k in group.points}
    for k in joints:
        out[k] = [np.full((n_rows, n_samples), np.nan) for _ in range(3)]
    cond = np.full((n_rows, n_samples), np.nan)
    ok = np.zeros((n_rows, n_samples), bool)
    for i in range(n_rows):
        one = _design(group, i, n_rows)
        if one is None:
            continue  # no ternary link: the whole row is invalid
        sub = Context(phi=np.array(phi[i]), xp=ctx.xp, mask=True, scene=ctx.scene)
        for n in group.requires():  # the ends (and a moving guide's points)
            jet = ctx.values[n]
            sub.values[n] = Jet(*(np.array(np.broadcast_to(np.asarray(x), (n_rows, n_samples))[i]) for x in jet))
        with np.errstate(all="ignore"):
            one.solve(sub)
        good = ~np.broadcast_to(np.asarray(sub.invalid, bool), (n_samples,))
        ok[i] = good
        for k in out:
            for m in range(3):
                out[k][m][i] = np.where(good, sub.values[k][m], np.nan)
        cond[i] = np.where(good, sub.conditioning[group.name], np.nan)
    ctx.require(group, ok, reason=reason)
    for k in out:
        ctx.values[k] = Jet(*out[k])
    ctx.conditioning[group.name] = cond


def _column(x: Any, rows: int) -> np.ndarray:
    """A parameter as (C, 1) (a constant repeated)."""
    x = np.asarray(x)
    return np.broadcast_to(x.reshape(-1, 1) if x.ndim else x, (rows, 1))


def solve_population(group: Any, ctx: Context) -> None:
    """Solve the triad ``group`` (parameters (C, 1) arrays or constants) at ``ctx.phi`` (C, S),
    each design following its own mode (module docstring)."""
    from ._triad_math import triad_analogs, triad_points, triad_roots

    phi = np.asarray(ctx.phi, float)
    n_rows, n_samples = phi.shape
    if n_samples >= LONG:
        own_sweeps(group, ctx, phi)
        return
    # the group's formulas take the (C, 1, 1) and (C, 1) parameters as they take scalars
    lengths: Any = tuple(_column(x, n_rows) for x in group.lengths)
    u: Any
    v: Any
    u, v = (_column(x, n_rows).astype(complex) for x in group.shape)
    jets = [ctx.values[n] for n in group.ends]
    full = [Jet(*(np.broadcast_to(np.asarray(x), (n_rows, n_samples)) for x in j)) for j in jets]
    with np.errstate(all="ignore"):
        theta, dd = triad_roots(full[0].value, full[1].value, full[2].value,
                                tuple(x[:, :, None] for x in lengths), u[:, :, None], v[:, :, None])
    th = np.full((n_rows, n_samples), np.nan)
    d = np.full((n_rows, n_samples), np.nan, complex)
    ok = np.zeros((n_rows, n_samples), bool)
    has = np.isfinite(theta).any(axis=-1)
    cols = np.arange(n_samples)
    for i in np.flatnonzero(has.any(axis=1)):
        one = replace(group, lengths=tuple(float(x[i, 0]) for x in lengths), shape=(complex(u[i, 0]), complex(v[i, 0])),
                      _last={}, _end_state={})
        with np.errstate(all="ignore"):
            slots, jumps = one._pick_sweep(phi[i], theta[i], dd[i], *(Jet(*(x[i] for x in j)) for j in full))
        pick = np.maximum(slots, 0)
        good = (slots >= 0) & ~jumps & has[i]
        th[i] = np.where(good, theta[i, cols, pick], np.nan)
        d[i] = np.where(good, dd[i, cols, pick], np.nan)
        ok[i] = good
    ctx.require(group, ok, reason=_tick.NO_ROOT)
    w = np.cos(th) + 1j * np.sin(th)
    with np.errstate(all="ignore"):
        d1, t1, d2, t2, det = triad_analogs(d, w, u, v, *jets)
    for name, jet in zip(group.points, triad_points(d, w, u, v, d1, t1, d2, t2)):
        ctx.values[name] = jet
    if group.joint is not None:
        ctx.values[group.joint] = Jet(th, t1, t2)
    a, b, c = lengths
    ctx.conditioning[group.name] = np.abs(det) / (a * b * c * (np.abs(u) + np.abs(v)))
