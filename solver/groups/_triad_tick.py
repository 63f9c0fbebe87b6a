"""The triad's mode followed tick by tick (solver.groups.triad's per-tick and compiled paths).

One tick is one opaque call (``xp.call``: the compiled instant records it as one line, and the
scalar path runs it as it is), so that the state it carries — the previous tick's root — lives
at run time, never in a traced constant:

* **Follow** (no eigenvalues): from the previous tick's (φ, θ, θ') the root is predicted,
  θ_p = θ + θ'·Δφ, D from Cramer's rule at θ_p (solver.groups.triad's elimination), and polished
  by at most ``FOLLOW_STEPS`` Newton steps on the three loop equations (:func:`triad_polish`). It
  is accepted when Newton has converged (a last step ≤ ``FOLLOW_DONE``), the loop closes,
  |θ − θ_p| ≤ ``FOLLOW_SHARE`` × the distance from the previous full solve's root to its nearest
  other root (the branch rule's own radius, so the nearest root is the one found), and the
  Jacobian determinant keeps its sign and at least
  ``FOLLOW_DET`` of its size at that solve (a branch point, where two modes merge, is never
  crossed unseen: the determinant vanishes there).
* **Full** otherwise (the first tick, or a check failed): every real root (:func:`triad_roots`)
  and the branch rule of the module docstring of solver.groups.triad: the root nearest θ₀ at the
  first tick, else nearest θ_p, refused as a mode jump where the count of real roots dropped and
  the nearest is farther than half the previous root's gap.

The tick returns θ (NaN where no real root exists or the step would jump mode, with the reason
kept for the group's error), and keeps D and θ' for the group to read; the same instant again
(the same input and ends: a compiled instant handed back to the scalar path) returns the same
root, to the bit.
"""

from __future__ import annotations

import cmath
import math
from typing import Any

import numpy as np

from .._backend import SCALAR, dot

__all__ = ["tick", "tick_point", "FOLLOW_STEPS", "FOLLOW_DONE", "FOLLOW_SHARE", "FOLLOW_DET", "NO_ROOT", "JUMP"]

#: Newton steps from the predicted root at most: the prediction's error ~θ''·Δφ²/2 (≤ 1e-2 rad
#: for a tenth of a radian per tick) falls below round-off in three quadratic steps.
FOLLOW_STEPS: int = 3
#: A Newton step |Δθ| at most this (rad) ends the follow: the next step's ~|Δθ|²·(curvature)
#: is below round-off.
FOLLOW_DONE: float = 1e-8
#: The followed root must be within this share of its distance to the nearest other root.
FOLLOW_SHARE: float = 0.25
#: The Jacobian determinant must keep at least this share of its size at the last full solve.
FOLLOW_DET: float = 0.5

NO_ROOT = "has no real assembly mode (triad)"
JUMP = ("would jump assembly mode (a branch point: two of the triad's modes merge between this sample and "
        "the previous one; sample more finely or choose another mode)")

_NAN_POINT = complex(math.nan, math.nan)


def _wrap(x: float) -> float:
    return (x + math.pi) % (2.0 * math.pi) - math.pi


def tick(group: Any, step: float, a: complex, b: complex, c: complex, a1: Any, b1: Any, c1: Any) -> float:
    """θ of ``group``'s followed root at the input ``step`` (the sum of the inputs), the ends at
    ``a``, ``b``, ``c`` moving at ``a1``, ``b1``, ``c1`` (velocity analogs)."""
    from .triad import triad_polish, triad_start

    st: dict[str, Any] = group._last
    step, a, b, c = float(step), complex(a), complex(b), complex(c)
    key = (step, a, b, c)
    if st.get("key") == key:  # the same instant again (a compiled instant's miss): the same bits
        return st["theta"]  # type: ignore[no-any-return]
    u, v = group.shape
    found = None
    if "theta" in st:
        pred = st["theta"] + st["rate"] * (step - st["phi"])
        d0 = triad_start(pred, a, b, c, group.lengths, u, v, SCALAR)
        d, th, w, ok, last = triad_polish(d0, pred, a, b, c, group.lengths, u, v, steps=FOLLOW_STEPS, xp=SCALAR,
                                          until=FOLLOW_DONE)
        if ok and last <= FOLLOW_DONE and abs(_wrap(th - pred)) <= FOLLOW_SHARE * st["gap"]:
            rate, det = _rate(d, w, u, v, a, b, c, a1, b1, c1)
            if det * st["det"] > 0.0 and abs(det) >= FOLLOW_DET * st["det_full"]:
                found = (_wrap(th), d, rate, det)
    if found is None:
        full = _full(group, st, step, a, b, c)
        if full is None:
            st["d"] = _NAN_POINT
            return math.nan
        th, d, gap, count = full
        rate, det = _rate(d, cmath.rect(1.0, th), u, v, a, b, c, a1, b1, c1)
        st.update(gap=gap, count=count, det_full=abs(det))
        found = (th, d, rate, det)
    th, d, rate, det = found
    st.update(phi=step, theta=th, rate=rate, det=det, d=d, key=key)
    return th


def tick_point(group: Any, theta: float) -> complex:
    """D of the tick that gave ``theta``."""
    return group._last["d"] if theta == theta else _NAN_POINT  # type: ignore[no-any-return]


def _rate(d: complex, w: complex, u: complex, v: complex, a: complex, b: complex, c: complex, a1: Any, b1: Any,
          c1: Any) -> tuple[float, float]:
    """(θ', det) of the first-order analog system at the root."""
    from .triad import _solve3

    uw, vw = u * w, v * w
    p, q, s = d - a, d + uw - b, d + vw - c
    g, h = uw.real * q.imag - uw.imag * q.real, vw.real * s.imag - vw.imag * s.real
    _, t1, det = _solve3(p, q, s, g, h, dot(a1, p), dot(b1, q), dot(c1, s))
    return float(t1), float(det)


def _full(group: Any, st: dict[str, Any], step: float, a: complex, b: complex, c: complex,
          ) -> tuple[float, complex, float, int] | None:
    """Every real root and the branch rule: (θ, D, gap, count), or None with the reason kept."""
    from .triad import triad_roots

    theta, dd = triad_roots(a, b, c, group.lengths, *group.shape)
    real = np.flatnonzero(np.isfinite(theta))
    if not real.size:
        st["reason"] = NO_ROOT
        return None
    roots = theta[real].tolist()
    if "theta" not in st:
        target, jump_gap = group.angle, None
    else:
        target = st["theta"] + st["rate"] * (step - st["phi"])
        jump_gap = 0.5 * st["gap"] if real.size < st["count"] else None
    dist = [abs(_wrap(t - target)) for t in roots]
    k = min(range(len(roots)), key=dist.__getitem__)
    if jump_gap is not None and dist[k] > jump_gap:
        st["reason"] = JUMP
        return None
    others = [abs(_wrap(t - roots[k])) for m, t in enumerate(roots) if m != k]
    gap = min((x for x in others if x > 0.0), default=math.inf)
    return float(roots[k]), complex(dd[real[k]]), gap, int(real.size)
