"""The own step loop (issue 32): the fixed-step RK4 against the adaptive DOP853 (order of
convergence, energy balance), DOP853 taking scipy's own steps, breakpoint to breakpoint across a
table's kinks (angle tables and a motor's torque–speed table) in both integrators, the step for
a tick chosen from the tolerance, and no piece left held after a run."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import solver
from solver.dynamics import Stepper, fixed_step
from solver.dynamics import drive as drive_module
from solver.dynamics._breaks import breaks_of
from solver.dynamics.drive import make_drive
from solver.dynamics.integrate import Equation
from solver.forces import frames

BENCH_SCENE = Path(__file__).resolve().parents[2] / "bench" / "scenes" / "slider_crank_flywheel.yaml"


@pytest.fixture(scope="module")
def pendulum() -> solver.Scene:
    return solver.load_scene("four_bar_pendulum")


@pytest.fixture(scope="module")
def engine() -> solver.Scene:
    return solver.load_scene("engine")


def test_rk4_converges_at_fourth_order_to_the_adaptive_run(pendulum: solver.Scene) -> None:
    reference = pendulum.simulate(2.0, phi0=0.3, rtol=1e-13, atol=1e-13)

    def error(h: float) -> float:  # the largest over the run (at one time alone it may cancel)
        run = pendulum.simulate(2.0, phi0=0.3, method="RK4", step=h)
        return float(np.max(np.abs(run.phi - reference.at(run.t)[0])))

    errors = [error(h) for h in (4e-3, 2e-3, 1e-3)]
    orders = [math.log2(a / b) for a, b in zip(errors, errors[1:])]
    # at least fourth order (here about 5.3: the h⁴ term's constant is small for this pendulum)
    assert all(p > 3.7 for p in orders) and errors[-1] < 1e-7, (errors, orders)


def test_rk4_keeps_the_energy_balance_to_its_order(pendulum: solver.Scene) -> None:
    run = pendulum.simulate(5.0, phi0=0.3, method="RK4", step=1e-3)
    energy = run.energy()
    swing = float(np.ptp(energy["kinetic"]))
    assert float(np.max(np.abs(energy["balance"]))) <= 1e-7 * swing
    half = pendulum.simulate(5.0, phi0=0.3, method="RK4", step=5e-4).energy()
    # halving the step: the balance's error falls about 16-fold (RK4 is not symplectic: it drifts, at O(h⁴))
    assert np.max(np.abs(half["balance"])) < np.max(np.abs(energy["balance"])) / 8


def test_rk4_needs_a_step_and_the_methods_are_named_in_the_message(pendulum: solver.Scene) -> None:
    with pytest.raises(solver.DynamicsError, match=r"simulate: step must be given with method 'RK4': the fixed "
                                                   r"step, a positive number of seconds, got None"):
        pendulum.simulate(1.0, method="RK4")
    with pytest.raises(solver.DynamicsError, match=r"method must be one of 'DOP853', 'RK4', 'RK45', 'Radau'"):
        pendulum.simulate(1.0, method="Euler")


def test_the_own_dop853_takes_scipys_steps_on_a_smooth_scene() -> None:
    scene = solver.load_scene(BENCH_SCENE)
    model = scene.reduced()
    fn, _ = make_drive(1.5, scene.inputs, model.motors, scene=scene.name)
    for tol in (1e-6, 1e-9):
        ours = scene.simulate(2.0, drive=1.5, rtol=tol, atol=tol)
        theirs = solve_ivp(Equation(model, fn), (0.0, 2.0), np.zeros(4), method="DOP853", rtol=tol, atol=tol)
        # the same method and controller: as many evaluations, the same answer to the tolerance
        # (the step sizes agree to the round-off of the error norm, amplified by the controller)
        assert ours.evaluations == theirs.nfev and ours.t.size == theirs.t.size
        assert abs(ours.phi[-1] - theirs.y[0, -1]) <= 10 * tol * abs(theirs.y[0, -1])


def test_dop853_steps_breakpoint_to_breakpoint_through_the_gas_table(engine: solver.Scene) -> None:
    reference = engine.simulate(0.1, omega0=200.0, rtol=1e-12, atol=1e-12)
    run = engine.simulate(0.1, omega0=200.0, rtol=1e-8, atol=1e-8)
    assert abs(run.phi[-1] - reference.phi[-1]) <= 1e-9 * abs(reference.phi[-1])
    assert abs(run.omega[-1] - reference.omega[-1]) <= 1e-9 * abs(reference.omega[-1])
    # every 5° entry crossed lands on a step's end (within √rtol of the step's move: an error
    # O(δ²·Δslope)), and no step crawls into one: about 12 evaluations a kink
    kinks = (reference.phi[-1] - reference.phi[0]) / math.radians(5.0)
    assert run.evaluations <= 14 * kinks
    on_kinks = np.abs(np.remainder(np.degrees(run.phi[1:-1]) + 2.5, 5.0) - 2.5)
    assert np.median(on_kinks) < math.sqrt(1e-8) * 5.0
    # the energy balance holds across the kinks (W_other carries the gas force's work)
    assert np.max(np.abs(run.energy()["balance"])) < 1e-6 * np.ptp(run.energy()["kinetic"])


def test_rk4_keeps_its_order_across_the_kinks(engine: solver.Scene) -> None:
    reference = engine.simulate(0.05, omega0=200.0, rtol=1e-12, atol=1e-12)
    errors = [abs(engine.simulate(0.05, omega0=200.0, method="RK4", step=h).omega[-1] - reference.omega[-1])
              for h in (4e-4, 2e-4)]
    # kinks stepped over instead of landed on would leave O(h²): a ratio of 4
    assert errors[0] / errors[1] > 10, errors


def test_a_motor_table_is_a_breakpoint_and_the_error_falls_with_the_tolerance(tmp_path: Path) -> None:
    text = BENCH_SCENE.read_text().replace(
        "damping:", "motor:\n  crankshaft: {speed: [0, 30, 56.5, 57.5, 80], torque: [1.5, 1.0, 0.2, -0.3, -2.0]}\n"
                    "damping:")
    path = tmp_path / "motor_table.yaml"
    path.write_text(text)
    scene = solver.load_scene(path)
    assert [t.index for t in breaks_of(scene.reduced()).tables] == [1]  # the rate's component
    reference = scene.simulate(3.0, rtol=1e-13, atol=1e-13)
    errors = [abs(scene.simulate(3.0, rtol=tol, atol=tol).phi[-1] - reference.phi[-1])
              for tol in (1e-6, 1e-8, 1e-10)]
    assert errors[0] > errors[1] > errors[2] and errors[2] < 1e-7, errors


def test_no_piece_stays_held_after_a_run_or_a_failed_one(engine: solver.Scene) -> None:
    engine.simulate(0.02, omega0=200.0)
    assert not frames.HELD and not drive_module.HELD
    stepper = Stepper(engine, omega0=200.0, method="RK4", step=1e-3, works=False)
    stepper.advance(0.01)
    assert not frames.HELD
    tipper = solver.load_scene("tipper")
    with pytest.raises(solver.DynamicsError, match=r"stroke \[0.74, 1.3\] m"):
        tipper.simulate(2.0, phi0=1.0, drive=0.0)
    assert not frames.HELD and not drive_module.HELD


def test_fixed_step_meets_the_tolerance_at_a_ticks_rate(engine: solver.Scene) -> None:
    scene = solver.load_scene("four_bar_loaded")
    for tolerance in (1e-6, 1e-9):
        step, error = fixed_step(scene, period=1e-3, tolerance=tolerance, phi0=0.3, horizon=20)
        assert error <= 1.0 and 1e-3 / step in (1, 2, 4, 8, 16)
    coarse, _ = fixed_step(scene, period=1e-3, tolerance=1e-4, phi0=0.3, horizon=20)
    fine, _ = fixed_step(scene, period=1e-3, tolerance=1e-10, phi0=0.3, horizon=20)
    assert fine < coarse
    # the stepper at that step against the adaptive run, tick by tick
    step, _ = fixed_step(engine, period=1e-3, tolerance=1e-9, omega0=200.0, horizon=20)
    fixed = Stepper(engine, omega0=200.0, method="RK4", step=step, works=False)
    adaptive = Stepper(engine, omega0=200.0, rtol=1e-12, atol=1e-12, works=False)
    for i in range(1, 21):
        a, b = fixed.advance(i * 1e-3), adaptive.advance(i * 1e-3)
        assert abs(a[1] - b[1]) <= 1e-9 * (1 + abs(b[1]))


def test_fixed_step_takes_no_more_steps_than_fit_its_budget() -> None:
    scene = solver.load_scene("harvester_finger")  # 8 steps a tick for 1e-9 without a budget
    step, error = fixed_step(scene, period=1e-3, tolerance=1e-9, horizon=10, budget=0.0)
    assert step == 1e-3 and error > 1.0  # one step a tick, and the error says the tolerance is missed
