"""The public API: shapes, scalar and vector paths agreeing, pruning to what the scene asks for."""

from __future__ import annotations

import numpy as np
import pytest

import solver
from solver.tolerances import EPS

SCENES = ["four_bar", "four_bar_crossed", "harvester_finger", "slider_crank", "spherical_converter"]


@pytest.mark.parametrize("name", SCENES)
def test_array_phi_gives_n_by_dim_points_and_n_joints(name: str) -> None:
    scene = solver.load_scene(name)
    k = scene.solve(np.linspace(0, 1, 7), omega=2.0, epsilon=0.5)
    for p in scene.output_points:
        for arr in k.point(p):
            assert arr.shape == (7, scene.dim)
            assert np.all(np.isfinite(arr))
    for j in scene.output_joints:
        for arr in k.joint(j):
            assert arr.shape == (7,)


@pytest.mark.parametrize("name", SCENES)
def test_scalar_path_agrees_with_the_vectorised_path(name: str) -> None:
    scene = solver.load_scene(name).everything()
    phi = np.linspace(-7.0, 9.0, 23)
    vec = scene.solve(phi, omega=1.7, epsilon=-0.3)
    for i, angle in enumerate(phi):
        one = scene.solve(float(angle), omega=1.7, epsilon=-0.3)
        for p in scene.point_names:
            for a, b in zip(one.point(p), vec.point(p)):
                assert type(a) is tuple and len(a) == scene.dim  # one instant: plain floats (InstantMotion)
                np.testing.assert_allclose(a, b[i], rtol=16 * EPS, atol=16 * EPS)
        for j in scene.joint_names:
            for a, b in zip(one.joint(j), vec.joint(j)):
                assert type(a) is float
                np.testing.assert_allclose(a, b[i], rtol=16 * EPS, atol=16 * EPS)


def test_long_sweeps_are_solved_in_blocks_with_the_same_result() -> None:
    scene = solver.load_scene("four_bar")
    phi = np.linspace(0, 2 * np.pi, 3 * solver.scene.CHUNK + 5)
    whole = scene.solve(phi)
    part = scene.solve(phi[-10:])
    np.testing.assert_array_equal(whole.point("B").acceleration[-10:], part.point("B").acceleration)


def test_asking_only_for_the_finger_tip_does_not_evaluate_the_groove() -> None:
    """Model only what a scene needs: C alone must not evaluate E (nor the finger angle)."""
    scene = solver.load_scene("harvester_finger").with_outputs(points=["C"], joints=[])
    assert scene.plan.group_names == ("drum", "finger_link")
    link = scene.plan.groups[-1]
    evaluated = [name for name, _ in link.points]
    assert evaluated == ["C"], "the slotted link must be pruned to the requested point"
    k = scene.solve(np.array([0.1, 0.2]))
    with pytest.raises(solver.SolverError, match="point 'E' was not requested"):
        k.point("E")


def test_a_joint_alone_prunes_the_points_it_does_not_need() -> None:
    scene = solver.load_scene("four_bar").with_outputs(points=[], joints=["crank"])
    assert scene.plan.group_names == ("crank",)


def test_with_omega_one_and_epsilon_zero_the_motion_is_the_analogs() -> None:
    scene = solver.load_scene("four_bar")
    a = scene.solve(np.array([0.3]))
    b = scene.solve(np.array([0.3]), omega=1.0, epsilon=0.0)
    np.testing.assert_array_equal(a.point("B").acceleration, b.point("B").acceleration)


def test_shipped_scenes_carry_a_provenance_note() -> None:
    for name, path in solver.shipped_scenes().items():
        scene = solver.load_scene(path)
        assert len(scene.provenance) > 40, f"{name} has no provenance note"


def test_input_joint_reports_phi_unwrapped() -> None:
    k = solver.load_scene("four_bar").with_outputs(joints=["crank"]).solve(np.array([-7.0, 10.0]))
    np.testing.assert_array_equal(k.joint("crank").position, [-7.0, 10.0])
    np.testing.assert_array_equal(k.joint("crank").velocity, [1.0, 1.0])


def test_non_finite_inputs_are_rejected_with_the_offending_name() -> None:
    scene = solver.load_scene("four_bar")
    with pytest.raises(solver.SolverError, match="phi must be finite"):
        scene.solve(np.array([0.0, np.nan]))
    with pytest.raises(solver.SolverError, match="omega must be finite"):
        scene.solve(0.0, omega=np.inf)
    with pytest.raises(solver.SolverError, match="phi must be a float or a 1-D array"):
        scene.solve(np.zeros((2, 2)))


@pytest.mark.parametrize("name", ["spherical_converter", "four_bar"])
def test_omega_and_epsilon_may_mix_arrays_and_floats(name: str) -> None:
    scene = solver.load_scene(name)
    phi = np.linspace(0.0, 1.0, 5)
    both = scene.solve(phi, omega=np.full(5, 1.5), epsilon=np.full(5, 0.3))
    for omega, epsilon in ((np.full(5, 1.5), 0.3), (1.5, np.full(5, 0.3)), (1.5, 0.3)):
        k = scene.solve(phi, omega=omega, epsilon=epsilon)
        p = scene.output_points[0]
        np.testing.assert_array_equal(k.point(p).acceleration, both.point(p).acceleration)
