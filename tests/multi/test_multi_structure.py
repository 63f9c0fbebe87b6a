"""Scenes whose inputs do not determine them are rejected at load, naming the groups concerned;
samples that cannot be assembled are named as rows of (q1, q2), or masked."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from multi_builders import FIVE_BAR, build, edited, five_bar

import solver
from solver.multi import SampleAssemblyError, assemblable

FOUR_BAR = yaml.safe_load(
    """
scene: four_bar_test
units: {length: m, angle: deg}
fixed: {O: [0, 0], C: [0.4, 0]}
groups:
  - {type: crank, name: crank, center: O, point: A, length: 0.1}
  - {type: rrr, name: dyad, ends: [A, C], point: B, lengths: [0.4, 0.3], M: +1}
outputs: {points: [B]}
"""
)


def _drop_right_crank(d: dict) -> None:
    d["groups"].pop(1)
    d["outputs"]["joints"] = ["q1"]


def test_a_point_no_input_moves_is_too_few_inputs() -> None:
    with pytest.raises(
        solver.SceneError,
        match=r"fb\.yaml: rrr 'distal': unknown point or joint 'A2' \(nothing provides it: .*too few inputs",
    ):
        build(edited(_drop_right_crank), file="fb.yaml")


def test_a_crank_on_a_point_a_dyad_determines_is_too_many_inputs() -> None:
    data = edited(lambda d: d["groups"].append({"type": "crank", "name": "rocker_drive", "center": "C", "point": "B",
                                                "length": 0.3}), FOUR_BAR)
    with pytest.raises(
        solver.SceneError,
        match=r"fb\.yaml: groups: 'B' is defined twice: by rrr 'dyad' and by crank 'rocker_drive': too many inputs "
        r"\(over-determined\) — input 'rocker_drive' of crank 'rocker_drive' moves a point that rrr 'dyad' also",
    ):
        build(data, file="fb.yaml")


def test_two_cranks_on_one_point_are_too_many_inputs() -> None:
    extra = {"type": "crank", "name": "extra", "center": "O2", "point": "A1", "length": 0.15, "joint": "q3"}
    with pytest.raises(solver.SceneError, match=r"'A1' is defined twice: by crank 'left_crank' and by crank 'extra'"):
        build(edited(lambda d: d["groups"].append(extra)), file="fb.yaml")


def test_an_input_that_moves_no_output_is_rejected_for_the_declared_outputs() -> None:
    def only_left(d: dict) -> None:
        d["outputs"] = {"points": ["A1"], "joints": ["q1"]}

    with pytest.raises(
        solver.SceneError,
        match=r"fb\.yaml: outputs: too many inputs: input 'q2' of crank 'right_crank' moves none of the outputs",
    ):
        build(edited(only_left), file="fb.yaml")
    # asking a loaded scene for fewer outputs is fine: that input's columns are zero
    k = five_bar().with_outputs(points=["A1"], joints=[]).solve(np.array([[0.3, 1.2]]))
    np.testing.assert_array_equal(k.point("A1").jacobian[0, :, 1], [0.0, 0.0])


def test_continuous_branches_are_single_input() -> None:
    with pytest.raises(solver.SceneError, match=r"rrr 'distal': through_change_points: continuous .* use 'keep'"):
        build(edited(lambda d: d["groups"][2].update(through_change_points="continuous")), file="fb.yaml")


def test_a_scene_without_input_keeps_its_message() -> None:
    with pytest.raises(solver.SceneError, match=r"a scene needs exactly one input \(a crank\), found 0"):
        build(edited(lambda d: d.update(groups=[d["groups"][2]])), file="fb.yaml")


# -- assembly in two dimensions ------------------------------------------------------------------
SHORT = 0.2
"""Distal links of 0.2 m: the five-bar closes only where |A1A2| ≤ 0.4 m."""


def _reach(q: np.ndarray) -> np.ndarray:
    """|A2 − A1| of the 0.15/0.2 m five-bar, in closed form."""
    a1 = 0.15 * np.exp(1j * q[:, 0])
    a2 = 0.2 + 0.15 * np.exp(1j * q[:, 1])
    return np.abs(a2 - a1)


def test_unassemblable_samples_are_named_with_every_input() -> None:
    scene = five_bar(distal=SHORT)
    q = np.radians([[90.0, 90.0], [180.0, 0.0], [170.0, 10.0], [60.0, 120.0]])
    with pytest.raises(
        SampleAssemblyError,
        match=r"group 'distal' cannot be assembled at 2 sample\(s\) of \(q1, q2\) = "
        r"\(180\.0000°, 0\.0000°\), \(170\.0000°, 10\.0000°\)",
    ) as info:
        scene.solve(q)
    assert isinstance(info.value, solver.AssemblyError)
    assert info.value.group == "distal" and info.value.intervals == ()
    np.testing.assert_array_equal(info.value.samples, q[1:3])
    with pytest.raises(solver.AssemblyError, match=r"at 1 sample\(s\) of \(q1, q2\) = \(180\.0000°, 0\.0000°\)"):
        scene.solve((math.pi, 0.0))


def test_mask_returns_the_assemblable_samples() -> None:
    scene = five_bar(distal=SHORT)
    grid = np.radians(np.arange(0.0, 360.0, 7.5))
    q = np.stack(np.meshgrid(grid, grid, indexing="ij"), axis=-1).reshape(-1, 2)
    k = scene.solve(q, mask=True)
    reach = _reach(q)
    clear = np.abs(reach - 2 * SHORT) > 1e-9  # away from the boundary, the verdict is unambiguous
    np.testing.assert_array_equal(k.valid[clear], (reach <= 2 * SHORT)[clear])
    ok = k.valid & clear
    assert np.isfinite(k.point("P").position[ok]).all()
    assert not scene.solve((math.pi, 0.0), mask=True).valid
    region = assemblable(scene, [grid, grid])
    assert region.shape == (len(grid), len(grid))
    np.testing.assert_array_equal(region.ravel(), k.valid)


def test_the_shipped_five_bar_closes_everywhere_but_at_coincident_elbows() -> None:
    """|A1A2| ≤ 0.2 + 2·0.15 = 0.5 = 2·0.25: it only fails where A1 = A2 (q1 = π − q2 = acos(2/3))."""
    scene = solver.load_scene("five_bar")
    grid = np.radians(np.arange(0.0, 360.0, 10.0))
    assert assemblable(scene, [grid, grid]).all()
    q1 = math.acos(0.2 / 0.3)
    with pytest.raises(solver.AssemblyError, match=r"group 'distal' has its two ends on one point"):
        scene.solve((q1, math.pi - q1))


def test_singular_samples_are_flagged_with_nan_derivatives_and_exact_positions() -> None:
    """q = (π, 0): A1, P and A2 on one line (the distal links stretched): a type-II singularity."""
    scene = solver.load_scene("five_bar")
    k = scene.solve(np.array([[math.pi, 0.0], [math.pi / 2, math.pi / 2]]), omega=[1.0, 1.0])
    assert k.singular.tolist() == [True, False]
    assert k.conditioning["distal"][0] < 1e-6
    np.testing.assert_allclose(k.point("P").position[0], [0.1, 0.0], atol=1e-12)
    assert np.isnan(k.point("P").jacobian[0]).all() and np.isnan(k.point("P").velocity[0]).all()
    assert np.isfinite(k.point("P").hessian[1]).all()
    tick = scene.solve((math.pi, 0.0))
    assert bool(tick.singular) and math.isnan(tick.floats("P")[1][0])


def test_scene_inputs_of_a_single_input_scene() -> None:
    scene = solver.load_scene("four_bar")
    assert scene.inputs == ("crank",) and scene.input_joint == "crank"
    assert build(FIVE_BAR).inputs == ("q1", "q2")
