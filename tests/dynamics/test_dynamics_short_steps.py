"""Issue 32, the cost of a step: a step cut short by a kink taken with Dormand and Prince's 5(4)
pair (half DOP853's evaluations, the tolerance kept), a run's samples and a tick's ε read off the
step's own last evaluation, the drive's scalar form equal to its list form."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import RK45

import solver
from solver.dynamics import Stepper, _stepping
from solver.dynamics._rk import (
    dop853_step,
    dop853_step_loop,
    dopri5_dense,
    dopri5_error,
    dopri5_step,
    dopri5_step_loop,
)
from solver.dynamics.drive import make_drive
from solver.forces.spec import Motor


@pytest.fixture(scope="module")
def engine() -> solver.Scene:
    return solver.load_scene("engine")


def _oscillator(t: float, y: list[float]) -> list[float]:
    return [y[1], -4.0 * y[0] + 0.3 * math.sin(t)]


def test_the_5_4_pair_is_scipys_rk45_step() -> None:
    y0, h = [1.0, 0.5], 0.07
    y_new, f_new, cols = dopri5_step(_oscillator, 0.2, y0, _oscillator(0.2, y0), h)
    theirs = RK45(lambda t, y: np.array(_oscillator(t, list(y))), 0.2, np.array(y0), 1.0, first_step=h,
                  rtol=1e-3, atol=1e-3)
    theirs.step()
    assert theirs.t == pytest.approx(0.2 + h, abs=1e-15)
    np.testing.assert_allclose(y_new, theirs.y, rtol=0, atol=1e-15)
    np.testing.assert_allclose(f_new, _oscillator(0.2 + h, y_new), rtol=0, atol=1e-15)
    # the error estimate is scipy's (its RMS norm of h·Kᵀ·E)
    scale = 1e-6 + 1e-6 * np.maximum(np.abs(y0), np.abs(y_new))
    expected = np.linalg.norm(h * np.array(cols) @ RK45.E / scale) / math.sqrt(2)
    assert dopri5_error(cols, h, y0, y_new, 1e-6, 1e-6) == pytest.approx(expected, rel=1e-12)
    # the dense output: its ends are the step's, its middle 4th-order close to scipy's own
    dense = dopri5_dense(0.2, y0, cols, h)
    np.testing.assert_allclose(dense(0.2 + h), y_new, rtol=0, atol=1e-15)
    np.testing.assert_allclose(dense(0.2 + 0.4 * h), theirs.dense_output()(0.2 + 0.4 * h), rtol=0, atol=1e-14)


def test_short_steps_through_the_gas_table_halve_the_evaluations_at_the_tolerance(
    engine: solver.Scene, monkeypatch: pytest.MonkeyPatch
) -> None:
    reference = engine.simulate(0.1, omega0=200.0, rtol=1e-12, atol=1e-12)
    run = engine.simulate(0.1, omega0=200.0)
    monkeypatch.setattr(_stepping, "SHORT_STEP", 0.0)  # DOP853 on every step
    plain = engine.simulate(0.1, omega0=200.0)
    kinks = (reference.phi[-1] - reference.phi[0]) / math.radians(5.0)
    # a 5° piece of the table is a step: 6 evaluations (the pair's), not DOP853's 12
    assert run.evaluations <= 7.5 * kinks and plain.evaluations >= 11 * kinks, (run.evaluations, plain.evaluations)
    # and the error stays DOP853's (0.1 s at rtol 1e-9: 3.9e-9 rad, 5.9e-8 rad/s; DOP853 on every
    # step 2.8e-9, 4.2e-8)
    assert abs(run.phi[-1] - reference.phi[-1]) <= 2e-8, abs(run.phi[-1] - reference.phi[-1])
    assert abs(run.omega[-1] - reference.omega[-1]) <= 3e-7, abs(run.omega[-1] - reference.omega[-1])
    # every sample lies on the run's dense output, and the samples' ε is the equation's there
    np.testing.assert_allclose(run.at(run.t)[0], run.phi, rtol=0, atol=1e-12)
    model = engine.reduced()
    fn, _ = make_drive(None, engine.inputs, model.motors, scene=engine.name)
    for i in (0, len(run.t) // 3, len(run.t) - 1):
        m, h, _ = model.instant((float(run.phi[i]),), (float(run.omega[i]),))
        eps = (fn(0.0, (run.phi[i],), (run.omega[i],))[0] - h[0]) / m
        assert run.epsilon[i] == pytest.approx(eps, rel=1e-9, abs=1e-6)


def test_a_ticks_acceleration_is_the_equations(engine: solver.Scene) -> None:
    harvester = solver.load_scene("harvester_finger")
    for scene, w in ((engine, 200.0), (harvester, 3.0)):
        stepper = Stepper(scene, omega0=w, method="RK4", step=2.5e-4, works=False)
        for t in (1e-3, 2e-3, 3.5e-3):
            stepper.advance(t)
            qdd, qdrive = stepper.accelerations()
            want_qdd, want_drive, _ = stepper.eq.accelerations(t, [float(stepper.y[0])], [float(stepper.y[1])])
            assert qdd[0] == pytest.approx(want_qdd[0], rel=1e-12, abs=1e-9)
            assert qdrive == pytest.approx(want_drive, rel=1e-15)


def test_a_drives_scalar_form_is_its_list_form() -> None:
    linear = Motor("drum", stall=40.0, no_load=8.0)
    table = Motor("drum", speeds=(0.0, 4.0, 8.0), torques=(40.0, 30.0, 0.0))
    for motor in (linear, table):
        fn, kind = make_drive(None, ["drum"], {"drum": motor}, scene="s")
        assert kind == "motor"
        for w in (-3.0, 0.0, 2.5, 7.9, 12.0):
            assert fn.one(0.0, 0.1, w) == fn(0.0, [0.1], [w])[0]  # type: ignore[attr-defined]
    constant, _ = make_drive(2.5, ["drum"], {}, scene="s")
    assert constant.one(0.0, 0.1, 3.0) == constant(0.0, [0.1], [3.0])[0] == 2.5  # type: ignore[attr-defined]


@pytest.mark.parametrize("n", [2, 4, 6])
def test_the_unrolled_steps_are_the_loops_to_the_bit(n: int) -> None:
    rng = np.random.default_rng(n)

    def f(t: float, y: list[float]) -> list[float]:
        return [math.sin(t + 0.3 * j) * y[(j + 1) % n] - 0.5 * y[j] ** 3 for j in range(n)]

    for _ in range(5):
        y = [float(v) for v in rng.uniform(-2.0, 2.0, n)]
        t, h = float(rng.uniform(0.0, 5.0)), float(rng.uniform(1e-4, 0.2))
        for fast, loop in ((dop853_step, dop853_step_loop), (dopri5_step, dopri5_step_loop)):
            assert fast(f, t, y, f(t, y), h) == loop(f, t, y, f(t, y), h)


def test_samples_between_short_steps_keep_the_runs_accuracy(engine: solver.Scene) -> None:
    # every dt sample read off a step's interpolant: the 5(4) pair's 4th-order one between kinks
    reference = engine.simulate(0.1, omega0=200.0, rtol=1e-12, atol=1e-12, dt=1e-4)
    run = engine.simulate(0.1, omega0=200.0, dt=1e-4)
    np.testing.assert_array_equal(run.t, reference.t)
    # (here 3.9e-9 rad and 6.8e-8 rad/s at most; DOP853 on every step: 2.8e-9, 4.9e-8)
    assert np.max(np.abs(run.phi - reference.phi)) < 2e-8
    assert np.max(np.abs(run.omega - reference.omega)) < 3.5e-7
