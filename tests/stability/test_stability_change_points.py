"""Parallelogram and anti-parallelogram through their change points (φ = 0 and π).

Exact geometry: a parallelogram has B = A + (C − O) at every φ, so B' = A' and B'' = A''; an
anti-parallelogram (crossed) is the other assembly on (0, π) and must never become parallel.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scene_builders import four_bar

import solver
from solver.singular import change_points

#: positions of the parallelogram against exact geometry (the issue's check).
PARALLEL_TOL = 1e-9
#: the analogs' limit at a change point (Richardson extrapolation, about 1e-11 relative).
LIMIT_TOL = 1e-10
TURN = np.linspace(0.0, 2 * math.pi, 3600, endpoint=False)


@pytest.fixture(scope="module")
def parallelogram() -> solver.Scene:
    return solver.load_scene("hard/parallelogram")


@pytest.fixture(scope="module")
def antiparallelogram() -> solver.Scene:
    return solver.load_scene("hard/antiparallelogram")


def test_parallelogram_rocker_stays_parallel_to_crank_over_3600_samples(parallelogram: solver.Scene) -> None:
    k = parallelogram.solve(TURN)
    crank = k.point("A").position  # O = (0, 0)
    rocker = k.point("B").position - np.array([0.4, 0.0])
    assert np.abs(rocker - crank).max() < PARALLEL_TOL
    assert TURN[0] == 0.0 and TURN[1800] == math.pi  # the change points are among the samples


def test_parallelogram_analogs_at_change_points_are_the_continuous_limit(parallelogram: solver.Scene) -> None:
    phi = np.array([0.0, math.pi, 2 * math.pi, -math.pi, 3 * math.pi])
    k = parallelogram.solve(phi)
    a, b = k.point("A"), k.point("B")
    assert np.all(k.singular)
    assert np.abs(b.velocity - a.velocity).max() < LIMIT_TOL
    assert np.abs(b.acceleration - a.acceleration).max() < LIMIT_TOL
    assert np.allclose(k.joint("rocker").velocity, 1.0, rtol=0, atol=LIMIT_TOL)
    assert np.abs(k.joint("coupler").velocity).max() < LIMIT_TOL


def test_parallelogram_keeps_its_branch_past_change_point_on_the_scalar_path(parallelogram: solver.Scene) -> None:
    for phi in (0.0, math.pi, 1e-9, math.pi - 1e-9, math.pi + 1e-9):
        k = parallelogram.solve(phi)
        b, a = (np.asarray(k.point(p), float) for p in ("B", "A"))  # one instant: tuples (InstantMotion)
        assert np.abs(b[0] - a[0] - [0.4, 0.0]).max() < PARALLEL_TOL
        assert np.abs(b[1] - a[1]).max() < LIMIT_TOL


def test_antiparallelogram_keeps_its_configuration_for_the_whole_turn(antiparallelogram: solver.Scene) -> None:
    k = antiparallelogram.solve(TURN)
    a, b = k.point("A").position, k.point("B").position
    regular = ~k.singular
    # the crossed configuration: the coupler's ends lie on opposite sides of the ground line
    assert np.all(a[regular, 1] * b[regular, 1] < 0.0)
    assert np.all(np.isfinite(k.point("B").velocity)) and np.all(np.isfinite(k.point("B").acceleration))
    # analogs continuous across the change points: compare the limit with its neighbours
    v = k.joint("rocker").velocity
    assert abs(v[0] - v[1]) < 1e-3 and abs(v[0] - v[-1]) < 1e-3
    assert abs(v[1800] - v[1799]) < 1e-3 and abs(v[1800] - v[1801]) < 1e-3


def test_antiparallelogram_limit_matches_its_closed_form_at_change_points(antiparallelogram: solver.Scene) -> None:
    # crossed four-bar with OA = CB = r = 0.1, AB = OC = g = 0.4: at a change point the rocker's
    # rate is −(g + r)/(g − r) (φ = 0) or −(g − r)/(g + r) (φ = π), from the instantaneous centre;
    # also checked against the regular analogs just beside the change point
    k = antiparallelogram.solve(np.array([0.0, math.pi]))
    near = antiparallelogram.solve(np.array([1e-4, -1e-4, math.pi + 1e-4, math.pi - 1e-4]))
    v, vn = k.joint("rocker").velocity, near.joint("rocker").velocity
    assert abs(v[0] - 0.5 * (vn[0] + vn[1])) < 1e-7
    assert abs(v[1] - 0.5 * (vn[2] + vn[3])) < 1e-7
    assert v[0] == pytest.approx(-5.0 / 3.0, rel=1e-10)  # −(0.4 + 0.1)/(0.4 − 0.1)
    assert v[1] == pytest.approx(-0.6, rel=1e-10)  # −(0.4 − 0.1)/(0.4 + 0.1)


def test_change_points_are_located_to_rounding(parallelogram: solver.Scene) -> None:
    dyad = next(g for g in parallelogram.plan.groups if g.name == "dyad")
    assert change_points(parallelogram, dyad) == pytest.approx((0.0, math.pi), abs=1e-15)


@pytest.mark.parametrize("name", ["hard/parallelogram", "hard/antiparallelogram"])
def test_branch_is_a_function_of_phi_not_of_the_sweep(name: str) -> None:
    scene = solver.load_scene(name)
    phi = np.linspace(-3 * math.pi, 3 * math.pi, 997)
    forward = scene.solve(phi)
    backward = scene.solve(phi[::-1])
    for p in ("B",):
        assert np.array_equal(forward.point(p).position, backward.point(p).position[::-1])
        assert np.array_equal(forward.point(p).velocity, backward.point(p).velocity[::-1])
    one_by_one = np.array([scene.solve(float(x)).point("B").position for x in phi[::83]])
    assert np.abs(one_by_one - forward.point("B").position[::83]).max() < 1e-15
    shifted = scene.solve(phi + 2 * math.pi)
    assert np.abs(shifted.point("B").position - forward.point("B").position).max() < 1e-12


def test_keeping_M_through_a_change_point_flags_the_kink_as_undefined() -> None:
    # the same parallelogram with M held (seed 003's default): at φ = 0 the mechanism switches
    # assembly, the left and right analogs differ, so none is returned — NaN, and flagged.
    scene = four_bar(0.1, 0.4, 0.1, 0.4, mode=-1)
    k = scene.solve(np.array([0.0, 0.5]))
    assert k.singular.tolist() == [True, False]
    v = k.point("B").velocity
    assert np.isnan(v[0]).all() and np.isfinite(v[1]).all()
    assert np.isfinite(k.point("B").position).all()


def test_unknown_through_change_points_value_is_a_scene_error() -> None:
    with pytest.raises(solver.SceneError, match=r"through_change_points: must be 'keep' .* or 'continuous'"):
        four_bar(0.1, 0.4, 0.1, 0.4, through="sometimes")


@pytest.mark.parametrize("name", ["hard/parallelogram", "hard/antiparallelogram"])
def test_positions_stay_exact_within_a_hair_of_the_change_points(name: str) -> None:
    """A crank-fed dyad evaluates D² − (l₁ − l₂)² in closed form in φ, so no √ε loss at a toggle."""
    scene = solver.load_scene(name)
    eps = np.array([1e-15, 1e-12, 1e-9, 1e-7])
    phi = np.concatenate([eps, -eps, np.pi + eps, np.pi - eps])
    k = scene.solve(phi)
    a, b = k.point("A").position, k.point("B").position
    c = np.array([0.4, 0.0])
    # |AB| = 0.4 and |CB| = 0.1 to rounding: B sits on both circles even beside the toggle
    np.testing.assert_allclose(np.hypot(*(b - a).T), 0.4, rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.hypot(*(b - c).T), 0.1, rtol=0, atol=1e-15)
    if name == "hard/parallelogram":
        np.testing.assert_allclose(b - a, np.broadcast_to(c, b.shape), rtol=0, atol=1e-15)
