"""Geometric invariants of the actuator group on bounded, finite random geometry (hypothesis):
the eye closes both circles in its assembly mode, the analogs satisfy the differentiated
constraints, agree with central differences, and the per-tick path gives the sweep's values."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scene_builders import build

import solver

SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])

lengths = st.floats(0.2, 3.0, allow_nan=False, allow_infinity=False)
coords = st.floats(-2.0, 2.0, allow_nan=False, allow_infinity=False)


def actuator(base: complex, link: float, mode: int, stroke: tuple[float, float]) -> solver.Scene:
    return build({
        "scene": "actuator_test",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0], "A": [base.real, base.imag]},
        "groups": [{"type": "actuator", "name": "ram", "base": "A", "point": "C", "pivot": "O", "length": link,
                    "M": mode, "joint": "s", "stroke": list(stroke)}],
        "joints": {"theta": {"angle": ["O", "C"]}},
        "outputs": {"points": ["C"], "joints": ["theta", "s"]},
    })


@st.composite
def cases(draw: st.DrawFn) -> tuple[solver.Scene, float, complex, float, int]:
    base = complex(draw(coords), draw(coords))
    link = draw(lengths)
    mode = draw(st.sampled_from([1, -1]))
    dist = abs(base)
    assume(dist > 0.1)
    lo, hi = abs(dist - link), dist + link  # the strokes that close
    assume(hi - lo > 0.05)
    frac = draw(st.floats(0.05, 0.95))
    s = lo + frac * (hi - lo)
    return actuator(base, link, mode, (lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo))), s, base, link, mode


@SETTINGS
@given(cases())
def test_the_eye_closes_both_circles_in_its_mode_and_the_analogs_satisfy_the_constraints(
    case: tuple[solver.Scene, float, complex, float, int],
) -> None:
    scene, s, base, link, mode = case
    k = scene.solve(np.array([s]))
    c, c1, c2 = (complex(*m[0]) for m in k.point("C"))
    scale = abs(base) + link + s
    eps = 1e-13 * scale
    assert abs(abs(c - base) - s) <= eps and abs(abs(c) - link) <= eps
    p, q = c - base, c  # C − A, C − O
    area = (p.conjugate() * (0 - base)).imag  # (C − A) × (O − A): A → C → O counter-clockwise
    cond = float(k.conditioning["ram"][0])
    assume(cond > 1e-3)
    assert math.copysign(1, area) == mode
    dot = lambda u, v: (u.conjugate() * v).real
    tol = 1e-12 * scale * scale / cond**2
    assert abs(dot(c1, p) - s) <= tol and abs(dot(c1, q)) <= tol  # C'·p = s·s', C'·q = 0
    assert abs(dot(c2, p) - (1.0 - abs(c1) ** 2)) <= tol / cond  # C''·p = s'² − |C'|²
    assert abs(dot(c2, q) + abs(c1) ** 2) <= tol / cond  # C''·q = −|C'|²


@SETTINGS
@given(cases())
def test_the_analogs_agree_with_central_differences_and_the_tick_with_the_sweep(
    case: tuple[solver.Scene, float, complex, float, int],
) -> None:
    scene, s, *_ = case
    k = scene.solve(np.array([s]))
    assume(float(k.conditioning["ram"][0]) > 0.05)
    lo, hi = scene.input_ranges[0]
    h = 1e-5 * (hi - lo)
    assume(lo < s - 2 * h and s + 2 * h < hi)
    pts = scene.solve(np.array([s - h, s, s + h])).point("C").position
    fd1 = (pts[2] - pts[0]) / (2 * h)
    fd2 = (pts[2] - 2 * pts[1] + pts[0]) / (h * h)
    size = float(np.abs(k.point("C").acceleration).max()) + float(np.abs(k.point("C").velocity).max()) + 1.0
    np.testing.assert_allclose(k.point("C").velocity[0], fd1, atol=1e-6 * size)
    np.testing.assert_allclose(k.point("C").acceleration[0], fd2, atol=1e-3 * size)
    tick = scene.solve(float(s), omega=0.3, epsilon=-0.7)
    sweep = scene.solve(np.array([s]), omega=0.3, epsilon=-0.7)
    for a, b in zip(tick.point("C"), sweep.point("C")):
        np.testing.assert_allclose(a, b[0], rtol=1e-14, atol=1e-14)
