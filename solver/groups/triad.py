"""The RRR–RRR–RRR triad (class-3 Assur group): a ternary link D, E, F joined by three binary
links to three known points A, B, C.

Loop equations
    |D − A| = a,  |E − B| = b,  |F − C| = c,  with E = D + u·w, F = D + v·w, w = e^{jθ}:
    θ is the ternary link's angle, u = E − D and v = F − D its shape in its own frame
    (``sides`` [DE, EF, FD] with ``M``: u = DE, v = FD·e^{jM·∠EDF}, ∠EDF from the law of
    cosines; or ``shape`` with the three local points).
Univariate polynomial (exact elimination; no search)
    With A moved to the origin, P = B − A − u·w and Q = C − A − v·w, subtracting |D|² = a² from
    the other two circles gives the linear pair D·P = s₁, D·Q = s₂ (planar dot products),
    s₁ = (|P|² + a² − b²)/2, s₂ = (|Q|² + a² − c²)/2, so D = j·(s₂P − s₁Q)/(P × Q) (Cramer) and
    the loop closes where  G(w) = |s₂P − s₁Q|² − a²·(P × Q)² = 0.
    On |w| = 1 (w̄ = 1/w) P and Q are polynomials in w of degree 1, s₁, s₂ and P × Q Laurent
    polynomials in w of degrees −1…1, so s₂P − s₁Q spans w^{−1}…w², its conjugate w^{−2}…w¹ and
    G spans w^{−3}…w³: w³·G(w) is a polynomial of degree 6 (the classical six assembly modes of
    the triad; the same degree as the half-angle-tangent form, t = tan(θ/2), w = (1+jt)/(1−jt),
    without the root at infinity θ = π). Its seven coefficients are the discrete Fourier
    transform of G at the seventh roots of unity — exact, since G has exactly seven terms —
    and its roots are the eigenvalues of the companion matrix (batched over samples). G is real
    on the circle, so the polynomial is self-inversive: real assembly modes are its roots on
    |w| = 1 (the others come in pairs w, 1/w̄).
Polish
    Each root on the circle (within ``ON_CIRCLE``) gives (D, θ) by Cramer, then Newton on the
    three loop equations (the 3×3 system below) to round-off; a root whose Newton step does
    not converge (a complex pair near the circle) is no assembly mode. Roots within
    ``SAME_ROOT`` of each other are one (a double root: a branch point).
Derivatives (exact): differentiate the three loop equations. With p = D − A, q = E − B,
    s = F − C, g = −(q × u·w), h = −(s × v·w) (real), unknowns D' and θ':
        D'·p = A'·p,    D'·q + g·θ' = B'·q,    D'·s + h·θ' = C'·s,
    second order: the same matrix with right-hand sides
        A''·p − |D' − A'|²,  (B'' + u·w·θ'²)·q − |E' − B'|²,  (C'' + v·w·θ'²)·s − |F' − C'|²,
    then E' = D' + j·u·w·θ', E'' = D'' + j·u·w·θ'' − u·w·θ'² (F alike).
Linear system: eliminating θ' from the last two rows, D'·m = h·r₂ − g·r₃ with m = h·q − g·s,
    D' = j·(r'·p − r₁·m)/(p × m) as for the dyads, θ' = (g·(r₂ − D'·q) + h·(r₃ − D'·s))/(g² + h²).
    Its determinant is p × m = h·(p × q) − g·(p × s).
Conditioning
    |p × m| / (a·b·c·(|u| + |v|)) ∈ [0, 1]: 0 where the three binary links' lines meet in one
    point with the ternary link's instant centre (a dead point: two assembly modes merge).
Branch rule (the mode)
    ``angle`` θ₀ names the mode: at the first sample of a sweep (or the sample nearest the
    input ``at`` when it is given) the mode is the real root whose ternary-link angle is nearest
    θ₀; from there every other sample takes the root nearest the previous sample's angle
    carried forward by its velocity analog (θ + θ'·Δφ), so the branch is followed
    continuously, not by an index that changes when roots appear or vanish. Per tick (the
    scalar path) the previous tick plays the previous sample; the scene's next block of one sweep
    starts from the previous block's last root. A step whose nearest root is
    farther than half the previous sample's distance to its neighbouring root, where the count of
    real roots drops, is a mode jump (a branch point, two roots merging, between the samples):
    refused, naming the φ.
Assembly fails where no real root exists (AssemblyError with the φ intervals, found on a grid
of one turn from the count of real roots).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._backend import cross
from .._fields import Entry, Units
from ..jet import Jet
from . import _triad_population as _population
from . import _triad_sweep as _sweep
from . import _triad_tick as _tick
from ._triad_math import (
    ON_CIRCLE,
    SAME_ROOT,
    _wrap,
    triad_analogs,
    triad_coefficients,
    triad_points,
    triad_polish,
    triad_roots,
)
from .base import Context, Group

__all__ = ["Triad", "ternary_shape", "triad_roots", "triad_coefficients", "triad_analogs", "ON_CIRCLE", "SAME_ROOT"]


@dataclass(frozen=True)
class Triad(Group):
    kind = "triad"
    ends: tuple[str, str, str]  # A, B, C
    points: tuple[str, str, str]  # D, E, F
    lengths: tuple[float, float, float]  # |AD|, |BE|, |CF|
    shape: tuple[complex, complex]  # u = E − D, v = F − D in the ternary link's frame
    angle: float  # θ₀: the mode's ternary-link angle arg(E − D) at the reference sample
    at: float | None = None  # the input value of the reference sample (None: a sweep's first)
    joint: str | None = None  # θ published as a joint coordinate, if named
    #: the per-tick path's previous tick (φ, θ, θ', gap to the neighbouring root): continuity
    _last: dict[str, Any] = field(default_factory=dict, compare=False, hash=False, repr=False)
    #: the last sample of the latest vectorised block (θ, θ', φ): the next block of one sweep starts there
    _end_state: dict[str, Any] = field(default_factory=dict, compare=False, hash=False, repr=False)

    def requires(self) -> tuple[str, ...]:
        return self.ends

    def provides(self) -> tuple[str, ...]:
        return (*self.points, *(() if self.joint is None else (self.joint,)))

    def joints(self) -> tuple[str, ...]:
        return () if self.joint is None else (self.joint,)

    def rigid_pairs(self) -> tuple[tuple[str, str, float], ...]:
        (a, b, c), (d, e, f) = self.ends, self.points
        u, v = self.shape
        return ((a, d, self.lengths[0]), (b, e, self.lengths[1]), (c, f, self.lengths[2]),
                (d, e, abs(u)), (e, f, abs(v - u)), (f, d, abs(v)))

    def links(self) -> tuple[tuple[str, ...], ...]:
        (a, b, c), (d, e, f) = self.ends, self.points
        return ((a, d), (b, e), (c, f), (d, e, f, d))

    def singular_names(self) -> tuple[str, ...]:
        return ()

    def roots(self, vals: Mapping[str, Jet]) -> tuple[np.ndarray, np.ndarray]:
        """Every real mode at the current values: ``(θ, D)`` (:func:`triad_roots`)."""
        a_, b_, c_ = (vals[n].value for n in self.ends)
        return triad_roots(a_, b_, c_, self.lengths, *self.shape)

    def solve(self, ctx: Context) -> None:
        vals = ctx.values
        ja, jb, jc = (vals[n] for n in self.ends)
        u, v = self.shape
        phi = ctx.phi
        th: Any
        d: Any
        w: Any
        if not ctx.xp.vectorised:  # one tick: Newton from the predicted root, in the traced lines
            xp = ctx.xp
            step = sum(phi) if isinstance(phi, (tuple, list, np.ndarray)) else phi
            saved = dict(self._last) if xp.name == "trace" else None  # a trace never moves the mode
            a_, b_, c_ = ja.value, jb.value, jc.value
            th = math.nan
            pred = xp.call(self._t_predict, step, a_, b_, c_)
            if pred == pred:
                d = xp.call(self._t_predicted_point, pred)
                d, th_n, w, closed, last = triad_polish(d, pred, a_, b_, c_, self.lengths, u, v,
                                                        steps=_tick.FOLLOW_STEPS, xp=xp, until=_tick.FOLLOW_DONE)
                analogs = triad_analogs(d, w, u, v, ja, jb, jc)
                if closed and last <= _tick.FOLLOW_DONE:
                    th = xp.call(self._t_accept, step, a_, b_, c_, pred, th_n, d, analogs[0], analogs[1],
                                 analogs[4])
            if not th == th:  # refused (or no prediction): every root and the branch rule
                th = xp.call(self._t_full, step, a_, b_, c_)
                d = xp.call(self._t_full_point, th)
                if not th == th:  # NaN: no real root, or a mode jump
                    ctx.require(self, False, reason=self._last.get("reason", _tick.NO_ROOT))
                w = xp.cis(th)
                analogs = triad_analogs(d, w, u, v, ja, jb, jc)
                if th == th:
                    th = xp.call(self._t_accept_full, step, a_, b_, c_, th, d, analogs[0], analogs[1], analogs[4])
            if saved is not None:
                self._last.clear()
                self._last.update(saved)
        elif ctx.seeds is None and np.ndim(phi) == 2:  # a population of designs (solver.synthesis)
            _population.solve_population(self, ctx)
            return
        else:
            # a block of a longer sweep (solver.scene solves in blocks of views into one array):
            # continue from where the previous block of the same array ended
            base = getattr(phi, "base", None)
            key = None
            if isinstance(phi, np.ndarray) and isinstance(base, np.ndarray) and base.size > phi.size:
                offset = (phi.__array_interface__["data"][0] - base.__array_interface__["data"][0]) // phi.itemsize
                key = (id(base), offset)
            carry = self._last.get("block")
            carry = carry if key is not None and carry is not None and carry["key"] == key else None
            with np.errstate(all="ignore"):
                fast = _sweep.fast_sweep(self, phi, ja, jb, jc, carry)
            while fast is not None:  # the determinant checked at every sample; else narrower anchors
                th, d, w = fast.theta, fast.d, fast.w
                analogs = triad_analogs(d, w, u, v, ja, jb, jc)
                if fast.holds(analogs[-1]):
                    break
                with np.errstate(all="ignore"):
                    fast = _sweep.fast_sweep(self, phi, ja, jb, jc, carry, spans=fast.narrower)
            if fast is None:
                th, d = self._full_sweep(ctx, phi, ja, jb, jc, carry)
                w = np.cos(th) + 1j * np.sin(th)
                analogs = triad_analogs(d, w, u, v, ja, jb, jc)
            if key is not None and self._end_state:
                self._last["block"] = dict(self._end_state, key=(key[0], key[1] + len(phi)))
        d1, t1, d2, t2, det = analogs
        for name, jet in zip(self.points, triad_points(d, w, u, v, d1, t1, d2, t2)):
            vals[name] = jet
        if self.joint is not None:
            vals[self.joint] = Jet(th, t1, t2)
        a, b, c = self.lengths
        ctx.conditioning[self.name] = abs(det) / (a * b * c * (abs(u) + abs(v)))

    # the per-tick follow's calls (solver.groups._triad_tick), bound methods the compiled code calls
    def _t_predict(self, step: float, a: complex, b: complex, c: complex) -> float:
        return _tick.predict(self, step, a, b, c)

    def _t_predicted_point(self, theta: float) -> complex:
        return _tick.predicted_point(self, theta)

    def _t_accept(self, step: float, a: complex, b: complex, c: complex, pred: float, theta: float, d: complex,
                  d1: complex, rate: float, det: float) -> float:
        return _tick.accept(self, step, a, b, c, pred, theta, d, d1, rate, det)

    def _t_full(self, step: float, a: complex, b: complex, c: complex) -> float:
        return _tick.full(self, step, a, b, c)

    def _t_full_point(self, theta: float) -> complex:
        return _tick.full_point(self, theta)

    def _t_accept_full(self, step: float, a: complex, b: complex, c: complex, theta: float, d: complex,
                       d1: complex, rate: float, det: float) -> float:
        return _tick.accept_full(self, step, a, b, c, theta, d, d1, rate, det)

    def _full_sweep(self, ctx: Context, phi: Any, ja: Jet, jb: Jet, jc: Jet,
                    carry: dict[str, Any] | None) -> tuple[Any, Any]:
        """Every sample's roots and the branch rule (the path that decides where the shortcut of
        solver.groups._triad_sweep does not): ``(θ, D)`` of the followed root."""
        a_, b_, c_ = ja.value, jb.value, jc.value
        theta, dd = triad_roots(a_, b_, c_, self.lengths, *self.shape)
        has = np.isfinite(theta).any(axis=-1)
        ctx.require(self, has, reason=_tick.NO_ROOT)
        self._end_state.clear()
        slots, jumps = self._pick_sweep(phi, theta, dd, ja, jb, jc, carry=carry)
        if jumps.any():
            ctx.require(self, ~jumps, reason=_tick.JUMP)
        rows = np.arange(len(theta))
        pick = np.maximum(slots, 0)
        return np.where(slots >= 0, theta[rows, pick], np.nan), np.where(slots >= 0, dd[rows, pick], np.nan)

    def _pick_sweep(self, phi: Any, theta: np.ndarray, dd: np.ndarray, ja: Jet, jb: Jet, jc: Jet, *,
                    carry: dict[str, Any] | None = None, rate: np.ndarray | None = None,
                    ) -> tuple[np.ndarray, np.ndarray]:
        """The followed root's slot at each sample, and where following it would jump mode
        (``rate``: θ' at every slot, if the caller has it already)."""
        n = len(theta)
        ph = np.asarray(phi, float).reshape(n, -1)
        idx = np.full(n, -1)
        jumps = np.zeros(n, bool)
        if self.at is None or ph.shape[1] != 1 or carry is not None:
            start = 0
        else:
            start = int(np.argmin(np.abs(_wrap(ph[:, 0] - self.at))))
        starts = np.flatnonzero(np.isfinite(theta[start:]).any(axis=-1))
        if not starts.size:
            return idx, jumps
        i0 = start + int(starts[0])
        real = np.isfinite(theta[i0])
        target = self.angle
        if carry is not None:  # the previous block's last root, carried forward
            target = carry["theta"] + carry["rate"] * (float(np.sum(ph[i0])) - carry["phi"])
        idx[i0] = int(np.flatnonzero(real)[np.argmin(np.abs(_wrap(theta[i0][real] - target)))])
        with np.errstate(all="ignore"):
            if rate is None:
                rate = self.slot_analogs(theta, dd, ja, jb, jc)[1]  # θ' at every slot: the predictor
            # each slot's distance to its nearest other real root (the matching's safe radius)
            diff = np.abs(_wrap(theta[:, :, None] - theta[:, None, :]))
            diff[:, np.arange(6), np.arange(6)] = np.inf
            gap = np.nan_to_num(np.nanmin(np.where(np.isnan(diff), np.inf, diff), axis=-1), nan=np.inf)
        two_pi, pi = 2.0 * math.pi, math.pi
        rows = [[t for t in r if t == t] for r in theta.tolist()]  # real roots, slots 0… in order
        rate_l, gap_l, step_phi = rate.tolist(), gap.tolist(), ph.sum(axis=1).tolist()
        angle = self.angle

        def nearest(r: list[float], target: float) -> tuple[int, float]:
            best, dist = 0, math.inf
            for m, t in enumerate(r):
                e = abs((t - target + pi) % two_pi - pi)
                if e < dist:
                    best, dist = m, e
            return best, dist
        out = idx.tolist()
        jump = [False] * n
        for step in (1, -1):
            i = i0
            while 0 <= i + step < n:
                j = i + step
                r = rows[j]
                if not r:
                    i = j
                    continue
                k = out[i]
                if k < 0:  # restart after a gap: nearest θ₀ again
                    out[j] = nearest(r, angle)[0]
                else:
                    m, dist = nearest(r, rows[i][k] + rate_l[i][k] * (step_phi[j] - step_phi[i]))
                    out[j] = m
                    jump[j] = dist > 0.5 * gap_l[i][k] and len(r) < len(rows[i])
                i = j
        last = out[-1]
        if last >= 0:
            self._end_state.update(theta=rows[-1][last], rate=rate_l[-1][last], phi=step_phi[-1])
        return np.array(out), np.array(jump)

    def slot_analogs(self, theta: np.ndarray, dd: np.ndarray, ja: Jet, jb: Jet, jc: Jet) -> tuple[Any, ...]:
        """:func:`triad_analogs` at every slot of :meth:`roots`' ``(θ, D)`` (shape (n, 6); NaN where a
        slot holds no root), the ends' jets of shape (n,) or scalars."""
        def col(x: Any) -> Any:
            return x[:, None] if np.ndim(x) == 1 else x
        jets = [Jet(col(j.value), col(j.d1), col(j.d2)) for j in (ja, jb, jc)]
        return triad_analogs(dd, np.cos(theta) + 1j * np.sin(theta), *self.shape, *jets)

    def assembly_residual(self, vals: Mapping[str, Jet]) -> tuple[Any, Any, Any]:
        """``R = +1`` where a real assembly mode exists, ``−1`` where none (a step: its sign change
        is bisected to the interval's end by solver.assembly), ``dR/dφ = 0``, scale 1."""
        theta, _ = self.roots(vals)
        r = np.where(np.isfinite(theta).any(axis=-1), 1.0, -1.0)
        return r, np.zeros_like(r), 1.0

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> Triad:
        """``{type: triad, name, ends: [A, B, C], points: [D, E, F], lengths: [AD, BE, CF],
        sides: [DE, EF, FD] with M (±1: D → E → F counter-clockwise) | shape: {D: [x, y], E, F},
        angle: θ₀, at?: φ₀, joint?}``."""
        ends = e.names("ends", 3)
        points = e.names("points", 3)
        raw = e.raw("lengths")
        if not isinstance(raw, (list, tuple)) or len(raw) != 3:
            raise e.error(f"must be [|AD|, |BE|, |CF|], got {raw!r}", "lengths")
        sub = e.child("lengths", {"AD": raw[0], "BE": raw[1], "CF": raw[2]})
        lengths = (sub.length("AD", units), sub.length("BE", units), sub.length("CF", units))
        u, v = ternary_shape(e, points, units)
        at = e.raw("at", None)
        joint = e.raw("joint", None)
        return cls(
            name=e.name("name"),
            ends=(ends[0], ends[1], ends[2]),
            points=(points[0], points[1], points[2]),
            lengths=lengths,
            shape=(u, v),
            angle=e.angle("angle", units),
            at=None if at is None else e.angle("at", units),
            joint=None if joint is None else e.name("joint"),
        )


def ternary_shape(e: Entry, points: tuple[str, ...], units: Units) -> tuple[Any, Any]:
    """A ternary link's shape from its entry: ``sides: [DE, EF, FD]`` with ``M`` or ``shape: {D: [x, y],
    E, F}`` → ``(u, v)`` = (E − D, F − D) in the link's own frame (θ = arg(E − D)); (C, 1) arrays with
    NaN where a design has no ternary link in a population (solver.synthesis). Shared by the
    triads (solver.groups.triad, solver.groups.slider_triad)."""
    has_sides, has_shape = "sides" in e.data, "shape" in e.data
    u: Any  # complex, or (C, 1) arrays in a population (solver.synthesis)
    v: Any
    if has_sides == has_shape:
        raise e.error("give the ternary link as either sides: [DE, EF, FD] (with M) or shape: {D: [x, y], E, F}",
                      "sides")
    if has_sides:
        raw = e.raw("sides")
        if not isinstance(raw, (list, tuple)) or len(raw) != 3:
            raise e.error(f"must be [|DE|, |EF|, |FD|], got {raw!r}", "sides")
        ss = e.child("sides", {"DE": raw[0], "EF": raw[1], "FD": raw[2]})
        de, ef, fd = (ss.length(k, units) for k in ("DE", "EF", "FD"))
        mode = e.mode()
        if any(isinstance(x, np.ndarray) for x in (de, ef, fd)):  # a population: no triangle → NaN, rejected
            u, v = _each(lambda a, b, c: _from_sides(a, b, c, mode), de, ef, fd)
        else:
            u, v = _from_sides(de, ef, fd, mode)
            if u != u:
                raise e.error(f"[{de:.6g}, {ef:.6g}, {fd:.6g}] is no triangle (each side shorter than the "
                              "other two)", "sides")
    else:
        sh = e.child("shape", e.raw("shape"))
        pts: list[Any] = []
        for k in points:
            xy = sh.raw(k)
            if not isinstance(xy, (list, tuple)) or len(xy) != 2:
                raise sh.error(f"must be [x, y], got {xy!r}", k)
            pts.append(sh.length_value(sh.as_number(xy[0], k), k, units, positive=False)
                       + 1j * sh.length_value(sh.as_number(xy[1], k), k, units, positive=False))
        sh.done()
        if any(isinstance(p, np.ndarray) for p in pts):  # a population: three points on one line → NaN, rejected
            u, v = _each(_from_shape, *pts)
        else:
            u, v = _from_shape(*pts)
            if u != u:
                raise e.error("the ternary link's three points are on one line", "shape")
    return u, v


def _from_sides(de: float, ef: float, fd: float, mode: int) -> tuple[complex, complex]:
    """``(u, v)`` of a ternary link from its sides and M; NaN where they make no triangle."""
    cos_d = (de * de + fd * fd - ef * ef) / (2.0 * de * fd)
    if not -1.0 < cos_d < 1.0:
        return complex(math.nan, math.nan), complex(math.nan, math.nan)
    ang = mode * math.acos(cos_d)
    return complex(de, 0.0), fd * complex(math.cos(ang), math.sin(ang))


def _from_shape(d: complex, e: complex, f: complex) -> tuple[complex, complex]:
    """``(u, v)`` of a ternary link from its three points in any frame, turned so that θ =
    arg(E − D); NaN where the points are on one line."""
    u, v = complex(e - d), complex(f - d)
    if abs(cross(u, v)) <= 1e-12 * abs(u) ** 2:
        return complex(math.nan, math.nan), complex(math.nan, math.nan)
    return complex(np.abs(u) + 0j), complex(v * np.conj(u) / np.abs(u))  # numpy scalars: the loader's bits


def _each(formula: Any, *args: Any) -> tuple[Any, Any]:
    """A scalar formula of two complex results applied to each design of a population's (C, 1)
    arrays: each design's values have the bits of its own scene's (solver.synthesis compares them)."""
    a = np.broadcast_arrays(*(np.asarray(x) for x in args))
    out = [formula(*(x[i] for x in a)) for i in np.ndindex(a[0].shape)]
    u = np.array([o[0] for o in out], complex).reshape(a[0].shape)
    v = np.array([o[1] for o in out], complex).reshape(a[0].shape)
    return u, v
