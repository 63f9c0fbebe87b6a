"""Vector-loop scenes (seed 004) export as URDF: bodies from the vectors' classes, slides for
variable lengths, one pin cut per contour; the same tree and joint states as the group form of the
same mechanism; clear errors where a scene does not say enough (docs/urdf.md, "Vector scenes")."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np
import pytest

import solver
from linkage_ros.urdf import build_model, exportable_model, main, tree_joint_states

EPS = float(np.finfo(float).eps)
#: Vector form against group form of one mechanism: two closed-form solutions of one closure.
TOL_SAME_MECHANISM = 1e-12
PHI = np.linspace(0.0, 2.0 * math.pi, 72, endpoint=False)


def _structure(name: str) -> tuple[list[tuple[str, str, str]], list[tuple[str, str, str]]]:
    model = build_model(solver.load_scene(name))
    joints = [(j.type, j.parent, j.child) for j in model.joints]
    cuts = [(c.point, c.side_a, c.side_b) for c in model.cuts]
    return joints, cuts


def _states(name: str) -> np.ndarray:
    scene = solver.load_scene(name).everything()
    states = tree_joint_states(build_model(scene), scene.solve(PHI, omega=1.3, epsilon=-0.2))
    return np.concatenate([states.position, states.velocity], axis=1)


def test_four_bar_vectors_opens_into_the_group_forms_tree_with_the_same_joint_states() -> None:
    assert _structure("four_bar_vectors") == _structure("four_bar")
    assert build_model(solver.load_scene("four_bar_vectors")).joint_names == (
        "crank_joint", "dyad_AB_joint", "dyad_CB_joint"
    )
    np.testing.assert_allclose(_states("four_bar_vectors"), _states("four_bar"), rtol=0, atol=TOL_SAME_MECHANISM)


def test_harvester_vectors_has_drum_finger_and_eyelet_and_cuts_the_eyelet_pin() -> None:
    model = build_model(solver.load_scene("harvester_finger_vectors"))
    assert [(j.name, j.type, j.parent) for j in model.joints] == [
        ("drum_joint", "continuous", "base_link"),
        ("finger_link_AB_joint", "continuous", "base_link"),
        ("finger_link_AB_slider_joint", "prismatic", "finger_link_AB"),
    ]
    assert [(c.name, c.side_a, c.side_b) for c in model.cuts] == [("finger_link_B", "finger_link_AB_slider", "drum")]
    assert model.bodies["drum"].role == "drum"
    assert set(model.bodies["finger_link_AB"].local) == {"A", "C", "E"}
    np.testing.assert_allclose(
        _states("harvester_finger_vectors"), _states("harvester_finger"), rtol=0, atol=TOL_SAME_MECHANISM
    )


def test_slider_crank_vectors_matches_the_group_form_and_puts_the_guide_origin_on_the_frame() -> None:
    vec, group = _structure("vectors/pl3_slider_crank"), _structure("slider_crank")
    assert [j[0] for j in vec[0]] == [j[0] for j in group[0]] == ["continuous", "continuous", "prismatic"]
    assert [c[0] for c in vec[1]] == [c[0] for c in group[1]] == ["B"]
    model = build_model(solver.load_scene("vectors/pl3_slider_crank"))
    slide = model.joints[-1]
    assert (slide.type, slide.parent, slide.axis) == ("prismatic", "base_link", (1.0, 0.0, 0.0))
    assert slide.xyz == pytest.approx((0.0, 0.01, 0.0), abs=EPS)
    np.testing.assert_allclose(_states("vectors/pl3_slider_crank"), _states("slider_crank"), rtol=0,
                               atol=TOL_SAME_MECHANISM)


def test_scotch_yoke_hangs_two_slides_in_series_and_cuts_the_crank_pin() -> None:
    model = build_model(solver.load_scene("vectors/pl2_scotch_yoke"))
    assert [(j.name, j.type, j.parent, j.axis[:2]) for j in model.joints][1:] == [
        ("yoke_OY_joint", "prismatic", "base_link", (1.0, 0.0)),
        ("yoke_YA_joint", "prismatic", "yoke_OY", pytest.approx((0.0, 1.0), abs=EPS)),
    ]
    assert [(c.point, c.side_a, c.side_b) for c in model.cuts] == [("A", "yoke_YA", "crank")]
    scene = solver.load_scene("vectors/pl2_scotch_yoke").everything()
    k = scene.solve(PHI, omega=2.0)
    states = tree_joint_states(model, k)
    np.testing.assert_allclose(states.position[:, 1], k.joint("stroke").position, rtol=0, atol=64 * EPS)
    np.testing.assert_allclose(states.position[:, 2], k.joint("slot").position, rtol=0, atol=64 * EPS)
    np.testing.assert_allclose(states.velocity[:, 2], k.joint("slot").velocity, rtol=0, atol=64 * EPS)


def test_linked_slides_keep_their_geared_offset_in_the_joint_states() -> None:
    """Пл2s: r_YZ = r_OY + 0.02 m is no loop of the tree, yet the slides' states keep it exactly."""
    scene = solver.load_scene("vectors/pl2s_linked_slides").everything()
    model = build_model(scene)
    states = tree_joint_states(model, scene.solve(PHI))
    q = dict(zip(states.names, states.position.T))
    np.testing.assert_allclose(q["carriage_YZ_joint"] - q["carriage_OY_joint"], 0.02, rtol=0, atol=64 * EPS)


def test_offset_slot_slider_rides_the_slot_from_the_arms_end() -> None:
    """Пл1s: the lever (arm CE at 90° to the slot, and ED) pivots at C; the slider slides from E."""
    scene = solver.load_scene("vectors/pl1s_offset_slot").everything()
    model = build_model(scene)
    lever = model.bodies["lever_EA"]
    assert lever.local["E"] == pytest.approx((0.0, 0.03, 0.0), abs=EPS)
    slide = model.joints[-1]
    assert (slide.parent, slide.xyz) == ("lever_EA", lever.local["E"])
    k = scene.solve(PHI, omega=1.5)
    states = tree_joint_states(model, k)
    np.testing.assert_allclose(states.position[:, -1], k.joint("slide").position, rtol=0, atol=64 * EPS)


def test_bent_four_bar_bodies_carry_their_bent_plates() -> None:
    model = build_model(solver.load_scene("vectors/pl4s_bent_four_bar"))
    assert set(model.bodies["dyad_AK"].local) == {"A", "K", "B"}
    assert set(model.bodies["dyad_CL"].local) == {"C", "L", "B"}
    assert [(c.name, c.side_a, c.side_b) for c in model.cuts] == [("dyad_B", "dyad_AK", "dyad_CL")]


@pytest.mark.parametrize("name", ["four_bar_vectors", "harvester_finger_vectors", "vectors/pl2_scotch_yoke"])
def test_vector_input_crank_follows_phi_unwrapped(name: str) -> None:
    scene = solver.load_scene(name).everything()
    states = tree_joint_states(build_model(scene), scene.solve(np.array([-7.0, 0.0, 9.5, 40.0]), omega=2.0))
    assert states.names[0] == f"{scene.input_joint}_joint"
    np.testing.assert_allclose(states.position[:, 0], [-7.0, 0.0, 9.5, 40.0], rtol=0, atol=64 * EPS * 40)


FOUR_BAR = """\
    scene: vector_four_bar
    units: {length: m, angle: deg}
    fixed: {O: [0, 0], C: [0.4, 0]}
    vector_model:
      input: crank
      vectors:
        OA: {r: 0.1, alpha: input}
        AB: {r: 0.4, alpha: unknown}
        CB: {r: 0.3, alpha: unknown}
        OC: {fixed: [O, C]}
      contours:
        dyad: {sum: [OA, AB, -CB, -OC], M: +1}
      points:
        A: {from: O, sum: [OA]}
    %s
      joints:
        rocker: {angle: CB}
    outputs: {points: [A]}
"""


def _scene(tmp_path: Path, extra: str = "") -> solver.Scene:
    path = tmp_path / "scene.yaml"
    path.write_text(textwrap.dedent(FOUR_BAR % extra), encoding="utf-8")
    return solver.load_scene(path)


def test_a_body_whose_angle_no_output_reads_is_a_clear_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    scene = _scene(tmp_path)
    with pytest.raises(solver.SceneError, match=r"the angle of vector 'AB' \(AB.alpha\) cannot be read .* add a "
                                                r"joint \{angle: AB\}"):
        build_model(scene)
    assert exportable_model(scene) is None  # the node still publishes the scene's own joints
    assert main([str(tmp_path / "scene.yaml")]) == 2
    assert "has no URDF export: the angle of vector 'AB'" in capsys.readouterr().err


def test_naming_a_second_point_on_the_body_makes_it_exportable(tmp_path: Path) -> None:
    model = build_model(_scene(tmp_path, "    B: {from: O, sum: [OA, AB]}"))
    assert model.bodies["dyad_AB"].axis == ("A", "B")
    assert [c.name for c in model.cuts] == ["dyad_B"]


def test_a_vector_used_as_a_free_vector_is_a_clear_error(tmp_path: Path) -> None:
    scene = _scene(tmp_path, "    B: {from: O, sum: [OA, AB]}\n        P: {from: O, sum: [AB]}")
    with pytest.raises(solver.SceneError, match=r"vector 'OA' start and end at one node \(O\).*used as a free vector"):
        build_model(scene)


def test_a_free_vector_that_closes_no_self_loop_is_caught_by_the_placement_check(tmp_path: Path) -> None:
    scene = _scene(tmp_path, "    B: {from: O, sum: [OA, AB]}\n        P: {from: C, sum: [AB]}")
    with pytest.raises(solver.SceneError, match="does not follow the solver .* used as a free vector"):
        build_model(scene)


@pytest.mark.parametrize("name", ["harvester_finger_vectors", "vectors/pl2s_linked_slides"])
def test_joint_states_of_a_vector_scene_carry_its_tree_joints(name: str) -> None:
    """messages.py publishes the tree joints for every scene exportable_model gives a tree."""
    from rosbags.typesys import Stores, get_typestore

    from linkage_ros.engine import Engine
    from linkage_ros.messages import build_messages
    from linkage_ros.motion import Motion

    store = get_typestore(Stores.ROS2_JAZZY)
    engine = Engine(name, Motion(phi0=0.3, omega=2.0, epsilon=0.1))
    frame = engine.frame(0.7)
    messages = dict(build_messages(frame, store.types, frame_id="world", stamp=1, engine=engine))
    js = messages["joint_states"]
    model = exportable_model(engine.scene)
    assert model is not None and model.joints
    assert list(js.name) == [*engine.scene.joint_names, *model.joint_names]  # type: ignore[attr-defined]
    assert all(math.isfinite(q) for q in js.position)  # type: ignore[attr-defined]
