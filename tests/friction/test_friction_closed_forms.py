"""Friction against the classical closed forms (textbook results, derived in each test's docstring)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from solver.forces.friction import breakaway, cycle_efficiency, locking_message
from tests.scene_builders import build

#: a closed form evaluated in float64 against the solver: a few ulps of the largest term
ROUNDING = 1e-13


def _incline(alpha: float, mu: float) -> Any:
    """Crank O–A (A = (0, 1) at φ = π/2), a massless rod A–B horizontal there, a massless block B on
    a guide inclined at α through B = (1.2, 1), weight W = 50 N on the block; friction only in the
    guide. At φ = π/2 the rod pushes the block horizontally: the wedge of the textbooks."""
    return build({
        "scene": "incline", "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0], "P": [1.2, 1.0]},
        "groups": [
            {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": 1.0},
            {"type": "rrp", "name": "rod", "end": "A", "point": "B", "length": 1.2,
             "guide": {"through": "P", "angle": alpha}, "M": 1},
        ],
        "outputs": {"points": ["A", "B"]},
        "bodies": {"block": {"points": ["B"], "mass": 0.0}},
        "loads": [{"body": "block", "point": "B", "force": [0.0, -50.0]}],
        "friction": {"slides": {"block": {"mu": mu}}},
    })


@pytest.mark.parametrize(("alpha", "mu"), [(0.3, 0.1), (0.6, 0.25), (1.0, 0.5), (0.2, 0.3)])
def test_incline_driven_up_and_lowered(alpha: float, mu: float) -> None:
    """Up the incline: P = W·tan(α + ρ), P₀ = W·tan α, η = tan α / tan(α + ρ), tan ρ = μ. Lowered
    (the weight drives): η' = tan(α − ρ) / tan α, negative where α < ρ (it holds itself)."""
    scene = _incline(alpha, mu)
    rho = math.atan(mu)
    up = scene.solve(math.pi / 2, omega=-1.0, epsilon=0.0)  # A moves +x: the block up the incline
    assert up.efficiency == pytest.approx(math.tan(alpha) / math.tan(alpha + rho), rel=ROUNDING)
    # the rod's push P = Q / (arm 1 m): W·tan(α + ρ)
    assert abs(up.effort("crank")) == pytest.approx(50.0 * math.tan(alpha + rho), rel=ROUNDING)
    down = scene.solve(math.pi / 2, omega=1.0, epsilon=0.0)
    assert down.efficiency == pytest.approx(math.tan(alpha - rho) / math.tan(alpha), rel=ROUNDING, abs=ROUNDING)
    total = down.friction_power + down.efficiency * 0.0
    assert total == pytest.approx(mu * abs(down.slide_reaction("block").force @ [-math.sin(alpha), math.cos(alpha)])
                                  * np.hypot(*down.point("B").velocity), rel=ROUNDING)


def _pushed(mu: float) -> Any:
    """Crank O–A (0.9 m), massless rod A–B (1 m), a massless block B on the x axis resisted by 100 N
    along −x; friction only in the guide."""
    return build({
        "scene": "pushed", "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0]},
        "groups": [
            {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": 0.9},
            {"type": "rrp", "name": "rod", "end": "A", "point": "B", "length": 1.0,
             "guide": {"through": "O", "angle": 0.0}, "M": 1},
        ],
        "outputs": {"points": ["A", "B"]},
        "bodies": {"block": {"points": ["B"], "mass": 0.0}},
        "loads": [{"body": "block", "point": "B", "force": [-100.0, 0.0]}],
        "friction": {"slides": {"block": {"mu": mu}}},
    })


def test_slider_pushed_at_an_angle_self_locks_beyond_the_friction_angle() -> None:
    """A rod at β to the guide pushes the block with P: P·(cos β − μ·sin β) = L. It drives only
    while tan β < 1/μ; beyond, no push moves the block (self-locking), and Q/Q₀ = cos β/(cos β − μ sin β)."""
    mu = 0.8
    scene = _pushed(mu)
    phi = np.linspace(0.05, math.pi - 0.05, 301)
    k = scene.solve(phi, omega=-1.0, epsilon=0.0)  # the block moves toward +x
    a, b = k.point("A").position, k.point("B").position
    beta = np.arctan2(a[:, 1] - b[:, 1], b[:, 0] - a[:, 0])
    margin = 1e-6
    clear = np.abs(np.tan(beta) - 1.0 / mu) > margin
    assert np.array_equal(k.locked[clear], (np.tan(beta) > 1.0 / mu)[clear])
    free = ~k.locked
    ratio = np.cos(beta[free]) / (np.cos(beta[free]) - mu * np.sin(beta[free]))
    np.testing.assert_allclose(k.effort("crank")[free] / k.ideal_effort("crank")[free], ratio, rtol=1e-12)
    assert np.all(np.isnan(k.effort("crank")[k.locked]))
    line = k.locking_message
    assert line.startswith("self-locking at φ = [") and "\n" not in line
    lo, hi = phi[k.locked][0], phi[k.locked][-1]
    assert f"{lo:.6g}" in line and f"{hi:.6g}" in line
    assert locking_message(phi, np.zeros(phi.shape, bool)) == ""


def _pendulum(mu: float, radius: float) -> Any:
    return build({
        "scene": "pendulum", "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0]},
        "groups": [{"type": "crank", "name": "arm", "center": "O", "point": "A", "length": 0.5}],
        "outputs": {"points": ["A"]},
        "bodies": {"arm": {"points": ["O", "A"], "mass": 2.0, "center": [0.3, 0.0], "inertia": 0.01}},
        "gravity": [0.0, -9.81],
        "friction": {"pins": {"O": {"mu": mu, "radius": radius}}},
    })


@pytest.mark.parametrize(("phi", "omega", "epsilon"), [(0.3, 2.0, -4.0), (2.5, -1.5, 7.0), (-1.0, 0.5, 0.0)])
def test_pendulum_friction_moment(phi: float, omega: float, epsilon: float) -> None:
    """One pin: R = m·(a_G − g) on the arm, friction moment μ·r·|R| against ω: Q = Q₀ + μ·r·|R|·sign ω;
    Q₀ = I_O·ε + m·g·l·cos φ; loss μ·r·|R|·|ω|."""
    m, l_g, inertia, g, mu, r = 2.0, 0.3, 0.01, 9.81, 0.2, 0.02
    k = _pendulum(mu, r).solve(phi, omega=omega, epsilon=epsilon)
    a_g = l_g * np.array([-omega ** 2 * math.cos(phi) - epsilon * math.sin(phi),
                          -omega ** 2 * math.sin(phi) + epsilon * math.cos(phi)])
    reaction = m * (a_g - np.array([0.0, -g]))
    q0 = (inertia + m * l_g ** 2) * epsilon + m * g * l_g * math.cos(phi)
    moment = mu * r * np.hypot(*reaction)
    assert k.ideal_effort("arm") == pytest.approx(q0, rel=ROUNDING)
    assert k.effort("arm") == pytest.approx(q0 + moment * math.copysign(1.0, omega), rel=ROUNDING)
    np.testing.assert_allclose(k.reaction("O", on="arm"), reaction, rtol=ROUNDING)
    assert k.friction_loss("O") == pytest.approx(moment * abs(omega), rel=ROUNDING)


def test_pendulum_at_rest_holds_within_the_breakaway_interval() -> None:
    """At rest the pin's friction can act either way: the holding efforts are Q₀ ∓ μ·r·m·g; the
    effort reported is the smallest that holds (the friction against the load's tendency)."""
    m, l_g, g, mu, r, phi = 2.0, 0.3, 9.81, 0.2, 0.02, 0.4
    scene = _pendulum(mu, r)
    q0 = m * g * l_g * math.cos(phi)
    lo, hi = breakaway(scene, phi)
    assert lo == pytest.approx(q0 - mu * r * m * g, rel=ROUNDING)
    assert hi == pytest.approx(q0 + mu * r * m * g, rel=ROUNDING)
    rest = scene.solve(phi, omega=0.0, epsilon=0.0)
    assert rest.effort("arm") == pytest.approx(lo, rel=ROUNDING)
    los, his = breakaway(scene, np.array([phi, phi + math.pi]))  # vectorised; Q₀ changes sign
    np.testing.assert_allclose(los, [lo, -hi], rtol=ROUNDING)
    np.testing.assert_allclose(his, [hi, -lo], rtol=ROUNDING)


def test_cycle_efficiency_of_a_steady_turn() -> None:
    """A pendulum turned at constant ω: the weight's work cancels over the turn, the input's work
    goes partly into lifting it back and all the rest into friction: η = 1 − W_loss / W_in."""
    scene = _pendulum(0.2, 0.02)
    phi = np.linspace(0.0, 2 * math.pi, 2001)
    k = scene.solve(phi, omega=3.0, epsilon=0.0)
    eta = cycle_efficiency(k)
    p = np.maximum(k.input_power, 0.0)
    dt = np.diff(phi) / 3.0
    w_in = np.sum(0.5 * (p[1:] + p[:-1]) * dt)
    w_loss = np.sum(0.5 * (k.friction_power[1:] + k.friction_power[:-1]) * dt)
    assert eta == pytest.approx(1.0 - w_loss / w_in, rel=ROUNDING)
    assert 0.0 < eta < 1.0


def test_the_paths_without_friction_in_the_dynamics_refuse_it_in_one_line() -> None:
    """scene.simulate runs friction on its own step loop (tests/dynamics/test_dynamics_friction.py);
    scipy's methods, the node's fixed-step Stepper and machine dynamics say in one line that they do not."""
    import solver
    from solver.dynamics import Stepper, steady_state

    scene = _pendulum(0.2, 0.02)
    with pytest.raises(solver.DynamicsError, match=r"pendulum.*method.*'DOP853' or 'RK4' for a scene with friction"):
        scene.simulate(1.0, method="Radau")
    with pytest.raises(solver.DynamicsError, match=r"pendulum: names friction: the fixed-step Stepper"):
        Stepper(scene)
    with pytest.raises(solver.DynamicsError, match=r"pendulum: steady_state: names friction"):
        steady_state(scene)


def test_a_scene_with_friction_is_not_compiled() -> None:
    import solver

    scene = _pendulum(0.2, 0.02)
    with pytest.raises(solver.SolverError, match=r"pendulum: a scene with friction is not compiled"):
        scene.compiled()
    assert scene.solve(0.3, omega=1.0, epsilon=0.0).effort("arm") == pytest.approx(
        float(scene.solve(np.array([0.3]), omega=1.0, epsilon=0.0).effort("arm")[0]), rel=1e-15)
