"""A folded RRR dyad (|l₁ − l₂| ≪ l₁ + l₂) at its boundary D = |l₁ − l₂|: accepted exactly at
and within rounding of it, refused beyond — not ~1e-8·(l₁ + l₂) beyond, as a slack scaled by
the largest D² once allowed (tolerances.CLOSURE_ROUNDING, rrr.closure_slack)."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scene_builders import build, four_bar

import solver
from solver import assembly

#: crank L against ground R = L + 1e-4: |C − A| is smallest, 1e-4 m, at φ = 0
R, L = 0.4, 0.4 - 1e-4
DMIN = R - L  # exact in doubles (Sterbenz)
#: the accepted positions' miss of the two circles, relative to l₁ + l₂ (rounding: ~1e-13 here)
CLOSE = 1e-11


def _miss(k: solver.Kinematics, l1: float, l2: float, c: tuple[float, float]) -> float:
    a, b = (np.asarray(k.point(p).position, float).reshape(-1, 2) for p in ("A", "B"))  # (tuples at one instant)
    return float(max(np.abs(np.hypot(*(b - a).T) - l1).max(), np.abs(np.hypot(*(b - np.array(c)).T) - l2).max()))


def _scene(tau: float) -> tuple[solver.Scene, float, float]:
    """|l₁ − l₂| = DMIN·(1 + tau): tau > 0 puts φ = 0 outside the folded boundary by 1e-4·tau m."""
    l2 = 0.3
    l1 = l2 + DMIN * (1.0 + tau)
    return four_bar(L, l1, l2, R), l1, l2


@pytest.mark.parametrize("tau", [0.0, 1e-15, 1e-14, -1e-14, -1e-9, -1e-6])
def test_at_and_within_rounding_of_the_folded_boundary_the_dyad_closes(tau: float) -> None:
    scene, l1, l2 = _scene(tau)
    for phi in (np.array([0.0, 1e-9, -1e-9]), 0.0):
        k = scene.solve(phi)
        assert _miss(k, l1, l2, (R, 0.0)) <= CLOSE * (l1 + l2)


@pytest.mark.parametrize("tau", [1e-10, 1e-9, 1e-8, 1e-7])
def test_beyond_rounding_of_the_folded_boundary_the_dyad_is_refused(tau: float) -> None:
    # the old slack, 256·EPS·(l₁² + l₂²)·(l₁ + l₂)², passed all of these: misses up to 3e-8 m
    scene, l1, l2 = _scene(tau)
    for phi in (np.array([0.0]), 0.0):
        with pytest.raises(solver.AssemblyError, match=r"group 'dyad' cannot be assembled") as err:
            scene.solve(phi)
        # the gap reported holds φ = 0: the closed-form intervals judge as the solve does
        assert any(lo <= 2 * math.pi <= hi or lo <= 0.0 <= hi for lo, hi in err.value.intervals)
    # the gap's half-width, D² = (R − L)² + 4RL·sin²(φ/2) = (l₁ − l₂)², in 50 digits from the doubles
    with mpmath.workdps(50):
        m = mpmath.mpf
        half = float(2 * mpmath.asin(mpmath.sqrt(((m(l1) - m(l2)) ** 2 - (m(R) - m(L)) ** 2) / (4 * m(R) * m(L)))))
    (gap,) = [iv for iv in assembly.gaps(scene)["dyad"] if iv[1] > 2 * math.pi]
    assert gap[0] == pytest.approx(2 * math.pi - half, rel=0, abs=1e-9 * half + 8e-16)
    assert gap[1] == pytest.approx(2 * math.pi + half, rel=0, abs=1e-9 * half + 8e-16)
    k = scene.solve(np.array([-2 * half, 0.0, 2 * half]), mask=True)
    assert k.valid.tolist() == [True, False, True]
    assert _miss(k, l1, l2, (R, 0.0)) <= CLOSE * (l1 + l2) or not k.valid.all()


def _five_bar(delta: float) -> solver.Scene:
    """Two cranks (no crank-fed dyad: D² from coordinates); distal lengths 0.25 and 0.25 − δ."""
    return build({
        "scene": "folded_five_bar",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O1": [0.0, 0.0], "O2": [0.2, 0.0]},
        "groups": [
            {"type": "crank", "name": "left", "center": "O1", "point": "A", "length": 0.15, "joint": "q1"},
            {"type": "crank", "name": "right", "center": "O2", "point": "C", "length": 0.15, "joint": "q2"},
            {"type": "rrr", "name": "dyad", "ends": ["A", "C"], "point": "B", "lengths": [0.25, 0.25 - delta],
             "M": -1},
        ],
        "outputs": {"points": ["A", "B", "C"]},
    })


def test_a_dyad_between_two_cranks_accepts_only_what_closes_to_rounding() -> None:
    # the cranks' circles cross at (0.1, ±0.1118): around there |C − A| sweeps 0 … 3e-4 m
    delta = 1e-4
    scene = _five_bar(delta)
    y = math.sqrt(0.15**2 - 0.1**2)
    q1, q2 = math.atan2(y, 0.1), math.atan2(y, -0.1)
    rng = np.random.default_rng(19)
    q = np.array([q1, q2]) + rng.uniform(-1e-3, 1e-3, size=(20_000, 2))
    k = scene.solve(q, mask=True)
    a, c = k.point("A").position, k.point("C").position
    d = np.hypot(*(c - a).T)
    ok = np.asarray(k.valid, bool)
    assert ok.any() and not ok.all()
    b = k.point("B").position
    miss = np.maximum(np.abs(np.hypot(*(b - a).T) - 0.25), np.abs(np.hypot(*(b - c).T) - (0.25 - delta)))
    assert miss[ok].max() <= CLOSE * 0.5
    # refused exactly where D is below the boundary by more than rounding, accepted above it
    assert not ok[d < delta * (1 - 1e-9)].any()
    assert ok[d > delta * (1 + 1e-9)].all()
