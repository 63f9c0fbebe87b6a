"""The public API's arguments, checked in one line each (issue 30): a wrong type, a non-finite
number or a value out of range is one ArgumentError naming the scene, the function, the argument
and the value — never a bare TypeError, a silent acceptance or a NaN further on."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import solver
from solver._arguments import Arguments
from solver.dynamics import Stepper, flywheel_for, run_up, steady_state
from solver.errors import ArgumentError, DynamicsArgumentError, DynamicsError, SynthesisArgumentError, SynthesisError

FOUR_BAR_PATH = Path(__file__).parents[2] / "config" / "templates" / "four_bar_path.yaml"


def _scene(name: str) -> solver.Scene:
    return solver.load_scene(name)


DYNAMICS = [
    (lambda: flywheel_for(_scene("engine"), "1/80"),  # type: ignore[arg-type]
     r"^engine: flywheel_for: delta must be a finite number in \(0, 2\), got '1/80' \(a str\)$"),
    (lambda: flywheel_for(_scene("engine"), math.nan), r"^engine: flywheel_for: delta must be finite, got nan$"),
    (lambda: flywheel_for(_scene("engine"), 2.0), r"delta must be a finite number in \(0, 2\), got 2.0$"),
    (lambda: steady_state(_scene("engine"), flywheel="heavy"),  # type: ignore[arg-type]
     r"^engine: steady_state: flywheel must be a finite number ≥ 0 kg·m², got 'heavy' \(a str\)$"),
    (lambda: steady_state(_scene("engine"), flywheel=-1.0),
     r"^engine: steady_state: flywheel must be a finite number ≥ 0 kg·m², got -1.0$"),
    (lambda: steady_state(_scene("engine"), samples=1), r"steady_state: samples must be a whole number ≥ 2, got 1$"),
    (lambda: steady_state(_scene("engine"), samples=7.0),  # type: ignore[arg-type]
     r"steady_state: samples must be a whole number ≥ 2, got 7.0$"),
    (lambda: steady_state(_scene("engine"), omega_guess=-3.0),
     r"steady_state: omega_guess must be a finite number > 0 rad/s or None, got -3.0$"),
    (lambda: steady_state(_scene("engine"), rtol=0.0), r"steady_state: rtol must be a finite number > 0, got 0.0$"),
    (lambda: steady_state(_scene("engine"), phi0="a"),  # type: ignore[arg-type]
     r"steady_state: phi0 must be a finite number \(rad\), got 'a' \(a str\)$"),
    (lambda: run_up(_scene("engine"), t_max=0), r"^engine: run_up: t_max must be a finite number > 0 s, got 0$"),
    (lambda: _scene("four_bar_pendulum").simulate("1"),
     r"^four_bar_pendulum: simulate: t_end must be a finite number > 0 s, got '1' \(a str\)$"),
    (lambda: _scene("four_bar_pendulum").simulate(True), r"simulate: t_end must be a finite number > 0 s, got True "
                                                         r"\(a bool\)$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, rtol="x"), r"simulate: rtol must be a finite number > 0, "
                                                                  r"got 'x' \(a str\)$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, dt=-0.1), r"simulate: dt must be a finite number > 0 s or "
                                                                 r"None, got -0.1$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, until_phi="x"), r"simulate: until_phi must be a finite "
                                                                       r"number or None, got 'x' \(a str\)$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, max_step=-1), r"simulate: max_step must be a number > 0 s, "
                                                                     r"got -1$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, max_step=math.nan), r"max_step must not be nan, got nan$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, events=3), r"simulate: events must be a list of functions, "
                                                                  r"got 3$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, omega0="fast"), r"simulate: omega0 must be a number or an "
                                                                       r"array of numbers, got 'fast' \(a str\)$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, method="Euler"),
     r"simulate: method must be one of 'DOP853', 'RK4', 'RK45', 'Radau', got 'Euler' \(a str\)$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, on_singular="ignore"),
     r"simulate: on_singular must be one of 'raise', 'stop', got 'ignore' \(a str\)$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, phi_0=0.3),
     r"simulate: phi_0 is not an option of simulate; options: phi0, omega0, drive, .*, got 0.3$"),
    (lambda: _scene("five_bar").simulate(1.0, phi0=[0.1, 0.2, 0.3]),
     r"^five_bar: simulate: phi0 must be a number or 2 numbers \(one per input\), got \[0.1, 0.2, 0.3\]$"),
    (lambda: _scene("four_bar_pendulum").simulate(1.0, drive=math.nan),
     r"the drive gives nan where it must give 1 effort\(s\), one per input, each a finite number$"),
    (lambda: Stepper(_scene("four_bar_pendulum"), atol=-1.0), r"^four_bar_pendulum: Stepper: atol must be a finite "
                                                              r"number > 0, got -1.0$"),
    (lambda: Stepper(_scene("four_bar_pendulum"), works=1), r"Stepper: works must be True or False, got 1$"),
    (lambda: _scene("four_bar_pendulum").reduced().mass("a"), r"^four_bar_pendulum: reduced model: q must be a number "
                                                              r"or an array of numbers, got 'a' \(a str\)$"),
    (lambda: _scene("four_bar_pendulum").simulate(0.1).at("x"), r"Trajectory.at: t must be a number or an array of "
                                                                r"numbers, got 'x' \(a str\)$"),
]


@pytest.mark.parametrize(("call", "message"), DYNAMICS)
def test_dynamics_arguments_are_one_line(call: Any, message: str) -> None:
    with pytest.raises(solver.SolverError, match=message) as info:  # DynamicsError, and the drive's SolverError
        call()
    assert "\n" not in str(info.value)


def test_a_dynamics_argument_error_is_both_kinds_and_carries_argument_and_value() -> None:
    with pytest.raises(DynamicsArgumentError) as info:
        steady_state(_scene("engine"), flywheel=-1.0)
    error = info.value
    assert isinstance(error, ArgumentError) and isinstance(error, DynamicsError)
    assert (error.scene, error.function, error.argument, error.value) == ("engine", "steady_state", "flywheel", -1.0)
    assert error.reason == "must be a finite number ≥ 0 kg·m²" and error.time is None


SCENE = [
    (lambda s: s.solve("a"), r"^four_bar: solve: phi must be a number or an array of numbers \(rad\), got 'a' "
                             r"\(a str\)$"),
    (lambda s: s.solve(None), r"solve: phi must be a number or an array of numbers \(rad\), got None$"),
    (lambda s: s.solve(0.1, omega="a"), r"solve: omega must be a number or an array of numbers, got 'a' \(a str\)$"),
    (lambda s: s.solve(0.1, omega=[1.0, 2.0]), r"solve: omega must be a number where phi is one \(one instant\), "
                                               r"got \[1.0, 2.0\]$"),
    (lambda s: s.solve([0.1, 0.2], epsilon=[0.0, math.inf]), r"solve: epsilon must be finite, got \[inf\]$"),
    (lambda s: s.solve(0.1, mask="yes"), r"^four_bar: solve: mask must be True or False, got 'yes' \(a str\)$"),
    (lambda s: s.solve(np.array([0.1]), mask=1), r"solve: mask must be True or False, got 1$"),
    (lambda s: s.instant("a"), r"^four_bar: instant: phi must be a finite number \(rad\), got 'a' \(a str\)$"),
    (lambda s: s.instant(0.1, order=3), r"^four_bar: compiled: order must be one of 0, 1, 2, got 3$"),
    (lambda s: s.compiled(order="2"), r"compiled: order must be one of 0, 1, 2, got '2' \(a str\)$"),
    (lambda s: s.compiled(derivatives="yes"), r"compiled: derivatives must be True or False, got 'yes' \(a str\)$"),
    (lambda s: s.with_outputs(points="AB"), r"^four_bar: with_outputs: points must be a list of names \(write \['AB'\] "
                                            r"for one\), got 'AB' \(a str\)$"),
    (lambda s: s.with_outputs(joints=3), r"with_outputs: joints must be a list of names, got 3$"),
    (lambda s: s.with_outputs(forces="no"), r"with_outputs: forces must be True or False, got 'no' \(a str\)$"),
    (lambda s: solver.load_scene(3), r"^find_scene: name_or_path must be a scene's name or a path, got 3$"),
    (lambda s: solver.load_scene("five_bar").solve("ab"), r"^five_bar: solve: phi must be a number or an array of "
                                                          r"numbers, got 'ab' \(a str\)$"),
    (lambda s: solver.load_scene("five_bar").instant((1.0, 2.0), (1.0, 2.0, 3.0)),
     r"^five_bar: instant: omega must be 2 numbers \(inputs q1, q2\) or one for every input, got \(1.0, 2.0, 3.0\)"),
]


@pytest.mark.parametrize(("call", "message"), SCENE)
def test_scene_arguments_are_one_line(call: Any, message: str) -> None:
    with pytest.raises(ArgumentError, match=message) as info:
        call(_scene("four_bar"))
    assert "\n" not in str(info.value)


def test_good_arguments_of_every_kind_still_pass() -> None:
    scene = _scene("four_bar")
    assert scene.solve(np.float32(0.3), mask=np.bool_(True)).valid
    assert scene.with_outputs(points=("B",), forces=False).output_points == ("B",)
    run = _scene("four_bar_pendulum").simulate(np.float64(0.05), phi0=np.array(0.3), rtol=1e-8, atol=1e-8,
                                               max_step=math.inf, dt=0.01)
    assert run.status == "done"


SYNTHESIS = [
    ({"time_limit": 0}, r"^synthesize: time_limit must be a finite number > 0 s or None, got 0$"),
    ({"time_limit": "1 min"}, r"synthesize: time_limit must be a finite number > 0 s or None, got '1 min' \(a str\)$"),
    ({"seed": -1}, r"synthesize: seed must be a whole number ≥ 0, got -1$"),
    ({"seed": 1.5}, r"synthesize: seed must be a whole number ≥ 0, got 1.5$"),
    ({"starts": 0}, r"synthesize: starts must be a whole number ≥ 1, got 0$"),
    ({"samples": 4}, r"synthesize: samples must be a whole number ≥ 8, got 4$"),
    ({"popsize": 0}, r"synthesize: popsize must be a whole number ≥ 1, got 0$"),
    ({"maxiter": "many"}, r"synthesize: maxiter must be a whole number ≥ 1, got 'many' \(a str\)$"),
    ({"max_ratio": 0.5}, r"synthesize: max_ratio must be a finite number ≥ 1 or None, got 0.5$"),
    ({"effort_weight": -1.0}, r"synthesize: effort_weight must be a finite number ≥ 0, got -1.0$"),
    ({"speed": math.inf}, r"synthesize: speed must be finite, got inf$"),
    ({"min_transmission": 95.0}, r"synthesize: min_transmission must be a finite number in \[0, π/2\) rad, got 95.0$"),
    ({"input_range": "0:1"}, r"synthesize: input_range must be \(lo, hi\), two finite numbers with lo < hi \(rad\), "
                             r"got '0:1' \(a str\)$"),
    ({"point": 3}, r"synthesize: point must be a name \(a str\) or None, got 3$"),
    ({"workers": 0}, r"synthesize: workers must be a whole number ≥ 1, got 0$"),
    ({"workers": "4"}, r"synthesize: workers must be a number of local processes \(≥ 1\), a dask.distributed.Client "
                       r"or None, got '4' \(a str\)$"),
    ({"at": "x"}, r"synthesize: at must be a number or an array of numbers \(rad\), got 'x' \(a str\)$"),
    ({"progress": "yes"}, r"synthesize: progress must be a function or None, got 'yes' \(a str\)$"),
]


@pytest.mark.parametrize(("task", "message"), SYNTHESIS)
def test_synthesize_arguments_are_one_line(task: dict[str, Any], message: str) -> None:
    given = {"point": "P", "through": [[0.1, 0.2], [0.2, 0.25]], **task}
    with pytest.raises(SynthesisArgumentError, match=message) as info:
        solver.synthesize(FOUR_BAR_PATH, **given)
    assert isinstance(info.value, SynthesisError) and "\n" not in str(info.value)


def test_synthesize_names_a_template_that_is_none() -> None:
    with pytest.raises(SynthesisArgumentError, match=r"^synthesize: template must be a template scene: a path, a "
                                                     r"shipped name, a Template or its data, got 3$"):
        solver.synthesize(3, point="P", through=[[0.1, 0.2]])  # type: ignore[arg-type]


def test_the_helper_says_ranges_and_units_one_way() -> None:
    args = Arguments("f", scene="s")
    assert args.number("x", 2, low=0.0, high=2.0) == 2.0 and type(args.number("x", 2)) is float
    assert args.number("x", None, none=True) is None
    with pytest.raises(ArgumentError, match=r"^s: f: x must be a finite number in \[0, 2\) m, got 2$"):
        args.number("x", 2, low=0.0, high=2.0, high_open=True, unit="m")
    with pytest.raises(ArgumentError, match=r"^s: f: x must be a finite number < 1, got 1.0$"):
        args.number("x", 1.0, high=1.0, high_open=True)
    with pytest.raises(ArgumentError, match=r"^s: f: x must be a finite number, got np.float64|^s: f: x must be "
                                            r"finite, got nan$"):
        args.number("x", np.float64("nan"))
    with pytest.raises(ArgumentError, match=r"^s: f: n must be a whole number ≥ 1, got True \(a bool\)$"):
        args.integer("n", True, low=1)
    with pytest.raises(ArgumentError, match=r"^s: f: r must be \(lo, hi\), two finite numbers with lo < hi, got "
                                            r"\(1.2, 1.0\)$"):
        args.span("r", (1.2, 1.0))
    assert args.numbers("q", [1, 2]).dtype == float and args.names("p", ["A"]) == ("A",)
