"""Unassemblable ranges: exact φ intervals in the error, the CLI's message and the masked sweep."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scene_builders import build, four_bar, slider_crank

import solver
from solver.assembly import _residual_intervals, gaps, unassemblable_intervals
from solver.cli import main

#: the double rocker: cos φ < −0.40625 cannot be assembled (|C − A| > AB + CB).
EDGE = float(mpmath.acos(mpmath.mpf("-0.40625")))
EXPECTED = (EDGE, 2 * math.pi - EDGE)
#: the interval's ends against the 50-digit closed form: to rounding of φ.
END_TOL = 4e-15


@pytest.fixture(scope="module")
def double_rocker() -> solver.Scene:
    return solver.load_scene("hard/double_rocker")


def test_double_rocker_interval_matches_the_closed_form(double_rocker: solver.Scene) -> None:
    (iv,) = unassemblable_intervals(double_rocker, "dyad")
    assert iv == pytest.approx(EXPECTED, abs=END_TOL)


def test_root_finding_on_the_residual_agrees_with_the_closed_form(double_rocker: solver.Scene) -> None:
    dyad = next(g for g in double_rocker.plan.groups if g.name == "dyad")
    (iv,) = _residual_intervals(double_rocker, dyad)
    assert iv == pytest.approx(EXPECTED, abs=END_TOL)


def test_sweep_over_the_gap_raises_assembly_error_with_exact_interval(double_rocker: solver.Scene) -> None:
    message = r"group 'dyad' cannot be assembled for φ in \(113\.9695°, 246\.0305°\)"
    with pytest.raises(solver.AssemblyError, match=message) as info:
        double_rocker.solve(np.linspace(0, 2 * math.pi, 360, endpoint=False))
    assert info.value.intervals[0] == pytest.approx(EXPECTED, abs=END_TOL)
    assert len(info.value.phi) == 133  # the requested angles inside, all of them


def test_scalar_solve_inside_the_gap_raises_with_the_interval(double_rocker: solver.Scene) -> None:
    with pytest.raises(solver.AssemblyError, match=r"\(113\.9695°, 246\.0305°\); requested φ = 180\.0000°"):
        double_rocker.solve(math.pi)


def test_masked_sweep_returns_the_assemblable_part(double_rocker: solver.Scene) -> None:
    phi = np.linspace(0, 2 * math.pi, 721)
    k = double_rocker.solve(phi, mask=True)
    inside = (phi > EXPECTED[0]) & (phi < EXPECTED[1])
    assert np.array_equal(k.valid, ~inside)
    assert gaps(double_rocker) == {"dyad": [pytest.approx(EXPECTED, abs=END_TOL)]}


def test_linkage_solve_exits_nonzero_and_states_the_interval(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["hard/double_rocker"]) == 2
    err = capsys.readouterr().err
    assert "(113.9695°, 246.0305°)" in err and "Traceback" not in err


def test_linkage_solve_mask_prints_the_gap(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["hard/double_rocker", "--mask"]) == 0
    out = capsys.readouterr().out
    assert "gap: dyad cannot be assembled for φ in (113.9695°, 246.0305°)" in out
    assert "double_rocker: 227 positions" in out


def test_a_gap_through_phi_zero_is_one_interval_past_two_pi() -> None:
    # ground 0.4, crank 0.1, AB − CB = 0.35: D = 0.3 at φ = 0 is shorter than |l1 − l2|
    scene = four_bar(0.1, 0.5, 0.15, 0.4)
    (lo, hi), = unassemblable_intervals(scene, "dyad")
    half = math.acos((0.4**2 + 0.1**2 - 0.35**2) / (2 * 0.4 * 0.1))
    assert (lo, hi) == pytest.approx((2 * math.pi - half, 2 * math.pi + half), abs=END_TOL)
    dyad = next(g for g in scene.plan.groups if g.name == "dyad")
    assert _residual_intervals(scene, dyad) == [pytest.approx((lo, hi), abs=END_TOL)]


def test_slider_crank_gap_is_found_by_root_finding() -> None:
    # crank 0.1, rod 0.08, offset 0: A is farther than the rod from the guide where |sin φ| > 0.8
    scene = slider_crank(0.1, 0.08, 0.0)
    got = unassemblable_intervals(scene, "rod")
    a = math.asin(0.8)
    assert got == [
        pytest.approx((a, math.pi - a), abs=END_TOL),
        pytest.approx((math.pi + a, 2 * math.pi - a), abs=END_TOL),
    ]


def test_narrow_gap_of_a_near_toggle_four_bar_is_not_missed_by_the_grid() -> None:
    # AB + CB exceeds the largest |C − A| = 0.5 by −1e-9: a gap about 2·sqrt(2e-9/0.04) rad wide
    scene = four_bar(0.1, 0.25, 0.25 - 1e-9, 0.4)
    dyad = next(g for g in scene.plan.groups if g.name == "dyad")
    (iv,) = _residual_intervals(scene, dyad)
    (closed,) = unassemblable_intervals(scene, "dyad")
    assert iv[0] < math.pi < iv[1] and iv[1] - iv[0] < 1e-3
    assert iv == pytest.approx(closed, abs=1e-9)  # both to rounding of a sqrt-conditioned end


def test_chain_after_a_dyad_reports_the_failing_group_only() -> None:
    scene = build({
        "scene": "chain",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0], "C": [0.4, 0.0], "E": [0.3, 0.1]},
        "groups": [
            {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": 0.1},
            {"type": "rrr", "name": "first", "ends": ["A", "C"], "point": "B", "lengths": [0.4, 0.3], "M": 1},
            {"type": "rrr", "name": "second", "ends": ["B", "E"], "point": "F", "lengths": [0.2, 0.17], "M": 1},
        ],
        "outputs": {"points": ["F"]},
    })
    assert unassemblable_intervals(scene, "first") == []
    second = unassemblable_intervals(scene, "second")
    assert len(second) == 1 and 0.0 < second[0][1] - second[0][0] < 2 * math.pi
    phi = np.linspace(0, 2 * math.pi, 2000)
    k = scene.solve(phi, mask=True)
    inside = np.zeros_like(phi, bool)
    for lo, hi in second:
        inside |= ((phi > lo) & (phi < hi)) | ((phi + 2 * math.pi > lo) & (phi + 2 * math.pi < hi))
    assert np.array_equal(~k.valid, inside)
