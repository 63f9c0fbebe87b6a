"""Many polishes at once: a batched Levenberg–Marquardt on B starts in one pass of the plan.

The residuals and Jacobian are :mod:`~.polish`'s (the same ``_rows``: targets' misses over the
task's size; the phases' columns exact from the analogs, the design values' central differences
with the step ∛ε·max(|x|, range/100)), for B starts together: one population of B·(2n + 1)
designs, each at its own phases, is one evaluation of all B residual vectors and Jacobians.
``scipy.optimize.least_squares`` solves one problem per call, and on the four-bar each of its
evaluations costs about as much (Python overhead of building the population) as 100 starts'
here; the search uses this batch to try hundreds of cheap starts (search.py, the seeded stage)
and hands the few that end exact to the regular polish (bounded, to round-off) and check.

Iteration, per start (z = (x, φ) or x with timing; r, J at z; λ its damping):

    (JᵀJ + λ·diag(JᵀJ) + λ·δ·I) Δ = −Jᵀr,   z' = z + Δ (the free values clipped into their bounds;
                                             an angle free over a whole turn is not clipped)

z' is taken when ½‖r(z')‖² < ½‖r(z)‖² (λ ← λ/3), else λ ← 4λ. A start leaves the batch once its
cost is at round-off (``ROUND_OFF`` ulps per residual, as the polish), when λ exceeds 1e12 (no
descent left: a local minimum), or when its cost fell by less than 1 % over ``STALL``
iterations while still above ``NEAR`` (a minimum that is not a zero).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..tolerances import EPS
from .polish import ROUND_OFF, _rows
from .population import Goal, run
from .template import Template

__all__ = ["Batch", "polish_batch"]

_STEP = EPS ** (1.0 / 3.0)
#: Iterations over which a start must lower its cost by 1 % to stay in the batch.
STALL = 8
#: Above this RMS residual (relative to the targets' size) a stalled start is dropped.
NEAR = 1e-6


@dataclass
class Batch:
    """The ends of B starts: design values (B, n), phases (B, K) and ½‖r‖² (B,)."""

    x: np.ndarray
    phases: np.ndarray
    cost: np.ndarray


def _evaluate(template: Template, goal: Goal, targets: np.ndarray, x: np.ndarray, phases: np.ndarray,
              h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Residuals (B, m) and Jacobians (B, m, p) of the starts at (x, phases), each start against
    its own ``targets`` (B, K, w)."""
    b, n = x.shape
    k = phases.shape[1]
    eye = np.eye(n)
    xs = np.concatenate([x[:, None, :], x[:, None, :] + h[:, None, :] * eye, x[:, None, :] - h[:, None, :] * eye],
                        axis=1)  # (B, 2n + 1, n)
    ph = np.repeat(phases[:, None, :], 2 * n + 1, axis=1)
    ctx = run(template, xs.reshape(-1, n), ph.reshape(-1, k), goal.names)
    r, d1 = _rows(replace(goal, targets=np.repeat(targets, 2 * n + 1, axis=0)), ctx, b * (2 * n + 1), k)
    r = r.reshape(b, 2 * n + 1, -1)
    m = r.shape[2]
    jac_x = ((r[:, 1 : n + 1] - r[:, n + 1 :]) / (2.0 * h[:, :, None])).transpose(0, 2, 1)  # (B, m, n)
    if goal.at is None:
        d1 = d1.reshape(b, 2 * n + 1, -1)[:, 0]  # (B, m)
        rows = m // k
        jac_p = np.zeros((b, m, k))
        idx = np.arange(k)
        for j in range(rows):
            jac_p[:, j * k + idx, idx] = d1[:, j * k + idx]
        jac = np.concatenate([jac_x, jac_p], axis=2)
    else:
        jac = jac_x
    return r[:, 0], np.nan_to_num(jac, nan=0.0, posinf=1e6, neginf=-1e6)


def polish_batch(template: Template, goal: Goal, x0: np.ndarray, phases0: np.ndarray, *,
                 iterations: int = 40) -> Batch:
    """Levenberg–Marquardt from each row of (x0, phases0) at once (module docstring)."""
    x = np.clip(np.asarray(x0, float), template.lo, template.hi)
    phases = np.array(np.asarray(phases0, float) if goal.at is None else
                      np.broadcast_to(goal.at, (x.shape[0], goal.at.size)), float)
    width = np.maximum(template.hi - template.lo, 1e-12)
    round_ = np.isfinite(template.periods)
    lo = np.where(round_, -np.inf, template.lo)
    hi = np.where(round_, np.inf, template.hi)
    targets = np.broadcast_to(goal.targets, (x.shape[0], *goal.targets.shape))
    cost = _lm(template, goal, targets, x, phases, lo, hi, width, iterations)
    period = np.where(round_, template.periods, 1.0)
    x = np.where(round_, template.lo + np.mod(x - template.lo, period), x)
    if goal.at is None and goal.full_turn:
        phases = goal.sweep[0] + np.mod(phases - goal.sweep[0], 2.0 * math.pi)
    return Batch(x, phases, cost)


def _lm(template: Template, goal: Goal, targets: np.ndarray, x: np.ndarray, phases: np.ndarray, lo: np.ndarray,
        hi: np.ndarray, width: np.ndarray, iterations: int) -> np.ndarray:
    """Levenberg–Marquardt iterations on every start against its ``targets`` (B, K, w); ``x`` and
    ``phases`` are updated in place; returns each start's ½‖r‖²."""
    n = x.shape[1]
    free_phases = goal.at is None
    active = np.arange(x.shape[0])
    h = _STEP * np.maximum(np.abs(x), width / 100.0)
    cost = np.full(x.shape[0], np.inf)
    r_a, j_a = _evaluate(template, goal, targets[active], x[active], phases[active], h[active])
    r = np.zeros((x.shape[0], r_a.shape[1]))
    jac = np.zeros((x.shape[0], *j_a.shape[1:]))
    r[active], jac[active] = r_a, j_a
    cost[active] = 0.5 * np.sum(r_a * r_a, axis=1)
    lam = np.full(x.shape[0], 1e-3)
    floor = 0.5 * (ROUND_OFF * EPS) ** 2 * r.shape[1]
    near = 0.5 * NEAR**2 * r.shape[1]
    history = [cost.copy()]
    for it in range(iterations):
        stalled = np.zeros(active.size, bool)
        if it >= STALL:
            stalled = (cost[active] > 0.99 * history[-STALL][active]) & (cost[active] > near)
        keep = (cost[active] > floor) & (lam[active] < 1e12) & ~stalled
        active = active[keep]
        if active.size == 0:
            break
        ja, ra = jac[active], r[active]
        a = np.einsum("bmi,bmj->bij", ja, ja)
        g = np.einsum("bmi,bm->bi", ja, ra)
        diag = np.einsum("bii->bi", a)
        damp = lam[active, None] * (diag + 1e-12 * (1.0 + diag.max(axis=1, keepdims=True)))
        with np.errstate(all="ignore"):
            try:
                step = -np.linalg.solve(a + damp[:, :, None] * np.eye(a.shape[1]), g[:, :, None])[:, :, 0]
            except np.linalg.LinAlgError:
                step = -np.stack([np.linalg.lstsq(ai + np.diag(di), gi, rcond=None)[0]
                                  for ai, di, gi in zip(a, damp, g)])
        step = np.nan_to_num(step)
        xt = np.clip(x[active] + step[:, :n], lo, hi)
        pt = phases[active] + step[:, n:] if free_phases else phases[active]
        ht = _STEP * np.maximum(np.abs(xt), width / 100.0)
        rt, jt = _evaluate(template, goal, targets[active], xt, pt, ht)
        ct = 0.5 * np.sum(rt * rt, axis=1)
        better = np.isfinite(ct) & (ct < cost[active])
        good = active[better]
        x[good], phases[good], r[good], jac[good], cost[good] = (
            xt[better], pt[better], rt[better], jt[better], ct[better])
        lam[good] = np.maximum(lam[good] / 3.0, 1e-12)
        lam[active[~better]] *= 4.0
        history.append(cost.copy())
    return cost
