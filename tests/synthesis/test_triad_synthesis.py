"""Synthesis varies a triad's free values: its binary links' lengths, its ternary link's sides or
shape, the fixed pivots (docs/synthesis.md § Triads).

A population of triad designs is solved design by design, each row the same sweep as its own
loaded scene (compared to the bit); the shipped triad_press is recovered exactly from its output
angle function with its three lengths and a pivot free; a design that cannot be assembled over the
range is rejected with the reason; faults are one line."""

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
from solver.errors import SceneError, SynthesisError
from solver.synthesis.api import make_goal
from solver.synthesis.population import INFEASIBLE, evaluate, objective, run
from solver.synthesis.result import meets_constraints
from solver.synthesis.template import load_template
from solver.tolerances import EXACT_MISS

TEMPLATES = Path(__file__).parent / "templates"
FUNCTION = TEMPLATES / "triad_press_function.yaml"
PATH = TEMPLATES / "triad_press_path.yaml"
#: triad_press's own values in the function template's order: C x, C y, |AD|, |BE|, |CF| (m)
PRESS = np.array([0.23, 0.05, 0.24515301344262527, 0.6174139616173253, 0.6082762530298219])


def _data(path: Path) -> Any:
    return yaml.safe_load(path.read_text(encoding="utf-8"))


def _sides_template() -> Any:
    """The function template with the ternary link given by its sides, all three free."""
    data = _data(FUNCTION)
    group = data["groups"][1]
    del group["shape"]
    group["sides"] = [{"free": [0.3, 0.7]}, {"free": [0.1, 0.9]}, {"free": [0.3, 0.8]}]
    group["M"] = 1
    return load_template(data)


def _constant_triad_template() -> Any:
    """triad_press with only the crank's length free: the triad's values are constants."""
    data = _data(Path(solver.find_scene("triad_press")))
    data["groups"][0]["length"] = {"free": [0.05, 0.12]}
    return load_template(data)


@pytest.mark.parametrize("which", ["function", "path", "sides", "constant"])
def test_a_population_of_triads_solves_as_each_design_s_own_scene(which: str) -> None:
    """16 random designs × a sweep, and × scattered phases: every point, the ternary link's angle
    and their analogs equal the design's own loaded scene's solve to the bit (each design follows
    its own mode from θ₀), and the invalid samples are the same."""
    tpl = {"sides": _sides_template, "constant": _constant_triad_template}.get(
        which, lambda: load_template(FUNCTION if which == "function" else PATH))()
    rng = np.random.default_rng(7)
    x = tpl.lo + (tpl.hi - tpl.lo) * rng.random((16, len(tpl.lo)))
    for phi in (np.linspace(0.0, 2.0 * math.pi, 90, endpoint=False), np.radians([10.0, 80.0, 150.0, 230.0, 300.0])):
        ctx = run(tpl, x, np.broadcast_to(phi, (16, phi.size)), ("D", "F", "ternary"))
        invalid = np.broadcast_to(ctx.invalid, (16, phi.size))
        assert invalid.any(axis=1).sum() < 16  # most designs assemble: the comparison means something
        for i in range(16):
            try:
                scene = tpl.scene(x[i])
            except SceneError as exc:  # sides that make no triangle: the population's row is all invalid
                assert "is no triangle" in str(exc) and invalid[i].all()
                continue
            k = scene.with_outputs(points=["D", "F"], joints=["ternary"], forces=False).solve(phi, mask=True)
            np.testing.assert_array_equal(invalid[i], ~k.valid)
            good = k.valid
            for m, part in enumerate(("position", "velocity", "acceleration")):
                q = getattr(k.joint("ternary"), part)[good]
                np.testing.assert_array_equal(ctx.values["ternary"][m][i][good], q)
                xy = getattr(k.point("F"), part)[good]
                np.testing.assert_array_equal(ctx.values["F"][m][i][good], xy[:, 0] + 1j * xy[:, 1])


@pytest.mark.slow
def test_synthesis_recovers_the_triad_press_from_its_output_angle_function() -> None:
    """triad_press's ternary-link angle at five crank angles; the template's |AD|, |BE|, |CF| and
    the pivot C free (ranges around them, ±20 %): the search ends at triad_press itself, every
    pair met to ≤ 1e-9 rad (measured on the design's own scene), its values within 1e-8 m."""
    press = solver.load_scene("triad_press")
    phi = np.radians([0.0, 60.0, 130.0, 200.0, 280.0])
    q = press.with_outputs(joints=["ternary"], forces=False).solve(phi).joint("ternary").position
    res = solver.synthesize(FUNCTION, joint="ternary", pairs=np.c_[phi, q], seed=0, time_limit=300)
    assert res.error <= EXACT_MISS
    assert np.abs(np.array(list(res.values.values())) - PRESS).max() <= 1e-8
    # the design's whole output function is the press's, not only at the five pairs
    check = np.linspace(0.0, 2.0 * math.pi, 73)
    got = res.scene.with_outputs(joints=["ternary"], forces=False).solve(check).joint("ternary").position
    want = press.with_outputs(joints=["ternary"], forces=False).solve(check).joint("ternary").position
    assert np.abs(got - want).max() <= 1e-7
    assert "triad A–D" in res.summary() and "C x" in res.summary()


@pytest.mark.slow
def test_synthesis_recovers_the_ternary_link_s_sides_from_the_output_angle_function() -> None:
    """triad_press written with its ternary link as sides [DE, EF, FD] (M = −1: D → E → F turns
    clockwise), the three sides free: the search returns the drawn sides, every pair to ≤ 1e-9 rad."""
    data = _data(FUNCTION)
    group = data["groups"][1]
    del group["shape"]
    d, e, f = 0.34 - 0.05j, -0.06 + 0.38j, 0.33 + 0.65j
    sides = [abs(e - d), abs(f - e), abs(d - f)]
    group.update(M=-1, sides=[{"free": [0.5, 0.7]}, {"free": [0.4, 0.55]}, {"free": [0.6, 0.8]}],
                 lengths=PRESS[2:].tolist())
    data["fixed"]["C"] = PRESS[:2].tolist()
    press = solver.load_scene("triad_press")
    phi = np.radians([0.0, 60.0, 130.0, 200.0, 280.0])
    q = press.with_outputs(joints=["ternary"], forces=False).solve(phi).joint("ternary").position
    res = solver.synthesize(data, joint="ternary", pairs=np.c_[phi, q], seed=0, time_limit=300)
    assert res.error <= EXACT_MISS
    assert np.abs(np.array(list(res.values.values())) - sides).max() <= 1e-8
    assert "triad E–F" in res.summary()


@pytest.mark.slow
def test_synthesis_recovers_the_triad_press_from_a_timed_path_of_a_ternary_link_point() -> None:
    """F's path of triad_press at five given crank angles; |AD|, |BE|, |CF| and F's place on the
    ternary link free: the search ends at the press (F = (0.33, 0.65) in the drawn frame), every
    target met to ≤ 1e-9 m on the design's own scene."""
    press = solver.load_scene("triad_press")
    phi = np.radians([10.0, 80.0, 150.0, 230.0, 300.0])
    xy = press.with_outputs(points=["F"], forces=False).solve(phi).point("F").position
    res = solver.synthesize(PATH, point="F", through=xy, at=phi, seed=0, samples=90, time_limit=300)
    assert res.error <= EXACT_MISS
    want = np.array([*PRESS[2:], 0.33, 0.65])
    assert np.abs(np.array(list(res.values.values())) - want).max() <= 1e-8
    np.testing.assert_allclose(res.phases, phi)


def _function_goal(tpl: Any) -> Any:
    phi = np.radians([0.0, 90.0, 180.0])
    return make_goal(tpl, point=None, through=None, at=None, joint="ternary", pairs=np.c_[phi, [2.3, 2.2, 2.0]],
                     poses=None, input_range=None, min_transmission=math.radians(30.0), max_ratio=None, samples=180)


def test_a_triad_that_cannot_be_assembled_over_the_range_is_rejected_with_the_reason() -> None:
    """|AD| = 0.02 m: the triad has no real root over four intervals of the turn. The population
    scores it infeasible (above every feasible figure, by the share of the turn it fails) and the
    design's own check names the group and the interval; triad_press itself is feasible."""
    tpl = load_template(FUNCTION)
    goal = _function_goal(tpl)
    bad = PRESS.copy()
    bad[2] = 0.02
    ev = evaluate(tpl, goal, np.array([PRESS, bad]))
    figure = objective(goal, ev)
    assert ev.invalid[0] == 0.0 and 0.3 < ev.invalid[1] < 0.9
    assert figure[0] < INFEASIBLE <= figure[1]
    assert meets_constraints(tpl.scene(PRESS), goal) is None
    assert meets_constraints(tpl.scene(bad), goal) == "group 'triad' cannot be assembled for φ in (8.7°, 12.6°)"


def test_force_terms_of_triad_designs_are_each_design_s_own() -> None:
    """With bodies on the triad and the crank, the population's peak input effort over the sweep
    (ω = 2 rad/s, gravity) is each design's own scene's, to 1e-12 relative: the triad's pin
    reactions (route 2) evaluated on the population's arrays."""
    data = _data(FUNCTION)
    data["bodies"] = {"triad": {"points": ["D", "E", "F"], "mass": 1.0}, "crank": {"points": ["O", "A"], "mass": 0.5}}
    data["gravity"] = [0.0, -9.81]
    tpl = load_template(data)
    goal = replace(_function_goal(tpl), effort_weight=1.0, pin_weight=0.1, speed=2.0)
    x = np.array([PRESS, [0.2, 0.05, 0.25, 0.6, 0.6]])
    ev = evaluate(tpl, goal, x)
    assert ev.effort is not None and ev.pin_load is not None and np.isfinite(ev.pin_load).all()
    for i in range(2):
        k = tpl.scene(x[i]).solve(goal.sweep, omega=2.0)
        want = np.abs(k.effort("crank")).max()
        assert abs(ev.effort[i] - want) <= 1e-12 * want


def test_a_search_whose_triads_never_assemble_says_so_in_one_line() -> None:
    """|AD| ≤ 0.02 m: no design assembles over the turn; the search ends in one SynthesisError line
    (no transmission angle named: the template has no dyad)."""
    data = _data(FUNCTION)
    data["groups"][1]["lengths"][0] = {"free": [0.01, 0.02]}
    pairs = [(0.0, 2.3), (1.0, 2.2), (2.0, 2.0)]
    with pytest.raises(SynthesisError, match=r"^template: no design found that assembles over the required input "
                       r"range (before the time limit expired|in \d+ start\(s\)); ") as info:
        solver.synthesize(data, joint="ternary", pairs=pairs, starts=1, maxiter=5, samples=60, time_limit=60)
    assert "\n" not in str(info.value) and "transmission" not in str(info.value)


def test_sides_that_make_no_triangle_are_rejected_not_a_nan() -> None:
    """In a population a design whose sides make no triangle is invalid at every sample (the row
    is NaN-free in the figure: infeasible); loaded alone, it is the loader's one-line refusal."""
    tpl = _sides_template()
    goal = _function_goal(tpl)
    x = np.array([[*PRESS, 0.5, 0.6, 0.7], [*PRESS, 0.3, 0.9, 0.4]])
    ev = evaluate(tpl, goal, x)
    assert ev.invalid[0] < 0.1 and ev.invalid[1] == 1.0
    short = run(tpl, x, np.radians([[0.0, 90.0, 180.0]] * 2), ("ternary",))  # the batched rows (the polish's)
    assert np.broadcast_to(short.invalid, (2, 3))[1].all() and np.isnan(short.values["ternary"].value[1]).all()
    assert np.isfinite(objective(goal, ev)).all() and objective(goal, ev)[1] >= INFEASIBLE
    with pytest.raises(SceneError, match=r"^groups\[1\]\.sides: \[0\.3, 0\.9, 0\.4\] is no triangle \(each side"):
        tpl.scene(x[1])


@pytest.mark.parametrize(("edit", "message"), [
    (lambda g: g.__setitem__("angle", {"free": [120.0, 140.0]}),
     r"^groups\[1\]\.angle: a free value in a place that cannot vary \(.*a triad's lengths, sides and shape\)$"),
    (lambda g: g.__setitem__("at", {"free": [0.0, 10.0]}),
     r"^groups\[1\]\.at: a free value in a place that cannot vary"),
    (lambda g: g["shape"].__setitem__("F", [{"free": [0.4, 0.3]}, 0.65]),
     r"^groups\[1\]\.shape\.F\[0\]: free range \[0\.4, 0\.3\] has lo > hi$"),
    (lambda g: g["lengths"].__setitem__(1, {"free": [-0.1, 0.7]}),
     r"^groups\[1\]\.lengths\[1\]: a length's free range must be positive, got \[-0\.1, 0\.7\]$"),
    (lambda g: g["shape"].__setitem__("F", {"free": [0.3, 0.4]}),
     r"^groups\[1\]\.shape\.F: a free value in a place that cannot vary"),
])
def test_triad_template_faults_are_one_line(edit: Any, message: str) -> None:
    data = copy.deepcopy(_data(FUNCTION))
    edit(data["groups"][1])
    with pytest.raises(SceneError, match=message) as info:
        load_template(data)
    assert "\n" not in str(info.value)


def test_free_values_of_a_triad_are_named_by_the_link_they_are() -> None:
    tpl = _sides_template()
    assert [tpl.label(f) for f in tpl.free] == ["C x", "C y", "triad A–D", "triad B–E", "triad C–F",
                                                  "triad D–E", "triad E–F", "triad F–D"]
    assert [tpl.label(f) for f in load_template(PATH).free][-2:] == ["triad F x (ternary link's frame)",
                                                                     "triad F y (ternary link's frame)"]
