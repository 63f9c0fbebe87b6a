"""The slider triad's array functions (the class-3 Assur group with one prismatic pair of
:mod:`solver.groups.slider_triad`, whose docstring states the loop equations, the polynomial,
the linear system and the branch rule): the polynomial's coefficients, every root polished by
Newton on the loop equations, the analogs and the branch rule's matching over a sweep — on arrays
of samples (numpy) or numbers and tracers (the backends), with no group state.

Notation: the guide through O (offset applied) with unit direction e; D = O + s·e; the ends B, C
of the binary links BE = b and CF = c; the ternary link's shape u = E − D, v = F − D in its own
frame, w = e^{jθ}; q = E − B = D + u·w − B, r = F − C = D + v·w − C.

The variants (solver.groups.slider_triad's docstring): every function takes the guide at the
instant (o, e: values, or arrays of one per sample for a guide on a moving link) and, keyword-only,
``line = (o₁, e₁)`` for a guide carried by the ternary link: then the guide at w is
O(w) = o + o₁·w, e(w) = e + e₁·w (the swinging block: o = A, e = 0, o₁ = −p, e₁ = −e_t) and
R_E = E − o − s·e = (o₁ + s·e₁ + u)·w replaces u·w as E's arm of θ (R_F alike); ``guide = (O, e)``
jets give a moving guide's derivatives (solver.groups.slider_triad: the analogs' extra terms).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._backend import NUMPY, Backend, abs2, cross, dot
from ..jet import Jet
from ..tolerances import EPS
from ._triad_math import ON_CIRCLE, POLISH_DONE, POLISH_STEPS, RESIDUAL_ROUNDING, SAME_ROOT

__all__ = ["slider_coefficients", "slider_start", "slider_polish", "slider_roots", "slider_analogs", "slider_jets",
           "follow_roots", "pick", "closest", "spread", "mode_distance", "DEGREE", "DEGREE_DROP", "Line"]

#: The degree of the loop polynomial in w (w³·G(w), G a Laurent polynomial of w^{−3} … w³).
DEGREE: int = 6

#: w³·G's leading coefficient (and, self-inversive, its constant one) counts as 0 below this
#: share of size⁴ (G's terms are of order size⁴, size = |B − O| + |C − O| + b + c + |u| + |v|):
#: B = C (both binary links on one pivot), where the degree drops to 4 (two roots at 0 and ∞, none
#: on the circle) and a rounding-noise leading coefficient would spoil the others.
DEGREE_DROP: float = 1e-13

_ROOTS7 = np.exp(2j * np.pi * np.arange(7) / 7)

Line = tuple[Any, Any] | None  # (o₁, e₁): the guide carried by the ternary link, else None


def _at(o: Any, e: Any, w: Any, line: Line) -> tuple[Any, Any]:
    """The guide's point and direction at w: (o, e), or (o + o₁·w, e + e₁·w) on the ternary link."""
    if line is None:
        return o, e
    return o + line[0] * w, e + line[1] * w


def _arms(s: Any, w: Any, u: complex, v: complex, line: Line) -> tuple[Any, Any, Any]:
    """R_D, R_E, R_F: the arms of θ at D, E, F (each point's d/dθ is j·R): 0, u·w, v·w on a guide
    not carried by the ternary link, else (o₁ + s·e₁)·w, then + u·w, + v·w."""
    if line is None:
        return 0.0, u * w, v * w
    rd = (line[0] + s * line[1]) * w
    return rd, rd + u * w, rd + v * w


def _column(x: Any) -> Any:
    """A per-sample guide value as a column against the roots' last axis; a constant as it is."""
    return np.asarray(x)[..., None] if np.ndim(x) else x


def _subset(x: Any, shape: tuple[int, ...], at: tuple[np.ndarray, ...]) -> Any:
    """A per-sample value (broadcast to ``shape``) at the candidates ``at``; a constant as it is."""
    return np.broadcast_to(x, shape)[at] if np.ndim(x) else x


def _laurent_terms(o: Any, e: complex, b_: Any, c_: Any, lengths: tuple[float, float], u: complex, v: complex,
                   w: Any, line: Line = None) -> tuple[Any, Any, Any, Any]:
    """N, Dn, e·p₁ and k₁ at w (module docstring of solver.groups.slider_triad): s = N/Dn."""
    b, c = lengths
    o, e = _at(o, e, w, line)
    p1 = o - b_ + u * w
    p2 = o - c_ + v * w
    k1 = abs2(p1) - b * b
    k2 = abs2(p2) - c * c
    return k2 - k1, 2.0 * dot(e, p1 - p2), dot(e, p1), k1


def slider_coefficients(o: Any, e: complex, b_: Any, c_: Any, lengths: tuple[float, float], u: complex,
                        v: complex, *, line: Line = None) -> np.ndarray:
    """The seven coefficients of w³·G(w), lowest power first, shape (..., 7): the DFT of G at the
    seventh roots of unity (G has exactly seven terms, w^{−3} … w³, on a guide carried by the
    ternary link too: e(w)·p₁ and k₁ stay within w^{−1} … w¹)."""
    b_ = np.asarray(b_, complex)[..., None]
    c_ = np.asarray(c_, complex)[..., None]
    n, dn, ep, k1 = _laurent_terms(_column(o), _column(e), b_, c_, lengths, u, v, _ROOTS7, line)
    g = n * n + 2.0 * n * dn * ep + k1 * dn * dn  # G(w_k), real
    f = np.fft.fft(g, axis=-1) / 7.0  # f[m] = coefficient of w^m, m mod 7 (−3 … 3)
    return np.concatenate([f[..., 4:], f[..., :4]], axis=-1)


def _quadratic_slides(w: Any, o: Any, e: complex, b_: Any, c_: Any, lengths: tuple[float, float], u: complex,
                      v: complex, line: Line = None) -> tuple[Any, Any, Any, Any]:
    """Both roots of the first circle's quadratic in s at the unit complex w and how far each
    leaves the second circle: ``(s_a, s_b, |r_a|, |r_b|)``."""
    b, c = lengths
    o, e = _at(o, e, w, line)
    p1 = o - b_ + u * w
    p2 = o - c_ + v * w
    ep = dot(e, p1)
    disc = np.sqrt(np.maximum(ep * ep - (abs2(p1) - b * b), 0.0))
    s_a, s_b = -ep + disc, -ep - disc
    return s_a, s_b, np.abs(abs2(p2 + s_a * e) - c * c), np.abs(abs2(p2 + s_b * e) - c * c)


def slider_start(w: Any, o: Any, e: complex, b_: Any, c_: Any, lengths: tuple[float, float], u: complex,
                 v: complex, *, line: Line = None) -> Any:
    """The slide s at the unit complex w: the root of the first circle's quadratic in s that
    best closes the second (robust where Dn, the divisor of s = N/Dn, is small): the Newton start."""
    s_a, s_b, r_a, r_b = _quadratic_slides(w, o, e, b_, c_, lengths, u, v, line)
    return np.where(r_a <= r_b, s_a, s_b)


def _residuals(s: Any, w: Any, o: Any, e: complex, b_: Any, c_: Any, lengths: tuple[float, float], u: complex,
               v: complex, line: Line = None) -> tuple[Any, Any, Any, Any, Any]:
    """D, q, r and the loop residuals |q|² − b², |r|² − c² (plain operators: the same lines on
    arrays, floats and traced values)."""
    o, e = _at(o, e, w, line)
    d = o + s * e
    q, r = d + u * w - b_, d + v * w - c_
    b, c = lengths
    return d, q, r, q.real * q.real + q.imag * q.imag - b * b, r.real * r.real + r.imag * r.imag - c * c


def _solve2(e: complex, q: Any, r: Any, g: Any, h: Any, r1: Any, r2: Any) -> tuple[Any, Any, Any]:
    """(e·q)·x + g·t = r₁, (e·r)·x + h·t = r₂ by Cramer: ``(x, t, det)``, det = (e·q)·h − (e·r)·g."""
    eq, er = dot(e, q), dot(e, r)
    det = eq * h - er * g
    return (r1 * h - r2 * g) / det, (eq * r2 - er * r1) / det, det


def slider_polish(s: Any, theta: Any, o: Any, e: complex, b_: Any, c_: Any, lengths: tuple[float, float],
                  u: complex, v: complex, *, steps: int, xp: Backend, until: float | None = None,
                  line: Line = None) -> tuple[Any, Any, Any, Any, Any]:
    """Up to ``steps`` Newton steps on the two loop equations from (s, θ) — also ended by a step
    |Δθ| ≤ ``until`` (on arrays, once no sample's step exceeds it, NaN counting as done) — :
    ``(s, θ, e^{jθ}, closed, |Δθ| of the last step)``, ``closed`` where both residuals are within
    ``RESIDUAL_ROUNDING``·EPS·size²."""
    dt: Any = 0.0
    for _ in range(steps):
        w = xp.cis(theta)
        _, q, r, f1, f2 = _residuals(s, w, o, e, b_, c_, lengths, u, v, line)
        _, uw, vw = _arms(s, w, u, v, line)
        g = uw.real * q.imag - uw.imag * q.real  # −(q × R_E) = q·(j·R_E)
        h = vw.real * r.imag - vw.imag * r.real
        ds, dt, _ = _solve2(_at(o, e, w, line)[1], q, r, g, h, -0.5 * f1, -0.5 * f2)
        s = s + ds
        theta = theta + dt
        if until is not None:
            if isinstance(dt, np.ndarray):
                if not (np.abs(dt) > until).any():
                    break
            elif abs(dt) <= until:
                break
    w = xp.cis(theta)
    *_, f1, f2 = _residuals(s, w, o, e, b_, c_, lengths, u, v, line)
    size = abs(o) + abs(b_) + abs(c_) + sum(lengths) + abs(u) + abs(v) + abs(s)
    bound = RESIDUAL_ROUNDING * EPS * size * size
    return s, theta, w, (abs(f1) <= bound) & (abs(f2) <= bound), abs(dt)


def slider_roots(o: Any, e: Any, b_: Any, c_: Any, lengths: tuple[float, float], u: complex,
                 v: complex, *, line: Line = None) -> tuple[np.ndarray, np.ndarray]:
    """Every real assembly mode at each sample: ``(θ, s)``, shape (..., 6), NaN where a slot holds
    no real root; θ in (−π, π] sorted ascending per sample (two modes of one θ in either order);
    polished by Newton to round-off.

    Each root w on the circle starts Newton from the root s of the first circle's quadratic that
    best closes the second, and from the other one too where it closes the second within
    ``ON_CIRCLE``·size² (the two quadratics one: N = Dn = 0, a double root w of the polynomial
    with two modes of one θ, told apart by s); candidates within ``SAME_ROOT`` in θ and
    ``SAME_ROOT``·(|u| + |v|) in s are one root.
    ``o``, ``e`` the guide at each sample (constants, or arrays for a moving guide)."""
    b_, c_ = (np.asarray(x, complex) for x in (b_, c_))
    shape = np.broadcast_shapes(b_.shape, c_.shape, np.shape(o), np.shape(e))
    b_, c_ = (np.broadcast_to(x, shape)[..., None] for x in (b_, c_))
    if np.ndim(o) or np.ndim(e):
        o, e = (np.broadcast_to(np.asarray(x, complex), shape) for x in (o, e))
    coef = slider_coefficients(o, e, b_[..., 0], c_[..., 0], lengths, u, v, line=line)
    comp = np.zeros((*shape, DEGREE, DEGREE), complex)
    comp[..., 1:, :-1] = np.eye(DEGREE - 1)
    with np.errstate(all="ignore"):
        comp[..., :, -1] = -coef[..., :DEGREE] / coef[..., DEGREE:]
        size = np.abs(b_[..., 0] - o) + np.abs(c_[..., 0] - o) + sum(lengths) + abs(u) + abs(v)
        drop = np.abs(coef[..., DEGREE]) <= DEGREE_DROP * size**4
        if drop.any():  # degree 4 (c₁ … c₅): its companion in the top-left corner, 0 for the rest
            low = np.zeros((int(drop.sum()), DEGREE, DEGREE), complex)
            low[:, 1:4, :3] = np.eye(3)
            low[:, :4, 3] = -coef[drop][:, 1:5] / coef[drop][:, 5:6]
            comp[drop] = low
        ok = np.isfinite(comp).all(axis=(-2, -1))
        comp[~ok] = 0.0
        w = np.linalg.eigvals(comp)
        w[~ok] = np.nan
        near = np.abs(np.abs(w) - 1.0) <= ON_CIRCLE
        w = np.where(near, w / np.abs(w), np.nan)
        oc, ec = _column(o), _column(e)
        s_a, s_b, r_a, r_b = _quadratic_slides(w, oc, ec, b_, c_, lengths, u, v, line)
        second = np.maximum(r_a, r_b) <= ON_CIRCLE * size[..., None] ** 2  # both close the second circle
        angle = np.angle(w)
        s, theta, w, good, _ = slider_polish(np.where(r_a <= r_b, s_a, s_b), angle, oc, ec, b_, c_, lengths, u, v,
                                             steps=POLISH_STEPS, xp=NUMPY, until=POLISH_DONE, line=line)
        if second.any():  # (nearly) two modes of one θ: the other slide polished too, as six more candidates
            at = np.nonzero(second)
            o2, e2, b2, c2 = (_subset(x, second.shape, at) for x in (oc, ec, b_, c_))
            s2, _, w2, good2, _ = slider_polish(np.where(r_a <= r_b, s_b, s_a)[at], angle[at], o2, e2, b2, c2,
                                                lengths, u, v, steps=POLISH_STEPS, xp=NUMPY, until=POLISH_DONE,
                                                line=line)
            more = [np.full(second.shape, np.nan, x.dtype) for x in (s2, w2)]
            more[0][at], more[1][at] = s2, w2
            s, w = (np.concatenate([x, y], axis=-1) for x, y in zip((s, w), more))
            good = np.concatenate([good, np.zeros(second.shape, bool)], axis=-1)
            good[..., DEGREE:][at] = good2
        good = good & np.isfinite(s)
    theta = np.where(good, np.angle(w), np.nan)
    order = np.argsort(theta, axis=-1)  # NaN last
    theta = np.take_along_axis(theta, order, axis=-1)
    s = np.take_along_axis(np.where(good, s, np.nan), order, axis=-1)
    if not (np.abs(np.diff(theta, axis=-1)) <= SAME_ROOT).any():  # no two candidates of one θ: sorted already
        return theta[..., :DEGREE], s[..., :DEGREE]
    same = ((np.abs(theta[..., :, None] - theta[..., None, :]) <= SAME_ROOT)
            & (np.abs(s[..., :, None] - s[..., None, :]) <= SAME_ROOT * (abs(u) + abs(v))))
    dup = np.triu(same, k=1).any(axis=-2)  # the same root as an earlier candidate
    theta[dup] = np.nan
    s[dup] = np.nan
    order = np.argsort(theta, axis=-1)
    return np.take_along_axis(theta, order, axis=-1)[..., :DEGREE], np.take_along_axis(s, order, axis=-1)[..., :DEGREE]


def slider_analogs(s: Any, w: Any, o: Any, e: complex, u: complex, v: complex, jb: Jet,
                   jc: Jet, *, line: Line = None, guide: tuple[Jet, Jet] | None = None) -> tuple[Any, ...]:
    """``(s', θ', s'', θ'', det)`` from the linear system of solver.groups.slider_triad; ``guide``
    the moving guide's jets (O, e) (the values ``o``, ``e`` with their derivatives), ``line`` as in
    :func:`slider_roots` — the extra terms of the variants (module docstring)."""
    _, uw, vw = _arms(s, w, u, v, line)  # R_E, R_F
    o, e = _at(o, e, w, line)
    d = o + s * e
    q, r = d + u * w - jb.value, d + v * w - jc.value
    g, h = -cross(q, uw), -cross(r, vw)
    b1, c1, b2, c2 = jb.d1, jc.d1, jb.d2, jc.d2
    if guide is not None:  # B' − O' − s·e'... as seen from the moving guide
        jo, je = guide
        b1, c1 = b1 - jo.d1 - s * je.d1, c1 - jo.d1 - s * je.d1
    s1, t1, det = _solve2(e, q, r, g, h, dot(b1, q), dot(c1, r))
    e1, f1 = s1 * e + 1j * uw * t1, s1 * e + 1j * vw * t1
    if guide is not None:
        more = jo.d2 + 2.0 * s1 * je.d1 + s * je.d2
        b2, c2 = b2 - more, c2 - more
    if line is not None:
        turn = 2j * s1 * t1 * line[1] * w  # the guide's direction turning with the ternary link
        b2, c2 = b2 - turn, c2 - turn
    r1 = dot(b2 + uw * t1 * t1, q) - abs2(e1 - b1)
    r2 = dot(c2 + vw * t1 * t1, r) - abs2(f1 - c1)
    s2, t2, _ = _solve2(e, q, r, g, h, r1, r2)
    return s1, t1, s2, t2, det


def slider_jets(s: Any, w: Any, analogs: tuple[Any, ...], o: Any, e: complex, u: complex, v: complex, *,
                line: Line = None, guide: tuple[Jet, Jet] | None = None) -> tuple[Jet, Jet, Jet]:
    """The jets of D, E, F from (s, θ) and :func:`slider_analogs`' values:
    D' = O' + s·e_k' + s'·e + j·R_D·θ',
    D'' = s''·e + j·R_D·θ'' + O'' + 2s'·e_k' + s·e_k'' + 2j·s'·θ'·e₁·w − R_D·θ'²,
    E = D + u·w, E' = D' + j·u·w·θ', E'' = D'' + j·u·w·θ'' − u·w·θ'² (F alike); on a fixed guide
    D' = s'·e, D'' = s''·e."""
    s1, t1, s2, t2, _ = analogs
    rd, _, _ = _arms(s, w, u, v, line)
    og, eg = _at(o, e, w, line)
    d = og + s * eg
    d1, d2 = s1 * eg, s2 * eg
    if line is not None:
        d1 = d1 + 1j * rd * t1
        d2 = d2 + 1j * rd * t2 - rd * t1 * t1 + 2j * s1 * t1 * line[1] * w
    if guide is not None:
        jo, je = guide
        d1 = d1 + jo.d1 + s * je.d1
        d2 = d2 + jo.d2 + 2.0 * s1 * je.d1 + s * je.d2
    out = [Jet(d, d1, d2)]
    for off in (u * w, v * w):
        out.append(Jet(d + off, d1 + 1j * off * t1, d2 + 1j * off * t2 - off * t1 * t1))
    return out[0], out[1], out[2]


def _wrap(x: float) -> float:
    return (x + math.pi) % (2.0 * math.pi) - math.pi


def nearest(roots: list[float], target: float) -> tuple[int, float]:
    """The index of the root nearest ``target`` on the circle and its distance."""
    best, dist = 0, math.inf
    for m, t in enumerate(roots):
        x = abs(_wrap(t - target))
        if x < dist:
            best, dist = m, x
    return best, dist


def gap_of(roots: list[float], k: int) -> float:
    """Root k's distance to its nearest other root (inf when alone)."""
    return min((abs(_wrap(t - roots[k])) for m, t in enumerate(roots) if m != k), default=math.inf)


def pick(roots: list[float], slides: list[float], target: float, slide: float | None, scale: float) -> int:
    """The mode rule at the reference sample. With the drawn slide s₀ (``slide``; the scene's
    ``angle`` is the drawn one): the root nearest the drawn pose (θ₀, s₀) by
    :func:`mode_distance` — the root nearest θ₀ but where two modes are close in θ (two modes of
    one θ differ in s only). Without: the root nearest θ₀ (``target``) on the circle, roots of
    one θ (their distances within ``SAME_ROOT`` of the nearest's) told apart by the lower s."""
    if slide is not None:
        return closest(roots, slides, target, slide, scale)[0]
    dist = [abs(_wrap(t - target)) for t in roots]
    low = min(dist)
    return min((k for k, x in enumerate(dist) if x <= low + SAME_ROOT), key=lambda k: slides[k])


def mode_distance(theta: float, s: float, theta_to: float, s_to: float, scale: float) -> float:
    """How far two modes (θ, s) are apart for following one: |Δθ| on the circle + |Δs| / ``scale``
    (|u| + |v|, the ternary link's size: a slide as far as its points swing for that angle)."""
    return abs(_wrap(theta - theta_to)) + abs(s - s_to) / scale


def closest(roots: list[float], slides: list[float], theta_to: float, s_to: float, scale: float) -> tuple[int, float]:
    """The index of the root nearest (θ, s) = (``theta_to``, ``s_to``) by :func:`mode_distance`, and its distance."""
    dist = [mode_distance(t, s, theta_to, s_to, scale) for t, s in zip(roots, slides)]
    k = min(range(len(dist)), key=dist.__getitem__)
    return k, dist[k]


def spread(roots: list[float], slides: list[float], k: int, scale: float) -> float:
    """Root k's :func:`mode_distance` to its nearest other root (inf when alone)."""
    return min((mode_distance(t, s, roots[k], slides[k], scale) for m, (t, s) in enumerate(zip(roots, slides))
                if m != k), default=math.inf)


def follow_roots(theta: np.ndarray, slide: np.ndarray, rate: np.ndarray, slide_rate: np.ndarray, step: np.ndarray,
                 start: int, target: float, *, slide0: float | None, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """The branch rule over a sweep (solver.groups.slider_triad): the slot followed at each sample
    (−1: no real root) and where following it jumps mode. ``theta``, ``slide`` (n, 6) every real
    root (NaN last), ``rate``, ``slide_rate`` (n, 6) their θ' and s', ``step`` (n,) the input; the
    mode at the first sample with a root from ``start`` is :func:`pick`'s (θ₀ = ``target``, s₀ =
    ``slide0``); then each neighbour takes the root nearest the previous one carried forward by
    (θ', s')·Δφ (:func:`closest`, ``scale`` = |u| + |v|); a match farther than half the previous
    root's distance to its nearest other root (:func:`spread`), where the count of real roots
    drops, is a jump."""
    n = len(theta)
    out = [-1] * n
    jump = [False] * n
    rows = [[t for t in r if t == t] for r in theta.tolist()]  # NaN last: a list's index is the slot
    slides = [r[:len(q)] for r, q in zip(slide.tolist(), rows)]
    rates = rate.tolist()
    s_rates = slide_rate.tolist()
    st = step.tolist()
    with_root = [i for i in range(start, n) if rows[i]]
    if not with_root:
        return np.array(out), np.array(jump)
    i0 = with_root[0]
    out[i0] = pick(rows[i0], slides[i0], target, slide0, scale)
    for direction in (1, -1):
        i = i0
        while 0 <= i + direction < n:
            j = i + direction
            r = rows[j]
            if r:
                k = out[i]
                if k < 0:  # restart after a gap: the mode rule again
                    out[j] = pick(r, slides[j], target, slide0, scale)
                else:
                    dphi = st[j] - st[i]
                    m, dist = closest(r, slides[j], rows[i][k] + rates[i][k] * dphi,
                                      slides[i][k] + s_rates[i][k] * dphi, scale)
                    out[j] = m
                    jump[j] = dist > 0.5 * spread(rows[i], slides[i], k, scale) and len(r) < len(rows[i])
            i = j
    return np.array(out), np.array(jump)
