"""Derivative alternatives to the solver's exact analogs, written in the bench from positions alone.

``position_functions[scene](phi)`` is the closed-form geometry of each shipped scene written with
real arithmetic only (numpy ufuncs that also take complex arguments), so that the same code gives
central finite differences (real φ ± h) and the complex step (φ + i·h). Angle joints are measured
relative to the real part of their vector, so atan2 is never called on a complex number.

Dimensions are the contract of issue 2 (docs/architecture.md); tests/bench/ checks that these
functions give the solver's positions.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = [
    "COMPLEX_STEP",
    "FD_STEPS",
    "Geometry",
    "central_differences",
    "complex_step",
    "position_functions",
]

Array = Any  # float or complex ndarray
Geometry = tuple[dict[str, Array], dict[str, tuple[str, Array]]]
"""(points {name: (N, dim)}, joints {name: (kind, (N,))}); kind 'angle' or 'length'."""

FD_STEPS = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
COMPLEX_STEP = 1e-30
#: Real step of the central difference of complex-step first derivatives (≈ ε^(1/3)).
HYBRID_STEP = 6e-6


def _angle(x: Array, y: Array) -> Array:
    """atan2(y, x), complex-step safe: the angle of the real part plus the small complex turn."""
    if not np.iscomplexobj(x) and not np.iscomplexobj(y):
        return np.arctan2(y, x)
    x0, y0 = x.real, y.real
    return np.arctan2(y0, x0) + np.arctan((x0 * y - y0 * x) / (x0 * x + y0 * y))


def _stack(*cols: Array) -> Array:
    return np.stack(cols, axis=-1)


def four_bar(phi: Array, *, mode: int = 1) -> Geometry:
    """Crank OA = 0.1, coupler AB = 0.4, rocker CB = 0.3, O = (0, 0), C = (0.4, 0)."""
    oa, ab, cb, cx = 0.1, 0.4, 0.3, 0.4
    ax, ay = oa * np.cos(phi), oa * np.sin(phi)
    dx, dy = cx - ax, -ay
    d2 = dx * dx + dy * dy
    along = (ab * ab - cb * cb + d2) / (2.0 * d2)  # along AC, in units of |AC|
    across = np.sqrt(ab * ab / d2 - along * along)
    # M = +1: A → B → C counter-clockwise puts B on the right of A→C.
    bx = ax + along * dx + mode * across * dy
    by = ay + along * dy - mode * across * dx
    points = {"A": _stack(ax, ay), "B": _stack(bx, by)}
    joints = {"coupler": ("angle", _angle(bx - ax, by - ay)), "rocker": ("angle", _angle(bx - cx, by))}
    return points, joints


def harvester_finger(phi: Array) -> Geometry:
    """Crank OB = 0.20 about O = (0, 0); slotted link through B about A = (0.04, −0.03)."""
    ax, ay, ob, ac, ae = 0.04, -0.03, 0.20, 0.30, 0.22
    bx, by = ob * np.cos(phi), ob * np.sin(phi)
    rx, ry = bx - ax, by - ay
    inv = 1.0 / np.sqrt(rx * rx + ry * ry)
    ux, uy = rx * inv, ry * inv
    points = {
        "B": _stack(bx, by),
        "C": _stack(ax + ac * ux, ay + ac * uy),
        "E": _stack(ax + ae * ux, ay + ae * uy),
    }
    return points, {"finger": ("angle", _angle(ux, uy))}


def slider_crank(phi: Array) -> Geometry:
    """Crank OA = 0.05; rod AB = 0.20; B on y = 0.01, to the right of A."""
    oa, ab, guide = 0.05, 0.20, 0.01
    ax, ay = oa * np.cos(phi), oa * np.sin(phi)
    h = guide - ay
    bx = ax + np.sqrt(ab * ab - h * h)
    points = {"A": _stack(ax, ay), "B": _stack(bx, np.full_like(bx, guide))}
    return points, {"slider": ("length", bx)}


TAN_ALPHA = math.tan(math.radians(40.0))


def spherical_converter(phi: Array) -> Geometry:
    """Seed 001 corrected: ψ = atan(sin φ / tan α), K = R (0, sin ψ, cos ψ), R = 0.05."""
    radius = 0.05
    psi = np.arctan(np.sin(phi) / TAN_ALPHA)
    k = _stack(np.zeros_like(psi), radius * np.sin(psi), radius * np.cos(psi))
    return {"K": k}, {"cage": ("angle", psi)}


position_functions: dict[str, Callable[[Array], Geometry]] = {
    "four_bar": four_bar,
    "harvester_finger": harvester_finger,
    "slider_crank": slider_crank,
    "spherical_converter": spherical_converter,
}

Analogs = tuple[dict[str, tuple[Array, Array, Array]], dict[str, tuple[Array, Array, Array]]]


def _wrap(d: Array) -> Array:
    return (d + math.pi) % (2.0 * math.pi) - math.pi


def central_differences(scene: str, phi: np.ndarray, h: float) -> Analogs:
    """Positions and central-difference analogs: f' ≈ (f₊ − f₋)/2h, f'' ≈ (f₊ − 2f + f₋)/h²."""
    f = position_functions[scene]
    p0, j0 = f(phi)
    pp, jp = f(phi + h)
    pm, jm = f(phi - h)
    points = {n: (p0[n], (pp[n] - pm[n]) / (2 * h), (pp[n] - 2 * p0[n] + pm[n]) / (h * h)) for n in p0}
    joints = {}
    for n, (kind, v) in j0.items():
        up, down = jp[n][1] - v, v - jm[n][1]
        if kind == "angle":
            up, down = _wrap(up), _wrap(down)
        joints[n] = (v, (up + down) / (2 * h), (up - down) / (h * h))
    return points, joints


def complex_step(scene: str, phi: np.ndarray, *, h: float = COMPLEX_STEP, delta: float = HYBRID_STEP) -> Analogs:
    """Complex-step analogs: f' = Im f(φ + ih)/h (no cancellation, exact to rounding);
    f'' by a central difference of complex-step first derivatives at φ ± δ (no pure complex-step
    second derivative exists in one imaginary unit without cancellation)."""
    f = position_functions[scene]
    p0, j0 = f(phi + 1j * h)
    pp, jp = f(phi + delta + 1j * h)
    pm, jm = f(phi - delta + 1j * h)
    scale = 1.0 / h
    d2 = scale / (2 * delta)
    points = {n: (p0[n].real, p0[n].imag * scale, (pp[n].imag - pm[n].imag) * d2) for n in p0}
    joints = {n: (v.real, v.imag * scale, (jp[n][1].imag - jm[n][1].imag) * d2) for n, (_, v) in j0.items()}
    return points, joints
