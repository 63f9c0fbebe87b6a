"""The triad's mode followed over a vectorised sweep without an eigenvalue problem per sample.

solver.groups.triad's branch rule follows the mode from sample to sample. Most sweeps are dense
and far from any branch point, and there every sample's root is where its neighbours say it is.
So the sweep is solved on *anchors* only — every ``stride``-th sample (as many as span ``SPAN`` of
the input, at most ``STRIDE``; no shortcut below ``MIN_STRIDE``), the reference sample and the
last — with every real root (:func:`triad_roots`) and the branch rule itself; between two
anchors L and R the followed root is interpolated (the cubic through θ and θ' at both: Hermite,
θ' the velocity analog; D alike with D') and polished by Newton on the three loop equations at
every sample at once (:func:`triad_polish`, ``SWEEP_STEPS``). Accepted only when all of this holds, else the
sweep takes the full path (every sample's roots, as before), so the result never depends on the
shortcut:

* every anchor has a real root, no anchor step jumps mode, and each anchor step is short against
  the root's distance to its nearest other root: |θ_R − (θ_L + θ'_L·Δ)| and |θ_L − (θ_R − θ'_R·Δ)|
  ≤ ``FOLLOW_SHARE`` × that distance at L and at R;
* the sweep is monotone in the input (the sum of the inputs); Newton has converged at every sample
  (a last step ≤ ``FOLLOW_DONE``), its loop closes to round-off, its root is within ``FOLLOW_SHARE`` × the smaller of
  the two anchors' distances of its interpolated guess, and its Jacobian determinant has the sign
  of the anchors' and at least ``FOLLOW_DET`` of the smaller of their sizes (a branch point, where
  the determinant vanishes, is never passed unseen: checked by the group once its analogs are in).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._backend import NUMPY
from ..jet import Jet
from ._triad_tick import FOLLOW_DET, FOLLOW_DONE, FOLLOW_SHARE

__all__ = ["STRIDE", "fast_sweep", "Shortcut"]

#: Samples from one anchor to the next: as many as fit in ``SPAN`` of the input, at most this.
STRIDE: int = 256
#: The input span (rad; the sum of the inputs with several) from one anchor to the next at most.
SPAN: float = 0.2
#: Fewer samples than this between anchors: no shortcut (every sample's roots are as cheap).
MIN_STRIDE: int = 4
#: Newton steps from the interpolated root: its error ~θ⁗·SPAN⁴/384 (≲ 1e-4 rad on the reference
#: triads) falls below round-off in three quadratic steps (convergence and closure are checked).
SWEEP_STEPS: int = 3


def _wrap(x: Any) -> Any:
    return (x + np.pi) % (2.0 * np.pi) - np.pi


def _take(x: Any, rows: np.ndarray) -> Any:
    return x[rows] if np.ndim(x) else x


class Shortcut:
    """The followed root at every sample (θ, D, e^{jθ}), and what the group checks once it has the
    Jacobian determinant ``det`` at every sample: :meth:`holds`."""

    def __init__(self, theta: np.ndarray, d: np.ndarray, w: np.ndarray, sign: np.ndarray, floor: np.ndarray) -> None:
        self.theta, self.d, self.w, self._sign, self._floor = theta, d, w, sign, floor

    def holds(self, det: np.ndarray) -> bool:
        return bool(np.all(det * self._sign > 0.0) and np.all(np.abs(det) >= self._floor))


def fast_sweep(group: Any, phi: Any, ja: Jet, jb: Jet, jc: Jet, carry: dict[str, Any] | None) -> Shortcut | None:
    """The sweep through anchors (module docstring), or None where the full path must decide."""
    from ._triad_math import triad_analogs, triad_polish, triad_roots

    n = len(phi)
    ph = np.asarray(phi, float).reshape(n, -1)
    step = ph.sum(axis=1)
    if n < 2 * MIN_STRIDE:
        return None
    rise_all = np.diff(step)
    if not (np.all(rise_all > 0.0) or np.all(rise_all < 0.0)):  # not a sweep: the full path decides
        return None
    stride = min(STRIDE, int(SPAN / (abs(float(step[-1] - step[0])) / (n - 1))))
    if stride < MIN_STRIDE:
        return None
    if group.at is None or ph.shape[1] != 1 or carry is not None:
        i0 = 0
    else:
        i0 = int(np.argmin(np.abs(_wrap(ph[:, 0] - group.at))))
    anchors = np.unique(np.concatenate([np.arange(i0, -1, -stride), np.arange(i0, n, stride), [0, n - 1]]))
    a, b, c = (_take(j.value, anchors) for j in (ja, jb, jc))
    theta, dd = triad_roots(a, b, c, group.lengths, *group.shape)
    if not np.isfinite(theta).any(axis=-1).all():
        return None
    sub = [Jet(_take(j.value, anchors), _take(j.d1, anchors), _take(j.d2, anchors)) for j in (ja, jb, jc)]
    saved = dict(group._end_state)
    slots, jumps = group._pick_sweep(phi[anchors], theta, dd, *sub, carry=carry)
    if jumps.any() or (slots < 0).any():
        group._end_state.clear()
        group._end_state.update(saved)
        return None
    rows = np.arange(len(anchors))
    th_a, d_a = theta[rows, slots], dd[rows, slots]
    u, v = group.shape
    with np.errstate(all="ignore"):
        d_rate, rate, _, _, det_a = triad_analogs(d_a, np.cos(th_a) + 1j * np.sin(th_a), u, v, *sub)
        diff = np.abs(_wrap(theta - th_a[:, None]))
        diff[rows, slots] = np.inf
        gap = np.nanmin(np.where(np.isnan(diff), np.inf, diff), axis=-1)
    x = step[anchors]
    span = np.diff(x)
    rise = _wrap(np.diff(th_a))  # θ_R − θ_L, unwrapped onto the short way
    share = FOLLOW_SHARE * np.minimum(gap[:-1], gap[1:])
    if not (np.all(np.abs(rise - rate[:-1] * span) <= share) and np.all(np.abs(rise - rate[1:] * span) <= share)):
        group._end_state.clear()
        group._end_state.update(saved)
        return None
    # Hermite between the anchors, every sample at once
    seg = np.clip(np.searchsorted(anchors, np.arange(n), side="right") - 1, 0, len(anchors) - 2)
    h = span[seg]
    s = np.where(h != 0.0, (step - x[seg]) / np.where(h != 0.0, h, 1.0), 0.0)
    h10, h01, h11 = s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
    guess = th_a[seg] + h10 * h * rate[seg] + h01 * rise[seg] + h11 * h * rate[seg + 1]
    d0 = d_a[seg] + h10 * h * d_rate[seg] + h01 * (d_a[seg + 1] - d_a[seg]) + h11 * h * d_rate[seg + 1]
    av, bv, cv = ja.value, jb.value, jc.value
    with np.errstate(all="ignore"):
        d, th, w, closed, last = triad_polish(d0, guess, av, bv, cv, group.lengths, u, v, steps=SWEEP_STEPS,
                                              xp=NUMPY)
        near = np.abs(th - guess) <= FOLLOW_SHARE * np.minimum(gap[seg], gap[seg + 1])
    if not np.all(closed & near & (last <= FOLLOW_DONE)):
        group._end_state.clear()
        group._end_state.update(saved)
        return None
    th = _wrap(th)
    th[anchors] = th_a  # the anchors' own roots, polished by triad_roots
    w[anchors] = np.cos(th_a) + 1j * np.sin(th_a)
    d[anchors] = d_a
    sign = np.sign(det_a[seg])
    ok_sign = np.sign(det_a[seg + 1]) == sign
    if not ok_sign.all():
        group._end_state.clear()
        group._end_state.update(saved)
        return None
    floor = FOLLOW_DET * np.minimum(np.abs(det_a[seg]), np.abs(det_a[seg + 1]))
    return Shortcut(th, d, w, sign, floor)

