"""The local polish: scipy's ``least_squares`` on the design values and the free phases together.

Unknowns z = (x, φ₁ … φ_K): the n free values (within their bounds) and, without timing, the
input angle at each of the K targets. Residuals, per target k (over the task's size L for
lengths, so that every component is dimensionless):

* path      (P(φ_k; x) − T_k)/L, its real and imaginary parts;
* motion    the same and the body's angle miss wrap(θ(φ_k; x) − θ_k);
* function  wrap(q(φ_k; x) − q_k) (a slide in m: q − q_k), φ_k given.

Jacobian. The columns of the phases are exact: ∂P/∂φ_k = P'(φ_k), the analogs the groups'
jets carry. The columns of the design values are central differences, all 2n of them evaluated
in the same pass of the plan as the point itself (a population of 1 + 2n designs), with the step
h_i = ∛ε·max(|x_i|, (hi − lo)/100): the groups give no derivatives in their parameters, and
central differences with that step are accurate to ~ε^(2/3) ≈ 4e-11 relative, which leaves the
Gauss–Newton iteration's limit — the residual's zero — untouched (it only slows the last steps).
First ``trf`` without bounds (quadratic convergence on the four-bar and six-bar cases, 5–50
evaluations); where that leaves a free value's range, ``dogbox`` within the bounds (rectangular
trust regions; ``trf``'s bound scaling took hundreds of evaluations) from the same start, and
the better of it and the unbounded answer clipped into the bounds.
An exact problem (no more equations than unknowns) ends at round-off: the polish stops once
½‖r‖² is at ``ROUND_OFF`` ulps per residual (``least_squares``' callback, scipy ≥ 1.16).

With ``feasible=w`` the residuals also hold, times w, one row per dyad and sample of the sweep:
max(sin(μ_min + ``MARGIN``) − c(φ_s; x), 0), c the dyad's conditioning (|sin μ| of an RRR's
transmission angle), the whole threshold where the dyad cannot be assembled; zero for a
feasible design, so the zeros of the targets' residuals that are feasible are still zeros. Their
columns are the same central differences (the sweep joins the phases in the one pass); their
phase columns are zero. The search uses it to move an exact but infeasible polish along the
family of zeros of an under-determined task to a feasible one (search.py, ``_slide``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import least_squares

from ..groups import Context
from ..tolerances import EPS
from .population import Goal, group_of, run, wrap
from .template import Template

__all__ = ["Polished", "polish", "residuals"]

_STEP = EPS ** (1.0 / 3.0)
#: The polish stops once every residual (relative to the targets' size) is about this many ulps.
ROUND_OFF = 16.0
#: A feasible polish keeps every dyad's transmission angle this far (rad) above the minimum on
#: its sweep, so that the finer sweep of the final check (between the samples) holds it too.
MARGIN = math.radians(1.0)


@dataclass
class Polished:
    x: np.ndarray  # design values (scene units)
    phases: np.ndarray  # (K,) input angles (rad)
    cost: float  # ½‖r‖² at the end


def _split(goal: Goal, z: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    return z[:n], (goal.at if goal.at is not None else z[n:])


def residuals(template: Template, goal: Goal, xs: np.ndarray, phases: np.ndarray) -> tuple[np.ndarray, ...]:
    """Residual rows (C, m) of the designs ``xs`` (C, n) at ``phases`` (K,), and their φ-analogs."""
    ctx = run(template, xs, phases, goal.names)
    return _rows(goal, ctx, xs.shape[0], phases.size)


def _rows(goal: Goal, ctx: Context, c: int, k: int) -> tuple[np.ndarray, np.ndarray]:
    """:func:`residuals` read off a pass whose first ``k`` input angles are the phases."""
    t = goal.targets

    def cols(a: Any) -> np.ndarray:
        return np.broadcast_to(a, (c, np.shape(ctx.phi)[-1]))[:, :k]

    parts, d1s = [], []
    if goal.kind in ("path", "motion"):
        jet = ctx.values[goal.point]  # type: ignore[index]
        p = cols(jet.value) - (t[..., 0] + 1j * t[..., 1])  # targets (K, w), or (C, K, w): one set per design
        p1 = cols(jet.d1)
        parts += [p.real / goal.scale, p.imag / goal.scale]
        d1s += [p1.real / goal.scale, p1.imag / goal.scale]
    if goal.kind in ("function", "motion"):
        jet = ctx.values[goal.joint]  # type: ignore[index]
        col = 1 if goal.kind == "function" else 2
        d = cols(jet.value) - t[..., col]
        parts.append(wrap(d) if goal.joint_wraps else d)
        d1s.append(cols(jet.d1))
    r = np.concatenate(parts, axis=1)
    return np.nan_to_num(r, nan=1e3, posinf=1e3, neginf=-1e3), np.concatenate(d1s, axis=1)


def _deficits(template: Template, goal: Goal, ctx: Context, c: int, k: int) -> np.ndarray:
    """Rows (C, D·S) of the feasibility residuals over the sweep that follows the ``k`` phases:
    per dyad D and sample, how far its conditioning lies below sin(μ_min + ``MARGIN``); a sample
    that cannot be assembled counts the whole threshold. Zero for a feasible design."""
    floor = math.sin(min(goal.min_transmission + MARGIN, math.pi / 2))
    total = np.shape(ctx.phi)[-1]
    bad = np.broadcast_to(np.asarray(ctx.invalid, bool), (c, total))[:, k:]
    rows = []
    for name in dict.fromkeys(group_of(template, g) for g in goal.closures):
        cond = ctx.conditioning.get(name)
        if cond is None:
            continue
        kk = np.nan_to_num(np.broadcast_to(cond, (c, total))[:, k:], nan=0.0)
        rows.append(np.where(bad, floor, np.maximum(floor - np.abs(kk), 0.0)))
    return np.concatenate(rows, axis=1) if rows else np.zeros((c, 0))


class _Clipped:
    """The unbounded answer clipped into the bounds, as least_squares' result reads."""

    def __init__(self, z: np.ndarray, both: Any) -> None:
        self.x, self.cost = z, 0.5 * float(np.sum(both(z)[0] ** 2))


def polish(template: Template, goal: Goal, x0: np.ndarray, phases0: np.ndarray, *, max_nfev: int = 60,
           feasible: float = 0.0) -> Polished:
    """Least squares from (x0, phases0) to the nearest zero of the residuals (module docstring);
    with ``feasible``, the feasibility residuals over the sweep too (:func:`_deficits`)."""
    n, k = x0.size, len(goal.targets)
    period = template.periods  # an angle free over a whole turn has no bounds: it wraps
    round_ = np.isfinite(period)
    lo = np.where(round_, -np.inf, template.lo)
    hi = np.where(round_, np.inf, template.hi)
    free_phases = goal.at is None
    width = np.maximum(template.hi - template.lo, 1e-12)
    x0 = np.clip(x0, template.lo + 1e-9 * width, template.hi - 1e-9 * width)
    z0 = np.concatenate([x0, phases0]) if free_phases else x0.copy()
    h = _STEP * np.maximum(np.abs(x0), width / 100.0)
    eye = np.eye(n)
    cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def both(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        key = z.tobytes()
        if key not in cache:
            x, ph = _split(goal, z, n)
            xs = np.vstack([x, x + h * eye, x - h * eye])
            ph = np.asarray(ph, float)
            if feasible:
                ctx = run(template, xs, np.concatenate([ph, goal.sweep]), goal.names)
                r, d1 = _rows(goal, ctx, xs.shape[0], ph.size)
                r = np.hstack([r, feasible * _deficits(template, goal, ctx, xs.shape[0], ph.size)])
            else:
                r, d1 = residuals(template, goal, xs, ph)
            jac_x = ((r[1 : n + 1] - r[n + 1 :]) / (2.0 * h[:, None])).T
            if free_phases:
                m = d1.shape[1] // k
                jac_p = np.zeros((r.shape[1], k))
                for j in range(m):
                    jac_p[j * k : (j + 1) * k] = np.diag(d1[0, j * k : (j + 1) * k])
                jac = np.hstack([jac_x, jac_p])
            else:
                jac = jac_x
            cache.clear()
            cache[key] = (r[0], np.nan_to_num(jac, nan=0.0, posinf=1e6, neginf=-1e6))
        return cache[key]

    ph_lo, ph_hi = (-np.inf, np.inf) if goal.full_turn else (goal.sweep[0], goal.sweep[-1])
    if free_phases and not goal.full_turn:
        z0[n:] = np.clip(z0[n:], ph_lo, ph_hi)
    bounds_lo = np.concatenate([lo, np.full(k, ph_lo)]) if free_phases else lo
    bounds_hi = np.concatenate([hi, np.full(k, ph_hi)]) if free_phases else hi
    floor = 0.5 * (ROUND_OFF * EPS) ** 2 * (2 * k + n)  # ½‖r‖² at round-off: nothing left to gain

    def stop(intermediate_result: Any) -> bool:
        return bool(intermediate_result.cost <= floor)

    def solve(bounds: tuple[np.ndarray, np.ndarray] | tuple[float, float], method: str) -> Any:
        with np.errstate(all="ignore"):
            return least_squares(
                lambda z: both(z)[0], z0, jac=lambda z: both(z)[1], bounds=bounds, method=method,
                x_scale="jac", ftol=1e-15, xtol=1e-15, gtol=1e-15, max_nfev=max_nfev, callback=stop,
            )

    out = solve((-np.inf, np.inf), "trf")
    if not (np.all(out.x[:n] >= lo) and np.all(out.x[:n] <= hi)) or (free_phases and not goal.full_turn):
        bounded = solve((bounds_lo, bounds_hi), "dogbox")
        inside = np.clip(out.x, bounds_lo, bounds_hi)  # (a wrapping angle is never out of its bounds)
        out = bounded if bounded.cost <= 0.5 * float(np.sum(both(inside)[0] ** 2)) else _Clipped(inside, both)
    x, ph = _split(goal, out.x, n)
    x = np.where(round_, template.lo + np.mod(x - template.lo, np.where(round_, period, 1.0)), x)
    return Polished(np.asarray(x, float), np.asarray(ph, float), float(out.cost))
