"""The triad's mode followed over a vectorised sweep without an eigenvalue problem per sample.

solver.groups.triad's branch rule follows the mode from sample to sample. Most sweeps are dense
and far from any branch point, and there every sample's root is where its neighbours say it is.
So the sweep is solved on *anchors* only — every ``stride``-th sample (as many as span the first
of ``SPANS`` of the input, at most ``STRIDE``; no shortcut below ``MIN_STRIDE``), the reference
sample and the last — with every real root (:func:`triad_roots`) and the branch rule itself;
between two anchors L and R the followed root is interpolated (the quintic through θ, θ' and θ''
at both: Hermite, θ' and θ'' the analogs; D alike with D' and D'') and polished by Newton on the
three loop equations at every sample at once (:func:`triad_polish`, ``SWEEP_STEPS``; the
interpolation is ~1e-5 rad off at 0.8 rad between anchors, so two quadratic steps reach
round-off). Where a sample's last step is still above ``FOLLOW_DONE`` (the quadratic bound shows
no round-off yet) up to ``EXTRA_STEPS`` more are taken there only. Accepted only when all of this
holds, else the next, narrower span of ``SPANS`` is tried, and at last the full path (every
sample's roots, as before), so the result never depends on the shortcut:

* every anchor has a real root, no anchor step jumps mode, and each anchor step is short against
  the root's distance to its nearest other root: |θ_R − (θ_L + θ'_L·Δ + θ''_L·Δ²/2)| and
  |θ_L − (θ_R − θ'_R·Δ + θ''_R·Δ²/2)| ≤ ``FOLLOW_SHARE`` × that distance at L and at R, and the
  Jacobian determinant has one sign at all anchors;
* the sweep is monotone in the input (the sum of the inputs); Newton has converged at every sample
  (a last step ≤ ``FOLLOW_DONE``), its loop closes to round-off, its root is within
  ``FOLLOW_SHARE`` × the smaller of the two anchors' distances of its interpolated guess, and its
  Jacobian determinant has the sign of the anchors' and at least ``FOLLOW_DET`` of the smaller of
  their sizes (a branch point, where the determinant vanishes, is never passed unseen: checked by
  the group once its analogs are in; refused there, the group tries the narrower spans, then the
  full path).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._backend import NUMPY
from ..jet import Jet
from ._triad_tick import FOLLOW_DET, FOLLOW_DONE, FOLLOW_SHARE

__all__ = ["SPANS", "STRIDE", "SWEEP_STEPS", "EXTRA_STEPS", "fast_sweep", "Shortcut"]

#: The anchors' spans tried in turn (rad of the input; the sum of the inputs with several): the
#: wide one first (few eigenvalue problems; its quintic interpolation is ~1e-5 rad off on the
#: reference triads, two Newton steps), the narrow one where the wide one's checks fail (a fast
#: or strongly curved branch), then the full path.
SPANS: tuple[float, ...] = (0.8, 0.2)
#: Samples from one anchor to the next at most.
STRIDE: int = 1024
#: Fewer samples than this between anchors: no shortcut (every sample's roots are as cheap).
MIN_STRIDE: int = 4
#: Newton steps from the interpolated root at every sample: its error ≲ 1e-5 rad falls below
#: round-off in two quadratic steps (the last step then ≲ 1e-10 rad ≤ ``FOLLOW_DONE``).
SWEEP_STEPS: int = 2
#: Further Newton steps at most, only at the samples whose last step was above ``FOLLOW_DONE``
#: (where the quadratic bound does not yet show round-off): near a strongly curved stretch.
EXTRA_STEPS: int = 3


def _wrap(x: Any) -> Any:
    return (x + np.pi) % (2.0 * np.pi) - np.pi


def _take(x: Any, rows: np.ndarray) -> Any:
    return x[rows] if np.ndim(x) else x


def _quintic(y0: Any, y1: Any, d0: Any, d1: Any, c0: Any, c1: Any) -> Any:
    """The coefficients (s⁰ … s⁵, stacked first) of the quintic on s ∈ [0, 1] with value, first and
    second derivative ``y0, d0, c0`` at 0 and ``y1, d1, c1`` at 1."""
    e0 = y1 - y0 - d0 - 0.5 * c0
    e1 = d1 - d0 - c0
    e2 = c1 - c0
    return np.stack([y0, d0, 0.5 * c0, 10.0 * e0 - 4.0 * e1 + 0.5 * e2, -15.0 * e0 + 7.0 * e1 - e2,
                     6.0 * e0 - 3.0 * e1 + 0.5 * e2])


class Shortcut:
    """The followed root at every sample (θ, D, e^{jθ}), and what the group checks once it has the
    Jacobian determinant ``det`` at every sample: :meth:`holds`; ``narrower``, the spans of
    ``SPANS`` after the one taken (to try where :meth:`holds` fails)."""

    def __init__(self, theta: np.ndarray, d: np.ndarray, w: np.ndarray, sign: np.ndarray, floor: np.ndarray) -> None:
        self.theta, self.d, self.w, self._sign, self._floor = theta, d, w, sign, floor
        self.narrower: tuple[float, ...] = ()

    def holds(self, det: np.ndarray) -> bool:
        return bool(np.all(det * self._sign > 0.0) and np.all(np.abs(det) >= self._floor))


def fast_sweep(group: Any, phi: Any, ja: Jet, jb: Jet, jc: Jet, carry: dict[str, Any] | None, *,
               spans: tuple[float, ...] = SPANS) -> Shortcut | None:
    """The sweep through anchors ``spans`` apart, each tried in turn (module docstring), or None
    where the full path must decide."""
    n = len(phi)
    if n < 2 * MIN_STRIDE:
        return None
    step = np.asarray(phi, float).reshape(n, -1).sum(axis=1)
    rise_all = np.diff(step)
    if not (np.all(rise_all > 0.0) or np.all(rise_all < 0.0)):  # not a sweep: the full path decides
        return None
    pitch = abs(float(step[-1] - step[0])) / (n - 1)
    saved = dict(group._end_state)
    for i, span in enumerate(spans):
        stride = min(STRIDE, int(span / pitch))
        if stride < MIN_STRIDE:
            return None
        out = _through_anchors(group, phi, step, stride, ja, jb, jc, carry)
        if out is not None:
            out.narrower = spans[i + 1:]
            return out
        group._end_state.clear()
        group._end_state.update(saved)
    return None


def _through_anchors(group: Any, phi: Any, step: np.ndarray, stride: int, ja: Jet, jb: Jet, jc: Jet,
                     carry: dict[str, Any] | None) -> Shortcut | None:
    """The shortcut with anchors ``stride`` samples apart, or None where a check fails."""
    from ._triad_math import triad_polish, triad_roots

    n = len(step)
    ph = np.asarray(phi, float).reshape(n, -1)
    if group.at is None or ph.shape[1] != 1 or carry is not None:
        i0 = 0
    else:
        i0 = int(np.argmin(np.abs(_wrap(ph[:, 0] - group.at))))
    anchors = np.unique(np.concatenate([np.arange(i0, -1, -stride), np.arange(i0, n, stride), [0, n - 1]]))
    sub = [Jet(_take(j.value, anchors), _take(j.d1, anchors), _take(j.d2, anchors)) for j in (ja, jb, jc)]
    theta, dd = triad_roots(sub[0].value, sub[1].value, sub[2].value, group.lengths, *group.shape)
    if not np.isfinite(theta).any(axis=-1).all():
        return None
    slot = group.slot_analogs(theta, dd, *sub)  # every slot's analogs: the branch rule's and the Hermite's
    slots, jumps = group._pick_sweep(phi[anchors], theta, dd, *sub, carry=carry, rate=slot[1])
    if jumps.any() or (slots < 0).any():
        return None
    rows = np.arange(len(anchors))
    th_a, d_a = theta[rows, slots], dd[rows, slots]
    u, v = group.shape
    d_rate, rate, d_acc, acc, det_a = (x[rows, slots] for x in slot)
    diff = np.abs(_wrap(theta - th_a[:, None]))
    diff[rows, slots] = np.inf
    gap = np.nanmin(np.where(np.isnan(diff), np.inf, diff), axis=-1)
    x = step[anchors]
    h = np.diff(x)
    rise = _wrap(np.diff(th_a))  # θ_R − θ_L, unwrapped onto the short way
    share = FOLLOW_SHARE * np.minimum(gap[:-1], gap[1:])
    # each anchor step against the second-order prediction from either end
    ahead = rate[:-1] * h + 0.5 * acc[:-1] * h * h
    back = rate[1:] * h - 0.5 * acc[1:] * h * h
    if not (np.all(np.abs(rise - ahead) <= share) and np.all(np.abs(rise - back) <= share)):
        return None
    if not np.all(np.sign(det_a[1:]) == np.sign(det_a[:-1])):
        return None
    # the quintic Hermite between the anchors (θ, θ', θ'' and D, D', D'' at both), evaluated by
    # Horner in s ∈ [0, 1] of each anchor step: θ, Re D and Im D as three rows of one table
    h2 = h * h
    c_th = _quintic(th_a[:-1], th_a[:-1] + rise, rate[:-1] * h, rate[1:] * h, acc[:-1] * h2, acc[1:] * h2)
    c_d = _quintic(d_a[:-1], d_a[1:], d_rate[:-1] * h, d_rate[1:] * h, d_acc[:-1] * h2, d_acc[1:] * h2)
    counts = np.diff(anchors)
    counts[-1] += 1  # the last sample belongs to the last step (s = 1)
    seg = np.repeat(rows[:-1], counts)
    table = np.stack([c_th, c_d.real, c_d.imag], axis=1)  # (6, 3, steps): s⁰ … s⁵ of θ, Re D, Im D
    s = (step - x[seg]) * (1.0 / h)[seg]
    guess = table[5].take(seg, axis=-1)
    for k in range(4, -1, -1):
        guess *= s
        guess += table[k].take(seg, axis=-1)
    g_theta = guess[0]
    g_d = np.empty(n, complex)
    g_d.real, g_d.imag = guess[1], guess[2]
    av, bv, cv = ja.value, jb.value, jc.value
    d, th, w, closed, last = triad_polish(g_d, g_theta, av, bv, cv, group.lengths, u, v, steps=SWEEP_STEPS,
                                          xp=NUMPY)
    done = last <= FOLLOW_DONE
    if not done.all():  # the quadratic bound shows no round-off yet there: more steps there only
        more = np.flatnonzero(~done)
        if more.size > n // 8:
            return None
        d2_, th2, w2, closed2, last2 = triad_polish(d[more], th[more], _take(av, more), _take(bv, more),
                                                    _take(cv, more), group.lengths, u, v, steps=EXTRA_STEPS,
                                                    xp=NUMPY)
        d[more], th[more], w[more], closed[more] = d2_, th2, w2, closed2
        done[more] = last2 <= FOLLOW_DONE
    near = np.abs(th - g_theta) <= share.take(seg)
    if not np.all(closed & near & done):
        return None
    th = _wrap(th)
    th[anchors] = th_a  # the anchors' own roots, polished by triad_roots
    w[anchors] = np.cos(th_a) + 1j * np.sin(th_a)
    d[anchors] = d_a
    sign = np.sign(det_a[:-1]).take(seg)
    floor = (FOLLOW_DET * np.minimum(np.abs(det_a[:-1]), np.abs(det_a[1:]))).take(seg)
    return Shortcut(th, d, w, sign, floor)
