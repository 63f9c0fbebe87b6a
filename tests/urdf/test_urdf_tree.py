"""The URDF is a valid tree, cuts the loops where docs/urdf.md says, and fails clearly where it
cannot export a scene."""

from __future__ import annotations

import io
import textwrap
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import pytest
from urdf_scene_lists import EXPORTABLE, NOT_EXPORTABLE, SHIPPED, VECTOR_SCENES

import solver
from linkage_ros.urdf import build_model, generate_urdf, main

SCENES = EXPORTABLE


def _exportable(name: str) -> solver.Scene:
    return solver.load_scene(name)


@pytest.mark.parametrize("name", SCENES)
def test_urdf_is_one_tree_with_unique_names_and_existing_parents_and_children(name: str) -> None:
    root = ET.fromstring(generate_urdf(_exportable(name)))
    links = [e.get("name") for e in root.findall("link")]
    joints = root.findall("joint")
    joint_names = [j.get("name") for j in joints]
    assert len(set(links)) == len(links), "link names repeat"
    assert len(set(joint_names)) == len(joint_names), "joint names repeat"
    parents = [j.find("parent").get("link") for j in joints]  # type: ignore[union-attr]
    children = [j.find("child").get("link") for j in joints]  # type: ignore[union-attr]
    assert set(parents) | set(children) <= set(links)
    assert len(set(children)) == len(children), "a link with two parents is not a tree"
    roots = set(links) - set(children)
    assert roots == {"world"}
    # connected: every link is reached from the root
    reached: set[str | None] = {"world"}
    frontier: list[str | None] = ["world"]
    while frontier:
        here = frontier.pop()
        for p, c in zip(parents, children):
            if p == here and c not in reached:
                reached.add(c)
                frontier.append(c)
    assert reached == set(links)


@pytest.mark.parametrize("name", SCENES)
def test_yourdfpy_validates_the_urdf_and_sees_one_base(name: str) -> None:
    yourdfpy = pytest.importorskip("yourdfpy", reason="yourdfpy is the independent URDF parser")
    urdf = yourdfpy.URDF.load(io.StringIO(generate_urdf(_exportable(name))), load_meshes=False)
    assert urdf.validate()
    assert urdf.base_link == "world"
    model = build_model(solver.load_scene(name))
    assert tuple(urdf.actuated_joint_names) == model.joint_names


@pytest.mark.parametrize("name", SCENES)
def test_every_cut_has_two_fixed_frames_on_its_two_sides(name: str) -> None:
    scene = _exportable(name)
    model = build_model(scene)
    root = ET.fromstring(generate_urdf(scene))
    fixed = {j.find("child").get("link"): j for j in root.findall("joint") if j.get("type") == "fixed"}  # type: ignore[union-attr]
    assert model.cuts, "every shipped mechanism has a loop"
    for cut in model.cuts:
        for side, body in (("a", cut.side_a), ("b", cut.side_b)):
            joint = fixed[f"{cut.name}_{side}"]
            assert joint.find("parent").get("link") == body  # type: ignore[union-attr]
        assert cut.side_a != cut.side_b


def test_four_bar_is_cut_at_the_coupler_rocker_pin() -> None:
    model = build_model(solver.load_scene("four_bar"))
    assert [(c.name, c.side_a, c.side_b) for c in model.cuts] == [("dyad_B", "dyad_AB", "dyad_CB")]
    assert [(j.name, j.type, j.parent, j.child) for j in model.joints] == [
        ("crank_joint", "continuous", "base_link", "crank"),
        ("dyad_AB_joint", "continuous", "crank", "dyad_AB"),
        ("dyad_CB_joint", "continuous", "base_link", "dyad_CB"),
    ]


def test_harvester_finger_has_drum_finger_and_eyelet_slider_and_cuts_the_eyelet_pin() -> None:
    model = build_model(solver.load_scene("harvester_finger"))
    assert [(j.name, j.type, j.parent, j.child) for j in model.joints] == [
        ("drum_joint", "continuous", "base_link", "drum"),
        ("finger_joint", "continuous", "base_link", "finger"),  # the scene's body 'finger' (group finger_link)
        ("finger_link_eyelet_joint", "prismatic", "finger", "finger_link_eyelet"),
    ]
    assert [(c.name, c.side_a, c.side_b) for c in model.cuts] == [("finger_link_B", "finger_link_eyelet", "drum")]
    assert model.bodies["drum"].role == "drum"
    root = ET.fromstring(generate_urdf(solver.load_scene("harvester_finger")))
    drum = next(e for e in root.findall("link") if e.get("name") == "drum")
    assert drum.find("visual/geometry/cylinder").get("radius") == "0.2"  # type: ignore[union-attr]


def test_slider_crank_slides_the_slider_on_its_guide_and_cuts_the_rod_slider_pin() -> None:
    model = build_model(solver.load_scene("slider_crank"))
    slide = model.joints[-1]
    expected = ("rod_slider_joint", "prismatic", "base_link", (0.0, 0.01, 0.0))
    assert (slide.name, slide.type, slide.parent, slide.xyz) == expected
    assert [(c.side_a, c.side_b) for c in model.cuts] == [("rod", "rod_slider")]
    root = ET.fromstring(generate_urdf(solver.load_scene("slider_crank")))
    limit = next(j for j in root.findall("joint") if j.get("name") == "rod_slider_joint").find("limit")
    lower, upper = float(limit.get("lower")), float(limit.get("upper"))  # type: ignore[union-attr, arg-type]
    # B travels between sqrt(0.25² − 0.01²) and sqrt(0.15² − 0.01²) (offset slider-crank extremes)
    assert lower < (0.15**2 - 0.01**2) ** 0.5 < (0.25**2 - 0.01**2) ** 0.5 < upper


def test_spherical_converter_opens_the_spherical_four_bar_at_the_ring_cage_pin() -> None:
    model = build_model(solver.load_scene("spherical_converter"))
    assert [(j.name, j.parent, j.axis) for j in model.joints][0::2] == [
        ("converter_shaft_joint", "base_link", (0.0, 1.0, 0.0)),
        ("converter_cage_joint", "base_link", (-1.0, 0.0, 0.0)),
    ]
    assert [(c.side_a, c.side_b) for c in model.cuts] == [("converter_ring", "converter_cage")]


def _scene_file(tmp_path: Path, body: str) -> solver.Scene:
    path = tmp_path / "scene.yaml"
    path.write_text(textwrap.dedent(body), encoding="utf-8")
    return solver.load_scene(path)


FOUR_BAR = """\
    scene: coupler_curve
    units: {length: m, angle: deg}
    fixed: {O: [0, 0], C: [0.4, 0]}
    groups:
      - {type: crank, name: crank, center: O, point: A, length: 0.1}
      - {type: rrr, name: dyad, ends: [A, C], point: B, lengths: [0.4, 0.3], M: +1}
      - {type: attached, name: tracer, point: P, base: A, along: [A, B], distance: 0.2, angle: 30}
    joints: {%s: {angle: [C, B]}}
    outputs: {points: [P]}
"""


def test_attached_point_rides_on_the_body_that_carries_its_direction(tmp_path: Path) -> None:
    scene = _scene_file(tmp_path, FOUR_BAR % "rocker")
    model = build_model(scene)
    assert model.owner["P"] == "dyad_AB"
    assert ("A", "P") in model.bodies["dyad_AB"].bars


def test_attached_point_across_two_bodies_is_a_clear_error(tmp_path: Path) -> None:
    body = FOUR_BAR.replace("along: [A, B]", "along: [O, B]") % "rocker"
    with pytest.raises(solver.SceneError, match=r"attached to \['A', 'O', 'B'\], which lie on no single rigid body"):
        build_model(_scene_file(tmp_path, body))


def test_scene_joint_named_like_a_tree_joint_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(solver.SceneError, match="tree joint names dyad_CB_joint are also scene joints"):
        build_model(_scene_file(tmp_path, FOUR_BAR % "dyad_CB_joint"))


@dataclass(frozen=True)
class _VectorContour:
    name: str = "loop1"
    kind: str = "vector_contour"


def test_group_kind_without_export_is_a_clear_error() -> None:
    scene = solver.load_scene("four_bar")
    odd = type("OddScene", (), {})()
    for attr in ("name", "path", "dim", "input_joint", "joint_names", "fixed_points"):
        setattr(odd, attr, getattr(scene, attr))
    odd.ordered = (*scene.ordered, _VectorContour())  # type: ignore[attr-defined]
    with pytest.raises(solver.SceneError, match="group kind 'vector_contour' has no URDF export; supported: crank"):
        build_model(odd)


def test_cli_writes_the_urdf_to_a_file(tmp_path: Path) -> None:
    out = tmp_path / "four_bar.urdf"
    assert main(["four_bar", "-o", str(out)]) == 0
    assert ET.fromstring(out.read_text(encoding="utf-8")).get("name") == "four_bar"


def test_cli_prints_to_stdout_with_another_root(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["slider_crank", "--frame-id", "base_link"]) == 0
    root = ET.fromstring(capsys.readouterr().out.split("\n", 1)[1])
    assert "world" not in {e.get("name") for e in root.findall("link")}


def test_cli_reports_an_unknown_scene_and_exits_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["no_such_scene"]) == 2
    assert "linkage-urdf: error:" in capsys.readouterr().err


def test_every_shipped_scene_is_exportable_vector_scenes_included() -> None:
    assert NOT_EXPORTABLE == []  # the triad (issue 28) included: three bars, the ternary link, two cuts
    assert EXPORTABLE == SHIPPED
    assert {"four_bar_vectors", "harvester_finger_vectors", "vectors/pl2s_linked_slides"} <= set(VECTOR_SCENES)
