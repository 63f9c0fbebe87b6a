"""The shipped Watt II six-bar (config/scenes/six_bar.yaml) against an independent computation:
every loop closes, each dyad in its declared assembly, E from a separate circle intersection, and
the velocity analog against central differences of the positions."""

from __future__ import annotations

import math

import numpy as np

import solver

PHI = np.linspace(0.0, 2 * math.pi, 3601)
PIVOT_O, C, F = 0.0 + 0.0j, 0.4 + 0.0j, 0.65 + 0.1j


def _z(k: solver.Kinematics, name: str) -> np.ndarray:
    p = k.point(name).position
    return p[:, 0] + 1j * p[:, 1]


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return (u.conjugate() * v).imag


def test_six_bar_closes_both_loops_in_its_assembly_modes_over_a_turn() -> None:
    scene = solver.load_scene("six_bar")
    assert [g.kind for g in scene.plan.groups if g.kind != "joint"] == ["crank", "rrr", "attached", "rrr"]
    k = scene.solve(PHI)
    a, b, d, e = (_z(k, n) for n in "ABDE")
    tol = 4e-16
    np.testing.assert_allclose(a, PIVOT_O + 0.1 * np.exp(1j * PHI), rtol=0, atol=tol)
    for got, want in ((abs(b - a), 0.4), (abs(b - C), 0.3), (abs(d - C), 0.2), (abs(e - d), 0.35), (abs(e - F), 0.3)):
        assert np.abs(got - want).max() <= tol
    # D on the rocker, 60° clockwise from C→B
    np.testing.assert_allclose(np.angle((d - C) / (b - C)), -math.pi / 3, rtol=0, atol=4e-15)
    assert (_cross(b - a, C - b) > 0).all()  # M = +1: A → B → C counter-clockwise
    assert (_cross(e - d, F - e) < 0).all()  # M = −1: D → E → F clockwise
    assert not k.singular.any()


def test_six_bar_output_from_a_separate_circle_intersection() -> None:
    k = solver.load_scene("six_bar").everything().solve(PHI)
    d, e = _z(k, "D"), _z(k, "E")
    # law of cosines at D: the angle between D→F and D→E, on the clockwise side (M = −1)
    span = F - d
    dist = abs(span)
    cos_d = (0.35**2 + dist**2 - 0.3**2) / (2 * 0.35 * dist)
    want = d + 0.35 * span / dist * np.exp(1j * np.arccos(cos_d))
    np.testing.assert_allclose(e, want, rtol=0, atol=1e-15)
    out = k.joint("output").position
    np.testing.assert_allclose(np.exp(1j * out), (e - F) / 0.3, rtol=0, atol=2e-15)


def test_six_bar_velocity_analog_is_the_derivative_of_the_position() -> None:
    scene = solver.load_scene("six_bar")
    phi, h = np.linspace(0.1, 6.1, 13), 1e-5
    k = scene.solve(phi)
    ahead, behind = scene.solve(phi + h), scene.solve(phi - h)
    for name in ("E", "D"):
        fd = (ahead.point(name).position - behind.point(name).position) / (2 * h)
        np.testing.assert_allclose(k.point(name).velocity, fd, rtol=0, atol=1e-10)
