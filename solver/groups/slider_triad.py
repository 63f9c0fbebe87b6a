"""The slider triad: the class-3 Assur group with one prismatic pair (PRR–RRR–RRR). A ternary
link D, E, F whose point D is pinned to a slider block on a fixed straight guide, and whose
points E, F are joined by binary links to two known points B, C.

The variant a drawing or an importer meets where a triad's leg is a slider (a press ram, a
walking linkage's foot on a rail), with its two other one-prismatic variants as options
(``docs/scenes.md``):

* **a guide on a moving link** (``guide: {on: [P, Q], angle?, offset?}``): the guide fixed to the
  known link through P, Q (solved by earlier groups) — through P (offset along its normal) at
  ``angle`` from P→Q. At an instant the same polynomial with that instant's O, e; the analogs
  gain O', O'' and e' = j·ω·e, e'' = (j·α − ω²)·e of the carrier (ω = arg(Q − P)').
* **the swinging block** (``block_at: A``, ``guide: {angle?, offset?}``): a block pinned at the
  known point A (fixed or moving) slides along a line fixed in the ternary link — through D
  (offset along its normal) at ``angle`` from D→E, p = offset·j·e_t, e_t = e^{j·angle} in the
  link's frame. A = D + (p + s·e_t)·w, so D = A − (p + s·e_t)·w: the same two circle quadratics in
  s (leading coefficient 1) with O(w) = A − p·w and e(w) = −e_t·w; e(w)·p₁ and k₁ stay Laurent
  polynomials of w^{−1} … w¹, so G stays within w^{−3} … w³ and the same DFT-of-7 and companion
  eigenvalues give every mode. E's arm of θ is R_E = E − A (u·w on a fixed guide), and the
  analogs gain the turning guide's 2j·s'·θ'·e₁·w (solver.groups._slider_triad_math). The P joint
  being symmetric, this is also "a binary link sliding through the ternary link".

Loop equations
    D = O + s·e (the guide through the fixed point O, offset applied, unit direction e; s the
    slide), |E − B| = b, |F − C| = c, E = D + u·w, F = D + v·w, w = e^{jθ}: θ the ternary link's
    angle, u = E − D and v = F − D its shape in its own frame (as the RRR triad's).
Univariate polynomial (exact elimination; no search)
    With p₁ = O − B + u·w, p₂ = O − C + v·w the two circles are the quadratics in s
        s² + 2s·(e·p₁) + k₁ = 0,  s² + 2s·(e·p₂) + k₂ = 0,  kᵢ = |pᵢ|² − (b², c²);
    their difference is linear in s: s = N/Dn with N = k₂ − k₁, Dn = 2e·(p₁ − p₂); put back,
        G(w) = N² + 2N·Dn·(e·p₁) + k₁·Dn² = 0.
    On |w| = 1, N, Dn, e·p₁ and k₁ are Laurent polynomials of w^{−1} … w¹, so G spans w^{−3} …
    w³: w³·G(w) is a polynomial of degree 6 — the degree does **not** drop against the RRR
    triad's: its w³ coefficient is conj(e)²·u·v·(u − v)·conj(B − C) ≠ 0, and six real modes occur
    (157 of 20 000 random instances; 4 in 3 925, 2 in 7 662). Its seven coefficients are the DFT
    of G at the seventh roots of unity (exact: G has seven terms), its roots the eigenvalues of the
    companion matrix (batched over samples); real modes are the roots on |w| = 1.
Polish
    Each root on the circle (within ``ON_CIRCLE``) gives s as the root of the first quadratic
    that best closes the second (robust where Dn is small) — and the other root too where it
    closes the second within ``ON_CIRCLE``·size² (two modes of one θ) —, then Newton on the two
    loop equations (the 2×2 system below) to round-off; roots within ``SAME_ROOT`` in θ and
    ``SAME_ROOT``·(|u| + |v|) in s are one.
Derivatives (exact): with q = E − B, r = F − C, g = −(q × u·w), h = −(r × v·w):
        (e·q)·s' + g·θ' = B'·q,     (e·r)·s' + h·θ' = C'·r,
    second order: the same matrix with right-hand sides
        (B'' + u·w·θ'²)·q − |E' − B'|²,   (C'' + v·w·θ'²)·r − |F' − C'|²,
    D' = s'·e, D'' = s''·e, E' = D' + j·u·w·θ', E'' = D'' + j·u·w·θ'' − u·w·θ'² (F alike).
Linear system: the 2×2 above by Cramer; its determinant det = (e·q)·h − (e·r)·g.
    The variants: R_E = E − O − s·e_k replaces u·w (g = q·(j·R_E)), B' becomes B' − O' − s·e_k' and
    B'' becomes B'' − O'' − 2s'·e_k' − s·e_k'' − 2j·s'·θ'·e₁·w (solver.groups._slider_triad_math's
    ``slider_analogs`` and ``slider_jets``, the one source of every path).
Conditioning
    |det| / (b·c·(|u| + |v|)) ∈ [0, 1] (|R_E| + |R_F| for the swinging block): 0 where the guide's
    normal at D and the lines of the two binary links meet in one point (a dead point: two
    assembly modes merge).
Branch rule (the mode): the RRR triad's, with the slide beside the angle. ``angle`` θ₀ names the
    mode: at the reference sample (nearest ``at``, else a sweep's first) the real root whose θ is
    nearest θ₀ — where θ₀ is the drawn one (``shape:`` given and θ₀ its arg(E − D)), the root
    nearest the drawn pose (θ₀, s₀), s₀ = e·(D − O) the drawn slide, by |Δθ| + |Δs|/(|u| + |v|):
    the same root but where two modes are close in θ, and the drawn one of two modes of one θ
    (a double root w of the polynomial where N = Dn = 0: both roots of the quadratic in s close
    the loop; without s₀ the lower s of them). Every other sample the root nearest the previous
    (θ, s) carried forward by (θ', s')·Δφ, by the same distance; a match farther than half the
    previous root's distance to its nearest other root where the count of real roots drops is a
    mode jump (a branch point between the samples): refused naming the φ. Per tick the previous
    tick plays the previous sample: Newton from the root it predicts, kept when unambiguous, else
    every root and the rule (solver.groups._slider_triad_tick); a dense monotone sweep finds every
    root on anchors only and polishes the interpolated root between them under the same checks
    (solver.groups._slider_triad_sweep), else every sample's roots (next to two modes of one θ
    the checks, in θ alone, refuse: every sample's roots and the rule decide).
Assembly fails where no real root exists (AssemblyError with the φ intervals).
Population (solver.synthesis: parameters (C, 1) arrays, φ (C, S)): each design's row solved as
    its own scene solves those samples, design by design (``own_sweeps``, shared with the RRR
    triad, solver.groups._triad_population); the guide's direction computed per design by the
    scalar formula (``_unit``) so that a design's values have its own scene's bits.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._backend import NUMPY, Backend
from .._fields import MISSING, Entry, Units
from ..jet import Jet, direction, sub
from . import _slider_triad_sweep as _fast
from . import _slider_triad_tick as _tick
from ._slider_triad_math import Line, follow_roots, slider_analogs, slider_jets, slider_polish, slider_roots
from ._slider_triad_tick import JUMP, NO_ROOT
from ._triad_math import SAME_ROOT
from ._triad_population import own_sweeps
from ._triad_tick import FOLLOW_DONE, FOLLOW_STEPS
from .base import Context, Group
from .triad import ternary_shape

__all__ = ["SliderTriad", "NO_ROOT", "JUMP"]


def _unit(angle: Any) -> Any:
    """e^{j·angle} by math.cos and math.sin, elementwise for a population's (C, 1) array: a design's
    guide direction has the bits of its own scene's (np.cos may differ from math.cos in the last bit)."""
    if isinstance(angle, np.ndarray):
        return np.vectorize(_unit, otypes=[complex])(angle)
    return complex(math.cos(angle), math.sin(angle))


def _col(x: Any) -> Any:
    return np.asarray(x)[:, None] if np.ndim(x) == 1 else x


def _cols(j: Jet) -> Jet:
    return Jet(_col(j.value), _col(j.d1), _col(j.d2))


def _drawn_slide(e: Entry, points: tuple[str, ...], units: Units, origin: Any, direction: Any, angle: float) -> Any:
    """s₀ = e·(D − O) of the drawn D where ``angle`` names the drawn mode (``shape:`` given, checked
    by ternary_shape, and θ₀ its arg(E − D) within ``SAME_ROOT``), else None (``sides:``, another
    mode named); in a population (solver.synthesis) a (C, 1) array, NaN for none, each design's
    value its own scene's (the same operations elementwise)."""
    if "shape" not in e.data:
        return None
    sh = e.child("shape", e.raw("shape"))
    xd, yd, xe, ye = (sh.length_value(sh.as_number(c, k), k, units, positive=False)
                      for k in points[:2] for c in sh.raw(k))
    if not any(isinstance(x, np.ndarray) for x in (xd, yd, xe, ye, origin, direction)):
        off = complex(xd, yd) - origin
        if abs(math.remainder(math.atan2(ye - yd, xe - xd) - angle, 2.0 * math.pi)) > SAME_ROOT:
            return None
        return float(off.real * direction.real + off.imag * direction.imag)
    off = xd + 1j * yd - origin
    drawn = np.abs(np.remainder(np.arctan2(ye - yd, xe - xd) - angle + np.pi, 2.0 * np.pi) - np.pi) <= SAME_ROOT
    return np.where(drawn, off.real * np.real(direction) + off.imag * np.imag(direction), np.nan)


@dataclass(frozen=True)
class SliderTriad(Group):
    kind = "slider_triad"
    #: O, e: the guide's fixed point (offset applied) and unit direction — in the world on a fixed
    #: guide, in the carrier's frame (P at 0, P→Q along x) with ``carrier``, in the ternary link's
    #: frame (p, e_t: D at 0, D→E along x) with ``block_at``
    origin: complex
    direction: complex
    ends: tuple[str, str]  # B, C
    points: tuple[str, str, str]  # D (on the guide), E, F
    lengths: tuple[float, float]  # |BE|, |CF|
    shape: tuple[complex, complex]  # u = E − D, v = F − D in the ternary link's frame
    angle: float  # θ₀
    at: float | None = None
    slide0: Any = None  # s₀: the drawn D's slide (None: not the drawn mode; a population: (C, 1), NaN for none)
    joint: str | None = None  # θ published as a joint coordinate
    slide: str | None = None  # s published as a joint coordinate (m)
    carrier: tuple[str, str] | None = None  # P, Q: the guide on the moving known link P–Q
    block_at: str | None = None  # A: the swinging block's pivot (the guide in the ternary link)
    #: the per-tick path's previous tick (φ, θ, θ', gap, count) and a block's carry
    _last: dict[str, Any] = field(default_factory=dict, compare=False, hash=False, repr=False)

    def requires(self) -> tuple[str, ...]:
        more = self.carrier if self.carrier is not None else (self.block_at,) if self.block_at is not None else ()
        return (*self.ends, *more)

    @property
    def line(self) -> Line:
        """(o₁, e₁) = (−p, −e_t) for the swinging block (the guide at w: O(w) = A − p·w, e(w) = −e_t·w)."""
        return None if self.block_at is None else (-self.origin, -self.direction)

    def guide_at(self, vals: Mapping[str, Jet], xp: Backend) -> tuple[Any, Any, tuple[Jet, Jet] | None]:
        """The guide's point and direction at the current values and, where it moves, their jets:
        ``(o, e, (O, e) jets | None)`` (O = A, e = 0 for the swinging block: :attr:`line` adds the rest)."""
        if self.block_at is not None:
            ja = vals[self.block_at]
            return ja.value, 0j, (ja, Jet(0j, 0.0, 0.0))
        if self.carrier is None:
            return self.origin, self.direction, None
        jp, jq = (vals[n] for n in self.carrier)
        turn = direction(sub(jq, jp), xp)
        c = turn.unit
        w1, w2 = turn.w.imag, turn.w1.imag  # the carrier's ω, α
        c1, c2 = 1j * w1 * c, (1j * w2 - w1 * w1) * c
        o0, e0 = self.origin, self.direction
        jo = Jet(jp.value + o0 * c, jp.d1 + o0 * c1, jp.d2 + o0 * c2)
        je = Jet(e0 * c, e0 * c1, e0 * c2)
        return jo.value, je.value, (jo, je)

    def joints(self) -> tuple[str, ...]:
        return tuple(n for n in (self.joint, self.slide) if n is not None)

    def provides(self) -> tuple[str, ...]:
        return (*self.points, *self.joints())

    def joint_units(self) -> dict[str, str]:
        out = {} if self.joint is None else {self.joint: "rad"}
        if self.slide is not None:
            out[self.slide] = "m"
        return out

    def rigid_pairs(self) -> tuple[tuple[str, str, float], ...]:
        (b, c), (d, e, f) = self.ends, self.points
        u, v = self.shape
        return ((b, e, self.lengths[0]), (c, f, self.lengths[1]), (d, e, abs(u)), (e, f, abs(v - u)),
                (f, d, abs(v)))

    def links(self) -> tuple[tuple[str, ...], ...]:
        (b, c), (d, e, f) = self.ends, self.points
        return ((b, e), (c, f), (d, e, f, d))

    def roots(self, vals: Mapping[str, Jet]) -> tuple[np.ndarray, np.ndarray]:
        """Every real mode at the current values: ``(θ, s)`` (:func:`slider_roots`)."""
        b_, c_ = (vals[n].value for n in self.ends)
        with np.errstate(all="ignore"):
            o, e, _ = self.guide_at(vals, NUMPY)
        return slider_roots(o, e, b_, c_, self.lengths, *self.shape, line=self.line)

    def solve(self, ctx: Context) -> None:
        vals = ctx.values
        jb, jc = (vals[n] for n in self.ends)
        u, v = self.shape
        line = self.line
        o, e, guide = self.guide_at(vals, ctx.xp)
        phi = ctx.phi
        th: Any
        s: Any
        if not ctx.xp.vectorised:  # one tick: Newton from the predicted root, else every root
            xp = ctx.xp
            step = sum(phi) if isinstance(phi, (tuple, list, np.ndarray)) else phi
            saved = dict(self._last) if xp.name == "trace" else None  # a trace never moves the mode
            b_, c_ = jb.value, jc.value
            th = math.nan
            pred = xp.call(self._t_predict, step, b_, c_)
            if pred == pred:
                s = xp.call(self._t_predicted_slide, pred)
                s, th_n, w, closed, last = slider_polish(s, pred, o, e, b_, c_, self.lengths, u, v,
                                                         steps=FOLLOW_STEPS, xp=xp, until=FOLLOW_DONE, line=line)
                analogs = slider_analogs(s, w, o, e, u, v, jb, jc, line=line, guide=guide)
                if closed and last <= FOLLOW_DONE:
                    th = xp.call(self._t_accept, step, b_, c_, pred, th_n, s, analogs[0], analogs[1], analogs[4])
            if not th == th:  # refused (or no prediction): every root and the branch rule
                th = (xp.call(self._t_full, step, b_, c_) if guide is None
                      else xp.call(self._t_full_moving, step, b_, c_, o, e))
                if not th == th:  # NaN: no real root, or a mode jump
                    ctx.require(self, False, reason=self._last.get("reason", NO_ROOT))
                s = xp.call(self._t_full_slide, th)
                w = xp.cis(th)
                analogs = slider_analogs(s, w, o, e, u, v, jb, jc, line=line, guide=guide)
                if th == th:
                    th = xp.call(self._t_accept_full, step, b_, c_, th, s, analogs[0], analogs[1], analogs[4])
            if saved is not None:
                self._last.clear()
                self._last.update(saved)
        else:
            if ctx.seeds is None and np.ndim(phi) == 2:  # a population of designs (solver.synthesis)
                own_sweeps(self, ctx, np.asarray(phi, float), reason=NO_ROOT)
                return
            th, s, w, analogs = self._sweep(ctx, phi, jb, jc, o, e, guide)
        s1, t1, s2, t2, det = analogs
        for name, jet in zip(self.points, slider_jets(s, w, analogs, o, e, u, v, line=line, guide=guide)):
            vals[name] = jet
        if self.joint is not None:
            vals[self.joint] = Jet(th, t1, t2)
        if self.slide is not None:
            vals[self.slide] = Jet(s, s1, s2)
        b, c = self.lengths
        if line is None:
            arms: Any = abs(u) + abs(v)
        else:  # |R_E| + |R_F|, R_E = E − A
            ra = o - vals[self.points[1]].value
            arms = abs(ra) + abs(ra + vals[self.points[1]].value - vals[self.points[2]].value)
        ctx.conditioning[self.name] = abs(det) / (b * c * arms)

    def _sweep(self, ctx: Context, phi: Any, jb: Jet, jc: Jet, o: Any, e: Any,
               guide: tuple[Jet, Jet] | None) -> tuple[Any, Any, Any, tuple[Any, ...]]:
        """The followed root at every sample and its analogs: ``(θ, s, e^{jθ}, analogs)`` — through the
        anchors' shortcut (solver.groups._slider_triad_sweep) where it holds, else every sample's
        roots and the branch rule; a block of a longer sweep (solver.scene solves in blocks of
        views into one array) continues from the previous block's last root."""
        n = len(phi)
        ph = np.asarray(phi, float).reshape(n, -1)
        step = ph.sum(axis=1)
        base = getattr(phi, "base", None)
        key = None
        if isinstance(phi, np.ndarray) and isinstance(base, np.ndarray) and base.size > phi.size:
            offset = (phi.__array_interface__["data"][0] - base.__array_interface__["data"][0]) // phi.itemsize
            key = (id(base), offset)
        carry = self._last.get("block")
        carry = carry if key is not None and carry is not None and carry["key"] == key else None
        slide0 = self.slide0
        if carry is not None:
            dphi = float(step[0]) - carry["phi"]
            start, target = 0, carry["theta"] + carry["rate"] * dphi
            slide0 = carry["s"] + carry["s_rate"] * dphi
        elif self.at is None or ph.shape[1] != 1:
            start, target = 0, self.angle
        else:
            off = ph[:, 0] - self.at
            off -= (2.0 * np.pi) * np.round(off * (0.5 / np.pi))  # wrapped (cheaper than a remainder)
            start, target = int(np.argmin(np.abs(off))), self.angle
        u, v = self.shape
        line = self.line
        moving = None if guide is None else (o, e, guide)
        with np.errstate(all="ignore"):
            fast = _fast.fast_sweep(self, step, jb, jc, start, target, slide0, moving=moving)
            while fast is not None:  # refused at the determinant check: the narrower anchors, then none
                th, s, w = fast.theta, fast.s, fast.w
                analogs = slider_analogs(s, w, o, e, u, v, jb, jc, line=line, guide=guide)
                if fast.holds(analogs[4]):
                    break
                fast = _fast.fast_sweep(self, step, jb, jc, start, target, slide0, spans=fast.narrower, moving=moving)
        if fast is None:
            th, s = self._full_sweep(ctx, step, jb, jc, start, target, slide0, o, e, guide)
            with np.errstate(all="ignore"):
                w = NUMPY.cis(th)
                analogs = slider_analogs(s, w, o, e, u, v, jb, jc, line=line, guide=guide)
        if key is not None and np.isfinite(th[-1]):
            self._last["block"] = {"key": (key[0], key[1] + n), "theta": float(th[-1]),
                                   "rate": float(np.real(analogs[1][-1])), "phi": float(step[-1]),
                                   "s": float(s[-1]), "s_rate": float(np.real(analogs[0][-1]))}
        return th, s, w, analogs

    def _full_sweep(self, ctx: Context, step: np.ndarray, jb: Jet, jc: Jet, start: int, target: float,
                    slide0: float | None, o: Any, e: Any, guide: tuple[Jet, Jet] | None) -> tuple[Any, Any]:
        """Every sample's roots and the branch rule: ``(θ, s)`` of the followed root."""
        n = len(step)
        line = self.line
        with np.errstate(all="ignore"):
            theta, ss = slider_roots(o, e, jb.value, jc.value, self.lengths, *self.shape, line=line)
        theta, ss = np.broadcast_to(theta, (n, 6)), np.broadcast_to(ss, (n, 6))
        ctx.require(self, np.isfinite(theta).any(axis=-1), reason=NO_ROOT)
        u, v = self.shape
        jets = [_cols(j) for j in (jb, jc)]
        moved = None if guide is None else (_cols(guide[0]), _cols(guide[1]))
        with np.errstate(all="ignore"):
            s_rate, rate = slider_analogs(ss, np.cos(theta) + 1j * np.sin(theta), _col(o), _col(e),
                                          u, v, *jets, line=line, guide=moved)[:2]
        slots, jumps = follow_roots(theta, ss, np.real(rate), np.real(s_rate), step, start, target, slide0=slide0,
                                    scale=abs(u) + abs(v))
        if jumps.any():
            ctx.require(self, ~jumps, reason=JUMP)
        rows = np.arange(n)
        pick = np.maximum(slots, 0)
        return np.where(slots >= 0, theta[rows, pick], np.nan), np.where(slots >= 0, ss[rows, pick], np.nan)

    # the per-tick follow's calls (solver.groups._slider_triad_tick), bound methods the compiled code calls
    def _t_predict(self, step: float, b: complex, c: complex) -> float:
        return _tick.predict(self, step, b, c)

    def _t_predicted_slide(self, theta: float) -> float:
        return _tick.predicted_slide(self, theta)

    def _t_accept(self, step: float, b: complex, c: complex, pred: float, theta: float, s: float, s1: float,
                  rate: float, det: float) -> float:
        return _tick.accept(self, step, b, c, pred, theta, s, s1, rate, det)

    def _t_full(self, step: float, b: complex, c: complex) -> float:
        return _tick.full(self, step, b, c)

    def _t_full_moving(self, step: float, b: complex, c: complex, o: complex, e: complex) -> float:
        return _tick.full(self, step, b, c, guide=(o, e))

    def _t_full_slide(self, theta: float) -> float:
        return _tick.full_slide(self, theta)

    def _t_accept_full(self, step: float, b: complex, c: complex, theta: float, s: float, s1: float, rate: float,
                       det: float) -> float:
        return _tick.accept_full(self, step, b, c, theta, s, s1, rate, det)

    def assembly_residual(self, vals: Mapping[str, Jet]) -> tuple[Any, Any, Any]:
        """``R = +1`` where a real mode exists, ``−1`` where none (its sign change is bisected by
        solver.assembly), ``dR/dφ = 0``, scale 1."""
        theta, _ = self.roots(vals)
        r = np.where(np.isfinite(theta).any(axis=-1), 1.0, -1.0)
        return r, np.zeros_like(r), 1.0

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> SliderTriad:
        """``{type: slider_triad, name, guide: {through, angle?, offset?} | {on: [P, Q], angle?, offset?},
        ends: [B, C], points: [D, E, F], lengths: [BE, CF], sides: [DE, EF, FD] with M | shape: {D, E, F},
        angle: θ₀, at?: φ₀, joint?, slide?}``; or the swinging block ``block_at: A`` with
        ``guide?: {angle?, offset?}`` (the line in the ternary link, through D at ``angle`` from D→E)."""
        name = e.name("name")
        block_at = e.raw("block_at", None)
        g = e.child("guide", e.raw("guide", {} if block_at is not None else MISSING))
        carrier: tuple[str, str] | None = None
        data = g.data if isinstance(g.data, Mapping) else {}
        if block_at is not None:
            block_at = e.name("block_at")
            for key in ("through", "on"):
                if key in data:
                    raise g.error("the swinging block's guide is a line in the ternary link (through D at angle "
                                  f"from D→E, offset along its normal): no '{key}'", key)
            base: Any = 0j
        elif "on" in data:
            if "through" in data:
                raise g.error("give the guide either through: <fixed point> or on: [P, Q] (a moving link)", "on")
            on = g.names("on", 2)
            if on[0] == on[1]:
                raise g.error(f"[{on[0]}, {on[1]}]: two different points of the carrying link", "on")
            carrier = (on[0], on[1])
            base = 0j
        else:
            through = g.name("through")
            if through not in fixed:
                raise g.error(f"the guide is fixed; '{through}' is not a fixed point (a guide on a moving link: "
                              "on: [P, Q])", "through")
            base = fixed[through]
        angle = g.angle("angle", units, 0.0)
        offset = g.length("offset", units, positive=False, default=0.0)
        g.done()
        direction: Any = _unit(angle)  # complex, or (C, 1) arrays in a population (solver.synthesis)
        origin: Any = base + offset * 1j * direction
        if not isinstance(origin, np.ndarray):
            origin = complex(origin)
        ends = e.names("ends", 2)
        points = e.names("points", 3)
        raw = e.raw("lengths")
        if not isinstance(raw, (list, tuple)) or len(raw) != 2:
            raise e.error(f"must be [|BE|, |CF|], got {raw!r}", "lengths")
        sub = e.child("lengths", {"BE": raw[0], "CF": raw[1]})
        lengths = (sub.length("BE", units), sub.length("CF", units))
        u, v = ternary_shape(e, points, units)  # (C, 1) arrays in a population, as the lengths may be
        theta0 = e.angle("angle", units)
        # s₀ from the drawn D on a fixed guide (a moving guide or pivot is placed only at run time)
        fixed_guide = carrier is None and block_at is None
        slide0 = _drawn_slide(e, points, units, origin, direction, theta0) if fixed_guide else None
        at = e.raw("at", None)
        joint = e.raw("joint", None)
        slide = e.raw("slide", None)
        return cls(
            name=name,
            origin=origin,
            direction=direction,
            ends=(ends[0], ends[1]),
            points=(points[0], points[1], points[2]),
            lengths=lengths,
            shape=(u, v),
            angle=theta0,
            at=None if at is None else e.angle("at", units),
            slide0=slide0,
            joint=None if joint is None else e.name("joint"),
            slide=None if slide is None else e.name("slide"),
            carrier=carrier,
            block_at=block_at,
        )

