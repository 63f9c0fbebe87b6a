"""Every module Пл1–Пл4, Пл1s–Пл4s, every branch: the contour closes, the analogs are its derivatives.

Checks (issue 3, "How it is checked"):
* closure: the contour's signed sum Σ σ_s·z_s is zero to TOL_CLOSE of its scale Σ|z_s|, and so are
  its first and second derivatives (the analogs close the differentiated contour: seed 004 eq. 1
  differentiated once and twice);
* analogs against differentiation of the positions: the points are complex numbers, so a complex
  step in φ would mix with them; instead a 7-point central difference (error O(h⁶)) with step
  H, held to TOL_D1 / TOL_D2 of the output's scale (rounding: ε/H ≈ 2e-13, ε/H² ≈ 2e-10);
* branches: every module with two solutions is solved with M = +1 and M = −1, both close, they
  differ, and the documented rule holds (Пл4: the summed vectors turn counter-clockwise for
  M = +1; Пл3, Пл1s: M = +1 gives the larger root of the unknown length).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

import solver
from solver._backend import NUMPY, cross
from solver._loader import parse_scene
from solver.groups import Context
from solver.scene import Scene
from solver.vectors import SOLUTIONS, Contour
from solver.vectors.terms import length_jet, unit_jet, vector_jet

TOL_CLOSE = 1e-12
H = 1e-3
TOL_D1 = 1e-9
TOL_D2 = 1e-6
PHI = np.linspace(0.0, 2 * math.pi, 97, endpoint=False) + 0.0123

MODULE_SCENES = {
    "Пл1": "vectors/pl1_slotted_lever",
    "Пл2": "vectors/pl2_scotch_yoke",
    "Пл3": "vectors/pl3_slider_crank",
    "Пл4": "vectors/pl4_four_bar_crossed",
    "Пл1s": "vectors/pl1s_offset_slot",
    "Пл2s": "vectors/pl2s_linked_slides",
    "Пл3s": "vectors/pl3s_bent_rod",
    "Пл4s": "vectors/pl4s_bent_four_bar",
}
CASES = [
    (module, name, mode)
    for module, name in MODULE_SCENES.items()
    for mode in ((1, -1) if SOLUTIONS[module] == 2 else (None,))
] + [("Пл4", "four_bar_vectors", 1), ("Пл1", "harvester_finger_vectors", None)]


def _scene(name: str, mode: int | None) -> Scene:
    path = solver.find_scene(name)
    data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    if mode is not None:
        for c in data["vector_model"]["contours"].values():
            c["M"] = mode
    return Scene(parse_scene(data, file=str(path), default_name=path.stem)).everything()


def _run(scene: Scene, phi: np.ndarray) -> dict:
    ctx = Context(phi=phi, xp=NUMPY)
    with np.errstate(divide="ignore", invalid="ignore"):
        scene.plan.run(ctx)
    return ctx.values


def _contours(scene: Scene) -> list[Contour]:
    return [g for g in scene.plan.groups if isinstance(g, Contour)]


@pytest.mark.parametrize(("module", "name", "mode"), CASES)
def test_solution_closes_its_contour_with_both_analogs(module: str, name: str, mode: int | None) -> None:
    scene = _scene(name, mode)
    (contour,) = _contours(scene)
    assert contour.module == module
    values = _run(scene, PHI)
    total, scale = contour.closure(values)
    for order, part in enumerate(total):
        assert np.max(np.abs(part)) <= TOL_CLOSE * np.max(scale), (order, np.max(np.abs(part)))


def _stencil(scene: Scene, phi: np.ndarray) -> list[dict]:
    out = []
    for k in (-3, -2, -1, 0, 1, 2, 3):
        kin = scene.solve(phi + k * H)
        row = {p: kin.point(p).position for p in scene.output_points}
        row.update({j: kin.joint(j).position for j in scene.output_joints})
        out.append(row)
    return out


@pytest.mark.parametrize(("module", "name", "mode"), CASES)
def test_analogs_agree_with_central_differences(module: str, name: str, mode: int | None) -> None:
    scene = _scene(name, mode)
    kin = scene.solve(PHI)
    rows = _stencil(scene, PHI)
    c1 = np.array([-1, 9, -45, 0, 45, -9, 1]) / (60 * H)
    c2 = np.array([2, -27, 270, -490, 270, -27, 2]) / (180 * H * H)
    outputs = [(p, kin.point(p)) for p in scene.output_points] + [(j, kin.joint(j)) for j in scene.output_joints]
    for out, motion in outputs:
        samples = [r[out] for r in rows]
        if out in scene.output_joints:  # angles: differences relative to the centre, unwrapped
            samples = [samples[3] + np.angle(np.exp(1j * (s - samples[3]))) for s in samples]
        d1 = sum(c * s for c, s in zip(c1, samples))
        d2 = sum(c * s for c, s in zip(c2, samples))
        scale = max(1.0 if out in scene.output_joints else 0.0, float(np.max(np.abs(motion.position))))
        v_scale = max(scale, float(np.max(np.abs(motion.velocity))))
        assert np.max(np.abs(d1 - motion.velocity)) <= TOL_D1 * v_scale, out
        a_scale = max(scale, float(np.max(np.abs(motion.acceleration))))
        assert np.max(np.abs(d2 - motion.acceleration)) <= TOL_D2 * a_scale, out


def _summed(contour: Contour, values: dict, index: int) -> np.ndarray:
    """Σ z_s of the terms whose angle follows unknown ``index`` (Пл4's v₁ or v₂)."""
    total = 0j
    for d in contour.deps:
        if d.ang_of == index:
            t = d.term
            total = total + vector_jet(t.sign, length_jet(t.r, values), unit_jet(t.alpha, values)).value
    return total


@pytest.mark.parametrize("module", [m for m, n in SOLUTIONS.items() if n == 2])
def test_both_branches_are_reached_and_follow_the_documented_rule(module: str) -> None:
    name = MODULE_SCENES[module]
    solved = {}
    for mode in (1, -1):
        scene = _scene(name, mode)
        (contour,) = _contours(scene)
        values = _run(scene, PHI)
        solved[mode] = (contour, values)
        if contour.form == "pl4":
            turn = cross(_summed(contour, values, 0), _summed(contour, values, 1))
            assert np.all(np.sign(turn) == mode), module
    (c, plus), (_, minus) = solved[1], solved[-1]
    moved = [u for u in c.unknowns if not np.allclose(plus[u].value, minus[u].value, rtol=0, atol=1e-9)]
    assert moved, f"{module}: M = ±1 gave the same solution"
    if c.form in ("pl1", "pl3"):
        length = next(u for u in c.unknowns if u.endswith(".r"))
        assert np.all(plus[length].value > minus[length].value), module


def test_elementary_pl1_reports_a_non_negative_length() -> None:
    scene = _scene(MODULE_SCENES["Пл1"], None)
    values = _run(scene, PHI)
    assert np.all(values["CA.r"].value > 0.0)


def test_pl4s_closure_has_no_solution_beyond_the_two_that_M_selects() -> None:
    """Seed 004 counts 4 for Пл4s; with α_s = θ_k + Δ_s the closure has two: count the roots in θ₁."""
    scene = _scene(MODULE_SCENES["Пл4s"], 1)
    (c,) = _contours(scene)
    phi = 0.7
    values = _run(scene, np.array([phi]))
    k = c.closure(values)[0].value - _summed(c, values, 0) - _summed(c, values, 1)
    p1 = sum(d.term.sign * d.term.r.offset * d.term.alpha.rot for d in c.deps if d.ang_of == 0)
    p2 = sum(d.term.sign * d.term.r.offset * d.term.alpha.rot for d in c.deps if d.ang_of == 1)
    theta = np.linspace(0.0, 2 * math.pi, 200001)
    f = np.abs(np.exp(1j * theta) * p1 + k) ** 2 - abs(p2) ** 2  # v₂ = −(v₁ + K) must have length |P₂|
    roots = np.count_nonzero(np.sign(f[1:]) != np.sign(f[:-1]))
    assert roots == 2


def test_pl3s_closure_has_no_solution_beyond_the_two_that_M_selects() -> None:
    """Seed 004 counts 4 for Пл3s: eliminating ρ leaves D × (e^{jθ}·P + K) = 0, two roots in θ."""
    scene = _scene(MODULE_SCENES["Пл3s"], 1)
    (c,) = _contours(scene)
    values = _run(scene, np.array([0.7]))
    i_a = next(i for i, u in enumerate(c.unknowns) if u.endswith(".alpha"))
    slide = next(d for d in c.deps if d.len_of is not None and d.ang_of is None)
    d_unit = slide.term.sign * unit_jet(slide.term.alpha, values).value
    k = (
        c.closure(values)[0].value
        - _summed(c, values, i_a)
        - vector_jet(slide.term.sign, length_jet(slide.term.r, values), unit_jet(slide.term.alpha, values)).value
    )
    p = sum(d.term.sign * d.term.r.offset * d.term.alpha.rot for d in c.deps if d.ang_of == i_a)
    theta = np.linspace(0.0, 2 * math.pi, 200001)
    f = cross(d_unit, np.exp(1j * theta) * p + k)
    assert np.count_nonzero(np.sign(f[1:]) != np.sign(f[:-1])) == 2


def test_pl4s_coupler_point_is_the_four_bar_of_the_summed_links() -> None:
    """Пл4s reduces to the four-bar whose coupler and rocker are the plates' summed vectors."""
    scene = _scene(MODULE_SCENES["Пл4s"], 1)
    (c,) = _contours(scene)
    l1 = abs(sum(d.term.sign * d.term.r.offset * d.term.alpha.rot for d in c.deps if d.ang_of == 0))
    l2 = abs(sum(d.term.sign * d.term.r.offset * d.term.alpha.rot for d in c.deps if d.ang_of == 1))
    data = yaml.safe_load(Path(solver.find_scene("four_bar")).read_text(encoding="utf-8"))
    data["groups"][1]["lengths"] = [l1, l2]
    groups = Scene(parse_scene(data, file=None))
    a, b = groups.solve(PHI, omega=1.3, epsilon=0.2).point("B"), scene.solve(PHI, omega=1.3, epsilon=0.2).point("B")
    for x, y in zip(a, b):
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-13)


TWO_CONTOURS = """
scene: two_contours
units: {length: m, angle: deg}
fixed: {O: [0, 0], C: [0, -0.15], G: [0.05, -0.1]}
vector_model:
  input: crank
  vectors:
    OA: {r: 0.06, alpha: {input: 15}}
    OC: {fixed: [O, C]}
    CG: {fixed: [C, G]}
    CA: {r: unknown, alpha: unknown}
    CQ: {r: {link: CA, plus: 0.05}, alpha: {link: CA, plus: 20}}
    QB: {r: {link: CA, plus: 0.3}, alpha: unknown}
    GB: {r: unknown, alpha: {link: CA, plus: -70}}
  contours:
    slider: {sum: [CQ, QB, -GB, -CG], M: 1}
    lever: {sum: [OC, CA, -OA]}
  points:
    A: {from: O, sum: [OA]}
    Q: {from: C, sum: [CQ]}
    B: {from: C, sum: [CQ, QB]}
  joints:
    swing: {angle: CA}
    slide: {length: GB}
    rod: {angle: QB}
outputs: {points: [A, Q, B], joints: [swing, slide, rod]}
"""


def test_contours_are_solved_in_dependency_order_with_moving_known_parameters() -> None:
    """The second contour reads the first's unknowns through links: moving lengths and angles in
    its terms (the known parts r', r'', α', α'' of the linear system), listed before the first."""
    scene = Scene(parse_scene(yaml.safe_load(TWO_CONTOURS), file=None)).everything()
    contours = _contours(scene)
    assert [c.name for c in contours] == ["lever", "slider"]
    assert [c.module for c in contours] == ["Пл1", "Пл3"]
    values = _run(scene, PHI)
    for c in contours:
        total, scale = c.closure(values)
        for part in total:
            assert np.max(np.abs(part)) <= TOL_CLOSE * np.max(scale), c.name
    kin = scene.solve(PHI)
    rows = _stencil(scene, PHI)
    c1 = np.array([-1, 9, -45, 0, 45, -9, 1]) / (60 * H)
    c2 = np.array([2, -27, 270, -490, 270, -27, 2]) / (180 * H * H)
    for out in ("B", "slide"):
        motion = kin.point(out) if out == "B" else kin.joint(out)
        samples = [r[out] for r in rows]
        d1 = sum(c * s for c, s in zip(c1, samples))
        d2 = sum(c * s for c, s in zip(c2, samples))
        np.testing.assert_allclose(d1, motion.velocity, rtol=0, atol=TOL_D1 * np.max(np.abs(motion.velocity)))
        np.testing.assert_allclose(d2, motion.acceleration, rtol=0, atol=TOL_D2 * np.max(np.abs(motion.acceleration)))


@pytest.mark.parametrize("mode", [1, -1])
def test_pl3s_whose_slide_turns_with_the_unknown_angle_is_the_pl1s_mechanism(mode: int) -> None:
    """The offset-slot lever written with the unknown angle on the arm CE and the unknown length on
    the slot EA (α_EA = α_CE − 90°): Пл3s solved in the rotating (Пл1s) form, same motion."""
    data = yaml.safe_load(Path(solver.find_scene(MODULE_SCENES["Пл1s"])).read_text(encoding="utf-8"))
    v = data["vector_model"]["vectors"]
    v["CE"]["alpha"] = "unknown"
    v["EA"]["alpha"] = {"link": "CE", "plus": -90}
    v["ED"]["alpha"] = {"link": "CE", "plus": -90}
    data["vector_model"]["contours"]["lever"]["M"] = mode
    other = Scene(parse_scene(data, file=None))
    ((contour,),) = [[g for g in other.plan.groups if isinstance(g, Contour)]]
    assert (contour.module, contour.form) == ("Пл3s", "pl1")
    ref = _scene(MODULE_SCENES["Пл1s"], mode)
    a = ref.solve(PHI, omega=1.1, epsilon=0.3)
    b = other.solve(PHI, omega=1.1, epsilon=0.3)
    for x, y in zip(a.point("D"), b.point("D")):
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-14)
    for x, y in zip(a.joint("slide"), b.joint("slide")):
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-14)
