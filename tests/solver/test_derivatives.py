"""Analogs checked two ways: against high-order finite differences of the positions, and
against the differentiated loop constraints of each group (they must vanish identically)."""

from __future__ import annotations

import numpy as np
import pytest

import solver
from solver.tolerances import EPS

SCENES = ["four_bar", "four_bar_crossed", "harvester_finger", "slider_crank", "spherical_converter"]
#: 5-point stencils with h = 1e-3: truncation ~h⁴, rounding ~eps/h (first) and eps/h² (second).
STEP = 1e-3
FIRST_TOL = 1e-9
SECOND_TOL = 1e-6
#: derivatives of a constraint that holds identically vanish to rounding of its terms.
CONSTRAINT_TOL = 1e3 * EPS

PHI = np.linspace(0.05, 2 * np.pi - 0.05, 37)


def _values(k: solver.Kinematics, name: str, scene: solver.Scene) -> solver.Motion:
    return k.point(name) if name in scene.output_points else k.joint(name)


def _wrap(x: np.ndarray) -> np.ndarray:
    return (x + np.pi) % (2 * np.pi) - np.pi


@pytest.mark.parametrize("name", SCENES)
def test_analogs_match_five_point_finite_differences(name: str) -> None:
    scene = solver.load_scene(name).everything()
    k = scene.solve(PHI)
    shifted = {s: scene.solve(PHI + s * STEP) for s in (-2, -1, 1, 2)}
    for out in (*scene.point_names, *scene.joint_names):
        m = _values(k, out, scene)
        f = {s: _values(kk, out, scene).position for s, kk in shifted.items()}
        angle = out in scene.joint_names and np.ptp(m.position) > 3  # wrapped angle: difference mod 2π
        d = (lambda a, b: _wrap(a - b)) if angle else (lambda a, b: a - b)
        d1 = (8 * d(f[1], f[-1]) - d(f[2], f[-2])) / (12 * STEP)
        d2 = (-d(f[2], m.position) + 16 * d(f[1], m.position) + 16 * d(f[-1], m.position) - d(f[-2], m.position)) / (
            12 * STEP**2
        )
        scale = max(1.0, float(np.max(np.abs(m.velocity))))
        np.testing.assert_allclose(m.velocity, d1, atol=FIRST_TOL * scale, err_msg=f"{name}.{out} velocity")
        scale = max(1.0, float(np.max(np.abs(m.acceleration))))
        np.testing.assert_allclose(m.acceleration, d2, atol=SECOND_TOL * scale, err_msg=f"{name}.{out} acceleration")


def _jets(k: solver.Kinematics, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    p = k.point(name)
    return tuple(x[:, 0] + 1j * x[:, 1] for x in p)  # type: ignore[return-value]


def _distance_constraint(p: tuple, q: tuple) -> tuple[np.ndarray, np.ndarray]:
    """d/dφ and d²/dφ² of |P − Q|² (which is constant on a rigid link)."""
    r0, r1, r2 = (a - b for a, b in zip(p, q))
    dot = lambda a, b: (np.conj(a) * b).real
    return 2 * dot(r0, r1), 2 * dot(r1, r1) + 2 * dot(r0, r2)


def _collinear_constraint(p: tuple, q: tuple, o: tuple) -> tuple[np.ndarray, np.ndarray]:
    """d/dφ and d²/dφ² of (P − O) × (Q − O) (zero while P, Q and O stay on one line)."""
    u = [a - b for a, b in zip(p, o)]
    v = [a - b for a, b in zip(q, o)]
    cross = lambda a, b: (np.conj(a) * b).imag
    return cross(u[1], v[0]) + cross(u[0], v[1]), cross(u[2], v[0]) + 2 * cross(u[1], v[1]) + cross(u[0], v[2])


@pytest.mark.parametrize(
    ("name", "constraints"),
    [
        ("four_bar", [("dist", "A", "O"), ("dist", "B", "A"), ("dist", "B", "C")]),
        ("four_bar_crossed", [("dist", "B", "A"), ("dist", "B", "C")]),
        (
            "harvester_finger",
            [
                ("dist", "B", "O"),
                ("dist", "C", "A"),
                ("dist", "E", "A"),
                ("line", "C", "B", "A"),
                ("line", "E", "B", "A"),
            ],
        ),
        ("slider_crank", [("dist", "A", "O"), ("dist", "B", "A")]),
    ],
)
def test_analogs_satisfy_the_differentiated_loop_constraints(name: str, constraints: list) -> None:
    scene = solver.load_scene(name).everything()
    k = scene.solve(PHI)
    scale = 1.0
    for kind, *pts in constraints:
        jets = [_jets(k, p) for p in pts]
        g1, g2 = _distance_constraint(*jets) if kind == "dist" else _collinear_constraint(*jets)
        assert np.max(np.abs(g1)) < CONSTRAINT_TOL * scale, (kind, pts)
        assert np.max(np.abs(g2)) < CONSTRAINT_TOL * scale, (kind, pts)


def test_slider_stays_on_its_guide_with_velocity_along_it() -> None:
    k = solver.load_scene("slider_crank").solve(PHI)
    b = k.point("B")
    np.testing.assert_allclose(b.position[:, 1], 0.01, atol=4 * EPS)
    np.testing.assert_allclose(b.velocity[:, 1], 0.0, atol=4 * EPS)
    np.testing.assert_allclose(b.acceleration[:, 1], 0.0, atol=4 * EPS)
    np.testing.assert_allclose(k.joint("slider").velocity, b.velocity[:, 0], rtol=0, atol=4 * EPS)


def test_spherical_rod_centre_stays_on_the_sphere_in_the_plane_x0() -> None:
    k = solver.load_scene("spherical_converter").solve(PHI)
    p, v, a = k.point("K")
    np.testing.assert_allclose(np.linalg.norm(p, axis=1), 0.05, rtol=4 * EPS)
    np.testing.assert_allclose(p[:, 0], 0.0, atol=0)
    np.testing.assert_allclose(np.sum(p * v, axis=1), 0.0, atol=16 * EPS)  # d/dφ |K|² = 0
    np.testing.assert_allclose(np.sum(p * a, axis=1) + np.sum(v * v, axis=1), 0.0, atol=16 * EPS)


@pytest.mark.parametrize("name", SCENES)
def test_real_motion_follows_from_the_analogs(name: str) -> None:
    """seed 000 eq. 11–12: v = v_q·ω, a = a_q·ω² + v_q·ε, also for ω, ε varying per sample."""
    scene = solver.load_scene(name)
    omega = np.linspace(-3.0, 5.0, PHI.size)
    epsilon = np.linspace(2.0, -7.0, PHI.size)
    q = scene.solve(PHI)
    k = scene.solve(PHI, omega=omega, epsilon=epsilon)
    for p in scene.output_points:
        w = omega[:, None]
        np.testing.assert_allclose(k.point(p).velocity, q.point(p).velocity * w, rtol=8 * EPS, atol=1e-300)
        np.testing.assert_allclose(
            k.point(p).acceleration,
            q.point(p).acceleration * w**2 + q.point(p).velocity * epsilon[:, None],
            rtol=1e-13,
            atol=1e-15,
        )
    for j in scene.output_joints:
        np.testing.assert_allclose(k.joint(j).velocity, q.joint(j).velocity * omega, rtol=8 * EPS, atol=1e-300)
