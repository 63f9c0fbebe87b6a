"""The triad's mode followed tick by tick (solver.groups.triad's per-tick and compiled paths).

The state — the previous tick's root — lives at run time, never in a traced constant: the group
reads and moves it through small opaque calls (``xp.call``: the compiled instant records each as
one line, the scalar path runs it as it is) — :func:`predict` and :func:`predicted_point`, then
:func:`accept`, or :func:`full`, :func:`full_point` and :func:`accept_full` — while the Newton
steps and the analogs between them are the group's own lines, traced like a dyad's:

* **Follow** (no eigenvalues): from the previous tick's (φ, θ, θ', D, D') the root is predicted,
  θ_p = θ + θ'·Δφ, D_p = D + D'·Δφ, and polished by at most ``FOLLOW_STEPS`` Newton steps on the
  three loop equations (:func:`triad_polish`). It is accepted when Newton has converged (a last
  step ≤ ``FOLLOW_DONE``), the loop closes, |θ − θ_p| ≤ ``FOLLOW_SHARE`` × the distance from the
  last full solve's root to its nearest other root (the branch rule's own radius, so the nearest
  root is the one found), and the Jacobian determinant keeps its sign and at least ``FOLLOW_DET``
  of its size at that solve (a branch point, where two modes merge, is never crossed unseen: the
  determinant vanishes there). At the first tick the prediction is the full solve's root.
* **Full** otherwise (a check failed): every real root (:func:`triad_roots`) and the branch rule
  of the module docstring of solver.groups.triad: the root nearest θ₀ at the first tick, else
  nearest θ_p, refused as a mode jump where the count of real roots dropped and the nearest is
  farther than half the previous root's gap.

θ is NaN where no real root exists or the step would jump mode (the reason kept for the group's
error). The same instant again (the same input and ends: a compiled instant handed back to the
scalar path) starts again from the same state, so it gives the same bits.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["predict", "predicted_point", "accept", "full", "full_point", "accept_full", "FOLLOW_STEPS", "FOLLOW_DONE",
           "FOLLOW_SHARE", "FOLLOW_DET", "NO_ROOT", "JUMP"]

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


#: The follow's state (besides the reason of a failure and the pending values of one instant).
_STATE = ("phi", "theta", "rate", "d", "d1", "det", "det_full", "gap", "count", "key")


def predict(group: Any, step: float, a: complex, b: complex, c: complex) -> float:
    """The predicted θ at the input ``step`` (the sum of the inputs), the ends at ``a``, ``b``,
    ``c``: the previous tick's root carried forward, θ + θ'·Δφ (D + D'·Δφ kept for
    :func:`predicted_point`); at the first tick the full solve's root itself; NaN where it fails.
    The same instant again (a compiled instant handed back to the scalar path) starts from the
    same state, so that it gives the same bits."""
    st: dict[str, Any] = group._last
    step, a, b, c = float(step), complex(a), complex(b), complex(c)
    key = (step, a, b, c)
    if st.get("key") == key:
        for k in _STATE:
            st.pop(k, None)
        st.update(st["before"])
    st["pending"] = {k: st[k] for k in _STATE if k in st}
    st["fresh"] = "theta" not in st
    if st["fresh"]:
        full = _full(group, st, step, a, b, c)
        if full is None:
            st["d_pred"] = _NAN_POINT
            return math.nan
        th, d, gap, count = full
        st.update(gap=gap, count=count, d_pred=d)
        return th
    dphi = step - st["phi"]
    st["d_pred"] = st["d"] + st["d1"] * dphi
    return st["theta"] + st["rate"] * dphi  # type: ignore[no-any-return]


def predicted_point(group: Any, theta: float) -> complex:
    """D of :func:`predict`'s θ."""
    return group._last["d_pred"]  # type: ignore[no-any-return]


def accept(group: Any, step: float, a: complex, b: complex, c: complex, pred: float, theta: float, d: complex,
           d1: complex, rate: float, det: float) -> float:
    """θ (wrapped) when the polished root is the one predicted — within ``FOLLOW_SHARE`` of its
    distance to the nearest other root, its determinant of the same sign and at least
    ``FOLLOW_DET`` of its size at the last full solve — and the state moved to it; else NaN."""
    st: dict[str, Any] = group._last
    theta, det = float(theta), float(det)
    if not st["fresh"] and not (abs(_wrap(theta - pred)) <= FOLLOW_SHARE * st["gap"] and det * st["det"] > 0.0
                                and abs(det) >= FOLLOW_DET * st["det_full"]):
        return math.nan
    if st["fresh"]:
        st["det_full"] = abs(det)
    return _store(st, step, a, b, c, _wrap(theta), d, d1, rate, det)


def full(group: Any, step: float, a: complex, b: complex, c: complex) -> float:
    """θ of every root and the branch rule (the follow refused), D kept for :func:`full_point`;
    NaN where no real root exists or the step would jump mode (the reason kept)."""
    st: dict[str, Any] = group._last
    res = _full(group, st, float(step), complex(a), complex(b), complex(c))
    if res is None:
        st["d_full"] = _NAN_POINT
        return math.nan
    th, d, gap, count = res
    st.update(gap=gap, count=count, d_full=d)
    return th


def full_point(group: Any, theta: float) -> complex:
    """D of :func:`full`'s θ."""
    return group._last["d_full"] if theta == theta else _NAN_POINT  # type: ignore[no-any-return]


def accept_full(group: Any, step: float, a: complex, b: complex, c: complex, theta: float, d: complex,
                d1: complex, rate: float, det: float) -> float:
    """The state moved to :func:`full`'s root; its θ."""
    st: dict[str, Any] = group._last
    st["det_full"] = abs(float(det))
    return _store(st, step, a, b, c, float(theta), d, d1, rate, float(det))


def _store(st: dict[str, Any], step: float, a: complex, b: complex, c: complex, theta: float, d: complex,
           d1: complex, rate: float, det: float) -> float:
    step = float(step)
    st["before"] = st.pop("pending")
    st.update(phi=step, theta=theta, rate=float(rate), d=complex(d), d1=complex(d1), det=det,
              key=(step, complex(a), complex(b), complex(c)))
    return theta


def _full(group: Any, st: dict[str, Any], step: float, a: complex, b: complex, c: complex,
          ) -> tuple[float, complex, float, int] | None:
    """Every real root and the branch rule: (θ, D, gap, count), or None with the reason kept."""
    from ._triad_math import triad_roots

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
