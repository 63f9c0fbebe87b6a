"""The slider triad's mode followed tick by tick (solver.groups.slider_triad's per-tick and
compiled paths), as the RRR triad's (solver.groups._triad_tick, whose constants it shares):

* **Follow** (no eigenvalues): from the previous tick's (φ, θ, θ', s, s') the root is predicted,
  θ_p = θ + θ'·Δφ, s_p = s + s'·Δφ, and polished by at most ``FOLLOW_STEPS`` Newton steps on the
  two loop equations (the group's own traced lines). It is accepted when Newton has converged (a
  last step ≤ ``FOLLOW_DONE``), the loop closes, |θ − θ_p| ≤ ``FOLLOW_SHARE`` × the last full
  solve's distance to the nearest other root, and the Jacobian determinant keeps its sign and at
  least ``FOLLOW_DET`` of its size at that solve (a branch point makes it vanish: never crossed
  unseen). At the first tick there is no prediction.
* **Full** otherwise: every real root (:func:`slider_roots`) and the branch rule — the mode
  rule's root at the first tick (nearest the drawn pose (θ₀, s₀), else nearest θ₀: ``pick``),
  else the root nearest (θ_p, s_p) (``closest``), refused as a mode jump where the count of real
  roots dropped and the nearest is farther than half the previous root's distance to its
  nearest other root (``spread``). The acceptance above keeps the θ-only gap: near two modes of
  one θ it refuses, and this rule decides.

The state lives at run time (read and moved by the group's opaque calls, ``xp.call``); the same
instant again (a compiled instant handed back to the scalar path) starts from the same state.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._slider_triad_math import closest, gap_of, pick, slider_roots, spread
from ._triad_tick import FOLLOW_DET, FOLLOW_SHARE

__all__ = ["begin", "predict", "predicted_slide", "accept", "full", "full_slide", "accept_full", "NO_ROOT", "JUMP"]

NO_ROOT = "has no real assembly mode (slider triad)"
JUMP = ("would jump assembly mode (a branch point: two of the slider triad's modes merge between this sample and "
        "the previous one; sample more finely or choose another mode)")

#: The follow's state (besides the reason of a failure and one instant's pending values).
_STATE = ("phi", "theta", "rate", "s", "s1", "det", "det_full", "gap", "spread", "count", "key")


def _wrap(x: float) -> float:
    return (x + math.pi) % (2.0 * math.pi) - math.pi


def begin(st: dict[str, Any], step: float, b: complex, c: complex) -> None:
    """The instant starts: the same instant again restores the state it started from."""
    if st.get("key") == (step, b, c) and "before" in st:
        for k in _STATE:
            st.pop(k, None)
        st.update(st["before"])
    st["pending"] = {k: st[k] for k in _STATE if k in st}


def predict(group: Any, step: float, b: complex, c: complex) -> float:
    """θ_p (s_p kept for :func:`predicted_slide`); NaN at the first tick."""
    st: dict[str, Any] = group._last
    step, b, c = float(step), complex(b), complex(c)
    begin(st, step, b, c)
    if "theta" not in st:
        st["s_pred"] = math.nan
        return math.nan
    dphi = step - st["phi"]
    st["s_pred"] = st["s"] + st["s1"] * dphi
    return st["theta"] + st["rate"] * dphi  # type: ignore[no-any-return]


def predicted_slide(group: Any, theta: float) -> float:
    return group._last["s_pred"]  # type: ignore[no-any-return]


def accept(group: Any, step: float, b: complex, c: complex, pred: float, theta: float, s: float, s1: float,
           rate: float, det: float) -> float:
    """θ (wrapped) when the polished root is the one predicted (module docstring), the state moved
    to it; else NaN (the full solve decides)."""
    st: dict[str, Any] = group._last
    theta, det = float(theta), float(det)
    if not (abs(_wrap(theta - pred)) <= FOLLOW_SHARE * st["gap"] and det * st["det"] > 0.0
            and abs(det) >= FOLLOW_DET * st["det_full"]):
        return math.nan
    return _store(st, step, b, c, _wrap(theta), s, s1, rate, det)


def full(group: Any, step: float, b: complex, c: complex, *, guide: tuple[complex, complex] | None = None) -> float:
    """θ of every root and the branch rule (s kept for :func:`full_slide`); NaN where no real root
    exists or the step would jump mode (the reason kept). ``guide`` the instant's (O, e) where the
    guide moves (its carrier's, or the swinging block's pivot A and 0), else the group's own."""
    st: dict[str, Any] = group._last
    step, b, c = float(step), complex(b), complex(c)
    begin(st, step, b, c)
    st["s_full"] = math.nan
    o, e = (group.origin, group.direction) if guide is None else (complex(guide[0]), complex(guide[1]))
    theta, ss = slider_roots(o, e, b, c, group.lengths, *group.shape, line=group.line)
    real = np.flatnonzero(np.isfinite(theta))
    if not real.size:
        st["reason"] = NO_ROOT
        return math.nan
    roots, slides = theta[real].tolist(), ss[real].tolist()
    u, v = group.shape
    scale = abs(u) + abs(v)
    if "theta" not in st:
        k = pick(roots, slides, group.angle, group.slide0, scale)
    else:
        dphi = step - st["phi"]
        k, dist = closest(roots, slides, st["theta"] + st["rate"] * dphi, st["s"] + st["s1"] * dphi, scale)
        if real.size < st["count"] and dist > 0.5 * st["spread"]:
            st["reason"] = JUMP
            return math.nan
    st.update(s_full=float(ss[real[k]]), new_gap=gap_of(roots, k), new_spread=spread(roots, slides, k, scale),
              new_count=int(real.size))
    return float(roots[k])


def full_slide(group: Any, theta: float) -> float:
    return float(group._last["s_full"]) if theta == theta else math.nan


def accept_full(group: Any, step: float, b: complex, c: complex, theta: float, s: float, s1: float, rate: float,
                det: float) -> float:
    """The state moved to :func:`full`'s root; its θ."""
    st: dict[str, Any] = group._last
    st.update(gap=st.pop("new_gap"), spread=st.pop("new_spread"), count=st.pop("new_count"), det_full=abs(float(det)))
    return _store(st, step, b, c, float(theta), s, s1, rate, float(det))


def _store(st: dict[str, Any], step: float, b: complex, c: complex, theta: float, s: float, s1: float, rate: float,
           det: float) -> float:
    step = float(step)
    st["before"] = st.pop("pending")
    st.update(phi=step, theta=theta, rate=float(rate), s=float(s), s1=float(s1), det=det,
              key=(step, complex(b), complex(c)))
    return theta
