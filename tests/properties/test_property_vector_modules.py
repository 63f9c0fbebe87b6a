"""Property-based checks of seed 004's vector modules (solver.vectors) over random mechanisms.

Random crank-rockers as Пл4(α_AB, α_CB) and offset slider-cranks as Пл3(α_AB, r_GB): they must
close their contour, keep their M along a sweep, not depend on the sweep, and agree with the
same mechanism written as structural groups (whose analogs are checked elsewhere against
central differences).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scene_builders import build, four_bar, slider_crank

import solver

#: two formulations of one mechanism, relative to its scale (rounding of either).
AGREE_TOL = 1e-12
SWEEP_TOL = 1e-14
SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
PHI = np.linspace(-math.pi, 3 * math.pi, 73)


def _vector_four_bar(crank: float, coupler: float, rocker: float, ground: float, mode: int) -> solver.Scene:
    return build({
        "scene": "vector_four_bar",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0], "C": [ground, 0.0]},
        "vector_model": {
            "input": "crank",
            "vectors": {
                "OA": {"r": crank, "alpha": "input"},
                "AB": {"r": coupler, "alpha": "unknown"},
                "CB": {"r": rocker, "alpha": "unknown"},
                "OC": {"fixed": ["O", "C"]},
            },
            "contours": {"dyad": {"sum": ["OA", "AB", "-CB", "-OC"], "M": mode}},
            "points": {"A": {"from": "O", "sum": ["OA"]}, "B": {"from": "O", "sum": ["OA", "AB"]}},
            "joints": {"coupler": {"angle": "AB"}, "rocker": {"angle": "CB"}},
        },
        "outputs": {"points": ["A", "B"], "joints": ["coupler", "rocker"]},
    })


def _vector_slider_crank(crank: float, rod: float, offset: float, mode: int) -> solver.Scene:
    return build({
        "scene": "vector_slider_crank",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0]},
        "vector_model": {
            "input": "crank",
            "vectors": {
                "OA": {"r": crank, "alpha": "input"},
                "AB": {"r": rod, "alpha": "unknown"},
                "OG": {"r": abs(offset), "alpha": math.copysign(math.pi / 2, offset)},
                "GB": {"r": "unknown", "alpha": 0},
            },
            "contours": {"rod": {"sum": ["OA", "AB", "-GB", "-OG"], "M": mode}},
            "points": {"A": {"from": "O", "sum": ["OA"]}, "B": {"from": "O", "sum": ["OG", "GB"]}},
            "joints": {"slider": {"length": "GB"}},
        },
        "outputs": {"points": ["A", "B"], "joints": ["slider"]},
    })


def _agree(a: solver.Kinematics, b: solver.Kinematics, point: str, scale: float) -> None:
    for attr in ("position", "velocity", "acceleration"):
        x, y = getattr(a.point(point), attr), getattr(b.point(point), attr)
        assert np.abs(x - y).max() <= AGREE_TOL * max(scale, np.abs(y).max())


@SETTINGS
@given(
    st.floats(1e-3, 1e2),
    st.lists(st.floats(1.3, 4.0), min_size=3, max_size=3),
    st.sampled_from([1, -1]),
)
def test_vector_four_bar_closes_and_agrees_with_the_rrr_dyad(s: float, others: list[float], mode: int) -> None:
    longest = max(others)
    assume(1.0 + longest < sum(others) - longest - 0.2)  # Grashof crank-rocker with a margin
    dims = (s, others[0] * s, others[1] * s, others[2] * s)
    vec, grp = _vector_four_bar(*dims, mode).solve(PHI), four_bar(*dims, mode=mode).solve(PHI)
    a, b = vec.point("A").position, vec.point("B").position
    assert np.abs(np.hypot(*(b - a).T) - dims[1]).max() <= AGREE_TOL * s
    assert np.abs(np.hypot(*(b - [dims[3], 0.0]).T) - dims[2]).max() <= AGREE_TOL * s
    _agree(vec, grp, "B", s)
    back = _vector_four_bar(*dims, mode).solve(PHI[::-1])
    assert np.abs(back.point("B").velocity[::-1] - vec.point("B").velocity).max() <= SWEEP_TOL * s * 10


@SETTINGS
@given(st.floats(1e-3, 1e2), st.floats(-0.8, 0.8), st.floats(1.4, 5.0), st.sampled_from([1, -1]))
def test_vector_slider_crank_agrees_with_the_rrp_dyad(s: float, offset: float, rod: float, mode: int) -> None:
    assume(abs(offset) > 1e-3)
    rod = (rod + abs(offset)) * s
    vec = _vector_slider_crank(s, rod, offset * s, mode).solve(PHI)
    grp = slider_crank(s, rod, offset * s, mode=mode).solve(PHI)
    _agree(vec, grp, "B", s)
    b = vec.point("B").position
    assert np.abs(b[:, 1] - offset * s).max() <= AGREE_TOL * s  # on its guide
    assert np.all(np.sign(b[:, 0] - vec.point("A").position[:, 0]) == mode)
