"""The triad's array functions (the class-3 Assur group of :mod:`solver.groups.triad`, whose
docstring states the loop equations, the degree-6 polynomial, the linear system of the analogs and
the branch rule): the polynomial's coefficients, every root polished by Newton on the loop
equations, and the analogs — on arrays of samples (numpy) or numbers and tracers (the backends),
with no group state. The group and its sweep, tick and population helpers call these; nothing here
calls them back."""

from __future__ import annotations

from typing import Any

import numpy as np

from .._backend import NUMPY, Backend, abs2, cross, dot
from ..jet import Jet
from ..tolerances import EPS
from .rrr import solve_linear

__all__ = ["ON_CIRCLE", "SAME_ROOT", "POLISH_STEPS", "POLISH_DONE", "RESIDUAL_ROUNDING", "triad_coefficients",
           "triad_start", "triad_polish", "triad_roots", "triad_analogs", "triad_points"]


#: A companion-matrix root counts as on the unit circle (a candidate real mode) within this of
#: |w| = 1: a double root splits by ~√EPS, so the band is wider; Newton decides.
ON_CIRCLE: float = 1e-5
#: Two polished roots closer than this in θ (rad) are one root (a double root).
SAME_ROOT: float = 1e-9
#: Newton steps on the loop equations per root; it converges quadratically from the
#: eigenvalue's ~1e-13 (a simple root) or ~1e-8 (near a double root).
POLISH_STEPS: int = 6
#: ... and fewer: the polish of every root ends once no candidate's Newton step exceeds this (rad;
#: the next step's ~|Δθ|²·curvature is below round-off) — one step from a simple root's eigenvalue.
POLISH_DONE: float = 1e-10
#: A polished root is accepted when its loop residuals are within this many EPS of size².
RESIDUAL_ROUNDING: float = 256.0

_ROOTS7 = np.exp(2j * np.pi * np.arange(7) / 7)


def _shape_terms(a0: Any, b0: Any, c0: Any, lengths: tuple[float, float, float], u: complex, v: complex,
                 w: Any) -> tuple[Any, Any]:
    """s₂P − s₁Q and P × Q at w (A at the origin: ``b0 = B − A``, ``c0 = C − A``)."""
    a, b, c = lengths
    p = b0 - u * w
    q = c0 - v * w
    s1 = 0.5 * (abs2(p) + a * a - b * b)
    s2 = 0.5 * (abs2(q) + a * a - c * c)
    return s2 * p - s1 * q, cross(p, q)


def triad_coefficients(b0: Any, c0: Any, lengths: tuple[float, float, float], u: complex, v: complex) -> np.ndarray:
    """The seven coefficients of w³·G(w), lowest power first, shape (..., 7): the DFT of G at the
    seventh roots of unity (``b0 = B − A``, ``c0 = C − A``, arrays broadcast)."""
    b0 = np.asarray(b0, complex)[..., None]
    c0 = np.asarray(c0, complex)[..., None]
    n, det = _shape_terms(0.0, b0, c0, lengths, u, v, _ROOTS7)
    g = abs2(n) - lengths[0] ** 2 * det * det  # G(w_k), real
    f = np.fft.fft(g, axis=-1) / 7.0  # f[m] = coefficient of w^m, m taken mod 7 (−3…3)
    return np.concatenate([f[..., 4:], f[..., :4]], axis=-1)  # w^−3 … w^3 → powers 0 … 6 of w³G


def _residuals(d: Any, w: Any, a_: Any, b_: Any, c_: Any, lengths: tuple[float, float, float], u: complex,
               v: complex) -> tuple[Any, Any, Any, Any, Any, Any]:
    """p, q, s and the three loop residuals |p|² − a², |q|² − b², |s|² − c² (plain operators: the
    same lines on arrays, on floats and on traced values)."""
    return _legs(d, u * w, v * w, a_, b_, c_, lengths)


def _legs(d: Any, uw: Any, vw: Any, a_: Any, b_: Any, c_: Any, lengths: tuple[float, float, float],
          ) -> tuple[Any, Any, Any, Any, Any, Any]:
    """:func:`_residuals` given u·w and v·w."""
    p, q, s = d - a_, d + uw - b_, d + vw - c_
    a, b, c = lengths
    return (p, q, s, p.real * p.real + p.imag * p.imag - a * a, q.real * q.real + q.imag * q.imag - b * b,
            s.real * s.real + s.imag * s.imag - c * c)


def _solve3(p: Any, q: Any, s: Any, g: Any, h: Any, r1: Any, r2: Any, r3: Any) -> tuple[Any, Any, Any]:
    """X·p = r₁, X·q + g·t = r₂, X·s + h·t = r₃ (module docstring): ``(X, t, p × m)``."""
    m = h * q - g * s
    det = cross(p, m)
    x = solve_linear(p, m, 1j / det, r1, h * r2 - g * r3)
    t = (g * (r2 - dot(x, q)) + h * (r3 - dot(x, s))) / (g * g + h * h)
    return x, t, det


def triad_start(at: Any, a_: Any, b_: Any, c_: Any, lengths: tuple[float, float, float], u: complex, v: complex,
                xp: Backend | None) -> Any:
    """D by Cramer's rule (module docstring) at the ternary link's angle ``at`` (``xp`` given) or
    at the unit complex w = e^{jθ} itself (``xp`` None): the start of the Newton polish."""
    w = at if xp is None else xp.cis(at)
    n, det = _shape_terms(0.0, b_ - a_, c_ - a_, lengths, u, v, w)
    return a_ + 1j * n / det


def triad_polish(d: Any, theta: Any, a_: Any, b_: Any, c_: Any, lengths: tuple[float, float, float], u: complex,
                 v: complex, *, steps: int, xp: Backend, until: float | None = None,
                 ) -> tuple[Any, Any, Any, Any, Any]:
    """Up to ``steps`` Newton steps on the three loop equations from (D, θ) — per tick also ended
    by a step |Δθ| ≤ ``until`` (the next would be below round-off; on arrays, once no sample's
    step exceeds it, NaN counting as done) — : ``(D, θ, e^{jθ}, closed,
    |Δθ| of the last step)``, ``closed`` where every residual is within
    ``RESIDUAL_ROUNDING``·EPS·size² (one source for the vectorised roots and the per-tick follow)."""
    dt: Any = 0.0
    for _ in range(steps):
        w = xp.cis(theta)
        uw, vw = u * w, v * w
        p, q, s, f1, f2, f3 = _legs(d, uw, vw, a_, b_, c_, lengths)
        g = uw.real * q.imag - uw.imag * q.real  # −(q × u·w)
        h = vw.real * s.imag - vw.imag * s.real
        dx, dt, _ = _solve3(p, q, s, g, h, -0.5 * f1, -0.5 * f2, -0.5 * f3)
        d = d + dx
        theta = theta + dt
        if until is not None:
            if isinstance(dt, np.ndarray):
                if not (np.abs(dt) > until).any():
                    break
            elif abs(dt) <= until:
                break
    w = xp.cis(theta)
    *_, f1, f2, f3 = _residuals(d, w, a_, b_, c_, lengths, u, v)
    size = abs(a_) + abs(b_) + abs(c_) + sum(lengths) + abs(u) + abs(v)
    bound = RESIDUAL_ROUNDING * EPS * size * size
    return d, theta, w, (abs(f1) <= bound) & (abs(f2) <= bound) & (abs(f3) <= bound), abs(dt)


def triad_roots(a_: Any, b_: Any, c_: Any, lengths: tuple[float, float, float], u: complex,
                v: complex) -> tuple[np.ndarray, np.ndarray]:
    """Every real assembly mode at each sample: ``(θ, D)``, shape (..., 6), NaN where a slot holds
    no real root; θ in (−π, π], sorted ascending per sample; polished by Newton to round-off."""
    a_, b_, c_ = (np.asarray(x, complex) for x in (a_, b_, c_))
    shape = np.broadcast_shapes(a_.shape, b_.shape, c_.shape)
    a_, b_, c_ = (np.broadcast_to(x, shape)[..., None] for x in (a_, b_, c_))
    coef = triad_coefficients(b_[..., 0] - a_[..., 0], c_[..., 0] - a_[..., 0], lengths, u, v)
    lead = coef[..., 6:7]
    comp = np.zeros((*shape, 6, 6), complex)
    comp[..., 1:, :-1] = np.eye(5)
    with np.errstate(all="ignore"):
        comp[..., :, -1] = -coef[..., :6] / lead
        ok = np.isfinite(comp).all(axis=(-2, -1))
        comp[~ok] = 0.0
        w = np.linalg.eigvals(comp)
        w[~ok] = np.nan
        near = np.abs(np.abs(w) - 1.0) <= ON_CIRCLE
        w = np.where(near, w / np.abs(w), np.nan)
        theta = np.angle(w)
        d = triad_start(w, a_, b_, c_, lengths, u, v, None)
        d, theta, w, good, _ = triad_polish(d, theta, a_, b_, c_, lengths, u, v, steps=POLISH_STEPS, xp=NUMPY,
                                            until=POLISH_DONE)
    theta = np.where(good, np.angle(w), np.nan)
    order = np.argsort(theta, axis=-1)  # NaN last
    theta = np.take_along_axis(theta, order, axis=-1)
    d = np.take_along_axis(np.where(good, d, np.nan), order, axis=-1)
    same = np.zeros(theta.shape, bool)
    same[..., 1:] = np.abs(np.diff(theta, axis=-1)) <= SAME_ROOT
    if not same.any():  # no double root: sorted already
        return theta, d
    theta[same] = np.nan
    d[same] = np.nan
    order = np.argsort(theta, axis=-1)
    return np.take_along_axis(theta, order, axis=-1), np.take_along_axis(d, order, axis=-1)


def _wrap(x: Any) -> Any:
    return (x + np.pi) % (2.0 * np.pi) - np.pi


def triad_analogs(d: Any, w: Any, u: complex, v: complex, ja: Jet, jb: Jet, jc: Jet) -> tuple[Any, ...]:
    """``(D', θ', D'', θ'', det)`` from the linear system of the module docstring."""
    uw, vw = u * w, v * w
    p, q, s = d - ja.value, d + uw - jb.value, d + vw - jc.value
    g, h = -cross(q, uw), -cross(s, vw)
    d1, t1, det = _solve3(p, q, s, g, h, dot(ja.d1, p), dot(jb.d1, q), dot(jc.d1, s))
    e1, f1 = d1 + 1j * uw * t1, d1 + 1j * vw * t1
    r1 = dot(ja.d2, p) - abs2(d1 - ja.d1)
    r2 = dot(jb.d2 + uw * t1 * t1, q) - abs2(e1 - jb.d1)
    r3 = dot(jc.d2 + vw * t1 * t1, s) - abs2(f1 - jc.d1)
    d2, t2, _ = _solve3(p, q, s, g, h, r1, r2, r3)
    return d1, t1, d2, t2, det


def triad_points(d: Any, w: Any, u: Any, v: Any, d1: Any, t1: Any, d2: Any, t2: Any) -> tuple[Jet, Jet, Jet]:
    """The jets of D, E = D + u·w and F = D + v·w from D's and θ's analogs (module docstring of
    solver.groups.triad): E' = D' + j·u·w·θ', E'' = D'' + j·u·w·θ'' − u·w·θ'², F alike (one
    source for the group's every path and its population)."""
    t1sq = t1 * t1
    e_, f_ = (Jet(d + off, d1 + joff * t1, d2 + joff * t2 - off * t1sq)
              for off, joff in ((x, 1j * x) for x in (u * w, v * w)))
    return Jet(d, d1, d2), e_, f_
