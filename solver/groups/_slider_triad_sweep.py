"""The slider triad's mode followed over a vectorised sweep without an eigenvalue problem per
sample (the RRR triad's shortcut, solver.groups._triad_sweep, written for the slider triad's two
unknowns s and θ): every real root (:func:`slider_roots`) and the branch rule on *anchors* only —
every ``stride``-th sample (as many as span the first of ``SPANS`` of the input, at most
``STRIDE``; none below ``MIN_STRIDE``), the reference sample and the last —; between two anchors
the followed root is interpolated (the quintic Hermite through θ, θ', θ'' and s, s', s'' at both,
the derivatives the analogs) and polished by ``SWEEP_STEPS`` Newton steps at every sample at once
(:func:`slider_polish`), ``EXTRA_STEPS`` more only where the last step shows no round-off yet.
Kept only when all of this holds, else the next, narrower span of ``SPANS`` is tried, and at last
the full path (every sample's roots), so the result never depends on the shortcut:

* every anchor has a real root, no anchor step jumps mode, each anchor step is short against the
  root's distance to its nearest other root — |θ_R − (θ_L + θ'_L·Δ + θ''_L·Δ²/2)| and
  |θ_L − (θ_R − θ'_R·Δ + θ''_R·Δ²/2)| ≤ ``FOLLOW_SHARE`` × that distance at L and at R — and the
  Jacobian determinant has one sign at all anchors;
* the input is monotone; Newton has converged at every sample (last step ≤ ``FOLLOW_DONE``), its
  loop closes to round-off, its root is within ``FOLLOW_SHARE`` × the smaller of the two anchors'
  distances of its interpolated guess, and (checked by the group once its analogs are in,
  :meth:`Shortcut.holds`; refused there, the group tries the narrower spans, then the full path)
  its Jacobian determinant has the anchors' sign and at least ``FOLLOW_DET`` of the smaller of
  their sizes: a branch point is never passed unseen.

Where the time goes (``python -m bench.triad``, 3600 samples a turn of the shipped press): the
anchors' roots (a batched 6×6 eigenvalue problem and its polish) a fixed ~0.3 ms plus ~20 µs an
anchor, the Newton steps at every sample ~0.1 µs a sample a step (a third of it the sine and
cosine), the analogs ~0.1 µs a sample: hence anchors wide apart and two steps, not three.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._backend import NUMPY
from ..jet import Jet
from ._slider_triad_math import follow_roots, slider_analogs, slider_polish, slider_roots
from ._triad_sweep import _quintic
from ._triad_tick import FOLLOW_DET, FOLLOW_DONE, FOLLOW_SHARE

__all__ = ["SPANS", "STRIDE", "MIN_STRIDE", "SWEEP_STEPS", "EXTRA_STEPS", "Shortcut", "fast_sweep"]

#: The anchors' spans tried in turn (rad of the input; the sum of the inputs with several): the
#: wide one first (few eigenvalue problems; on the shipped press its quintic interpolation is
#: ≲ 2e-5 rad off, two Newton steps reach round-off everywhere — at 0.8 rad, 1.5e-4 rad off, a
#: tenth of the samples need a third step, which costs more than the three anchors saved), the
#: narrow one where its checks fail, then the full path.
SPANS: tuple[float, ...] = (0.6, 0.2)
#: Samples from one anchor to the next at most.
STRIDE: int = 1024
#: Fewer samples than this between anchors: no shortcut.
MIN_STRIDE: int = 4
#: Newton steps from the interpolated root at every sample (its error ≲ 2e-5 rad at the wide
#: span falls below round-off in two quadratic steps: the last one ≲ 1e-8 rad, ``FOLLOW_DONE``).
SWEEP_STEPS: int = 2
#: Further Newton steps at most, only at the samples whose last step was above ``FOLLOW_DONE``.
EXTRA_STEPS: int = 3


#: A moving guide at every sample: (o, e, its (O, e) jets), as the group's ``guide_at`` gives it.
Moving = tuple[Any, Any, Any] | None


def _wrap(x: Any) -> Any:
    return (x + np.pi) % (2.0 * np.pi) - np.pi


def _take(x: Any, rows: np.ndarray) -> Any:
    return x[rows] if np.ndim(x) else x


class Shortcut:
    """The followed root at every sample (θ, s, e^{jθ}) and the determinant check of :meth:`holds`;
    ``narrower``, the spans of ``SPANS`` after the one taken (to try where :meth:`holds` fails)."""

    def __init__(self, theta: np.ndarray, s: np.ndarray, w: np.ndarray, sign: np.ndarray, floor: np.ndarray) -> None:
        self.theta, self.s, self.w, self._sign, self._floor = theta, s, w, sign, floor
        self.narrower: tuple[float, ...] = ()

    def holds(self, det: np.ndarray) -> bool:
        return bool(np.all(det * self._sign > 0.0) and np.all(np.abs(det) >= self._floor))


def fast_sweep(group: Any, step: np.ndarray, jb: Jet, jc: Jet, start: int, target: float, slide0: float | None, *,
               spans: tuple[float, ...] = SPANS, moving: Moving = None) -> Shortcut | None:
    """The sweep through anchors ``spans`` apart, each tried in turn (module docstring), or None
    where the full path must decide; ``step`` the input (the sum of the inputs) at each sample,
    the mode at the first sample from ``start`` the mode rule's for θ₀ = ``target`` and s₀ =
    ``slide0`` (solver.groups._slider_triad_math.pick); ``moving`` a moving guide's (o, e, jets)
    at every sample (the group's ``guide_at``; its ``line`` read off the group)."""
    n = len(step)
    if n < 2 * MIN_STRIDE:
        return None
    rise_all = np.diff(step)
    if not (np.all(rise_all > 0.0) or np.all(rise_all < 0.0)):
        return None
    pitch = abs(float(step[-1] - step[0])) / (n - 1)
    for i, span in enumerate(spans):
        stride = min(STRIDE, int(span / pitch))
        if stride < MIN_STRIDE:
            return None
        out = _through_anchors(group, step, stride, jb, jc, start, target, slide0, moving)
        if out is not None:
            out.narrower = spans[i + 1:]
            return out
    return None


def _through_anchors(group: Any, step: np.ndarray, stride: int, jb: Jet, jc: Jet, start: int,
                     target: float, slide0: float | None, moving: Moving = None) -> Shortcut | None:
    """The shortcut with anchors ``stride`` samples apart, or None where a check fails."""
    n = len(step)
    anchors = np.unique(np.concatenate([np.arange(start, -1, -stride), np.arange(start, n, stride), [0, n - 1]]))
    sub = [Jet(_take(j.value, anchors), _take(j.d1, anchors), _take(j.d2, anchors)) for j in (jb, jc)]
    o: Any = group.origin if moving is None else moving[0]
    e: Any = group.direction if moving is None else moving[1]
    line = group.line
    jets = None if moving is None else moving[2]
    u: complex = group.shape[0]
    v: complex = group.shape[1]
    o_a, e_a = _take(o, anchors), _take(e, anchors)
    theta, ss = slider_roots(o_a, e_a, sub[0].value, sub[1].value, group.lengths, u, v, line=line)
    theta, ss = np.broadcast_to(theta, (len(anchors), 6)), np.broadcast_to(ss, (len(anchors), 6))
    if not np.isfinite(theta).any(axis=-1).all():
        return None

    def col(x: Any) -> Any:
        return np.asarray(x)[:, None] if np.ndim(x) == 1 else x
    cols = [Jet(col(j.value), col(j.d1), col(j.d2)) for j in sub]
    moved = None if jets is None else (Jet(*(col(_take(x, anchors)) for x in jets[0])),
                                       Jet(*(col(_take(x, anchors)) for x in jets[1])))
    slot = slider_analogs(ss, np.cos(theta) + 1j * np.sin(theta), col(o_a), col(e_a), u, v, *cols, line=line,
                          guide=moved)  # every slot's
    slots, jumps = follow_roots(theta, ss, np.real(slot[1]), np.real(slot[0]), step[anchors],
                                int(np.searchsorted(anchors, start)), target, slide0=slide0, scale=abs(u) + abs(v))
    if jumps.any() or (slots < 0).any():
        return None
    rows = np.arange(len(anchors))
    th_a, s_a = theta[rows, slots], ss[rows, slots]
    s_rate, t_rate, s_acc, t_acc, det_a = (np.real(x[rows, slots]) for x in slot)
    diff = np.abs(_wrap(theta - th_a[:, None]))
    diff[rows, slots] = np.inf
    gap = np.nanmin(np.where(np.isnan(diff), np.inf, diff), axis=-1)
    x = step[anchors]
    h = np.diff(x)
    rise = _wrap(np.diff(th_a))  # θ_R − θ_L, the short way
    share = FOLLOW_SHARE * np.minimum(gap[:-1], gap[1:])
    ahead = t_rate[:-1] * h + 0.5 * t_acc[:-1] * h * h
    back = t_rate[1:] * h - 0.5 * t_acc[1:] * h * h
    if not (np.all(np.abs(rise - ahead) <= share) and np.all(np.abs(rise - back) <= share)):
        return None
    if not np.all(np.sign(det_a[1:]) == np.sign(det_a[:-1])):
        return None
    # the quintic Hermite between the anchors (θ and s with their first and second analogs at
    # both), by Horner in τ ∈ [0, 1] of each anchor step: θ and s as two rows of one table
    h2 = h * h
    c_th = _quintic(th_a[:-1], th_a[:-1] + rise, t_rate[:-1] * h, t_rate[1:] * h, t_acc[:-1] * h2, t_acc[1:] * h2)
    c_s = _quintic(s_a[:-1], s_a[1:], s_rate[:-1] * h, s_rate[1:] * h, s_acc[:-1] * h2, s_acc[1:] * h2)
    counts = np.diff(anchors)
    counts[-1] += 1  # the last sample belongs to the last step (τ = 1)
    seg = np.repeat(rows[:-1], counts)
    table = np.stack([c_th, c_s], axis=1)  # (6, 2, steps)
    tau = (step - x[seg]) * (1.0 / h)[seg]
    guess = table[5].take(seg, axis=-1)
    for k in range(4, -1, -1):
        guess *= tau
        guess += table[k].take(seg, axis=-1)
    g_theta = guess[0]
    bv, cv = jb.value, jc.value
    s, th, w, closed, last = slider_polish(guess[1], g_theta, o, e, bv, cv, group.lengths, u, v,
                                           steps=SWEEP_STEPS, xp=NUMPY, line=line)
    done = last <= FOLLOW_DONE
    if not done.all():  # the quadratic bound shows no round-off yet there: more steps there only
        more = np.flatnonzero(~done)
        if more.size > n // 8:
            return None
        s2, th2, w2, closed2, last2 = slider_polish(s[more], th[more], _take(o, more), _take(e, more), _take(bv, more),
                                                   _take(cv, more), group.lengths, u, v, steps=EXTRA_STEPS, xp=NUMPY,
                                                   line=line)
        s[more], th[more], w[more], closed[more] = s2, th2, w2, closed2
        done[more] = last2 <= FOLLOW_DONE
    near = np.abs(th - g_theta) <= share.take(seg)
    if not np.all(closed & near & done):
        return None
    th = np.where(th >= np.pi, th - 2.0 * np.pi, np.where(th < -np.pi, th + 2.0 * np.pi, th))  # into [−π, π)
    if not (th.min() >= -np.pi and th.max() < np.pi):  # more than a turn off: the general wrap
        th = _wrap(th)
    th[anchors], s[anchors] = th_a, s_a  # the anchors' own roots, polished by slider_roots
    w[anchors] = np.cos(th_a) + 1j * np.sin(th_a)
    sign = np.sign(det_a[:-1]).take(seg)
    floor = (FOLLOW_DET * np.minimum(np.abs(det_a[:-1]), np.abs(det_a[1:]))).take(seg)
    return Shortcut(th, s, w, sign, floor)
