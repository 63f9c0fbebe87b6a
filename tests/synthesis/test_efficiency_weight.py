"""The synthesis's efficiency term (issue 29): ``efficiency_weight`` adds weight · (1 − the worst
instantaneous efficiency over the input range) for a template with friction. The population's
worst efficiency is each design's own ``k.efficiency`` (its scene solved on its own), the figure
grows by exactly the term, a search ranks its exact designs by it, and the faults are one line."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import solver
from solver import SynthesisError
from solver.synth_cli import main as synth_main
from solver.synthesis import load_template
from solver.synthesis.api import make_goal
from solver.synthesis.population import evaluate, objective

HERE = Path(__file__).parent / "templates"
TEMPLATE = HERE / "four_bar_friction_function.yaml"
NO_FRICTION = HERE / "four_bar_loaded_function.yaml"
SPEED = 3.0
RANGE = (0.3, 2.0)
#: The population's friction solve on (C, S) arrays and a design's scene on (S,): the same
#: operations on the same numbers, in another arrangement.
ROUNDING = 1e-12
DESIGNS = np.array([[0.1, 0.4, 0.3], [0.08, 0.45, 0.28], [0.12, 0.38, 0.33], [0.06, 0.5, 0.25]])


def _goal(weight: float) -> tuple[object, object]:
    t = load_template(TEMPLATE)
    phi = np.array([0.5, 1.5])
    psi = t.scene([0.1, 0.4, 0.3]).solve(phi).joint("rocker").position
    goal = make_goal(t, point=None, through=None, at=None, joint="rocker", pairs=np.c_[phi, psi], poses=None,
                     input_range=RANGE, min_transmission=math.radians(20.0), max_ratio=None, samples=180)
    return t, replace(goal, efficiency_weight=weight, speed=SPEED)


def test_the_populations_worst_efficiency_is_each_designs_own() -> None:
    t, goal = _goal(1.0)
    ev = evaluate(t, goal, DESIGNS)  # type: ignore[arg-type]
    assert ev.efficiency is not None
    for x, worst in zip(DESIGNS, ev.efficiency):
        k = t.scene(x).solve(goal.sweep, omega=SPEED)  # type: ignore[attr-defined]
        eta = np.asarray(k.efficiency)
        assert 0.0 < worst < 1.0
        assert worst == pytest.approx(float(eta.min()), rel=ROUNDING)
    assert np.ptp(ev.efficiency) > 0.1  # the designs differ: the term ranks them


def test_the_figure_grows_by_the_weight_times_the_shortfall() -> None:
    t, goal = _goal(2.5)
    _, plain = _goal(0.0)
    with_term = objective(goal, evaluate(t, goal, DESIGNS))  # type: ignore[arg-type]
    without = objective(plain, evaluate(t, plain, DESIGNS))  # type: ignore[arg-type]
    worst = evaluate(t, goal, DESIGNS).efficiency  # type: ignore[arg-type]
    np.testing.assert_allclose(with_term - without, 2.5 * (1.0 - worst), rtol=1e-12, atol=1e-15)


def test_a_search_returns_the_exact_design_of_best_worst_efficiency() -> None:
    """Two pairs leave a family of exact designs; the weight ranks them by their worst efficiency
    (at ω = 3 rad/s, over the range): the design returned is the best found, and says it."""
    t, goal = _goal(1.0)
    phi = np.array([0.5, 1.5])
    psi = t.scene([0.1, 0.4, 0.3]).solve(phi).joint("rocker").position  # type: ignore[attr-defined]
    res = solver.synthesize(t, joint="rocker", pairs=np.c_[phi, psi], efficiency_weight=1.0, speed=SPEED,
                            input_range=RANGE, min_transmission=math.radians(20.0), seed=0)
    assert res.exact
    sweep = np.linspace(*RANGE, 400)
    worst = [float(np.min(d.scene.solve(sweep, omega=SPEED).efficiency)) for d in res.solutions if d.error <= 1e-9]
    assert worst[0] >= max(worst) - 2e-3  # the search ranks on its 180-sample sweep
    assert "worst efficiency" in res.summary()


def test_faults_are_one_line() -> None:
    with pytest.raises(SynthesisError, match=r"efficiency_weight needs a template with friction: without it every "
                                             r"design's efficiency is 1"):
        solver.synthesize(NO_FRICTION, joint="rocker", pairs=[[0.5, -1.9], [1.5, -1.7]], efficiency_weight=1.0)
    with pytest.raises(SynthesisError, match=r"efficiency_weight needs speed > 0"):
        solver.synthesize(TEMPLATE, joint="rocker", pairs=[[0.5, -1.9], [1.5, -1.7]], efficiency_weight=1.0,
                          speed=0.0)
    with pytest.raises(SynthesisError, match=r"efficiency_weight"):
        solver.synthesize(TEMPLATE, joint="rocker", pairs=[[0.5, -1.9], [1.5, -1.7]], efficiency_weight=-1.0)


def test_the_cli_flag_reaches_the_search(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pairs = tmp_path / "pairs.csv"
    pairs.write_text("0.5,-1.9\n1.5,-1.7\n", encoding="utf-8")
    assert synth_main([str(NO_FRICTION), "--joint", "rocker", "--pairs", str(pairs),
                       "--efficiency-weight", "1", "--speed", "3"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("linkage-synth: error: ") and "efficiency_weight needs a template with friction" in err
    with pytest.raises(SystemExit):
        synth_main([str(TEMPLATE), "--joint", "rocker", "--pairs", str(pairs), "--efficiency-weight", "-1"])
    assert "--efficiency-weight: must be in [0, inf)" in capsys.readouterr().err
