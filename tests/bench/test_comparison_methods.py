"""The bench's comparison methods are right on tiny inputs (no timing here).

The benchmark (bench/speed_vs_error.py) compares the solver with finite differences, the complex
step, a generic Newton–Raphson solver and time integrators that live in bench/. If those were
wrong, the report would compare against nonsense; these tests pin them to the solver's exact
answers and to their textbook error behaviour.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

import solver  # noqa: E402
from bench import _common, alternatives, integration, newton  # noqa: E402

EPS = float(np.finfo(float).eps)
TOL_POS = 64 * EPS  # × scale
TOL_ANALOG = 1e-12  # relative
TOL_COMPLEX_STEP = 256 * EPS  # relative: no cancellation, only rounding
SCENES = tuple(alternatives.position_functions)
PHI = np.array([0.0, 0.3, 1.7, 2.9, 4.4, 5.8])


def _exact(scene: str, phi: np.ndarray) -> tuple[dict, dict]:
    sc = solver.load_scene(scene)
    k = sc.solve(phi, omega=1.0, epsilon=0.0)
    q = ("position", "velocity", "acceleration")
    return (
        {p: tuple(getattr(k.point(p), x) for x in q) for p in sc.output_points},
        {j: tuple(getattr(k.joint(j), x) for x in q) for j in sc.output_joints},
    )


def _relative(got: np.ndarray, want: np.ndarray) -> float:
    return float(np.max(np.abs(got - want)) / max(np.max(np.abs(want)), 1e-300))


@pytest.mark.parametrize("scene", SCENES)
def test_bench_position_copies_equal_the_solver_positions(scene: str) -> None:
    points, joints = alternatives.position_functions[scene](PHI)
    want_p, want_j = _exact(scene, PHI)
    for name, values in want_p.items():
        assert np.max(np.abs(points[name] - values[0])) < TOL_POS
    for name, (_, value) in joints.items():
        assert np.max(np.abs(_common._wrap(value - want_j[name][0]))) < TOL_POS


@pytest.mark.parametrize("scene", SCENES)
def test_complex_step_velocity_matches_exact_analog_to_rounding(scene: str) -> None:
    points, joints = alternatives.complex_step(scene, PHI)
    want_p, want_j = _exact(scene, PHI)
    for name, values in want_p.items():
        assert _relative(points[name][1], values[1]) < TOL_COMPLEX_STEP
        assert _relative(points[name][2], values[2]) < 1e-8  # difference of complex steps
    for name, values in joints.items():
        assert _relative(values[1], want_j[name][1]) < TOL_COMPLEX_STEP


def test_central_difference_error_falls_with_the_square_of_the_step() -> None:
    want_p, _ = _exact("four_bar", PHI)
    errors = []
    for h in (1e-2, 1e-3):
        points, _ = alternatives.central_differences("four_bar", PHI, h)
        errors.append(_relative(points["B"][1], want_p["B"][1]))
    assert 50 < errors[0] / errors[1] < 200


def test_central_difference_acceleration_is_ruined_by_cancellation_at_tiny_steps() -> None:
    want_p, _ = _exact("four_bar", PHI)
    points, _ = alternatives.central_differences("four_bar", PHI, 1e-8)
    assert _relative(points["B"][2], want_p["B"][2]) > 1e-3


@pytest.mark.parametrize("scene", SCENES)
def test_newton_converges_to_the_closed_form_with_exact_analogs(scene: str) -> None:
    sweep = np.linspace(0.0, 0.5, 6)
    q, v, a, iterations = newton.solve_sweep(scene, sweep, 1e-13)
    points, joints = newton.outputs(scene, q, v, a)
    want_p, want_j = _exact(scene, sweep)
    assert 0 < iterations < 10
    for name, values in points.items():
        assert np.max(np.abs(values[0] - want_p[name][0])) < TOL_POS
        for i in (1, 2):
            assert _relative(values[i], want_p[name][i]) < TOL_ANALOG
    for name, values in joints.items():
        assert np.max(np.abs(_common._wrap(values[0] - want_j[name][0]))) < TOL_POS
        for i in (1, 2):
            assert _relative(values[i], want_j[name][i]) < TOL_ANALOG


def test_newton_with_a_loose_tolerance_stops_early_and_is_less_exact() -> None:
    sweep = np.linspace(0.0, 2 * math.pi, 12, endpoint=False)
    *_, loose = newton.solve_sweep("four_bar", sweep, 1e-3)
    *_, tight = newton.solve_sweep("four_bar", sweep, 1e-14)
    assert loose < tight


def test_errors_against_wraps_angles_and_counts_nan_as_infinite() -> None:
    ref = _common.Reference(
        "toy",
        np.zeros(2),
        2.0,
        {"P": (np.ones((2, 2)), np.ones((2, 2)), np.ones((2, 2)))},
        {"J": ("angle", np.array([math.pi - 1e-9, 0.0]), np.ones(2), np.ones(2))},
    )
    wrapped = {"J": (np.array([-math.pi + 1e-9, 0.0]),)}
    assert _common.errors_against(ref, {}, wrapped)["position"] == pytest.approx(2e-9, rel=1e-6)
    scaled = {"P": (np.full((2, 2), 1.5), np.full((2, 2), 1.5))}
    assert _common.errors_against(ref, scaled, {}) == {"position": 0.25, "velocity": 0.5}
    broken = {"P": (np.array([[1.0, np.nan], [1.0, 1.0]]),)}
    assert _common.errors_against(ref, broken, {})["position"] == math.inf


@pytest.mark.parametrize("rk4", [False, True])
def test_vectorised_steppers_equal_a_tick_by_tick_loop_bit_for_bit(rk4: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(integration, "CHUNK", 7)  # several chunks, carried over
    rate, ticks = 10, 40
    samples = np.arange(ticks + 1)
    phi, omega = integration._stepped(rate, ticks, samples, rk4=rk4)
    dt, p, w = 1.0 / rate, 0.0, integration.OMEGA0
    for n in range(ticks + 1):
        assert (phi[n], omega[n]) == (p, w)
        eps = float(integration._epsilon_at(n / rate))
        if rk4:
            mid = w + dt / 2.0 * eps
            p += dt / 6.0 * (w + 2.0 * mid + 2.0 * mid + (w + dt * eps))
            w += dt / 6.0 * (eps + 2.0 * eps + 2.0 * eps + eps)
        else:
            p += w * dt
            w += eps * dt


def test_euler_error_is_first_order_in_the_step_and_rk4_is_exact_for_constant_epsilon() -> None:
    rows = integration.run(duration=20.0, sample_every=10.0, tick_count=10)
    by = {(r.method, r.rate): r for r in rows}
    assert 5 < by[("Euler", 10)].phi_error / by[("Euler", 100)].phi_error < 20
    assert by[("RK4", 10)].phi_error < 1e-11
    assert by[("closed form, plain float", 10)].phi_error < 1e-12
