"""The slider triad's mode followed over a vectorised sweep without an eigenvalue problem per
sample (the RRR triad's shortcut, solver.groups._triad_sweep, written for the slider triad's two
unknowns s and θ): every real root (:func:`slider_roots`) and the branch rule on *anchors* only —
every ``stride``-th sample (as many as span ``SPAN`` of the input, at most ``STRIDE``; none below
``MIN_STRIDE``), the reference sample and the last —; between two anchors the followed root is
interpolated (the cubic Hermite through θ, θ' and s, s' at both) and polished by ``SWEEP_STEPS``
Newton steps at every sample at once (:func:`slider_polish`). Kept only when all of this holds,
else the sweep takes the full path (every sample's roots), so the result never depends on it:

* every anchor has a real root, no anchor step jumps mode, and each anchor step is short against
  the root's distance to its nearest other root (``FOLLOW_SHARE`` of it, at both ends);
* the input is monotone; Newton has converged at every sample (last step ≤ ``FOLLOW_DONE``), its
  loop closes to round-off, its root is within ``FOLLOW_SHARE`` × the smaller of the two anchors'
  distances of its interpolated guess, and (checked by the group once its analogs are in,
  :meth:`Shortcut.holds`) its Jacobian determinant has the anchors' sign and at least
  ``FOLLOW_DET`` of the smaller of their sizes: a branch point is never passed unseen.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._backend import NUMPY
from ..jet import Jet
from ._slider_triad_math import follow_roots, slider_analogs, slider_polish, slider_roots
from ._triad_tick import FOLLOW_DET, FOLLOW_DONE, FOLLOW_SHARE

__all__ = ["STRIDE", "SPAN", "MIN_STRIDE", "SWEEP_STEPS", "Shortcut", "fast_sweep"]

#: Samples from one anchor to the next: as many as fit in ``SPAN`` of the input, at most this.
STRIDE: int = 256
#: The input span (rad; the sum of the inputs with several) from one anchor to the next at most.
SPAN: float = 0.2
#: Fewer samples than this between anchors: no shortcut.
MIN_STRIDE: int = 4
#: Newton steps from the interpolated root (its error ≲ 1e-4 rad falls below round-off in three).
SWEEP_STEPS: int = 3


def _wrap(x: Any) -> Any:
    return (x + np.pi) % (2.0 * np.pi) - np.pi


def _take(x: Any, rows: np.ndarray) -> Any:
    return x[rows] if np.ndim(x) else x


class Shortcut:
    """The followed root at every sample (θ, s) and the determinant check of :meth:`holds`."""

    def __init__(self, theta: np.ndarray, s: np.ndarray, sign: np.ndarray, floor: np.ndarray) -> None:
        self.theta, self.s, self._sign, self._floor = theta, s, sign, floor

    def holds(self, det: np.ndarray) -> bool:
        return bool(np.all(det * self._sign > 0.0) and np.all(np.abs(det) >= self._floor))


def fast_sweep(group: Any, step: np.ndarray, jb: Jet, jc: Jet, start: int, target: float) -> Shortcut | None:
    """The sweep through anchors (module docstring), or None where the full path must decide;
    ``step`` the input (the sum of the inputs) at each sample, the mode the root nearest
    ``target`` at the first sample from ``start`` (the group's branch rule)."""
    n = len(step)
    if n < 2 * MIN_STRIDE:
        return None
    rise_all = np.diff(step)
    if not (np.all(rise_all > 0.0) or np.all(rise_all < 0.0)):
        return None
    stride = min(STRIDE, int(SPAN / (abs(float(step[-1] - step[0])) / (n - 1))))
    if stride < MIN_STRIDE:
        return None
    anchors = np.unique(np.concatenate([np.arange(start, -1, -stride), np.arange(start, n, stride), [0, n - 1]]))
    sub = [Jet(_take(j.value, anchors), _take(j.d1, anchors), _take(j.d2, anchors)) for j in (jb, jc)]
    o: complex = group.origin
    e: complex = group.direction
    u: complex = group.shape[0]
    v: complex = group.shape[1]
    theta, ss = slider_roots(o, e, sub[0].value, sub[1].value, group.lengths, u, v)
    theta, ss = np.broadcast_to(theta, (len(anchors), 6)), np.broadcast_to(ss, (len(anchors), 6))
    if not np.isfinite(theta).any(axis=-1).all():
        return None

    def col(x: Any) -> Any:
        return np.asarray(x)[:, None] if np.ndim(x) == 1 else x
    cols = [Jet(col(j.value), col(j.d1), col(j.d2)) for j in sub]
    rate = np.real(slider_analogs(ss, np.cos(theta) + 1j * np.sin(theta), o, e, u, v, *cols)[1])
    slots, jumps = follow_roots(theta, rate, step[anchors], int(np.searchsorted(anchors, start)), target)
    if jumps.any() or (slots < 0).any():
        return None
    rows = np.arange(len(anchors))
    th_a, s_a = theta[rows, slots], ss[rows, slots]
    s_rate, t_rate, _, _, det_a = slider_analogs(s_a, np.cos(th_a) + 1j * np.sin(th_a), o, e, u, v, *sub)
    diff = np.abs(_wrap(theta - th_a[:, None]))
    diff[rows, slots] = np.inf
    gap = np.nanmin(np.where(np.isnan(diff), np.inf, diff), axis=-1)
    x = step[anchors]
    span = np.diff(x)
    rise = _wrap(np.diff(th_a))
    share = FOLLOW_SHARE * np.minimum(gap[:-1], gap[1:])
    if not (np.all(np.abs(rise - t_rate[:-1] * span) <= share) and np.all(np.abs(rise - t_rate[1:] * span) <= share)):
        return None
    seg = np.clip(np.searchsorted(anchors, np.arange(n), side="right") - 1, 0, len(anchors) - 2)
    h = span[seg]
    t = np.where(h != 0.0, (step - x[seg]) / np.where(h != 0.0, h, 1.0), 0.0)
    h10, h01, h11 = t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
    guess = th_a[seg] + h10 * h * t_rate[seg] + h01 * rise[seg] + h11 * h * t_rate[seg + 1]
    s0 = s_a[seg] + h10 * h * s_rate[seg] + h01 * (s_a[seg + 1] - s_a[seg]) + h11 * h * s_rate[seg + 1]
    s, th, _, closed, last = slider_polish(s0, guess, o, e, jb.value, jc.value, group.lengths, u, v,
                                           steps=SWEEP_STEPS, xp=NUMPY)
    near = np.abs(th - guess) <= FOLLOW_SHARE * np.minimum(gap[seg], gap[seg + 1])
    if not np.all(closed & near & (last <= FOLLOW_DONE)):
        return None
    th = _wrap(th)
    th[anchors], s[anchors] = th_a, s_a  # the anchors' own roots, polished by slider_roots
    sign = np.sign(det_a[seg])
    if not np.all(np.sign(det_a[seg + 1]) == sign):
        return None
    floor = FOLLOW_DET * np.minimum(np.abs(det_a[seg]), np.abs(det_a[seg + 1]))
    return Shortcut(th, s, sign, floor)
