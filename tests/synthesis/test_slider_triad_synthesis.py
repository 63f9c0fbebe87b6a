"""Synthesis varies a slider triad's free values as it does the RRR triad's: its binary links'
lengths, its ternary link's sides or shape, its guide's angle and offset and the fixed pivots
(the guide's through point among them) (docs/synthesis.md § Triads).

A population of slider-triad designs is solved design by design, each row the same sweep as its
own loaded scene (compared to the bit, the ram's slide too); the shipped slider_triad_press is
recovered exactly from its ram's stroke function with its two lengths and a pivot free; a design
that cannot be assembled over the range is rejected with the reason; faults are one line."""

from __future__ import annotations

import copy
import math
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import solver
from solver.errors import SceneError
from solver.synthesis.api import make_goal
from solver.synthesis.population import INFEASIBLE, evaluate, objective, run
from solver.synthesis.result import meets_constraints
from solver.synthesis.template import load_template
from solver.tolerances import EXACT_MISS

TEMPLATES = Path(__file__).parent / "templates"
FUNCTION = TEMPLATES / "slider_triad_press_function.yaml"
PATH = TEMPLATES / "slider_triad_press_path.yaml"
#: slider_triad_press's own values in the function template's order: C x, C y, |BE|, |CF| (m)
PRESS = np.array([0.39, 0.5, 0.498196748283246, 0.49244289008980524])


def _data(path: Path) -> Any:
    return yaml.safe_load(path.read_text(encoding="utf-8"))


def _sides_template() -> Any:
    """The function template with the ternary link given by its sides, all three free, and the
    guide's through point free."""
    data = _data(FUNCTION)
    group = data["groups"][1]
    del group["shape"]
    group["sides"] = [{"free": [0.8, 1.0]}, {"free": [0.3, 0.5]}, {"free": [1.0, 1.2]}]
    group["M"] = -1
    data["fixed"]["G"] = [{"free": [-0.5, -0.4]}, -0.49]
    return load_template(data)


def _drawn_template() -> Any:
    """The path template with the drawn D and E free too: each design's drawn slide (the mode
    rule's tie-break) its own, or none where its angle is not its drawn one."""
    data = _data(PATH)
    shape = data["groups"][1]["shape"]
    shape["D"] = [-0.45, {"free": [-0.82, -0.78]}]
    shape["E"] = [{"free": [-0.42, -0.36]}, 0.09]
    return load_template(data)


def _constant_triad_template() -> Any:
    """slider_triad_press with only the crank's length free: the triad's values are constants."""
    data = _data(Path(solver.find_scene("slider_triad_press")))
    data["groups"][0]["length"] = {"free": [0.05, 0.12]}
    return load_template(data)


@pytest.mark.parametrize("which", ["function", "path", "sides", "constant", "drawn"])
def test_a_population_of_slider_triads_solves_as_each_design_s_own_scene(which: str) -> None:
    """12 random designs × a sweep, and × scattered phases: every point, the ternary link's angle,
    the ram's slide and their analogs equal the design's own loaded scene's solve to the bit (each
    design follows its own mode from θ₀), and the invalid samples are the same."""
    tpl = {"sides": _sides_template, "constant": _constant_triad_template, "drawn": _drawn_template}.get(
        which, lambda: load_template(FUNCTION if which == "function" else PATH))()
    rng = np.random.default_rng(7)
    x = tpl.lo + (tpl.hi - tpl.lo) * rng.random((12, len(tpl.lo)))
    for phi in (np.linspace(0.0, 2.0 * math.pi, 90, endpoint=False), np.radians([10.0, 80.0, 150.0, 230.0, 300.0])):
        ctx = run(tpl, x, np.broadcast_to(phi, (12, phi.size)), ("D", "F", "ternary", "ram"))
        invalid = np.broadcast_to(ctx.invalid, (12, phi.size))
        assert invalid.any(axis=1).sum() < 12  # most designs assemble: the comparison means something
        for i in range(12):
            try:
                scene = tpl.scene(x[i])
            except SceneError as exc:  # sides that make no triangle: the population's row is all invalid
                assert "is no triangle" in str(exc) and invalid[i].all()
                continue
            k = scene.with_outputs(points=["D", "F"], joints=["ternary", "ram"], forces=False).solve(phi, mask=True)
            np.testing.assert_array_equal(invalid[i], ~k.valid)
            good = k.valid
            for m, part in enumerate(("position", "velocity", "acceleration")):
                for joint in ("ternary", "ram"):
                    q = getattr(k.joint(joint), part)[good]
                    np.testing.assert_array_equal(ctx.values[joint][m][i][good], q)
                for point in ("D", "F"):
                    xy = getattr(k.point(point), part)[good]
                    np.testing.assert_array_equal(ctx.values[point][m][i][good], xy[:, 0] + 1j * xy[:, 1])


@pytest.mark.slow
def test_synthesis_recovers_the_slider_triad_press_from_its_ram_stroke_function() -> None:
    """slider_triad_press's ram slide at five crank angles; the template's |BE|, |CF| and the pivot
    C free (ranges around them): the search ends at slider_triad_press itself, every pair met to
    ≤ 1e-9 m (measured on the design's own scene), its values within 1e-8 m, and its whole stroke
    is the press's."""
    press = solver.load_scene("slider_triad_press")
    phi = np.radians([0.0, 60.0, 130.0, 200.0, 280.0])
    q = press.with_outputs(joints=["ram"], forces=False).solve(phi).joint("ram").position
    res = solver.synthesize(FUNCTION, joint="ram", pairs=np.c_[phi, q], seed=0, time_limit=300)
    assert res.error <= EXACT_MISS
    assert np.abs(np.array(list(res.values.values())) - PRESS).max() <= 1e-8
    check = np.linspace(0.0, 2.0 * math.pi, 73)
    got = res.scene.with_outputs(joints=["ram"], forces=False).solve(check).joint("ram").position
    want = press.with_outputs(joints=["ram"], forces=False).solve(check).joint("ram").position
    assert np.abs(got - want).max() <= 1e-7
    assert "triad B–E" in res.summary() and "C x" in res.summary()


def _function_goal(tpl: Any) -> Any:
    phi = np.radians([0.0, 90.0, 180.0])
    q = solver.load_scene("slider_triad_press").with_outputs(joints=["ram"], forces=False).solve(phi)
    return make_goal(tpl, point=None, through=None, at=None, joint="ram", pairs=np.c_[phi, q.joint("ram").position],
                     poses=None, input_range=None, min_transmission=math.radians(30.0), max_ratio=None, samples=180)


def test_a_slider_triad_that_cannot_be_assembled_over_the_range_is_rejected_with_the_reason() -> None:
    """|CF| = 0.1 m: the slider triad has no real root over part of the turn. The population
    scores it infeasible (above every feasible figure, by the share of the turn it fails) and the
    design's own check names the group and the interval; slider_triad_press itself is feasible and exact."""
    tpl = load_template(FUNCTION)
    goal = _function_goal(tpl)
    bad = PRESS.copy()
    bad[3] = 0.1
    ev = evaluate(tpl, goal, np.array([PRESS, bad]))
    figure = objective(goal, ev)
    assert ev.invalid[0] == 0.0 and 0.1 < ev.invalid[1] < 0.4
    assert figure[0] <= EXACT_MISS < INFEASIBLE <= figure[1]
    assert meets_constraints(tpl.scene(PRESS), goal) is None
    assert meets_constraints(tpl.scene(bad), goal) == "group 'triad' cannot be assembled for φ in (47.3°, 122.6°)"


def test_force_terms_of_slider_triad_designs_are_each_design_s_own() -> None:
    """With bodies on the ternary link, the ram and the crank and the guide's angle free, the
    population's peak input effort over the sweep (ω = 2 rad/s, gravity) is each design's own
    scene's, to 1e-12 relative: the slider triad's reactions evaluated on the population's arrays."""
    data = _data(FUNCTION)
    data["groups"][1]["guide"]["angle"] = {"free": [88.0, 92.0]}
    data["bodies"] = {"plate": {"points": ["D", "E", "F"], "mass": 1.0}, "block": {"points": ["D"], "mass": 0.8},
                      "crank": {"points": ["O", "B"], "mass": 0.5}}
    data["gravity"] = [0.0, -9.81]
    tpl = load_template(data)
    goal = replace(_function_goal(tpl), effort_weight=1.0, pin_weight=0.1, speed=2.0)
    x = np.array([[*PRESS[:2], 90.0, *PRESS[2:]], [0.4, 0.51, 89.0, 0.5, 0.5]])
    ev = evaluate(tpl, goal, x)
    assert ev.effort is not None and ev.pin_load is not None and np.isfinite(ev.pin_load).all()
    for i in range(2):
        k = tpl.scene(x[i]).solve(goal.sweep, omega=2.0)
        want = np.abs(k.effort("crank")).max()
        assert abs(ev.effort[i] - want) <= 1e-12 * want


def test_sides_that_make_no_triangle_are_rejected_not_a_nan() -> None:
    """In a population a slider-triad design whose sides make no triangle is invalid at every
    sample (infeasible, NaN-free); loaded alone, it is the loader's one-line refusal."""
    tpl = _sides_template()
    goal = _function_goal(tpl)
    drawn = [abs(complex(-0.39, 0.09) - complex(-0.45, -0.8)), abs(complex(-0.06, 0.3) - complex(-0.39, 0.09)),
             abs(complex(-0.45, -0.8) - complex(-0.06, 0.3))]
    x = np.array([[*PRESS[:2], -0.45, *PRESS[2:], *drawn], [*PRESS[:2], -0.45, *PRESS[2:], 0.8, 0.3, 1.2]])
    ev = evaluate(tpl, goal, x)
    assert ev.invalid[0] == 0.0 and ev.invalid[1] == 1.0
    assert np.isfinite(objective(goal, ev)).all() and objective(goal, ev)[1] >= INFEASIBLE
    with pytest.raises(SceneError, match=r"^groups\[1\]\.sides: \[0\.8, 0\.3, 1\.2\] is no triangle \(each side"):
        tpl.scene(x[1])


@pytest.mark.parametrize(("edit", "message"), [
    (lambda g: g.__setitem__("angle", {"free": [80.0, 90.0]}),
     r"^groups\[1\]\.angle: a free value in a place that cannot vary \(.*a guide's angle and offset"),
    (lambda g: g["guide"].__setitem__("through", {"free": [0.0, 1.0]}),
     r"^groups\[1\]\.guide\.through: a free value in a place that cannot vary"),
    (lambda g: g["guide"].__setitem__("offset", {"free": [0.1, -0.1]}),
     r"^groups\[1\]\.guide\.offset: free range \[0\.1, -0\.1\] has lo > hi$"),
    (lambda g: g["lengths"].__setitem__(1, {"free": [0.0, 0.7]}),
     r"^groups\[1\]\.lengths\[1\]: a length's free range must be positive, got \[0, 0\.7\]$"),
])
def test_slider_triad_template_faults_are_one_line(edit: Any, message: str) -> None:
    data = copy.deepcopy(_data(FUNCTION))
    edit(data["groups"][1])
    with pytest.raises(SceneError, match=message) as info:
        load_template(data)
    assert "\n" not in str(info.value)


def test_free_values_of_a_slider_triad_are_named_by_the_link_they_are() -> None:
    tpl = _sides_template()
    assert [tpl.label(f) for f in tpl.free] == ["C x", "C y", "G x", "triad B–E", "triad C–F",
                                                  "triad D–E", "triad E–F", "triad F–D"]
    assert [tpl.label(f) for f in load_template(PATH).free] == [
        "triad guide angle", "triad guide offset", "triad B–E", "triad C–F",
        "triad F x (ternary link's frame)", "triad F y (ternary link's frame)"]
